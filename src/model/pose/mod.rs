//! Forward kinematics: the one place where joint matrices and world positions are computed.
//!
//! A joint's local matrix is `T(t) · R1 · R2 · R3`: one translation, then its rotation channels in
//! the order the file lists them, in degrees. This is the product the article's `drawRecursive`
//! builds on the GL matrix stack (`glTranslatef`, then one `glRotatef` per channel), and the one
//! the renderer's draw issues call for call; the world matrix is the parent's world times local.
//!
//! One product, two precisions. [`world_matrices`] and [`FkPlan`] compute it in 32-bit floats
//! (glam's `Mat4`/`Quat`), as the file's values and the GL calls are; [`world_transforms_f64`]
//! computes the same product (the same channels in the same order, the same ASF axis) in 64-bit
//! floats, for retargeting alone, which must turn world rotations back into channel values: a
//! take retargeted onto its own skeleton is to give its values back within 1e-6 degrees (issue
//! 37). Measured on the five takes of that test (2026-11-27): through the 32-bit FK the worst
//! value came back 1.4e-3° off on CMU's 01_01 and 89.96° off on Rokoko's dance (a joint near
//! gimbal lock, where a rounding of the world rotation moves the first and third Euler angles
//! by as much as they like); through the 64-bit one, within 3.5e-14° on all five. So the
//! 32-bit path cannot meet the test and stays the one everything else uses (speed, and the
//! picture's exact GL product); a unit test below holds the two to the same positions.

use crate::model::skeleton::{Joint, Skeleton};
use glam::{Mat4, Vec3};

mod channels;
mod lanes;
mod mode;
mod rotations;

pub use channels::{channel_rotation, channel_rotations, local_rotation};
pub use lanes::{FkPlan, FkScratch, LANES, positions_all_frames, sin_cos_batch, sin_cos_degrees};
pub use mode::OffsetMode;
pub use rotations::{
    RotationKind, rotation_numbers_problem, rotation_of_numbers, write_local_rotations, write_quat,
    write_rotation,
};

/// Which world axis points up in a file: BVH's usual Y, or Z as some exporters write.
///
/// ```
/// use bvhview::{Take, model::pose::Up};
/// use glam::Vec3;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// assert_eq!(Up::guess(&take.skeleton), Up::Y);
/// // The turn that makes a Z-up take stand along Y.
/// assert!((Up::Z.to_y_up() * Vec3::Z).abs_diff_eq(Vec3::Y, 1e-6));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    /// Y up: BVH's usual convention.
    #[default]
    Y,
    /// Z up, as some exporters write.
    Z,
}

impl Up {
    /// The guess from the rest pose: Z when the skeleton stands clearly taller along Z than
    /// along Y (a figure is about as deep as it is wide, and much taller than either). The roots
    /// are left out: a root's child may be placed far away (Bandai's `joint_Root`), which says
    /// nothing about which way the body stands.
    pub fn guess(skeleton: &Skeleton) -> Up {
        if skeleton.y_up_stated {
            return Up::Y;
        }
        let points = world_positions(skeleton, &[], OffsetMode::Replace);
        let body: Vec<Vec3> = points
            .iter()
            .zip(&skeleton.joints)
            .filter(|(_, joint)| joint.parent.is_some())
            .map(|(p, _)| *p)
            .collect();
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &body {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let size = hi - lo;
        if body.len() > 1 && size.z > 1.5 * size.y && size.z >= size.x {
            Up::Z
        } else {
            Up::Y
        }
    }

    /// The rotation that stands a file with this up axis in the Y-up world the viewer draws:
    /// none, or -90° about X ((x, y, z) → (x, z, -y)).
    pub fn to_y_up(self) -> glam::Quat {
        match self {
            Up::Y => glam::Quat::IDENTITY,
            Up::Z => glam::Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        }
    }
}

/// An up axis a caller can state: any of the six signed axes. bvhview's stances stand along
/// +Y or +Z ([`Up`]); a take stated to stand along another is turned exactly to +Y when it
/// is read ([`crate::Take::stand_along`]), and says so.
///
/// ```
/// use bvhview::model::pose::{Up, UpAxis};
/// use glam::Vec3;
///
/// let axis: UpAxis = "-z".parse().unwrap();
/// assert_eq!(axis, UpAxis::NegZ);
/// assert_eq!(axis.standing(), None); // turned to +Y when read
/// assert_eq!(UpAxis::from(Up::Z).standing(), Some(Up::Z));
/// assert!((axis.to_y_up() * Vec3::NEG_Z).abs_diff_eq(Vec3::Y, 1e-6));
/// assert_eq!(axis.to_string(), "-z");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// +X.
    X,
    /// −X.
    NegX,
    /// +Y: BVH's usual convention.
    Y,
    /// −Y (a camera's image axes).
    NegY,
    /// +Z, as some exporters write.
    Z,
    /// −Z.
    NegZ,
}

