//! A take given as world transforms of named nodes, frame by frame → the `Skeleton` + `Motion` a
//! BVH loads into: every format is one more loader, not one more model, so every command takes
//! it unchanged.
//!
//! The FBX and glTF readers evaluate their scenes themselves (ufbx for FBX: pre/post rotations,
//! pivots, scale inheritance, unit and axis conversion all included) and hand over, for every
//! joint and every frame, the joint's world matrix. This module folds whatever made those
//! matrices into BVH channels so that BVH forward kinematics gives back the same world positions:
//!
//! - a joint's world rotation is the rotation part of its world matrix (scale and shear are
//!   dropped: BVH has none); its local rotation is its parent's world rotation inverted times its
//!   own, written as `Zrotation Yrotation Xrotation` Euler angles (degrees), pre-rotation, rest
//!   orientation and animation all in one;
//! - its local translation is the vector from its parent's world position to its own, in the
//!   parent's world rotation's frame, so that `parent + R_parent · t` is its world position even
//!   where the file scales a parent;
//! - OFFSET is that translation when it stays the same in every frame (no position channels),
//!   and the rest pose's otherwise, with `Xposition Yposition Zposition` channels carrying it;
//!   a root always has position channels;
//! - a leaf that is not a root and does not translate becomes an `End Site` (its rotation moves
//!   nothing), keeping its name.

use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, Joint, RotationOrder, Skeleton};
use glam::{DMat4, DQuat, DVec3, Vec3};

/// One node of the skeleton to be: its name and its parent among the nodes before it.
#[derive(Clone, Debug)]
pub struct Node {
    pub name: String,
    pub parent: Option<usize>,
}

/// World rotation and position of one node in one pose.
#[derive(Clone, Copy, Debug)]
pub struct Pose {
    pub rotation: DQuat,
    pub position: DVec3,
}

