//! Issue 48, point 2: HumanML3D's feature vectors made as its own pipeline makes them, checked
//! against its published pair (tests/humanml3d, MIT: `new_joints/012314.npy`, the processed
//! positions, and `new_joint_vecs/012314.npy`, the vectors its pipeline made).

use bvhview::humanml3d::{self, JOINTS, PARENTS, PARTS, REFERENCE_LENGTHS, WIDTH};
use glam::DVec3;
use std::path::Path;

fn pair() -> (Vec<DVec3>, Vec<f32>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/humanml3d");
    let joints = std::fs::read(root.join("new_joints_012314.npy")).unwrap();
    let (_, points) = bvhview::solve::read_npy(&joints, "new_joints").unwrap();
    let vectors = std::fs::read(root.join("new_joint_vecs_012314.npy")).unwrap();
    (
        points,
        humanml3d::read_vectors(&vectors, "new_joint_vecs").unwrap(),
    )
}

/// The reference bone lengths are those of every processed frame HumanML3D published.
#[test]
fn reference_lengths_are_humanml3ds() {
    let (points, _) = pair();
    let mut worst = 0.0f64;
    for pose in points.chunks(JOINTS) {
        for j in 1..JOINTS {
            let length = (pose[j] - pose[PARENTS[j]]).length();
            worst = worst.max((length - REFERENCE_LENGTHS[j]).abs());
        }
    }
    println!("reference lengths: worst difference {worst:.2e} m");
    assert!(worst < 3e-6, "{worst}");
}

/// HumanML3D's processed positions of a take (171 frames, of which it published 170), with the
/// last frame rebuilt from the last vector's joint velocities, run through the pipeline again
/// give its published vectors: the take is already uniform, on the floor, at the origin and
/// facing +z, so each placing step leaves it as it is, and every number must come out as its
/// pipeline (float32, PyTorch) made it.
#[test]
fn vectors_of_humanmls_own_positions_are_its_published_vectors() {
    let (mut points, published) = pair();
    let rows = published.len() / WIDTH;
    let last = &published[(rows - 1) * WIDTH..];
    // The root's rotation at the last published frame: its turns so far (half angles).
    let half: f64 = (0..rows - 1).map(|f| f64::from(published[f * WIDTH])).sum();
    let facing = glam::DQuat::from_xyzw(0.0, half.sin(), 0.0, half.cos());
    let before: Vec<DVec3> = points[(rows - 1) * JOINTS..].to_vec();
    for (j, at) in before.iter().enumerate() {
        let step = &last[193 + 3 * j..196 + 3 * j];
        let step = DVec3::new(step[0].into(), step[1].into(), step[2].into());
        points.push(*at + facing.inverse() * step);
    }
    let made = humanml3d::features(&points).unwrap();
    assert_eq!(made.frames(), rows);
    // Float32 rounding in HumanML3D's pipeline, and its contact threshold met exactly nowhere.
    let allowed = [
        ("root_turn", 1e-5),
        ("root_step", 1e-5),
        ("root_height", 1e-5),
        ("ric", 1e-5),
        ("rotations", 1e-5),
        ("velocities", 1e-5),
        ("contacts", 0.0),
    ];
    for ((name, start, width), (same, bound)) in PARTS.into_iter().zip(allowed) {
        assert_eq!(name, same);
        let mut worst = (0.0f32, 0usize);
        for f in 0..rows {
            for k in start..start + width {
                let d = (made.vectors[f * WIDTH + k] - published[f * WIDTH + k]).abs();
                if d > worst.0 {
                    worst = (d, f);
                }
            }
        }
        println!(
            "{name}: worst difference {:.2e} at frame {}",
            worst.0, worst.1
        );
        assert!(
            worst.0 <= bound,
            "{name}: {:.2e} at frame {}",
            worst.0,
            worst.1
        );
    }
    // And the positions the vectors stand for are the published ones.
    let worst = made
        .joints
        .chunks(3)
        .zip(&points)
        .map(|(m, p)| (DVec3::new(m[0].into(), m[1].into(), m[2].into()) - *p).length())
        .fold(0.0f64, f64::max);
    println!("new_joints: worst difference {worst:.2e} m");
    assert!(worst < 1e-4, "{worst}");
}