impl UpAxis {
    /// Every axis, in the order `--up` lists them.
    pub const ALL: [UpAxis; 6] = [
        UpAxis::Y,
        UpAxis::Z,
        UpAxis::X,
        UpAxis::NegY,
        UpAxis::NegZ,
        UpAxis::NegX,
    ];

    /// The stance's own up axis when it is one ([`Up::Y`], [`Up::Z`]); `None` for the four a
    /// take is turned from.
    pub fn standing(self) -> Option<Up> {
        match self {
            UpAxis::Y => Some(Up::Y),
            UpAxis::Z => Some(Up::Z),
            _ => None,
        }
    }

    /// The rotation that takes this axis to +Y by a quarter or half turn (about X for ±Z and
    /// −Y, about Z for ±X), as [`Up::to_y_up`] does for +Z.
    pub fn to_y_up(self) -> glam::Quat {
        use std::f32::consts::{FRAC_PI_2, PI};
        match self {
            UpAxis::Y => glam::Quat::IDENTITY,
            UpAxis::Z => glam::Quat::from_rotation_x(-FRAC_PI_2),
            UpAxis::NegZ => glam::Quat::from_rotation_x(FRAC_PI_2),
            UpAxis::NegY => glam::Quat::from_rotation_x(PI),
            UpAxis::X => glam::Quat::from_rotation_z(FRAC_PI_2),
            UpAxis::NegX => glam::Quat::from_rotation_z(-FRAC_PI_2),
        }
    }

    /// The unit vector along the axis.
    pub fn vector(self) -> Vec3 {
        match self {
            UpAxis::X => Vec3::X,
            UpAxis::NegX => Vec3::NEG_X,
            UpAxis::Y => Vec3::Y,
            UpAxis::NegY => Vec3::NEG_Y,
            UpAxis::Z => Vec3::Z,
            UpAxis::NegZ => Vec3::NEG_Z,
        }
    }
}

impl From<Up> for UpAxis {
    fn from(up: Up) -> UpAxis {
        match up {
            Up::Y => UpAxis::Y,
            Up::Z => UpAxis::Z,
        }
    }
}

impl std::fmt::Display for UpAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            UpAxis::X => "x",
            UpAxis::NegX => "-x",
            UpAxis::Y => "y",
            UpAxis::NegY => "-y",
            UpAxis::Z => "z",
            UpAxis::NegZ => "-z",
        })
    }
}

impl std::str::FromStr for UpAxis {
    type Err = String;

    /// `y`, `z`, `x`, `-y`, `-z`, `-x` (a leading `+` and capitals read too).
    fn from_str(text: &str) -> Result<UpAxis, String> {
        let lower = text.trim().to_ascii_lowercase();
        let wanted = lower.strip_prefix('+').unwrap_or(&lower);
        UpAxis::ALL
            .into_iter()
            .find(|axis| axis.to_string() == wanted)
            .ok_or_else(|| format!("expected an up axis (y, z, x, -y, -z or -x), found '{text}'"))
    }
}

/// How near a position channel's values must be to 0 (or to the OFFSET) to count as "written
/// for the other mode", as a fraction of the OFFSET's length along the channels' axes.
pub const OTHER_MODE_NEAR: f32 = 0.05;