impl Pose {
    /// The rotation and translation of a world matrix (its scale and shear dropped). Axes with
    /// a NaN or an infinity give a rotation of NaNs (not the identity the axes' fallbacks
    /// would make of it), which [`build_with`] refuses.
    pub fn of_matrix(matrix: &DMat4) -> Pose {
        let position = matrix.w_axis.truncate();
        let axes = glam::DMat3::from_mat4(*matrix);
        if !axes.is_finite() {
            return Pose {
                rotation: DQuat::from_xyzw(f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                position,
            };
        }
        let (x, y, z) = (
            matrix.x_axis.truncate(),
            matrix.y_axis.truncate(),
            matrix.z_axis.truncate(),
        );
        // Gram–Schmidt on the scaled axes: the rotation nearest a matrix with scale, also when a
        // parent's non-uniform scale shears the child; a mirrored matrix keeps its handedness out.
        let x = x.try_normalize().unwrap_or(DVec3::X);
        let y = (y - x * x.dot(y)).try_normalize().unwrap_or_else(|| {
            let z = z.try_normalize().unwrap_or(DVec3::Z);
            z.cross(x).try_normalize().unwrap_or(DVec3::Y)
        });
        let z = x.cross(y);
        let rotation = DQuat::from_mat3(&glam::DMat3::from_cols(x, y, z)).normalize();
        Pose { rotation, position }
    }
}

/// Frames beyond this are refused (a take of an hour at 240 Hz is 864,000).
pub const MAX_FRAMES: usize = 1_000_000;

/// Joints × frames beyond this are refused: 8 M (100 joints for 11 minutes at 120 Hz), whose
/// local poses take 235 MB while a take is built.
pub const MAX_JOINT_FRAMES: usize = 1 << 23;

/// Frames × (joints + tracks) one byte of a glTF may ask for (frames × (nodes evaluated + every
/// layer's animated values) for an FBX, whose every frame ufbx evaluates), above [`FRAME_WORK_FLOOR`]: every frame samples each track and
/// poses each joint. A file keyed at every frame holds about 20
/// bytes per joint and frame (about a seventh of a unit of this a byte); one keyed every tenth
/// frame still fits. A 15.5 KB file keyed 1 ms apart with one key far on asked for a million
/// frames (13 s). Measured in a debug build, 8.2 M units (2,000 joints × 4,100 frames) take
/// `info` 9.4 s, and glam's pose arithmetic runs about 6 times faster in a release build: at 2
/// a byte, a file under 1 MB asks for at most 2.3 M, well under a second in a release build.
pub const FRAME_WORK_PER_BYTE: u64 = 2;

/// Frames × (joints + tracks) any file may ask for, whatever its size (five minutes of 30
/// joints at 30 frames per second).
pub const FRAME_WORK_FLOOR: u64 = 1 << 18;

/// The frames × (joints + tracks) a file of `bytes` bytes may ask for.
pub fn frame_work_budget(bytes: u64) -> u64 {
    FRAME_WORK_FLOOR.saturating_add(FRAME_WORK_PER_BYTE.saturating_mul(bytes))
}

/// The number of frames of a take from `start` to `end` seconds at `fps`, or why not.
pub fn frame_count(start: f64, end: f64, fps: f64, joints: usize) -> Result<usize, String> {
    if !(start.is_finite() && end.is_finite() && fps.is_finite()) {
        return Err(format!(
            "the take's time range ({start} s to {end} s at {fps} fps) is not finite"
        ));
    }
    if !(crate::limits::MIN_FPS..=crate::limits::MAX_FPS).contains(&fps) {
        return Err(format!(
            "a frame rate of {fps} fps, outside {}..{}",
            crate::limits::MIN_FPS,
            crate::limits::MAX_FPS
        ));
    }
    let span = (end - start).max(0.0);
    // Key times are often f32: 8.275 s at 120 fps is 992.99995 frames past the first.
    let frames = (span * fps + 1e-3).floor() + 1.0;
    let joint_frames = frames * joints.max(1) as f64;
    if frames > MAX_FRAMES as f64 || joint_frames > MAX_JOINT_FRAMES as f64 {
        return Err(format!(
            "the take lasts {span} s at {fps} fps: {frames} frames of {joints} joints, more than \
             bvhview reads ({MAX_FRAMES} frames, {MAX_JOINT_FRAMES} joints × frames)"
        ));
    }
    Ok(frames as usize)
}

/// Makes every joint's name unique, as Blender's importers do: a name met again becomes `name.001`
/// (`.002`, …, skipping names the file has), so that the BVH written has one joint per name. Says
/// each renaming, for the take's warnings (two joints of one name were once written silently).
pub fn unique_names(nodes: &mut [Node]) -> Vec<String> {
    use std::collections::HashSet;
    let mut taken: HashSet<String> = nodes.iter().map(|n| n.name.clone()).collect();
    let mut seen: HashSet<String> = HashSet::new();
    let mut said = Vec::new();
    for node in nodes.iter_mut() {
        if seen.insert(node.name.clone()) {
            continue;
        }
        let renamed = (1..)
            .map(|k| format!("{}.{k:03}", node.name))
            .find(|candidate| !taken.contains(candidate))
            .expect("some suffix is free");
        said.push(format!(
            "two joints are named '{}': the later one is read as '{}'",
            crate::limits::quoted(&node.name),
            crate::limits::quoted(&renamed)
        ));
        taken.insert(renamed.clone());
        seen.insert(renamed.clone());
        node.name = renamed;
    }
    said
}

/// A name as a BVH can carry it: control characters become `_`, an empty name `node<index>`.
pub fn joint_name(name: &str, index: usize) -> Result<String, String> {
    let name: String = name
        .trim()
        .chars()
        .map(|c| if c.is_control() { '_' } else { c })
        .collect();
    if name.len() > crate::limits::MAX_NAME_BYTES {
        return Err(format!(
            "a node name of {} bytes, more than {}",
            name.len(),
            crate::limits::MAX_NAME_BYTES
        ));
    }
    Ok(if name.is_empty() {
        format!("node{index}")
    } else {
        name
    })
}

/// The pose of every node relative to its parent: (local rotation, local translation).
fn locals(nodes: &[Node], world: &[Pose]) -> Vec<(DQuat, DVec3)> {
    nodes
        .iter()
        .zip(world)
        .map(|(node, pose)| match node.parent {
            None => (pose.rotation, pose.position),
            Some(p) => {
                let parent = world[p];
                let inverse = parent.rotation.inverse();
                (
                    (inverse * pose.rotation).normalize(),
                    inverse * (pose.position - parent.position),
                )
            }
        })
        .collect()
}

/// Euler angles in degrees (Z, Y, X) of `q` for `Zrotation Yrotation Xrotation`, by the one
/// exact split ([`crate::model::euler::split`]: exact at the gimbal lock, where glam's `to_euler` of a
/// 32-bit quaternion turned a child 25° away), each moved by whole turns to the nearest of
/// `previous`'s, so a converted take does not jump by 360°.
fn euler_zyx(q: DQuat, previous: Option<[f64; 3]>) -> [f64; 3] {
    let previous = previous.map(|p| p.map(f64::to_radians));
    crate::model::euler::split(q, crate::model::skeleton::RotationOrder::Zyx, previous)
        .map(f64::to_degrees)
}

/// What is wrong with a world pose, if anything: a rotation that is not finite (NaN or
/// infinite keys, a broken transform) or a position that is not a finite 32-bit float.
fn pose_fault(pose: &Pose) -> Option<&'static str> {
    if !pose.rotation.is_finite() {
        Some("a rotation that is not finite (NaN or infinite keys, or a broken transform)")
    } else if !pose.position.as_vec3().is_finite() {
        Some("a position that is not finite or past a 32-bit float (3.4e38)")
    } else {
        None
    }
}

