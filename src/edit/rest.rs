//! The rest pose reset to a T-pose (`convert --rest tpose`), every joint's world position kept
//! on every frame: arms level and out, legs straight down, the spine, neck and head up, the feet
//! forward, by the reading of the body.
//!
//! Each joint j with one child gets a fixed turn B_j that takes its bone to the T-pose direction
//! (the child's OFFSET becomes B_j⁻¹ · OFFSET, of the same length); a joint with several
//! children, or none that the T-pose names (a hand, fingers, toes), keeps B_j = 1. Its world
//! matrix then becomes W_j · B_j, which puts every child where it was: its channels' rotation
//! becomes B_parent⁻¹ · R_j · B_j and its position channels B_parent⁻¹ · t_j.

use crate::edit::finite;
use crate::io::error::Error;
use crate::model::body::{Body, Limb};
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, joint_translation, local_rotation_f64, world_positions};
use crate::model::skeleton::{Channel, RotationOrder, Skeleton};
use glam::{DQuat, DVec3};

/// Which way a bone points in the T-pose.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Way {
    Up,
    Down,
    /// Out to this side (0 left, 1 right).
    Out(usize),
    Forward,
}

/// The take with its rest pose a T-pose, read in `mode` and standing along `up`; and what a
/// user should hear (the joints turned). Position channels replace OFFSETs in the result (read
/// it in [`OffsetMode::Replace`]); every joint that is not an End Site has three rotation
/// channels (its own order, or ZYX).
///
/// ```
/// use bvhview::Take;
/// use bvhview::edit::rest_tpose;
/// use bvhview::model::pose::{OffsetMode, Up, world_positions};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let (skeleton, motion, _) = rest_tpose(&walk.skeleton, &walk.motion, OffsetMode::Replace, Up::Y)?;
/// let before = world_positions(&walk.skeleton, walk.motion.frame(100), OffsetMode::Replace);
/// let after = world_positions(&skeleton, motion.frame(100), OffsetMode::Replace);
/// assert!(before.iter().zip(&after).all(|(a, b)| a.distance(*b) < 1e-3));
/// # Ok(())
/// # }
/// ```
pub fn rest_tpose(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    up: Up,
) -> Result<(Skeleton, Motion, Vec<String>), Error> {
    let body = Body::of(skeleton);
    let up = match up {
        Up::Y => DVec3::Y,
        Up::Z => DVec3::Z,
    };
    let rest: Vec<DVec3> = world_positions(skeleton, &[], mode)
        .into_iter()
        .map(|p| p.as_dvec3())
        .collect();
    let left = left_of(&body, &rest, up).ok_or_else(|| {
        Error::usage(
            crate::io::message::Message::from("")
                .argument("rest", Some("tpose"))
                .text(
                    ": the reading of the body finds no left and right thighs or upper arms to \
                     tell which way is out",
                ),
        )
    })?;
    let forward = left.cross(up);
    let ways = ways(skeleton, &body);
    // The turn of each joint: its one bone to the T-pose's way.
    let turns: Vec<DQuat> = (0..skeleton.joints.len())
        .map(|j| {
            let joint = &skeleton.joints[j];
            let (Some(way), [child]) = (ways[j], joint.children.as_slice()) else {
                return DQuat::IDENTITY;
            };
            let Some(bone) = skeleton.joints[*child].offset.as_dvec3().try_normalize() else {
                return DQuat::IDENTITY;
            };
            let want = match way {
                Way::Up => up,
                Way::Down => -up,
                Way::Out(0) => left,
                Way::Out(_) => -left,
                Way::Forward => forward,
            };
            // B⁻¹ takes the bone to the way it should point.
            DQuat::from_rotation_arc(bone, want).inverse()
        })
        .collect();
    let turned = turns
        .iter()
        .filter(|b| b.angle_between(DQuat::IDENTITY) > 1e-9)
        .count();
    let mut out = skeleton.clone();
    let mut column = 0;
    for (j, joint) in skeleton.joints.iter().enumerate() {
        let copy = &mut out.joints[j];
        let parent_turn = joint.parent.map_or(DQuat::IDENTITY, |p| turns[p]);
        copy.offset = (parent_turn.inverse() * joint.offset.as_dvec3()).as_vec3();
        copy.axis = None;
        copy.channels.clear();
        if joint.channels.iter().any(|c| c.is_position()) {
            copy.channels
                .extend([Channel::Xposition, Channel::Yposition, Channel::Zposition]);
        }
        if !joint.end_site {
            let order = joint.rotation_order.unwrap_or(RotationOrder::Zyx);
            copy.channels
                .extend(order.letters().bytes().map(|letter| match letter {
                    b'x' => Channel::Xrotation,
                    b'y' => Channel::Yrotation,
                    _ => Channel::Zrotation,
                }));
        }
        copy.rotation_order = RotationOrder::get_flags(&copy.channels);
        copy.first_channel = column;
        column += copy.channels.len();
    }
    let frames = motion.frame_count();
    let mut data = Vec::with_capacity(frames * column);
    let mut previous: Vec<Option<[f64; 3]>> = vec![None; skeleton.joints.len()];
    for f in 0..frames {
        let row = motion.frame(f);
        for (j, joint) in skeleton.joints.iter().enumerate() {
            let values = joint.values(row);
            let parent_turn = joint.parent.map_or(DQuat::IDENTITY, |p| turns[p]);
            if joint.channels.iter().any(|c| c.is_position()) {
                let t = joint_translation(joint, values, mode).as_dvec3();
                data.extend((parent_turn.inverse() * t).as_vec3().to_array());
            }
            if !joint.end_site {
                let order = out.joints[j].rotation_order.unwrap_or(RotationOrder::Zyx);
                let rotation = parent_turn.inverse() * local_rotation_f64(joint, values) * turns[j];
                let angles = euler::split(rotation, order, previous[j]);
                previous[j] = Some(angles);
                data.extend(angles.map(|a| a.to_degrees() as f32));
            }
        }
    }
    let motion = Motion::new(motion.frame_time, column, frames, data);
    let (skeleton, motion) = finite("the T-pose rest", out, motion)?;
    Ok((
        skeleton,
        motion,
        vec![format!(
            "rest pose reset to a T-pose: {turned} joints' bones turned (arms level and out, legs \
             down, spine up), every joint where it was on every frame"
        )],
    ))
}