/// Whether the non-root position channels look written for the other offset mode than `mode`,
/// by frame 0. A candidate is a non-root joint with position channels whose OFFSET, along those
/// channels' axes, is at least 1e-3 long; under `Replace` it looks written for `Add` when its
/// position values are within 5% of that length of 0 (MakeHuman's files: zeros, or deltas such
/// as 7e-4 against OFFSETs of 0.33, "added to OFFSET"); under `Add` it looks written for
/// `Replace` when they are within 5% of the OFFSET (adding would double the bone). Nine in ten
/// candidates or more must look so. `Some((matching, candidates))` when they do (`info` words
/// the warning, and [`guessed_mode`] follows it).
pub fn written_for_other_mode(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    mode: OffsetMode,
) -> Option<(usize, usize)> {
    if motion.frame_count() == 0 {
        return None;
    }
    let frame = motion.frame(0);
    let mut candidates = 0;
    let mut matching = 0;
    for joint in skeleton.joints.iter().filter(|j| j.parent.is_some()) {
        let values = joint.values(frame);
        // The values on each axis the channels set (the last channel of an axis wins, as in
        // `joint_translation`), and the OFFSET along the same axes.
        let mut set = [None; 3];
        for (channel, &value) in joint.channels.iter().zip(values) {
            if channel.is_position() {
                set[channel.axis()] = Some(value);
            }
        }
        let (mut value, mut offset) = (Vec3::ZERO, Vec3::ZERO);
        for (axis, v) in set.iter().enumerate() {
            if let Some(v) = v {
                value[axis] = *v;
                offset[axis] = joint.offset[axis];
            }
        }
        let length = offset.length();
        if set.iter().all(Option::is_none) || !(length >= 1e-3 && value.is_finite()) {
            continue;
        }
        candidates += 1;
        let near = (OTHER_MODE_NEAR * length).max(1e-4);
        let looks_other = match mode {
            OffsetMode::Replace => value.length() <= near,
            OffsetMode::Add => (value - offset).length() <= near,
        };
        if looks_other {
            matching += 1;
        }
    }
    if candidates == 0 || matching * 10 < candidates * 9 {
        return None;
    }
    Some((matching, candidates))
}

/// The mode a take looks written for, starting from `mode`: the other one when
/// [`written_for_other_mode`] says so, else `mode` itself.
pub fn guessed_mode(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    mode: OffsetMode,
) -> OffsetMode {
    match (written_for_other_mode(skeleton, motion, mode), mode) {
        (None, _) => mode,
        (Some(_), OffsetMode::Replace) => OffsetMode::Add,
        (Some(_), OffsetMode::Add) => OffsetMode::Replace,
    }
}

/// The joint's translation `t` for one frame: its OFFSET with its position channels replacing
/// (or added to) the matching components. `values` are this joint's channel values.
pub fn joint_translation(joint: &Joint, values: &[f32], mode: OffsetMode) -> Vec3 {
    let mut t = joint.offset;
    for (channel, &value) in joint.channels.iter().zip(values) {
        if channel.is_position() {
            let axis = channel.axis();
            match mode {
                OffsetMode::Replace => t[axis] = value,
                OffsetMode::Add => t[axis] += value,
            }
        }
    }
    t
}

/// `T(t) · R1 · R2 · R3` for one joint, or `T(t) · C · R1 · R2 · R3 · C⁻¹` when the joint has a
/// fixed axis C (ASF bones); `values` are this joint's channel values.
pub fn local_matrix(joint: &Joint, values: &[f32], mode: OffsetMode) -> Mat4 {
    Mat4::from_translation(joint_translation(joint, values, mode)) * local_rotation(joint, values)
}

/// World matrices of every joint for one MOTION row (`frame` has one value per channel). An empty
/// slice gives the rest pose: every joint at its OFFSET, no rotation. `out` gets one per joint.
pub fn world_matrices(skeleton: &Skeleton, frame: &[f32], mode: OffsetMode, out: &mut Vec<Mat4>) {
    out.clear();
    out.reserve(skeleton.joints.len());
    for joint in &skeleton.joints {
        let local = if frame.is_empty() {
            Mat4::from_translation(joint.offset)
        } else {
            local_matrix(joint, joint.values(frame), mode)
        };
        // Joints are in pre-order, so the parent's world matrix is already computed.
        let world = match joint.parent {
            Some(parent) => out[parent] * local,
            None => local,
        };
        out.push(world);
    }
}

/// World position of every joint (and End Site) for one MOTION row.
pub fn world_positions(skeleton: &Skeleton, frame: &[f32], mode: OffsetMode) -> Vec<Vec3> {
    let mut matrices = Vec::new();
    world_matrices(skeleton, frame, mode, &mut matrices);
    matrices.iter().map(|m| m.w_axis.truncate()).collect()
}