/// Builds the skeleton and motion. `nodes` are in an order where a parent comes before its
/// children; `rest` is the world pose of each in the file's rest pose; `pose_of(f, out)` fills
/// `out` with the world pose of every node in frame `f` of `frames` (at least one: a file
/// without animation passes its rest pose as its one frame). Frames are asked for once each, in
/// order, and only their local poses are kept (28 bytes a joint and frame).
///
/// `zero_at_rest` (a character's skeleton): no leaf becomes an End Site, and each joint's frame turned so that the file's rest pose is
/// the skeleton's zero pose (every channel 0, as a BVH's rest pose is), its world rotation in a
/// frame taken relative to its rest rotation. World positions are the same either way. A
/// character's skeleton is read so: retargeting aligns rest poses, and a mesh is bound in its
/// rest pose.
pub fn build_with(
    nodes: &[Node],
    rest: &[Pose],
    zero_at_rest: bool,
    frames: usize,
    frame_time: f64,
    mut pose_of: impl FnMut(usize, &mut Vec<Pose>) -> Result<(), Error>,
) -> Result<(Skeleton, Motion), Error> {
    debug_assert_eq!(nodes.len(), rest.len());
    let file_rest = rest;
    let zeroed: Vec<Pose>;
    let rest = if zero_at_rest {
        zeroed = rest
            .iter()
            .map(|pose| Pose {
                rotation: DQuat::IDENTITY,
                position: pose.position,
            })
            .collect();
        &zeroed[..]
    } else {
        rest
    };
    let mut pose_of = move |f: usize, out: &mut Vec<Pose>| -> Result<(), Error> {
        pose_of(f, out)?;
        if zero_at_rest {
            for (pose, at_rest) in out.iter_mut().zip(file_rest) {
                pose.rotation = (pose.rotation * at_rest.rotation.inverse()).normalize();
            }
        }
        Ok(())
    };
    check_rest(nodes, rest)?;
    let sampled = Sampled::read(nodes, rest, frames, frame_time, &mut pose_of)?;
    let layout = Layout::new(nodes, &sampled, zero_at_rest, frames)?;
    let (skeleton, channels) = layout.skeleton();
    let data = layout.rows(&sampled, frames, channels)?;
    check_rows(&skeleton, &data, channels)?;
    let motion = Motion::new(frame_time, channels, frames, data);
    Ok((skeleton, motion))
}

/// Refuses a rest pose with a value that is not finite, naming the joint. Every number is
/// checked where it is made: a take with one that is not finite is refused at load, never
/// passed on to poses and exports.
fn check_rest(nodes: &[Node], rest: &[Pose]) -> Result<(), Error> {
    for (node, pose) in nodes.iter().zip(rest) {
        if let Some(fault) = pose_fault(pose) {
            return Err(Error::usage(format!(
                "joint '{}': its rest pose has {fault}",
                crate::limits::quoted(&node.name)
            )));
        }
    }
    Ok(())
}

