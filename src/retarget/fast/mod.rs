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

mod lanes;
mod plan;
mod quats;
mod trig;
mod turns;

pub(super) use plan::frames;

#[cfg(test)]
mod tests {
    use crate::model::pose::OffsetMode;
    use crate::retarget::Map;
    use crate::retarget::fast::lanes::LANES;
    use crate::retarget::fast::plan::{Move, PIECE, Plan, Scratch};
    use crate::retarget::fast::quats::Quats;
    use crate::retarget::fast::trig::atan2;
    use crate::retarget::fast::trig::sin_cos;
    use crate::retarget::fast::turns::axis_order;
    use crate::retarget::plain::Setup;
    use glam::{DQuat, DVec3};

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
