//! The fast pass of [`super::retarget`] over the frames: the plain pass's products
//! ([`super::retarget_plain`]), term for term in the same order, on eight frames side by side
//! (`[f64; 8]` lanes, which the compiler turns into vector instructions), where the plain pass
//! takes a joint and a frame at a time.
//!
//! What differs is only `sin`, `cos` and `atan2`: libm's, one value at a time, in the plain pass;
//! here fdlibm's kernels (Sun's, the same polynomials most libms derive from), written as loops
//! over lanes without branches. Both are within one unit in the last place of the exact values,
//! so the two passes part by a few 1e-16 in a quaternion's components, which a test holds within
//! 1e-9 degrees in every channel on real takes. Also: source FK only of the joints the map reads
//! (and their ancestors), the per-joint decisions made once before the frames, the channel values
//! written straight into the output rows on the cores (only joints whose Euler form follows their
//! own previous frame, and the carrier's translation, which waits for the take's floor, are left
//! for one pass in frame order).

use super::{Map, Setup, limited_angles, nearest_form};
use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use glam::{DQuat, DVec3};
use std::sync::{Mutex, PoisonError};

/// Frames computed side by side: lane `l` of every value belongs to frame `l` of the batch.
const LANES: usize = 8;
type Lanes = [f64; LANES];

/// Frames a worker takes at a time (a multiple of [`LANES`]).
const PIECE: usize = 512;

/// The lanes `f(0), …, f(7)`, by a plain loop: one the compiler vectorises (`std::array::from_fn`
/// it leaves scalar once the body is more than a few operations).
#[inline(always)]
fn lanes(mut f: impl FnMut(usize) -> f64) -> Lanes {
    let mut out = [0.0; LANES];
    for (l, value) in out.iter_mut().enumerate() {
        *value = f(l);
    }
    out
}

/// [`lanes`] of a condition.
#[inline(always)]
fn mask(mut f: impl FnMut(usize) -> bool) -> [bool; LANES] {
    let mut out = [false; LANES];
    for (l, value) in out.iter_mut().enumerate() {
        *value = f(l);
    }
    out
}

/// A channel value as written: 32-bit in a take, 64-bit for the test against the plain pass.
pub(super) trait Value: Copy + Default + Send {
    fn of(value: f64) -> Self;
    fn is_finite(self) -> bool;
}

impl Value for f32 {
    fn of(value: f64) -> f32 {
        value as f32
    }
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
}