/// The local poses of the rest pose and of every frame, and how far a translation may move and
/// still count as the same in every frame.
struct Sampled {
    /// Each node's local (rotation, translation) in the rest pose.
    rest_local: Vec<(DQuat, DVec3)>,
    /// Frame by frame, each node's local rotation.
    rotations: Vec<glam::Quat>,
    /// Frame by frame, each node's local translation.
    translations: Vec<Vec3>,
    /// A millionth of the figure's size.
    tolerance: f32,
}

impl Sampled {
    /// Asks `pose_of` for every frame in order, refusing a frame with the wrong number of poses
    /// or a pose that is not finite (naming the joint, the frame and its time).
    fn read(
        nodes: &[Node],
        rest: &[Pose],
        frames: usize,
        frame_time: f64,
        pose_of: &mut impl FnMut(usize, &mut Vec<Pose>) -> Result<(), Error>,
    ) -> Result<Sampled, Error> {
        let count = nodes.len();
        let rest_local = locals(nodes, rest);
        let mut rotations: Vec<glam::Quat> = Vec::with_capacity(frames * count);
        let mut translations: Vec<Vec3> = Vec::with_capacity(frames * count);
        // The figure's size, for "the same translation in every frame".
        let (mut low, mut high) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        for pose in rest {
            low = low.min(pose.position);
            high = high.max(pose.position);
        }
        let mut world = Vec::with_capacity(count);
        for f in 0..frames {
            world.clear();
            pose_of(f, &mut world)?;
            if world.len() != count {
                return Err(Error::usage(format!(
                    "frame {f} has {} poses for {count} joints",
                    world.len()
                )));
            }
            for (node, pose) in nodes.iter().zip(&world) {
                if let Some(fault) = pose_fault(pose) {
                    return Err(Error::usage(format!(
                        "joint '{}', frame {f} (at {} s): {fault}",
                        crate::limits::quoted(&node.name),
                        crate::limits::brief(f as f64 * frame_time)
                    )));
                }
                low = low.min(pose.position);
                high = high.max(pose.position);
            }
            for (rotation, translation) in locals(nodes, &world) {
                rotations.push(rotation.as_quat());
                translations.push(translation.as_vec3());
            }
        }
        let size = if count > 0 && high.cmpge(low).all() {
            (high - low).max_element().max(1e-9)
        } else {
            1.0
        };
        Ok(Sampled {
            rest_local,
            rotations,
            translations,
            tolerance: (1e-6 * size) as f32,
        })
    }
}

/// The joints in the nodes' order, which of them translate, and the order a BVH lists them in.
struct Layout {
    joints: Vec<Joint>,
    /// Per node: whether it has position channels.
    translates: Vec<bool>,
    /// The nodes in pre-order, a joint's whole subtree before its next sibling.
    order: Vec<usize>,
}

impl Layout {
    /// Each node's joint: its OFFSET (the translation when it stays the same in every frame,
    /// else the rest pose's with position channels), its channels, whether it is an End Site.
    fn new(
        nodes: &[Node],
        sampled: &Sampled,
        zero_at_rest: bool,
        frames: usize,
    ) -> Result<Layout, Error> {
        let count = nodes.len();
        let (translations, rest_local) = (&sampled.translations, &sampled.rest_local);
        let mut children = vec![Vec::new(); count];
        for (i, node) in nodes.iter().enumerate() {
            if let Some(p) = node.parent {
                children[p].push(i);
            }
        }

        let mut joints: Vec<Joint> = Vec::with_capacity(count);
        // For each node: translates (needs position channels) and its OFFSET.
        let mut translates = vec![false; count];
        for i in 0..count {
            let first = if frames > 0 {
                translations[i]
            } else {
                rest_local[i].1.as_vec3()
            };
            let constant = (0..frames).all(|f| {
                (translations[f * count + i] - first).abs().max_element() <= sampled.tolerance
            });
            translates[i] = nodes[i].parent.is_none() || !constant;
            let offset = if translates[i] {
                rest_local[i].1.as_vec3()
            } else {
                first
            };
            if !offset.is_finite() {
                return Err(Error::usage(format!(
                    "joint '{}': a rest offset that is not finite (past a 32-bit float)",
                    crate::limits::quoted(&nodes[i].name)
                )));
            }
            let mut joint = Joint::new(nodes[i].name.clone(), nodes[i].parent);
            joint.offset = offset;
            joint.children = children[i].clone();
            // A character's leaf joints keep their rotations: a mesh may be bound to them (a
            // head, a hand without fingers).
            joint.end_site = !zero_at_rest
                && nodes[i].parent.is_some()
                && children[i].is_empty()
                && !translates[i];
            if !joint.end_site {
                if translates[i] {
                    joint.channels.extend([
                        Channel::Xposition,
                        Channel::Yposition,
                        Channel::Zposition,
                    ]);
                }
                joint
                    .channels
                    .extend([Channel::Zrotation, Channel::Yrotation, Channel::Xrotation]);
                joint.rotation_order = Some(RotationOrder::Zyx);
            }
            joints.push(joint);
        }
        let order = pre_order(nodes, &children);
        Ok(Layout {
            joints,
            translates,
            order,
        })
    }

