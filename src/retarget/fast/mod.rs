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

use crate::retarget::plain::Setup;
use glam::{DQuat, DVec3};

mod plan;
mod quats;
mod trig;

pub(super) use plan::frames;
use plan::{Move, Piece};
use quats::{Points, Quats};

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
            out.set(l, crate::retarget::align::arc(r * rest, chord.get(l)) * r);
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

/// [`nearest_form`](crate::retarget::hinge::nearest_form) of every lane: its operations in its order, as one loop over the lanes that
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
    use crate::model::pose::OffsetMode;
    use crate::retarget::Map;
    use crate::retarget::fast::plan::Plan;
    use crate::retarget::fast::plan::Scratch;
    use crate::retarget::fast::trig::atan2;
    use crate::retarget::fast::trig::sin_cos;

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
            root.join("tests/body/rokoko.bvh").display().to_string(),
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
            let setup = Setup::new(&source, &motion, &target, &map, ups, None);
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
