//! Smoothing jittery motion (`--smooth HZ`, `edit::smooth`). A real walk with
//! noise added, to its channels or to its joint positions before they are solved, comes back
//! nearer the clean walk: the mean distance of every point to where the clean take puts it at
//! least halved. The figures are printed for docs/GUIDE.md (`--nocapture`).

use crate::common;

use bvhview::Take;
use bvhview::model::pose::{OffsetMode, world_transforms_f64};
use glam::DVec3;

/// Numbers in -1..1 from a fixed seed (a linear congruential generator: the same on every
/// machine, no dependency).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn points(skeleton: &bvhview::Skeleton, motion: &bvhview::Motion) -> Vec<DVec3> {
    let mut out = Vec::new();
    let mut world = Vec::new();
    for f in 0..motion.frame_count() {
        world_transforms_f64(skeleton, motion.frame(f), OffsetMode::Replace, &mut world);
        out.extend(world.iter().map(|&(_, p)| p));
    }
    out
}

fn mean_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).length())
        .sum::<f64>()
        / a.len() as f64
}

#[test]
fn smoothing_a_noisy_copy_halves_its_error_at_least() {
    // A CMU walk at 120 frames per second; 1 unit = 5.6 cm.
    let take = Take::open(common::repo_data("bvh/bvhparser_walk_01.bvh")).unwrap();
    let clean = points(&take.skeleton, &take.motion);
    let mut noise = Noise(46_48);
    let mut noisy = take.motion.clone();
    for joint in &take.skeleton.joints {
        for (i, channel) in joint.channels.iter().enumerate() {
            // ±3° on every rotation channel, ±0.2 units (1.1 cm) on the root's position.
            let amount = if channel.is_position() { 0.2 } else { 3.0 };
            for f in 0..noisy.frame_count() {
                noisy.data[f * noisy.channels + joint.first_channel + i] +=
                    (amount * noise.next()) as f32;
            }
        }
    }
    let noisy_points = points(&take.skeleton, &noisy);
    let before = mean_distance(&noisy_points, &clean);
    for cutoff in [4.0, 6.0, 10.0] {
        let smooth = bvhview::edit::smooth(&take.skeleton, &noisy, cutoff).unwrap();
        let after = mean_distance(&points(&take.skeleton, &smooth), &clean);
        println!(
            "channels ±3° and ±1.1 cm, {cutoff} Hz: mean error {:.2} cm → {:.2} cm ({:.0} %)",
            before * 5.6,
            after * 5.6,
            100.0 * after / before
        );
        assert!(after <= 0.5 * before, "{cutoff} Hz: {before} → {after}");
    }
    // The clean take smoothed at 6 Hz moves as it did, within a few millimetres on average.
    let kept = bvhview::edit::smooth(&take.skeleton, &take.motion, 6.0).unwrap();
    let moved = mean_distance(&points(&take.skeleton, &kept), &clean);
    println!(
        "the clean walk at 6 Hz: moved {:.2} cm on average",
        moved * 5.6
    );
    assert!(moved * 5.6 < 0.5, "{moved}");
}

#[test]
fn smoothing_a_solve_of_noisy_positions_halves_its_error_at_least() {
    // The walk's joint positions with ±1 cm of noise each, as a pose estimator's jitter,
    // solved onto the walk's skeleton, then smoothed.
    let take = Take::open(common::repo_data("bvh/bvhparser_walk_01.bvh")).unwrap();
    let clean = points(&take.skeleton, &take.motion);
    let mut noise = Noise(2026);
    let jittered: Vec<DVec3> = clean
        .iter()
        .map(|p| *p + DVec3::new(noise.next(), noise.next(), noise.next()) * (1.0 / 5.6))
        .collect();
    let positions =
        bvhview::solve::Positions::new(take.point_names(), jittered, take.motion.frame_time)
            .unwrap();
    let (solved, _) = bvhview::solve::solve(
        &take.skeleton,
        bvhview::model::pose::Up::guess(&take.skeleton),
        &positions,
        None,
    )
    .unwrap();
    let before = mean_distance(&points(&take.skeleton, &solved), &clean);
    let smooth = bvhview::edit::smooth(&take.skeleton, &solved, 6.0).unwrap();
    let after = mean_distance(&points(&take.skeleton, &smooth), &clean);
    println!(
        "positions ±1 cm, solved, 6 Hz: mean error {:.2} cm → {:.2} cm ({:.0} %)",
        before * 5.6,
        after * 5.6,
        100.0 * after / before
    );
    assert!(after <= 0.5 * before, "{before} → {after}");
}