    /// The skeleton, its joints in pre-order with contiguous channel columns, and how many
    /// channels it has.
    fn skeleton(&self) -> (Skeleton, usize) {
        sorted_skeleton(&self.joints, &self.order)
    }

    /// The MOTION rows: per frame, each joint in pre-order, its translation if it has position
    /// channels, then its Euler angles, each the nearest to its previous frame's.
    fn rows(&self, sampled: &Sampled, frames: usize, channels: usize) -> Result<Vec<f32>, Error> {
        let count = self.joints.len();
        let values = frames
            .checked_mul(channels)
            .filter(|&v| v as u64 <= crate::limits::MAX_GENERATED_VALUES)
            .ok_or_else(|| {
                Error::limit(
                    "values",
                    crate::limits::MAX_GENERATED_VALUES,
                    (frames as u64).saturating_mul(channels as u64),
                    format!("{frames} frames of {channels} channels: more than bvhview reads"),
                )
            })?;
        let mut data = Vec::with_capacity(values);
        let mut previous: Vec<Option<[f64; 3]>> = vec![None; count];
        for f in 0..frames {
            for &i in &self.order {
                if self.joints[i].end_site {
                    continue;
                }
                if self.translates[i] {
                    data.extend(sampled.translations[f * count + i].to_array());
                }
                let rotation = sampled.rotations[f * count + i].as_dquat();
                let angles = euler_zyx(rotation, previous[i]);
                previous[i] = Some(angles);
                data.extend(angles.map(|v| v as f32));
            }
        }
        Ok(data)
    }
}

/// `joints` (parents and children as indices into it) as a skeleton in `order` (a pre-order of
/// them), each joint's channel columns after the one before; and how many channels it has.
pub(crate) fn sorted_skeleton(joints: &[Joint], order: &[usize]) -> (Skeleton, usize) {
    let mut new_index = vec![0; joints.len()];
    for (n, &i) in order.iter().enumerate() {
        new_index[i] = n;
    }
    let mut sorted: Vec<Joint> = order.iter().map(|&i| joints[i].clone()).collect();
    let mut column = 0;
    for joint in &mut sorted {
        joint.parent = joint.parent.map(|p| new_index[p]);
        for child in &mut joint.children {
            *child = new_index[*child];
        }
        joint.first_channel = column;
        column += joint.channels.len();
    }
    let skeleton = Skeleton {
        joints: sorted,
        source: crate::model::skeleton::Source::Bvh,
        // The reader says whether its file stated its axes (glTF always, FBX by its header).
        y_up_stated: false,
    };
    (skeleton, column)
}

/// The nodes in pre-order: they come parent first, but a BVH lists a joint's whole subtree
/// before its next sibling, so that a joint's channel columns are contiguous.
pub(crate) fn pre_order(nodes: &[Node], children: &[Vec<usize>]) -> Vec<usize> {
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack: Vec<usize> = (0..nodes.len())
        .filter(|&i| nodes[i].parent.is_none())
        .rev()
        .collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        stack.extend(children[i].iter().rev());
    }
    order
}