/// A joint's rotation for one frame in 64-bit floats: the same product as [`local_rotation`]
/// (`R1 · R2 · R3`, or `C · R1 · R2 · R3 · C⁻¹` with a fixed axis C), for work that carries
/// rotations from one skeleton to another and back into channels without 32-bit rounding
/// (retargeting: the module's docs say why 32 bits are not enough, measured).
pub fn local_rotation_f64(joint: &Joint, values: &[f32]) -> glam::DQuat {
    let rotation = channel_rotations_f64(joint, values);
    match joint.axis {
        None => rotation,
        Some(axis) => {
            let axis = axis.as_dquat().normalize();
            axis * rotation * axis.inverse()
        }
    }
}

/// [`channel_rotations`] in 64-bit floats: `R1 · R2 · R3` of the rotation channels in file order.
pub fn channel_rotations_f64(joint: &Joint, values: &[f32]) -> glam::DQuat {
    let mut rotation = glam::DQuat::IDENTITY;
    for (channel, &value) in joint.channels.iter().zip(values) {
        if channel.is_rotation() {
            let radians = f64::from(value).to_radians();
            rotation *= match channel.axis() {
                0 => glam::DQuat::from_rotation_x(radians),
                1 => glam::DQuat::from_rotation_y(radians),
                _ => glam::DQuat::from_rotation_z(radians),
            };
        }
    }
    rotation
}

