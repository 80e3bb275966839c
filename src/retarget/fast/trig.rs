//! `sin`, `cos` and `atan2` eight lanes at a time: loops over fdlibm's published polynomials,
//! each lane as the one-value function computes it.

use crate::retarget::fast::lanes::{LANES, Lanes, lanes};

/// fdlibm's constants: k_sin.c and k_cos.c's polynomials on [-π/4, π/4], the first two parts of
/// π/2 and the tail (e_rem_pio2.c), s_atan.c's polynomial and atan(0.5), atan(1), atan(1.5),
/// atan(∞) in two parts, π's tail; digit for digit as its sources print them (each rounds to
/// the double fdlibm means).
#[allow(clippy::excessive_precision)]
mod fdlibm {
    pub(super) const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    pub(super) const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    pub(super) const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    pub(super) const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    pub(super) const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    pub(super) const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    pub(super) const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    pub(super) const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    pub(super) const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    pub(super) const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    pub(super) const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    pub(super) const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    pub(super) const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
    pub(super) const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
    pub(super) const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
    pub(super) const AT: [f64; 11] = [
        3.333_333_333_333_293_180_27e-1,
        -1.999_999_999_987_648_324_76e-1,
        1.428_571_427_250_346_637_11e-1,
        -1.111_111_040_546_235_578_80e-1,
        9.090_887_133_436_506_561_96e-2,
        -7.691_876_205_044_829_994_95e-2,
        6.661_073_137_387_531_206_69e-2,
        -5.833_570_133_790_573_486_45e-2,
        4.976_877_994_615_932_360_17e-2,
        -3.653_157_274_421_691_552_70e-2,
        1.628_582_011_536_578_236_23e-2,
    ];
    pub(super) const ATAN_HI: [f64; 4] = [
        4.636_476_090_008_060_935_15e-1,
        std::f64::consts::FRAC_PI_4,
        9.827_937_232_473_290_540_82e-1,
        std::f64::consts::FRAC_PI_2,
    ];
    pub(super) const ATAN_LO: [f64; 4] = [
        2.269_877_745_296_168_709_24e-17,
        3.061_616_997_868_383_017_93e-17,
        1.390_331_103_123_099_845_16e-17,
        6.123_233_995_736_766_035_87e-17,
    ];
    pub(super) const PI_LO: f64 = 1.224_646_799_147_353_177_2e-16;
}
use fdlibm::{
    AT, ATAN_HI, ATAN_LO, C1, C2, C3, C4, C5, C6, PI_LO, PIO2_1, PIO2_2, PIO2_2T, S1, S2, S3, S4,
    S5, S6,
};

/// Angles (radians) this far from 0 or beyond go to libm: the reduction by parts of π/2 (33 bits
/// each) is exact for fewer than 2²⁰ quarter turns.
pub(super) const SIN_COS_LIMIT: f64 = 1.0e5;

/// `(sin x, cos x)` by fdlibm's kernels after reducing `x` to [-π/4, π/4]; no branches, so a loop
/// over lanes becomes vector code. For |x| < [`SIN_COS_LIMIT`].
#[inline(always)]
pub(super) fn sin_cos_lane(x: f64) -> (f64, f64) {
    // Rounding to a whole number of quarter turns by the 1.5·2⁵² trick; its low bits are the
    // quadrant.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let t = x * std::f64::consts::FRAC_2_PI + ROUND;
    let n = t - ROUND;
    let quadrant = t.to_bits();
    let r = ((x - n * PIO2_1) - n * PIO2_2) - n * PIO2_2T;
    let z = r * r;
    let v = z * r;
    // The polynomials by Estrin's scheme: pairs side by side, for shorter chains.
    let z2 = z * z;
    let sin = r + v * ((S1 + z * S2) + z2 * ((S3 + z * S4) + z2 * (S5 + z * S6)));
    let rest = z * ((C1 + z * C2) + z2 * ((C3 + z * C4) + z2 * (C5 + z * C6)));
    let half = 0.5 * z;
    let w = 1.0 - half;
    let cos = w + (((1.0 - w) - half) + z * rest);
    let (a, b) = if quadrant & 1 != 0 {
        (cos, sin)
    } else {
        (sin, cos)
    };
    (
        if quadrant & 2 != 0 { -a } else { a },
        if quadrant.wrapping_add(1) & 2 != 0 {
            -b
        } else {
            b
        },
    )
}

/// [`sin_cos_lane`] of every lane; libm's for an angle too large for it (or not finite).
#[inline(always)]
pub(super) fn sin_cos(x: &Lanes, sin: &mut Lanes, cos: &mut Lanes) {
    for l in 0..LANES {
        (sin[l], cos[l]) = sin_cos_lane(x[l]);
    }
    let wild = |x: f64| x.is_nan() || x.abs() >= SIN_COS_LIMIT;
    if x.iter().any(|&x| wild(x)) {
        for l in 0..LANES {
            if wild(x[l]) {
                (sin[l], cos[l]) = x[l].sin_cos();
            }
        }
    }
}

/// `atan2(y, x)` as fdlibm's `atan` of |y/x| (reduced about 0, 0.5, 1, 1.5 or ∞, its quotient taken
/// as one division of |y| and |x|), then turned into the quadrant; signed zeros as libm's. No
/// branches; for finite `y` and `x`.
#[inline(always)]
pub(super) fn atan2_lane(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    // The range of |y/x| (16·|y| against k·|x|: no division needed to pick it).
    let (y16, zero) = (ay * 16.0, ay == 0.0);
    let far = !zero && y16 >= ax * 39.0;
    let (c, hi, lo) = if zero || y16 < ax * 7.0 {
        (0.0, 0.0, 0.0)
    } else if y16 < ax * 11.0 {
        (0.5, ATAN_HI[0], ATAN_LO[0])
    } else if y16 < ax * 19.0 {
        (1.0, ATAN_HI[1], ATAN_LO[1])
    } else if !far {
        (1.5, ATAN_HI[2], ATAN_LO[2])
    } else {
        (0.0, ATAN_HI[3], ATAN_LO[3])
    };
    // atan(a) = atan(c) + atan((a − c) / (1 + c·a)) for a = |y/x|, in one division; about ∞,
    // π/2 + atan(−1/a).
    let u = if zero {
        0.0
    } else if far {
        -ax / ay
    } else {
        (ay - c * ax) / (ax + c * ay)
    };
    let z = u * u;
    let w = z * z;
    let w2 = w * w;
    let s1 = z * ((AT[0] + w * AT[2]) + w2 * ((AT[4] + w * AT[6]) + w2 * (AT[8] + w * AT[10])));
    let s2 = w * ((AT[1] + w * AT[3]) + w2 * ((AT[5] + w * AT[7]) + w2 * AT[9]));
    let angle = hi - ((u * (s1 + s2) - lo) - u);
    // x < 0 (or −0 with y = ±0): the far side, π − angle.
    let far_side = x.is_sign_negative() && !(x == 0.0 && y != 0.0);
    let angle = if far_side {
        std::f64::consts::PI - (angle - PI_LO)
    } else {
        angle
    };
    angle.copysign(y)
}

/// [`atan2_lane`] of every lane; libm's where a value is not finite.
#[inline(always)]
pub(super) fn atan2(y: &Lanes, x: &Lanes) -> Lanes {
    let mut out = lanes(|l| atan2_lane(y[l], x[l]));
    if y.iter().chain(x).any(|v| !v.is_finite()) {
        for l in 0..LANES {
            if !(y[l].is_finite() && x[l].is_finite()) {
                out[l] = y[l].atan2(x[l]);
            }
        }
    }
    out
}