/// Refuses rows with a value that is not finite, naming its joint and frame.
fn check_rows(skeleton: &Skeleton, data: &[f32], channels: usize) -> Result<(), Error> {
    if let Some(at) = crate::edit::first_non_finite(data) {
        let (frame, column) = (at / channels.max(1), at % channels.max(1));
        let joint = skeleton
            .joints
            .iter()
            .find(|j| (j.first_channel..j.first_channel + j.channels.len()).contains(&column))
            .map_or("?".to_string(), |j| crate::limits::quoted(&j.name));
        return Err(Error::usage(format!(
            "joint '{joint}', frame {frame}: the file's transforms give a value that is not \
             finite (a zero scale or a broken matrix)"
        )));
    }
    Ok(())
}

/// The world position of every joint of `skeleton` in frame `f` as BVH FK computes it, in f64
/// (for tests of the readers against the poses they were built from).
#[cfg(test)]
pub fn world_positions(skeleton: &Skeleton, motion: &Motion, f: usize) -> Vec<Vec3> {
    crate::model::pose::world_positions(
        skeleton,
        motion.frame(f),
        crate::model::pose::OffsetMode::Replace,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two nodes of one name become `name` and `name.001` (a name the file has is skipped), each
    /// renaming said.
    #[test]
    fn names_met_again_get_blenders_suffixes() {
        let node = |name: &str| Node {
            name: name.to_string(),
            parent: None,
        };
        let mut nodes = vec![node("arm"), node("arm"), node("arm.001"), node("arm")];
        let said = unique_names(&mut nodes);
        let names: Vec<&str> = nodes.iter().map(|n| n.name.as_str()).collect();
        assert_eq!(names, ["arm", "arm.002", "arm.001", "arm.003"]);
        assert_eq!(said.len(), 2, "{said:?}");
        assert!(said[0].contains("read as 'arm.002'"), "{said:?}");
    }

    #[test]
    fn euler_zyx_is_what_the_channels_multiply() {
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let [z, y, x] = euler_zyx(q, None);
        let back = DQuat::from_rotation_z(z.to_radians())
            * DQuat::from_rotation_y(y.to_radians())
            * DQuat::from_rotation_x(x.to_radians());
        assert!(back.dot(q).abs() > 1.0 - 1e-12, "{back:?} vs {q:?}");
    }

    #[test]
    fn world_positions_come_back_through_bvh_fk() {
        // A chain of three with a scaled, rotated parent and a translating middle joint.
        let nodes = vec![
            Node {
                name: "root".into(),
                parent: None,
            },
            Node {
                name: "mid".into(),
                parent: Some(0),
            },
            Node {
                name: "tip".into(),
                parent: Some(1),
            },
        ];
        let pose = |t: f64| {
            let root = DMat4::from_scale_rotation_translation(
                DVec3::splat(2.0),
                DQuat::from_rotation_y(t),
                DVec3::new(t, 1.0, 0.0),
            );
            let mid = root
                * DMat4::from_rotation_translation(
                    DQuat::from_rotation_x(0.5 * t),
                    DVec3::new(0.0, 1.0 + t, 0.0),
                );
            let tip = mid * DMat4::from_translation(DVec3::new(0.0, 0.0, 1.0));
            [root, mid, tip].map(|m| Pose::of_matrix(&m)).to_vec()
        };
        let rest = pose(0.0);
        let frames: Vec<Vec<Pose>> = (0..5).map(|f| pose(f as f64 * 0.2)).collect();
        let (skeleton, motion) = build_with(&nodes, &rest, false, frames.len(), 0.5, |f, out| {
            out.extend_from_slice(&frames[f]);
            Ok(())
        })
        .unwrap();
        assert_eq!(skeleton.joints.len(), 3);
        assert!(skeleton.joints[2].end_site);
        assert_eq!(skeleton.joints[1].channels.len(), 6);
        for (f, frame) in frames.iter().enumerate() {
            let got = world_positions(&skeleton, &motion, f);
            for (g, want) in got.iter().zip(frame) {
                assert!(
                    (g.as_dvec3() - want.position).length() < 1e-5,
                    "{g} vs {want:?}"
                );
            }
        }
    }
}
