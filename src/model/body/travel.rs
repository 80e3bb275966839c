//! The travel joint: the joint whose position channels carry a take across the floor. It is
//! the hips or a joint above them, never a limb.

use crate::model::body::roles::Body;
use crate::model::pose::{OffsetMode, world_positions};
use crate::model::skeleton::Skeleton;
use glam::Vec3;

/// The joints that may carry the travel: the root and the joints below it down to the first
/// that branches (where legs and spine part), and the hips the names say with every joint above
/// them. A limb is never one of them, though a file may give every joint position channels
/// (Perception Neuron, Rigify, Bandai). Where the hips are found, only the tree they are in
/// counts: a rig's other roots are its controls (Maya's IK handles, `LeftFootCtrl`), never the
/// body's travel.
pub fn travel_candidates(skeleton: &Skeleton) -> Vec<bool> {
    let mut candidate = vec![false; skeleton.joints.len()];
    let hips = Body::of(skeleton).hips;
    let root_of = |mut joint: usize| {
        while let Some(parent) = skeleton.joints[joint].parent {
            joint = parent;
        }
        joint
    };
    let body_root = hips.map(root_of);
    for root in skeleton
        .roots()
        .filter(|&r| body_root.is_none_or(|b| b == r))
    {
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
    let mut above = hips;
    while let Some(joint) = above {
        candidate[joint] = true;
        above = skeleton.joints[joint].parent;
    }
    candidate
}

/// The joint whose position channels carry the take's travel across the floor: of the
/// [`travel_candidates`] with position channels, the one whose world path strays farthest (x and
/// z) from where it starts; the root of the body's tree when none has position channels or none
/// moves. Most files put the travel on the root; some (Bandai's) on `Hips` under a root that
/// stays put.
pub fn travel_joint(skeleton: &Skeleton, world: &[Vec3]) -> usize {
    let points = skeleton.joints.len();
    let candidates = travel_candidates(skeleton);
    // The root of the body's tree (a rig's controls may stand in trees of their own).
    let root = candidates
        .iter()
        .position(|&c| c)
        .unwrap_or_else(|| skeleton.roots().next().unwrap_or(0));
    if points == 0 || world.is_empty() {
        return root;
    }
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
