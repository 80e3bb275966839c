//! The travel joint: the joint whose position channels carry a take across the floor. It is
//! the hips or a joint above them, never a limb.

use crate::model::body::Body;
use crate::model::pose::{OffsetMode, world_positions};
use crate::model::skeleton::Skeleton;
use glam::Vec3;

/// The joints that may carry the travel: the root and the joints below it down to the first
/// that branches (where legs and spine part), and the hips the names say with every joint above
/// them. A limb is never one of them, though a file may give every joint position channels
/// (Perception Neuron, Rigify, Bandai).
pub fn travel_candidates(skeleton: &Skeleton) -> Vec<bool> {
    let mut candidate = vec![false; skeleton.joints.len()];
    for root in skeleton.roots() {
        let mut joint = root;
        loop {
            candidate[joint] = true;
            let children: Vec<usize> = skeleton.joints[joint]
                .children
                .iter()
                .copied()
                .filter(|&c| !skeleton.joints[c].end_site)
                .collect();
            match children.as_slice() {
                [only] => joint = *only,
                _ => break,
            }
        }
    }
    let mut above = Body::of(skeleton).hips;
    while let Some(joint) = above {
        candidate[joint] = true;
        above = skeleton.joints[joint].parent;
    }
    candidate
}

/// The joint whose position channels carry the take's travel across the floor: of the
/// [`travel_candidates`] with position channels, the one whose world path strays farthest (x and
/// z) from where it starts; the first root when none has position channels or none moves. Most
/// files put the travel on the root; some (Bandai's) on `Hips` under a root that stays put.
pub fn travel_joint(skeleton: &Skeleton, world: &[Vec3]) -> usize {
    let points = skeleton.joints.len();
    let root = skeleton.roots().next().unwrap_or(0);
    if points == 0 || world.is_empty() {
        return root;
    }
    let candidates = travel_candidates(skeleton);
    let mut best = (root, 0.0f32);
    for (index, joint) in skeleton.joints.iter().enumerate() {
        if !candidates[index] || !joint.channels.iter().any(|c| c.is_position()) {
            continue;
        }
        let start = world[index];
        let reach = world
            .chunks(points)
            .map(|pose| (pose[index].x - start.x).hypot(pose[index].z - start.z))
            .fold(0.0f32, f32::max);
        // Ties (and rounding-sized differences) go to the joint nearer the top of the file.
        if reach > best.1 * (1.0 + 1e-4) + 1e-6 {
            best = (index, reach);
        }
    }
    best.0
}

/// [`travel_joint`] of a take, judged on at most 64 of its frames spread evenly over it.
pub fn travel_joint_of_take(
    skeleton: &Skeleton,
    motion: &crate::Motion,
    mode: OffsetMode,
) -> usize {
    let frames = motion.frame_count();
    let step = frames.div_ceil(64).max(1);
    let mut world = Vec::new();
    for frame in (0..frames).step_by(step) {
        world.extend(world_positions(skeleton, motion.frame(frame), mode));
    }
    travel_joint(skeleton, &world)
}