/// The body's left in the rest pose: from the right thigh to the left one (else the upper
/// arms), level.
fn left_of(body: &Body, rest: &[DVec3], up: DVec3) -> Option<DVec3> {
    [Limb::Thigh, Limb::UpperArm].into_iter().find_map(|limb| {
        let left = rest[body.limbs[0][limb as usize]?];
        let right = rest[body.limbs[1][limb as usize]?];
        let across = left - right;
        (across - up * across.dot(up)).try_normalize()
    })
}

/// Which way the bone from each joint (to its one child) points in the T-pose, where the
/// T-pose says: a role joint by its role, a joint inside a limb (a twist bone) or the spine as
/// the chain it lies in; nothing for a joint between the hips or chest and a limb (CMU's
/// `LHipJoint`), a hand, fingers or toes.
fn ways(skeleton: &Skeleton, body: &Body) -> Vec<Option<Way>> {
    let count = skeleton.joints.len();
    // The way of each role joint.
    let mut role: Vec<Option<Way>> = vec![None; count];
    let mut chain: Vec<Option<(usize, usize)>> = vec![None; count]; // (side, limb) of a limb joint
    for j in body
        .spine
        .iter()
        .chain(&body.hips)
        .chain(&body.neck)
        .chain(&body.head)
    {
        role[*j] = Some(Way::Up);
    }
    for (side, limbs) in body.limbs.iter().enumerate() {
        for (k, joint) in limbs.iter().enumerate() {
            let Some(j) = *joint else { continue };
            chain[j] = Some((side, k));
            role[j] = match k {
                k if k == Limb::Clavicle as usize
                    || k == Limb::UpperArm as usize
                    || k == Limb::ForeArm as usize =>
                {
                    Some(Way::Out(side))
                }
                k if k == Limb::Thigh as usize || k == Limb::Shin as usize => Some(Way::Down),
                k if k == Limb::Foot as usize => Some(Way::Forward),
                _ => None,
            };
        }
    }
    let is_role = |j: usize| role[j].is_some() || chain[j].is_some() || body.hips == Some(j);
    (0..count)
        .map(|j| {
            if is_role(j) {
                return role[j];
            }
            // Between two role joints: the nearest role joint above, and the next one below
            // along the single-child chain.
            let mut above = skeleton.joints[j].parent;
            while let Some(a) = above.filter(|&a| !is_role(a)) {
                above = skeleton.joints[a].parent;
            }
            let mut below = Some(j);
            while let Some(b) = below.filter(|&b| !is_role(b)) {
                below = match skeleton.joints[b].children.as_slice() {
                    [only] => Some(*only),
                    _ => None,
                };
            }
            let (above, below) = (above?, below?);
            let same_limb = match (chain[above], chain[below]) {
                (Some((s, a)), Some((t, b))) => s == t && b == a + 1,
                _ => false,
            };
            let up_chain = role[above] == Some(Way::Up) && role[below] == Some(Way::Up);
            (same_limb || up_chain).then_some(role[above]).flatten()
        })
        .collect()
}