impl Value for f64 {
    fn of(value: f64) -> f64 {
        value
    }
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

/// Whether every value is finite, by a loop without an early exit (which the compiler
/// vectorises).
fn all_finite<T: Value>(values: &[T]) -> bool {
    values.iter().fold(true, |all, v| all & v.is_finite())
}

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
use fdlibm::*;

/// Angles (radians) this far from 0 or beyond go to libm: the reduction by parts of π/2 (33 bits
/// each) is exact for fewer than 2²⁰ quarter turns.
const SIN_COS_LIMIT: f64 = 1.0e5;

/// `(sin x, cos x)` by fdlibm's kernels after reducing `x` to [-π/4, π/4]; no branches, so a loop
/// over lanes becomes vector code. For |x| < [`SIN_COS_LIMIT`].
#[inline(always)]
fn sin_cos_lane(x: f64) -> (f64, f64) {
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
fn sin_cos(x: &Lanes, sin: &mut Lanes, cos: &mut Lanes) {
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
fn atan2_lane(y: f64, x: f64) -> f64 {
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
fn atan2(y: &Lanes, x: &Lanes) -> Lanes {
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

/// A quaternion per lane.
#[derive(Clone, Copy, Debug)]
struct Quats {
    x: Lanes,
    y: Lanes,
    z: Lanes,
    w: Lanes,
}

/// A point per lane.
#[derive(Clone, Copy, Debug)]
struct Points {
    x: Lanes,
    y: Lanes,
    z: Lanes,
}

impl Points {
    fn splat(v: DVec3) -> Points {
        Points {
            x: [v.x; LANES],
            y: [v.y; LANES],
            z: [v.z; LANES],
        }
    }

    fn get(&self, l: usize) -> DVec3 {
        DVec3::new(self.x[l], self.y[l], self.z[l])
    }

    #[inline(always)]
    fn add(&self, b: &Points) -> Points {
        Points {
            x: lanes(|l| self.x[l] + b.x[l]),
            y: lanes(|l| self.y[l] + b.y[l]),
            z: lanes(|l| self.z[l] + b.z[l]),
        }
    }
}

impl Quats {
    const IDENTITY: Quats = Quats {
        x: [0.0; LANES],
        y: [0.0; LANES],
        z: [0.0; LANES],
        w: [1.0; LANES],
    };

    fn splat(q: DQuat) -> Quats {
        Quats {
            x: [q.x; LANES],
            y: [q.y; LANES],
            z: [q.z; LANES],
            w: [q.w; LANES],
        }
    }

    fn get(&self, l: usize) -> DQuat {
        DQuat::from_xyzw(self.x[l], self.y[l], self.z[l], self.w[l])
    }

    fn set(&mut self, l: usize, q: DQuat) {
        (self.x[l], self.y[l], self.z[l], self.w[l]) = (q.x, q.y, q.z, q.w);
    }

    #[inline(always)]
    fn conjugate(&self) -> Quats {
        Quats {
            x: lanes(|l| -self.x[l]),
            y: lanes(|l| -self.y[l]),
            z: lanes(|l| -self.z[l]),
            w: self.w,
        }
    }

    /// `self · b`, glam's `DQuat::mul_quat` term for term.
    #[inline(always)]
    fn mul(&self, b: &Quats) -> Quats {
        let a = self;
        Quats {
            x: lanes(|l| a.w[l] * b.x[l] + a.x[l] * b.w[l] + a.y[l] * b.z[l] - a.z[l] * b.y[l]),
            y: lanes(|l| a.w[l] * b.y[l] - a.x[l] * b.z[l] + a.y[l] * b.w[l] + a.z[l] * b.x[l]),
            z: lanes(|l| a.w[l] * b.z[l] + a.x[l] * b.y[l] - a.y[l] * b.x[l] + a.z[l] * b.w[l]),
            w: lanes(|l| a.w[l] * b.w[l] - a.x[l] * b.x[l] - a.y[l] * b.y[l] - a.z[l] * b.z[l]),
        }
    }

    /// `self · (axis · s, c)` (`s`, `c`: sine and cosine of half the angle): [`Quats::mul`] with
    /// its products by the axis's zeros left out, which changes no value (only, at most, the sign
    /// of a zero).
    #[inline(always)]
    fn times_axis(&self, axis: usize, s: &Lanes, c: &Lanes) -> Quats {
        let Quats { x, y, z, w } = self;
        match axis {
            0 => Quats {
                x: lanes(|l| w[l] * s[l] + x[l] * c[l]),
                y: lanes(|l| y[l] * c[l] + z[l] * s[l]),
                z: lanes(|l| z[l] * c[l] - y[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - x[l] * s[l]),
            },
            1 => Quats {
                x: lanes(|l| x[l] * c[l] - z[l] * s[l]),
                y: lanes(|l| w[l] * s[l] + y[l] * c[l]),
                z: lanes(|l| x[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - y[l] * s[l]),
            },
            _ => Quats {
                x: lanes(|l| x[l] * c[l] + y[l] * s[l]),
                y: lanes(|l| y[l] * c[l] - x[l] * s[l]),
                z: lanes(|l| w[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - z[l] * s[l]),
            },
        }
    }

    /// `v` turned by this quaternion, glam's `DQuat::mul_vec3` term for term.
    #[inline(always)]
    fn rotate(&self, v: &Points) -> Points {
        let Quats { x, y, z, w } = self;
        let b2 = lanes(|l| x[l] * x[l] + y[l] * y[l] + z[l] * z[l]);
        let k = lanes(|l| w[l] * w[l] - b2[l]);
        let d = lanes(|l| (v.x[l] * x[l] + v.y[l] * y[l] + v.z[l] * z[l]) * 2.0);
        let w2 = lanes(|l| w[l] * 2.0);
        Points {
            x: lanes(|l| v.x[l] * k[l] + x[l] * d[l] + (y[l] * v.z[l] - v.y[l] * z[l]) * w2[l]),
            y: lanes(|l| v.y[l] * k[l] + y[l] * d[l] + (z[l] * v.x[l] - v.z[l] * x[l]) * w2[l]),
            z: lanes(|l| v.z[l] * k[l] + z[l] * d[l] + (x[l] * v.y[l] - v.x[l] * y[l]) * w2[l]),
        }
    }

    /// The Euler angles in degrees of this rotation with the axes `[i, j, k]` of a rotation order
    /// (file order) and their `sign` (+1 when they turn as x, y, z do): [`crate::model::euler::split`]
    /// with no previous frame, step for step: the matrix of the normalised quaternion (glam's
    /// `DMat3::from_quat`), the middle angle against the length of the other two, the third
    /// read off it away from the lock (else 0), the first from the rotation with the third
    /// taken off.
    #[inline(always)]
    fn euler_degrees(&self, ([i, j, k], sign): ([usize; 3], f64)) -> [Lanes; 3] {
        let length = lanes(|l| {
            let q = self;
            (q.x[l] * q.x[l] + q.y[l] * q.y[l] + q.z[l] * q.z[l] + q.w[l] * q.w[l]).sqrt()
        });
        let unit = Quats {
            x: lanes(|l| self.x[l] * (1.0 / length[l])),
            y: lanes(|l| self.y[l] * (1.0 / length[l])),
            z: lanes(|l| self.z[l] * (1.0 / length[l])),
            w: lanes(|l| self.w[l] * (1.0 / length[l])),
        };
        let Quats { x, y, z, w } = &unit;
        let x2 = lanes(|l| x[l] + x[l]);
        let y2 = lanes(|l| y[l] + y[l]);
        let z2 = lanes(|l| z[l] + z[l]);
        let (xx, xy, xz) = (
            lanes(|l| x[l] * x2[l]),
            lanes(|l| x[l] * y2[l]),
            lanes(|l| x[l] * z2[l]),
        );
        let (yy, yz, zz) = (
            lanes(|l| y[l] * y2[l]),
            lanes(|l| y[l] * z2[l]),
            lanes(|l| z[l] * z2[l]),
        );
        let (wx, wy, wz) = (
            lanes(|l| w[l] * x2[l]),
            lanes(|l| w[l] * y2[l]),
            lanes(|l| w[l] * z2[l]),
        );
        // Column-major: m[column][row].
        let m: [[Lanes; 3]; 3] = [
            [
                lanes(|l| 1.0 - (yy[l] + zz[l])),
                lanes(|l| xy[l] + wz[l]),
                lanes(|l| xz[l] - wy[l]),
            ],
            [
                lanes(|l| xy[l] - wz[l]),
                lanes(|l| 1.0 - (xx[l] + zz[l])),
                lanes(|l| yz[l] + wx[l]),
            ],
            [
                lanes(|l| xz[l] + wy[l]),
                lanes(|l| yz[l] - wx[l]),
                lanes(|l| 1.0 - (xx[l] + yy[l])),
            ],
        ];
        let cos_middle = lanes(|l| (m[i][i][l] * m[i][i][l] + m[j][i][l] * m[j][i][l]).sqrt());
        let middle = atan2(&lanes(|l| sign * m[k][i][l]), &cos_middle);
        let free = mask(|l| cos_middle[l] > crate::model::euler::LOCK);
        let third = atan2(&lanes(|l| -sign * m[j][i][l]), &m[i][i]);
        let third = lanes(|l| if free[l] { third[l] } else { 0.0 });
        // Column j of the rotation with the third angle taken off: m · R_k(−third) · e_j.
        let (mut sin, mut cos) = ([0.0; LANES], [0.0; LANES]);
        sin_cos(&third, &mut sin, &mut cos);
        let turned = lanes(|l| sign * sin[l]);
        let left_k = lanes(|l| m[i][k][l] * turned[l] + m[j][k][l] * cos[l]);
        let left_j = lanes(|l| m[i][j][l] * turned[l] + m[j][j][l] * cos[l]);
        let first = atan2(&lanes(|l| sign * left_k[l]), &left_j);
        let degrees = |v: Lanes| lanes(|l| v[l].to_degrees());
        [degrees(first), degrees(middle), degrees(third)]
    }
}

/// The plain pass's turn of a bone onto a source chord (`near` to `far`): `arc(r · rest, chord) · r`
/// where the chord is longer than 1e-9, else `r`, glam's operations term for term. A lane whose
/// chord points against the bone (glam's other branch) takes the plain pass's code.
#[inline(always)]
fn follow(setup: &Setup, rotation: &Quats, near: &Points, far: &Points, rest: DVec3) -> Quats {
    let apart = Points {
        x: lanes(|l| far.x[l] - near.x[l]),
        y: lanes(|l| far.y[l] - near.y[l]),
        z: lanes(|l| far.z[l] - near.z[l]),
    };
    let chord = turn(setup.ut_inv, &turn(setup.us, &apart));
    let from = rotation.rotate(&Points::splat(rest));
    let length =
        |v: &Points| lanes(|l| (v.x[l] * v.x[l] + v.y[l] * v.y[l] + v.z[l] * v.z[l]).sqrt());
    let (chord_length, from_length) = (length(&chord), length(&from));
    let unit = |v: &Points, length: &Lanes| {
        let recip = lanes(|l| 1.0 / length[l]);
        Points {
            x: lanes(|l| v.x[l] * recip[l]),
            y: lanes(|l| v.y[l] * recip[l]),
            z: lanes(|l| v.z[l] * recip[l]),
        }
    };
    let (a, b) = (unit(&from, &from_length), unit(&chord, &chord_length));
    let dot = lanes(|l| a.x[l] * b.x[l] + a.y[l] * b.y[l] + a.z[l] * b.z[l]);
    // glam's from_rotation_arc: (a × b, 1 + a·b), normalised.
    let (x, y, z, w) = (
        lanes(|l| a.y[l] * b.z[l] - b.y[l] * a.z[l]),
        lanes(|l| a.z[l] * b.x[l] - b.z[l] * a.x[l]),
        lanes(|l| a.x[l] * b.y[l] - b.x[l] * a.y[l]),
        lanes(|l| 1.0 + dot[l]),
    );
    let recip = lanes(|l| 1.0 / (x[l] * x[l] + y[l] * y[l] + z[l] * z[l] + w[l] * w[l]).sqrt());
    let arc = Quats {
        x: lanes(|l| x[l] * recip[l]),
        y: lanes(|l| y[l] * recip[l]),
        z: lanes(|l| z[l] * recip[l]),
        w: lanes(|l| w[l] * recip[l]),
    };
    let turned = arc.mul(rotation);
    // Where the chord is too short, or already along the bone (`arc` gives the identity, and
    // the identity times `r` is `r` but for the sign of a zero), `r` stays.
    let moves = mask(|l| chord_length[l] > 1e-9 && dot[l] <= 1.0 - 1e-15);
    let pick = |t: &Lanes, r: &Lanes| lanes(|l| if moves[l] { t[l] } else { r[l] });
    let mut out = Quats {
        x: pick(&turned.x, &rotation.x),
        y: pick(&turned.y, &rotation.y),
        z: pick(&turned.z, &rotation.z),
        w: pick(&turned.w, &rotation.w),
    };
    for l in 0..LANES {
        if moves[l] && dot[l] < -(1.0 - 2.0 * f64::EPSILON) {
            let r = rotation.get(l);
            out.set(l, super::arc(r * rest, chord.get(l)) * r);
        }
    }
    out
}

/// `q · v` for every lane, or `v` itself when `q` is the identity (the same values but for the
/// sign of a zero).
#[inline(always)]
fn turn(q: DQuat, v: &Points) -> Points {
    match q == DQuat::IDENTITY {
        true => *v,
        false => Quats::splat(q).rotate(v),
    }
}

/// The axes of an Euler order in file order, and their handedness, as [`crate::model::euler::split`]
/// reads them.
fn axis_order(order: crate::model::skeleton::RotationOrder) -> ([usize; 3], f64) {
    let [i, j, k] = crate::model::euler::axes(order);
    ([i, j, k], crate::model::euler::handedness(i, j))
}

/// [`nearest_form`] of every lane: its operations in its order, as one loop over the lanes that
/// the compiler vectorises.
#[inline(always)]
fn nearest_forms(angles: &[Lanes; 3], reference: &[Lanes; 3]) -> [Lanes; 3] {
    let near = |angle: f64, to: f64| angle + 360.0 * ((to - angle) / 360.0).round();
    let mut best = [[0.0; LANES]; 3];
    for l in 0..LANES {
        let (a, r) = (
            [angles[0][l], angles[1][l], angles[2][l]],
            [reference[0][l], reference[1][l], reference[2][l]],
        );
        let first = [near(a[0], r[0]), near(a[1], r[1]), near(a[2], r[2])];
        let second = [
            near(a[0] + 180.0, r[0]),
            near(180.0 - a[1], r[1]),
            near(a[2] + 180.0, r[2]),
        ];
        let cost = |f: &[f64; 3]| (f[0] - r[0]).abs() + (f[1] - r[1]).abs() + (f[2] - r[2]).abs();
        let (first_cost, second_cost) = (cost(&first), cost(&second));
        // As `nearest_form`: the first form if its cost is below infinity, the second if below
        // that, else the angles as they are.
        let first_taken = first_cost < f64::INFINITY;
        let best_cost = if first_taken {
            first_cost
        } else {
            f64::INFINITY
        };
        let second_taken = second_cost < best_cost;
        for i in 0..3 {
            best[i][l] = if second_taken {
                second[i]
            } else if first_taken {
                first[i]
            } else {
                a[i]
            };
        }
    }
    best
}

/// A source joint whose world transform the map reads (or a descendant's does).
struct SourceJoint {
    index: usize,
    parent: Option<usize>,
    offset: DVec3,
    /// (axis, input) of each position channel: where in [`Plan::inputs`] its values are.
    positions: Vec<(usize, usize)>,
    /// Its rotation channels: a range of the plan's rotation list.
    rotations: std::ops::Range<usize>,
    /// An ASF bone's axis C: its rotation is `C · R1 · R2 · R3 · C⁻¹`.
    axis: Option<DQuat>,
    /// Whether its world position is read (or a descendant's is), not only its rotation.
    placed: bool,
}

/// How a target joint's rotation channels are found.
enum Turn {
    /// Three channels: the Euler angles, in file order (see [`axis_order`]), of
    /// `C⁻¹ · local · C` (`C` an ASF bone's axis).
    Euler {
        order: ([usize; 3], f64),
        axis: Option<DQuat>,
    },
    /// One or two: [`limited_angles`], a lane at a time.
    Limited,
    /// None: the joint turns by this fixed rotation (the identity, or `C · C⁻¹`).
    Fixed(DQuat),
}

/// Where a target channel's value comes from.
#[derive(Clone, Copy)]
enum Column {
    /// The joint's rotation angle this many into its channels (0 past the third).
    Angle(usize),
    /// The OFFSET's component.
    Offset(f64),
    /// The carrier's translation along this axis, written last.
    Carried(usize),
}

struct TargetJoint {
    parent: Option<usize>,
    offset: DVec3,
    source: Option<usize>,
    aligned: DQuat,
    follow: Option<(usize, DVec3)>,
    turn: Turn,
    bone: Option<DVec3>,
    /// The source's rotation values that pick the Euler form: where in [`Plan::inputs`].
    reference: Option<[usize; 3]>,
    /// Of the joints whose Euler form follows their own previous frame, its place.
    chained: Option<usize>,
    columns: Vec<(usize, Column)>,
    /// Whether its world position is read (the hips, the legs, their ancestors).
    placed: bool,
}

/// The pass compiled for one pair of skeletons and one map.
struct Plan<'a> {
    setup: &'a Setup,
    target: &'a Skeleton,
    mode: OffsetMode,
    source_joints: Vec<SourceJoint>,
    source_count: usize,
    /// Every rotation channel of the source joints read: (axis, input).
    rotations: Vec<(usize, usize)>,
    /// The MOTION columns read (source rotations and positions, the references for the Euler
    /// form), gathered from the rows once per batch.
    inputs: Vec<usize>,
    target_joints: Vec<TargetJoint>,
    /// The joints whose Euler form follows their own previous frame.
    chained: Vec<usize>,
    channels: usize,
}

/// Buffers one worker reuses from batch to batch.
#[derive(Default)]
struct Scratch {
    /// The batch's values of [`Plan::inputs`].
    inputs: Vec<Lanes>,
    half_angles: Vec<Lanes>,
    sin: Vec<Lanes>,
    cos: Vec<Lanes>,
    source_rotations: Vec<Quats>,
    source_points: Vec<Points>,
    target_rotations: Vec<Quats>,
    target_points: Vec<Points>,
    angles: Vec<[Lanes; 3]>,
    /// One batch's channel values, channel after channel.
    values: Vec<Lanes>,
}

/// Each frame's move of the hips and the carrier's parent's rotation, for its translation.
#[derive(Clone, Copy)]
struct Move {
    moved: DVec3,
    turned: DQuat,
}

impl Default for Move {
    fn default() -> Move {
        Move {
            moved: DVec3::ZERO,
            turned: DQuat::IDENTITY,
        }
    }
}

/// Per joint: whether it is one of `joints` or an ancestor of one.
fn with_ancestors(skeleton: &Skeleton, joints: impl Iterator<Item = usize>) -> Vec<bool> {
    let mut marked = vec![false; skeleton.joints.len()];
    for joint in joints {
        let mut joint = Some(joint);
        while let Some(j) = joint.filter(|&j| !marked[j]) {
            marked[j] = true;
            joint = skeleton.joints[j].parent;
        }
    }
    marked
}

impl<'a> Plan<'a> {
    fn new(setup: &'a Setup, source: &Skeleton, target: &'a Skeleton, map: &Map) -> Plan<'a> {
        // The source joints read: mapped ones, the far ends of followed chords, the hips, the
        // leg points, and their ancestors.
        // Of those, the ones whose positions are read: the ends of followed chords, the hips,
        // the leg points, and their ancestors.
        let placed_joints: Vec<usize> = (0..target.joints.len())
            .filter_map(|t| Some((map.source_of[t]?, setup.follow[t]?.0)))
            .flat_map(|(s, sd)| [s, sd])
            .chain(setup.hips.map(|(_, s)| s))
            .chain(setup.source_legs.iter().copied())
            .collect();
        let placed = with_ancestors(source, placed_joints.iter().copied());
        let needed = with_ancestors(
            source,
            map.source_of.iter().flatten().copied().chain(placed_joints),
        );
        // The MOTION columns read, each gathered once per batch.
        let mut inputs = Vec::new();
        let mut input_of = std::collections::HashMap::new();
        let mut input = |column: usize| {
            *input_of.entry(column).or_insert_with(|| {
                inputs.push(column);
                inputs.len() - 1
            })
        };
        let mut rotations = Vec::new();
        let source_joints = source
            .joints
            .iter()
            .enumerate()
            .filter(|&(j, _)| needed[j])
            .map(|(index, joint)| {
                let first = rotations.len();
                let mut positions = Vec::new();
                for (i, channel) in joint.channels.iter().enumerate() {
                    let column = joint.first_channel + i;
                    if channel.is_rotation() {
                        rotations.push((channel.axis(), input(column)));
                    } else if channel.is_position() && placed[index] {
                        positions.push((channel.axis(), input(column)));
                    }
                }
                SourceJoint {
                    index,
                    parent: joint.parent,
                    offset: joint.offset.as_dvec3(),
                    positions,
                    rotations: first..rotations.len(),
                    axis: joint.axis.map(|c| c.as_dquat().normalize()),
                    placed: placed[index],
                }
            })
            .collect();
        let target_placed = with_ancestors(
            target,
            setup
                .hips
                .map(|(t, _)| t)
                .into_iter()
                .chain(setup.target_legs.iter().copied()),
        );
        let mut chained = Vec::new();
        let target_joints = target
            .joints
            .iter()
            .enumerate()
            .map(|(t, joint)| {
                let rotation_channels = joint.channels.iter().filter(|c| c.is_rotation()).count();
                let turn = match joint.rotation_order {
                    Some(order) => Turn::Euler {
                        order: axis_order(order),
                        axis: joint.axis.map(|c| c.as_dquat().normalize()),
                    },
                    None if rotation_channels > 0 => Turn::Limited,
                    None => Turn::Fixed(crate::model::pose::local_rotation_f64(
                        joint,
                        &vec![0.0; joint.channels.len()],
                    )),
                };
                let reference = setup.reference_columns[t].map(|c| c.map(&mut input));
                let follows_itself = joint.rotation_order.is_some() && reference.is_none();
                if follows_itself {
                    chained.push(t);
                }
                let mut rotation = 0;
                let columns = joint
                    .channels
                    .iter()
                    .enumerate()
                    .map(|(i, channel)| {
                        let column = joint.first_channel + i;
                        if channel.is_position() {
                            if Some(t) == setup.carrier {
                                (column, Column::Carried(channel.axis()))
                            } else {
                                let offset = joint.offset.as_dvec3();
                                (column, Column::Offset(offset[channel.axis()]))
                            }
                        } else {
                            rotation += 1;
                            (column, Column::Angle(rotation - 1))
                        }
                    })
                    .collect();
                TargetJoint {
                    parent: joint.parent,
                    offset: joint.offset.as_dvec3(),
                    source: map.source_of[t],
                    aligned: setup.aligned[t],
                    follow: setup.follow[t],
                    turn,
                    bone: setup.bone_of[t],
                    reference,
                    chained: follows_itself.then(|| chained.len() - 1),
                    columns,
                    placed: target_placed[t],
                }
            })
            .collect();
        Plan {
            setup,
            target,
            mode: setup.source_mode,
            source_joints,
            source_count: source.joints.len(),
            rotations,
            inputs,
            target_joints,
            chained,
            channels: target.channel_count(),
        }
    }

    /// World rotation and position of every source joint read, for one batch of rows.
    #[inline(always)]
    fn source_fk(&self, rows: &[&[f32]; LANES], scratch: &mut Scratch) {
        scratch.inputs.resize(self.inputs.len(), [0.0; LANES]);
        for (l, row) in rows.iter().enumerate() {
            for (input, &column) in scratch.inputs.iter_mut().zip(&self.inputs) {
                input[l] = f64::from(row[column]);
            }
        }
        let n = self.rotations.len();
        scratch.half_angles.resize(n, [0.0; LANES]);
        scratch.sin.resize(n, [0.0; LANES]);
        scratch.cos.resize(n, [0.0; LANES]);
        for (half, &(_, input)) in scratch.half_angles.iter_mut().zip(&self.rotations) {
            // glam's from_rotation_x(θ) takes sin and cos of θ · 0.5.
            let degrees = &scratch.inputs[input];
            *half = lanes(|l| degrees[l].to_radians() * 0.5);
        }
        for ((half, sin), cos) in scratch
            .half_angles
            .iter()
            .zip(scratch.sin.iter_mut())
            .zip(scratch.cos.iter_mut())
        {
            sin_cos(half, sin, cos);
        }
        let origin = Points::splat(DVec3::ZERO);
        scratch
            .source_rotations
            .resize(self.source_count, Quats::IDENTITY);
        scratch.source_points.resize(self.source_count, origin);
        for joint in &self.source_joints {
            let mut t = [joint.offset.x, joint.offset.y, joint.offset.z].map(|v| [v; LANES]);
            for &(axis, input) in &joint.positions {
                let written = &scratch.inputs[input];
                for (value, &written) in t[axis].iter_mut().zip(written) {
                    match self.mode {
                        OffsetMode::Replace => *value = written,
                        OffsetMode::Add => *value += written,
                    }
                }
            }
            let t = Points {
                x: t[0],
                y: t[1],
                z: t[2],
            };
            let mut rotation = Quats::IDENTITY;
            for i in joint.rotations.clone() {
                rotation =
                    rotation.times_axis(self.rotations[i].0, &scratch.sin[i], &scratch.cos[i]);
            }
            if let Some(c) = joint.axis {
                rotation = Quats::splat(c)
                    .mul(&rotation)
                    .mul(&Quats::splat(c.inverse()));
            }
            // The plain pass multiplies by a joint's identity rotation too: the same values
            // (but for the sign of a zero).
            let turns = !joint.rotations.is_empty() || joint.axis.is_some();
            let (rotation, point) = match joint.parent {
                Some(p) => {
                    let (r, at) = (&scratch.source_rotations[p], &scratch.source_points[p]);
                    let rotation = if turns { r.mul(&rotation) } else { *r };
                    let point = if joint.placed {
                        at.add(&r.rotate(&t))
                    } else {
                        *at
                    };
                    (rotation, point)
                }
                None => (rotation, t),
            };
            scratch.source_rotations[joint.index] = rotation;
            scratch.source_points[joint.index] = point;
        }
    }

    /// Every target joint's world rotation and position and its rotation channels' angles (one
    /// Euler form, degrees), for one batch.
    #[inline(always)]
    fn target_pass(&self, scratch: &mut Scratch) {
        let setup = self.setup;
        let (us, us_inv) = (Quats::splat(setup.us), Quats::splat(setup.us.inverse()));
        let (ut, ut_inv) = (Quats::splat(setup.ut), Quats::splat(setup.ut_inv));
        let count = self.target_joints.len();
        let origin = Points::splat(DVec3::ZERO);
        scratch.target_rotations.resize(count, Quats::IDENTITY);
        scratch.target_points.resize(count, origin);
        scratch.angles.resize(count, [[0.0; LANES]; 3]);
        for (t, joint) in self.target_joints.iter().enumerate() {
            let parent_rotation = joint
                .parent
                .map_or(Quats::IDENTITY, |p| scratch.target_rotations[p]);
            // The plain pass's products, those by the identity (a Y-up skeleton's turn, a bone
            // aligned at rest) left out: the same values but for the sign of a zero.
            let mut rotation = match joint.source {
                Some(s) => {
                    let world = &scratch.source_rotations[s];
                    let carried = match setup.us == DQuat::IDENTITY {
                        true => *world,
                        false => us.mul(world).mul(&us_inv),
                    };
                    let mut rotation = match setup.ut == DQuat::IDENTITY {
                        true => carried,
                        false => ut_inv.mul(&carried),
                    };
                    if joint.aligned != DQuat::IDENTITY {
                        rotation = rotation.mul(&Quats::splat(joint.aligned));
                    }
                    if setup.ut != DQuat::IDENTITY {
                        rotation = rotation.mul(&ut);
                    }
                    if let Some((sd, rest)) = joint.follow {
                        let (near, far) = (&scratch.source_points[s], &scratch.source_points[sd]);
                        rotation = follow(setup, &rotation, near, far, rest);
                    }
                    rotation
                }
                None => parent_rotation,
            };
            let local = || parent_rotation.conjugate().mul(&rotation);
            match joint.turn {
                Turn::Euler { order, axis } => {
                    let local = local();
                    let channel_rotation = match axis {
                        Some(c) => Quats::splat(c.inverse()).mul(&local).mul(&Quats::splat(c)),
                        None => local,
                    };
                    scratch.angles[t] = channel_rotation.euler_degrees(order);
                }
                Turn::Limited => {
                    // Fewer than three rotation channels: the rotation the joint can take, and
                    // its children go on from that one, not from the one asked for.
                    let local = local();
                    for l in 0..LANES {
                        let (angles, realized) =
                            limited_angles(&self.target.joints[t], local.get(l), joint.bone);
                        for (a, angle) in angles.into_iter().enumerate() {
                            scratch.angles[t][a][l] = angle;
                        }
                        rotation.set(l, parent_rotation.get(l) * realized);
                    }
                }
                Turn::Fixed(realized) if realized != DQuat::IDENTITY => {
                    rotation = parent_rotation.mul(&Quats::splat(realized));
                }
                Turn::Fixed(_) => rotation = parent_rotation,
            }
            let position = match joint.parent {
                Some(p) if joint.placed => scratch.target_points[p]
                    .add(&scratch.target_rotations[p].rotate(&Points::splat(joint.offset))),
                Some(p) => scratch.target_points[p],
                None => Points::splat(joint.offset),
            };
            scratch.target_rotations[t] = rotation;
            scratch.target_points[t] = position;
        }
    }

    /// One piece of frames starting at `first`: their channel values into `rows` (all but the
    /// chained joints' and the carrier's translation), the chained joints' Euler angles into
    /// `chained`, the moves into `moves`; returns the lowest leg points of source and target.
    #[inline(always)]
    fn piece<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        let setup = self.setup;
        let frames = moves.len();
        let (mut source_floor, mut target_floor) = (f64::INFINITY, f64::INFINITY);
        for batch in (0..frames).step_by(LANES) {
            let used = (frames - batch).min(LANES);
            // A short batch repeats its last frame in the spare lanes.
            let source_rows: [&[f32]; LANES] =
                std::array::from_fn(|l| motion.frame(first + batch + l.min(used - 1)));
            self.source_fk(&source_rows, scratch);
            self.target_pass(scratch);
            // Where the carrier moves the hips, and the legs' lowest points.
            let mut moved = Points::splat(DVec3::ZERO);
            if let (Some((t, s)), Some(carrier)) = (setup.hips, setup.carrier) {
                let scaled = turn(setup.us, &scratch.source_points[s]);
                let scaled = Points {
                    x: lanes(|l| setup.ratio * scaled.x[l]),
                    y: lanes(|l| setup.ratio * scaled.y[l]),
                    z: lanes(|l| setup.ratio * scaled.z[l]),
                };
                let wanted = turn(setup.ut_inv, &scaled);
                let at = &scratch.target_points[t];
                moved = Points {
                    x: lanes(|l| wanted.x[l] - at.x[l]),
                    y: lanes(|l| wanted.y[l] - at.y[l]),
                    z: lanes(|l| wanted.z[l] - at.z[l]),
                };
                let parent = self.target.joints[carrier].parent;
                for (l, slot) in moves[batch..batch + used].iter_mut().enumerate() {
                    *slot = Move {
                        moved: moved.get(l),
                        turned: parent
                            .map_or(DQuat::IDENTITY, |p| scratch.target_rotations[p].get(l)),
                    };
                }
            }
            for &j in &setup.source_legs {
                let y = turn(setup.us, &scratch.source_points[j]).y;
                source_floor = y.iter().fold(source_floor, |a, &b| a.min(b));
            }
            for &j in &setup.target_legs {
                let mut point = scratch.target_points[j];
                if setup.under_carrier[j] {
                    point = point.add(&moved);
                }
                let y = turn(setup.ut, &point).y;
                target_floor = y.iter().fold(target_floor, |a, &b| a.min(b));
            }
            // The channel values, a channel at a time across the lanes, then row by row.
            scratch.values.resize(self.channels, [0.0; LANES]);
            let width = self.chained.len();
            for (t, joint) in self.target_joints.iter().enumerate() {
                let raw = &scratch.angles[t];
                let angles = match (&joint.turn, joint.reference, joint.chained) {
                    // A chained joint's angles wait for the pass in frame order.
                    (_, _, Some(slot)) => {
                        for l in 0..used {
                            chained[(batch + l) * width + slot] = raw.map(|a| a[l]);
                        }
                        None
                    }
                    (Turn::Euler { .. }, Some(inputs), _) => {
                        let reference = inputs.map(|i| scratch.inputs[i]);
                        Some(nearest_forms(raw, &reference))
                    }
                    _ => Some(*raw),
                };
                for &(column, what) in &joint.columns {
                    match (what, angles) {
                        (Column::Angle(a), Some(angles)) => {
                            scratch.values[column] = angles.get(a).copied().unwrap_or_default();
                        }
                        (Column::Offset(value), _) => scratch.values[column] = [value; LANES],
                        // Written in frame order after all pieces.
                        _ => {}
                    }
                }
            }
            for l in 0..used {
                let frame = batch + l;
                let row = &mut rows[frame * self.channels..(frame + 1) * self.channels];
                for (value, lanes) in row.iter_mut().zip(&scratch.values) {
                    *value = T::of(lanes[l]);
                }
            }
        }
        (source_floor, target_floor)
    }

    /// A piece's values that waited for the take's floor or for the frames before it: the
    /// chained joints' Euler forms (nearest `previous`, which it carries on) and the carrier's
    /// translation. Whether they are finite.
    fn rest_of_piece<T: Value>(
        &self,
        rows: &mut [T],
        angles: &[[f64; 3]],
        moves: &[Move],
        lift: DVec3,
        previous: &mut [[f64; 3]],
    ) -> bool {
        let (channels, width) = (self.channels, self.chained.len());
        let mut finite = true;
        for (frame, &Move { moved, turned }) in moves.iter().enumerate() {
            let row = &mut rows[frame * channels..(frame + 1) * channels];
            for (slot, &t) in self.chained.iter().enumerate() {
                let chosen = nearest_form(angles[frame * width + slot], previous[slot]);
                previous[slot] = chosen;
                for &(column, what) in &self.target_joints[t].columns {
                    if let Column::Angle(a) = what {
                        row[column] = T::of(chosen.get(a).copied().unwrap_or(0.0));
                        finite &= row[column].is_finite();
                    }
                }
            }
            if let Some(carrier) = self.setup.carrier {
                let joint = &self.target_joints[carrier];
                let translation = joint.offset + turned.inverse() * (moved + lift);
                for &(column, what) in &joint.columns {
                    if let Column::Carried(axis) = what {
                        row[column] = T::of(translation[axis]);
                        finite &= row[column].is_finite();
                    }
                }
            }
        }
        finite
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn piece_avx512<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        self.piece(motion, first, rows, chained, moves, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn piece_avx2<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        self.piece(motion, first, rows, chained, moves, scratch)
    }

    /// [`Plan::piece`] compiled for the widest vectors the CPU has: the same operations, so the
    /// same values, on any.
    fn piece_here<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has just been found to support AVX-512F.
                return unsafe { self.piece_avx512(motion, first, rows, chained, moves, scratch) };
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has just been found to support AVX2.
                return unsafe { self.piece_avx2(motion, first, rows, chained, moves, scratch) };
            }
        }
        self.piece(motion, first, rows, chained, moves, scratch)
    }
}

/// Every frame's channel values of the retargeted take, on up to `threads` threads (the same
/// values on any number), and whether they are all finite (checked on the cores as they are
/// written).
pub(super) fn frames<T: Value>(
    setup: &Setup,
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    threads: usize,
) -> (Vec<T>, bool) {
    let plan = Plan::new(setup, source, target, map);
    let frames = motion.frame_count();
    let (channels, width) = (plan.channels, plan.chained.len());
    let mut data = vec![T::default(); frames * channels];
    let mut chained = vec![[0.0; 3]; frames * width];
    // Each piece's moves, filled by the worker that computes it.
    let mut moves: Vec<Vec<Move>> = vec![Vec::new(); frames.div_ceil(PIECE)];
    let floors = Mutex::new((f64::INFINITY, f64::INFINITY, true));
    let work = Mutex::new(pieces(
        frames,
        (&mut data, channels),
        (&mut chained, width),
        &mut moves,
    ));
    crate::io::parallel::on_threads(threads.max(1), || {
        let mut scratch = Scratch::default();
        let (mut source_floor, mut target_floor, mut finite) = (f64::INFINITY, f64::INFINITY, true);
        loop {
            let next = work.lock().unwrap_or_else(PoisonError::into_inner).next();
            let Some((first, count, rows, angles, moves)) = next else {
                break;
            };
            moves.resize(count, Move::default());
            let (s, t) = plan.piece_here(motion, first, rows, angles, moves, &mut scratch);
            source_floor = source_floor.min(s);
            target_floor = target_floor.min(t);
            finite &= all_finite(rows);
        }
        let mut floors = floors.lock().unwrap_or_else(PoisonError::into_inner);
        floors.0 = floors.0.min(source_floor);
        floors.1 = floors.1.min(target_floor);
        floors.2 &= finite;
    });
    // The pieces' borrows of the outputs end here.
    drop(work);
    let (source_floor, target_floor, finite) =
        *floors.lock().unwrap_or_else(PoisonError::into_inner);
    let lift = setup.lift(source_floor, target_floor);
    // Then the values that waited: the chained joints' Euler form nearest their previous frame's
    // (in frame order, so on one thread), and the carrier's translation (on the cores when there
    // is no chained joint).
    let work = pieces(
        frames,
        (&mut data, channels),
        (&mut chained, width),
        &mut moves,
    );
    let finite = if width > 0 {
        let mut previous = vec![[0.0; 3]; width];
        work.fold(finite, |finite, (_, _, rows, angles, moves)| {
            finite & plan.rest_of_piece(rows, angles, moves, lift, &mut previous)
        })
    } else {
        let (work, all) = (Mutex::new(work), Mutex::new(finite));
        crate::io::parallel::on_threads(threads.max(1), || {
            let mut finite = true;
            loop {
                let next = work.lock().unwrap_or_else(PoisonError::into_inner).next();
                let Some((_, _, rows, angles, moves)) = next else {
                    break;
                };
                finite &= plan.rest_of_piece(rows, angles, moves, lift, &mut []);
            }
            *all.lock().unwrap_or_else(PoisonError::into_inner) &= finite;
        });
        all.into_inner().unwrap_or_else(PoisonError::into_inner)
    };
    (data, finite)
}

/// A piece of frames: its first frame, how many, and its part of the rows, of the chained
/// joints' angles and of the moves.
type Piece<'a, T> = (
    usize,
    usize,
    &'a mut [T],
    &'a mut [[f64; 3]],
    &'a mut Vec<Move>,
);

/// The pieces of the outputs, in frame order.
fn pieces<'a, T>(
    frames: usize,
    (mut rows, channels): (&'a mut [T], usize),
    (mut angles, width): (&'a mut [[f64; 3]], usize),
    moves: &'a mut [Vec<Move>],
) -> impl Iterator<Item = Piece<'a, T>> {
    moves.iter_mut().enumerate().map(move |(piece, moves)| {
        let first = piece * PIECE;
        let count = (frames - first).min(PIECE);
        let (piece_rows, rest) = std::mem::take(&mut rows).split_at_mut(count * channels);
        rows = rest;
        let (piece_angles, rest) = std::mem::take(&mut angles).split_at_mut(count * width);
        angles = rest;
        (first, count, piece_rows, piece_angles, moves)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few million angles of every size the files hold, by a fixed xorshift.
    fn numbers(count: usize) -> impl Iterator<Item = f64> {
        let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
        (0..count).map(move |_| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        })
    }

    #[test]
    fn sin_and_cos_are_libm_s_within_an_ulp_of_one() {
        let specials = [
            0.0f32, 90.0, 180.0, 270.0, 360.0, -90.0, 45.0, 720.0, 1e7, 3e38,
        ];
        let degrees = numbers(1 << 20)
            .enumerate()
            .map(|(i, v)| (v * [400.0, 1e5, 1.0][i % 3]) as f32)
            .chain(specials);
        for degrees in degrees {
            let x = f64::from(degrees).to_radians() * 0.5;
            let (mut sin, mut cos) = ([0.0; LANES], [0.0; LANES]);
            sin_cos(&[x; LANES], &mut sin, &mut cos);
            let (s, c) = x.sin_cos();
            assert!(
                (sin[0] - s).abs() <= f64::EPSILON / 2.0
                    && (cos[0] - c).abs() <= f64::EPSILON / 2.0,
                "{degrees}°: {} {} against {s} {c}",
                sin[0],
                cos[0]
            );
        }
    }

    #[test]
    fn atan2_is_libm_s_within_an_ulp() {
        let mut values = numbers(1 << 21);
        for i in 0..1 << 20 {
            let (y, x) = (values.next().unwrap(), values.next().unwrap());
            let (y, x) = match i % 4 {
                0 => (y * 1e-9, x),
                1 => (y, x * 1e-7),
                _ => (y, x),
            };
            let got = atan2(&[y; LANES], &[x; LANES])[0];
            let want = y.atan2(x);
            assert!(
                (got - want).abs() <= want.abs() * f64::EPSILON,
                "atan2({y}, {x}) = {got}, libm {want}"
            );
        }
        let zeros = [0.0, -0.0];
        for (y, x) in zeros
            .iter()
            .flat_map(|&y| zeros.iter().map(move |&x| (y, x)))
            .chain([
                (0.0, -1.0),
                (-0.0, -1.0),
                (1.0, 0.0),
                (-1.0, -0.0),
                (1.0, 1.0),
            ])
            .chain([(f64::INFINITY, 1.0), (1.0, f64::NAN)])
        {
            let got = atan2(&[y; LANES], &[x; LANES])[0];
            let want = y.atan2(x);
            assert!(
                got.to_bits() == want.to_bits() || got.is_nan() && want.is_nan(),
                "atan2({y}, {x}) = {got}, libm {want}"
            );
        }
    }

    /// The pass compiled for AVX-512, for AVX2 and for neither (what this CPU has of them): the
    /// same operations, so the same values, bit for bit; the tests of the values run on one.
    #[test]
    fn every_vector_width_gives_the_same_values() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/bvh/bvh11_131_01.bvh");
        let loaded = crate::take::load(&path, None, None).unwrap();
        let (source, motion) = (loaded.skeleton, loaded.motion);
        // The built-in skeleton, one turning in another order, an ASF one (hinges, fixed
        // axes), and the take's own.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let targets = [
            "smpl22".to_string(),
            root.join("tests/retarget/rokoko.bvh").display().to_string(),
            root.join("tests/data/asf_amc/heiden_12.asf")
                .display()
                .to_string(),
        ]
        .map(|name| {
            super::super::Target::load(&name, u64::MAX)
                .unwrap()
                .skeleton
        });
        for target in targets.into_iter().chain([source.clone()]) {
            let map = Map::guess(&source, &target);
            let up =
                crate::model::stance::Stance::guess(&source, &motion, OffsetMode::Replace, None).up;
            let ups = super::super::Ups {
                source: up,
                target: up,
            };
            let setup = Setup::new(&source, &motion, &target, &map, ups);
            let plan = Plan::new(&setup, &source, &target, &map);
            let frames = motion.frame_count().min(PIECE);
            let run = |width: &str| {
                let mut rows = vec![0.0f64; frames * plan.channels];
                let mut chained = vec![[0.0; 3]; frames * plan.chained.len()];
                let mut moves = vec![Move::default(); frames];
                let mut scratch = Scratch::default();
                let (r, c, m, s) = (&mut rows, &mut chained, &mut moves, &mut scratch);
                let floors = match width {
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: only where the CPU has been found to support AVX-512F.
                    "avx512" => unsafe { plan.piece_avx512(&motion, 0, r, c, m, s) },
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: only where the CPU has been found to support AVX2.
                    "avx2" => unsafe { plan.piece_avx2(&motion, 0, r, c, m, s) },
                    _ => plan.piece(&motion, 0, r, c, m, s),
                };
                let moves: Vec<(DVec3, DQuat)> =
                    moves.iter().map(|m| (m.moved, m.turned)).collect();
                (rows, chained, moves, floors)
            };
            let plain = run("none");
            #[cfg(target_arch = "x86_64")]
            for (width, feature) in [
                ("avx2", std::arch::is_x86_feature_detected!("avx2")),
                ("avx512", std::arch::is_x86_feature_detected!("avx512f")),
            ] {
                if feature {
                    assert!(run(width) == plain, "{width}");
                }
            }
        }
    }

    #[test]
    fn euler_angles_are_the_exact_split_s_at_and_near_the_lock() {
        use crate::model::skeleton::RotationOrder as R;
        let mut values = numbers(1 << 16);
        let mut next = || values.next().unwrap();
        let quarter = std::f64::consts::FRAC_PI_2;
        for _ in 0..1024 {
            let q = DQuat::from_xyzw(next(), next(), next(), next()).normalize();
            // Rotations at and near the lock of every order (90° about each axis, both ways,
            // exactly, within 1e-9 and at 89.99°), and a quaternion a hair off length 1.
            let near = quarter + next() * 1e-9;
            let mut cases = vec![q, q * 1.0001];
            for angle in [quarter, -quarter, near, 89.99f64.to_radians()] {
                for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                    let lock = DQuat::from_axis_angle(axis, angle);
                    cases.extend([lock, q * lock, lock * q]);
                }
            }
            for q in cases {
                for order in [R::Zyx, R::Yzx, R::Zxy, R::Xzy, R::Yxz, R::Xyz] {
                    let got = Quats::splat(q).euler_degrees(axis_order(order));
                    let want = crate::model::euler::split(q, order, None);
                    for (got, want) in got.iter().zip(want) {
                        assert!(
                            (got[0] - want.to_degrees()).abs() < 1e-9,
                            "{order:?} {q}: {} against {}",
                            got[0],
                            want.to_degrees()
                        );
                    }
                    let angles = got.map(|a| a[0].to_radians());
                    let back = crate::model::euler::compose(angles, order);
                    assert!(back.dot(q.normalize()).abs() > 1.0 - 1e-15, "{order:?} {q}");
                }
            }
        }
    }
}