/// [`world_matrices`] in 64-bit floats, as a world rotation and position per joint. An empty
/// `frame` gives the rest pose (every rotation the identity). Retargeting's FK: with the 32-bit
/// one, a take onto its own skeleton comes back up to 90° off near gimbal lock (module docs).
pub fn world_transforms_f64(
    skeleton: &Skeleton,
    frame: &[f32],
    mode: OffsetMode,
    out: &mut Vec<(glam::DQuat, glam::DVec3)>,
) {
    out.clear();
    out.reserve(skeleton.joints.len());
    for joint in &skeleton.joints {
        let (rotation, translation) = if frame.is_empty() {
            (glam::DQuat::IDENTITY, joint.offset.as_dvec3())
        } else {
            let values = joint.values(frame);
            let mut t = joint.offset.as_dvec3();
            for (channel, &value) in joint.channels.iter().zip(values) {
                if channel.is_position() {
                    let axis = channel.axis();
                    match mode {
                        OffsetMode::Replace => t[axis] = f64::from(value),
                        OffsetMode::Add => t[axis] += f64::from(value),
                    }
                }
            }
            (local_rotation_f64(joint, values), t)
        };
        let world = match joint.parent {
            Some(parent) => {
                let (r, p) = out[parent];
                (r * rotation, p + r * translation)
            }
            None => (rotation, translation),
        };
        out.push(world);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::skeleton::Channel::{self, *};

    fn joint(offset: Vec3, channels: Vec<Channel>) -> Joint {
        let mut joint = Joint::new("j".into(), None);
        joint.offset = offset;
        joint.channels = channels;
        joint
    }

    fn assert_close(got: Vec3, want: Vec3) {
        assert!(got.abs_diff_eq(want, 1e-5), "got {got}, want {want}");
    }

    /// Every order with 90° on each of its three rotations, applied to p = (1, 2, 3) and then
    /// translated by the OFFSET (10, 20, 30). Expected points worked out by hand, rightmost
    /// rotation first, with Rx(90): (x,y,z)→(x,−z,y), Ry(90): →(z,y,−x), Rz(90): →(−y,x,z).
    #[test]
    fn all_six_rotation_orders_match_hand_computed_points() {
        let cases = [
            ([Zrotation, Yrotation, Xrotation], Vec3::new(3.0, 2.0, -1.0)),
            ([Yrotation, Zrotation, Xrotation], Vec3::new(2.0, 1.0, -3.0)),
            ([Zrotation, Xrotation, Yrotation], Vec3::new(-1.0, 3.0, 2.0)),
            ([Xrotation, Zrotation, Yrotation], Vec3::new(-2.0, 1.0, 3.0)),
            ([Yrotation, Xrotation, Zrotation], Vec3::new(1.0, -3.0, 2.0)),
            ([Xrotation, Yrotation, Zrotation], Vec3::new(3.0, -2.0, 1.0)),
        ];
        let offset = Vec3::new(10.0, 20.0, 30.0);
        for (channels, rotated) in cases {
            let j = joint(offset, channels.to_vec());
            let m = local_matrix(&j, &[90.0, 90.0, 90.0], OffsetMode::Replace);
            assert_close(
                m.transform_point3(Vec3::new(1.0, 2.0, 3.0)),
                offset + rotated,
            );
        }
    }

    /// ZYX with unequal angles against the textbook product Rz(a)·Ry(b)·Rx(c), element by element.
    #[test]
    fn zyx_matches_closed_form() {
        let (a, b, c) = (30f32.to_radians(), 45f32.to_radians(), 60f32.to_radians());
        let (sa, ca, sb, cb, sc, cc) = (a.sin(), a.cos(), b.sin(), b.cos(), c.sin(), c.cos());
        let rows = [
            [ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc],
            [sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc],
            [-sb, cb * sc, cb * cc],
        ];
        let j = joint(Vec3::ZERO, vec![Zrotation, Yrotation, Xrotation]);
        let m = local_matrix(&j, &[30.0, 45.0, 60.0], OffsetMode::Replace);
        for (r, row) in rows.iter().enumerate() {
            for (c, &want) in row.iter().enumerate() {
                let got = m.col(c)[r];
                assert!((got - want).abs() < 1e-6, "[{r}][{c}] {got} vs {want}");
            }
        }
    }

    #[test]
    fn position_channels_replace_or_add_to_offset() {
        let j = joint(
            Vec3::new(1.0, 2.0, 3.0),
            vec![Zrotation, Xposition, Zposition],
        );
        let values = [0.0, 5.0, -7.0];
        assert_eq!(
            joint_translation(&j, &values, OffsetMode::Replace),
            Vec3::new(5.0, 2.0, -7.0)
        );
        assert_eq!(
            joint_translation(&j, &values, OffsetMode::Add),
            Vec3::new(6.0, 2.0, -4.0)
        );
    }

    /// Root at (0, 10, 0) turned 90° about Y; a child 5 along +X ends up 5 along −Z.
    /// The 64-bit FK is the 32-bit one's product: the same positions on every frame of a real
    /// take with mixed rotation orders (within 32-bit rounding), and rotations that move the
    /// same points.
    #[test]
    fn the_64_bit_fk_is_the_same_product() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/bvh/bvh11_131_01.bvh");
        let bvh = crate::bvh::load_bytes(&std::fs::read(path).unwrap(), "t.bvh").unwrap();
        let (skeleton, motion) = (&bvh.skeleton, &bvh.motion);
        let (mut wide, mut narrow) = (Vec::new(), Vec::new());
        let mut worst = 0.0f64;
        for frame in (0..motion.frame_count()).step_by(7) {
            let row = motion.frame(frame);
            world_transforms_f64(skeleton, row, OffsetMode::Replace, &mut wide);
            world_matrices(skeleton, row, OffsetMode::Replace, &mut narrow);
            for ((rotation, position), matrix) in wide.iter().zip(&narrow) {
                worst = worst.max((*position - matrix.w_axis.truncate().as_dvec3()).length());
                let turned = *rotation * glam::DVec3::new(1.0, 2.0, 3.0);
                let by_matrix = matrix.transform_vector3(Vec3::new(1.0, 2.0, 3.0));
                worst = worst.max((turned - by_matrix.as_dvec3()).length());
            }
        }
        // The figure stands some 170 units tall: 1e-3 is 32-bit rounding over a chain of 31.
        assert!(worst > 0.0 && worst < 1e-3, "{worst}");
    }

    #[test]
    fn world_is_parent_times_local() {
        let mut root = joint(Vec3::ZERO, vec![Xposition, Yposition, Zposition, Yrotation]);
        root.children = vec![1];
        let mut child = Joint::new("c".into(), Some(0));
        child.offset = Vec3::new(5.0, 0.0, 0.0);
        child.first_channel = 4;
        let skeleton = Skeleton {
            joints: vec![root, child],
            ..Skeleton::default()
        };
        let positions = world_positions(&skeleton, &[0.0, 10.0, 0.0, 90.0], OffsetMode::Replace);
        assert_close(positions[0], Vec3::new(0.0, 10.0, 0.0));
        assert_close(positions[1], Vec3::new(0.0, 10.0, -5.0));
        // The rest pose ignores channels: OFFSETs only.
        let rest = world_positions(&skeleton, &[], OffsetMode::Replace);
        assert_close(rest[1], Vec3::new(5.0, 0.0, 0.0));
    }
}
