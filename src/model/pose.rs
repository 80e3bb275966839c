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

use crate::model::skeleton::{Channel, Joint, Skeleton};
use glam::{Mat4, Vec3};

/// How a joint's position channels combine with its OFFSET.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OffsetMode {
    /// Position channels replace the matching OFFSET components (the article's
    /// `root->x = pFrame[0]`; Blender, bvhio).
    #[default]
    Replace,
    /// Position channels are added to the OFFSET (three.js; the paper's "OFFSET + translation").
    Add,
}

/// Which world axis points up in a file: BVH's usual Y, or Z as some exporters write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    #[default]
    Y,
    Z,
}

impl Up {
    /// The guess from the rest pose: Z when the skeleton stands clearly taller along Z than
    /// along Y (a figure is about as deep as it is wide, and much taller than either). The roots
    /// are left out: a root's child may be placed far away (Bandai's `joint_Root`), which says
    /// nothing about which way the body stands.
    pub fn guess(skeleton: &Skeleton) -> Up {
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

/// The joint whose position channels carry the take's travel across the floor: of the joints
/// with position channels, the one whose world path strays farthest (x and z) from where it
/// starts; the first root when none has position channels or none moves. Most files put the
/// travel on the root; some (Bandai's) on `Hips` under a root that stays put.
pub fn travel_joint(skeleton: &Skeleton, world: &[Vec3]) -> usize {
    let points = skeleton.joints.len();
    let root = skeleton.roots().next().unwrap_or(0);
    if points == 0 || world.is_empty() {
        return root;
    }
    let mut best = (root, 0.0f32);
    for (index, joint) in skeleton.joints.iter().enumerate() {
        if !joint.channels.iter().any(|c| c.is_position()) {
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

/// The rotation of one channel, as `glRotatef(degrees, axis)` makes it.
pub fn channel_rotation(channel: Channel, degrees: f32) -> Mat4 {
    let radians = degrees.to_radians();
    match channel.axis() {
        0 => Mat4::from_rotation_x(radians),
        1 => Mat4::from_rotation_y(radians),
        _ => Mat4::from_rotation_z(radians),
    }
}

/// `R1 · R2 · R3`: the joint's rotation channels in file order.
pub fn channel_rotations(joint: &Joint, values: &[f32]) -> Mat4 {
    let mut rotation = Mat4::IDENTITY;
    for (channel, &value) in joint.channels.iter().zip(values) {
        if channel.is_rotation() {
            rotation *= channel_rotation(*channel, value);
        }
    }
    rotation
}

/// A joint's rotation for one frame: `R1 · R2 · R3` of its channels, or `C · R1 · R2 · R3 · C⁻¹`
/// when it turns about a fixed axis C of its own (ASF bones); `values` are the joint's channel
/// values. Every matrix form of a joint's rotation is this one (the FK plan's quaternion lanes
/// compute the same product, and the draw issues it as GL calls).
pub fn local_rotation(joint: &Joint, values: &[f32]) -> Mat4 {
    let rotation = channel_rotations(joint, values);
    match joint.axis {
        None => rotation,
        Some(axis) => Mat4::from_quat(axis) * rotation * Mat4::from_quat(axis.inverse()),
    }
}

/// How a joint's local rotation is written as numbers (Python's `local_rotations(kind=…)`, the
/// dataset's `--rotations`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotationKind {
    /// (w, x, y, z), w ≥ 0.
    Quat,
    /// The 3 × 3 matrix, row after row.
    Matrix,
    /// The matrix's first two columns one after the other (Zhou et al. 2019).
    SixD,
    /// The joint's rotation channels in its file order, in degrees (0 past the ones it has).
    Euler,
    /// The rotation vector: the unit axis times the angle in radians (at most π).
    AxisAngle,
}

impl RotationKind {
    pub const NAMES: &'static str = "\"quat\", \"matrix\", \"6d\", \"euler\" or \"axis_angle\"";

    pub fn parse(text: &str) -> Option<RotationKind> {
        match text {
            "quat" => Some(RotationKind::Quat),
            "matrix" => Some(RotationKind::Matrix),
            "6d" => Some(RotationKind::SixD),
            "euler" => Some(RotationKind::Euler),
            "axis_angle" => Some(RotationKind::AxisAngle),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            RotationKind::Quat => "quat",
            RotationKind::Matrix => "matrix",
            RotationKind::SixD => "6d",
            RotationKind::Euler => "euler",
            RotationKind::AxisAngle => "axis_angle",
        }
    }

    /// Numbers per rotation.
    pub fn width(self) -> usize {
        match self {
            RotationKind::Quat => 4,
            RotationKind::Matrix => 9,
            RotationKind::SixD => 6,
            RotationKind::Euler | RotationKind::AxisAngle => 3,
        }
    }
}

/// The rotation matrix `kind` numbers stand for, as [`write_rotation`] writes them: a quaternion
/// normalised, a 6D pair made orthonormal again (Gram-Schmidt). `None` for Euler angles, whose
/// meaning is the joint's own channel order.
pub fn rotation_of_numbers(kind: RotationKind, numbers: &[f32]) -> Option<glam::Mat3> {
    match kind {
        RotationKind::Quat => Some(glam::Mat3::from_quat(
            glam::Quat::from_xyzw(numbers[1], numbers[2], numbers[3], numbers[0]).normalize(),
        )),
        RotationKind::Matrix => Some(glam::Mat3::from_cols_slice(numbers).transpose()),
        RotationKind::SixD => {
            let a = Vec3::new(numbers[0], numbers[1], numbers[2]).normalize_or_zero();
            let b = Vec3::new(numbers[3], numbers[4], numbers[5]);
            let b = (b - a * a.dot(b)).normalize_or_zero();
            Some(glam::Mat3::from_cols(a, b, a.cross(b)))
        }
        RotationKind::AxisAngle => {
            let vector = Vec3::new(numbers[0], numbers[1], numbers[2]);
            Some(glam::Mat3::from_quat(glam::Quat::from_scaled_axis(vector)))
        }
        RotationKind::Euler => None,
    }
}

/// Why `kind` numbers (finite ones) stand for no rotation, if they do not: a quaternion of
/// (nearly) zero length, which normalises to NaN; a matrix that is not a rotation (columns not
/// orthonormal within 1e-3, or a reflection); a 6D pair with a zero or parallel column. Euler
/// angles and rotation vectors always make a rotation.
pub fn rotation_numbers_problem(kind: RotationKind, numbers: &[f32]) -> Option<String> {
    // Shorter than this, a quaternion or a column is rounding noise, not a direction.
    const SHORTEST: f64 = 1e-6;
    const TOLERANCE: f64 = 1e-3;
    let length = |v: &[f32]| v.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt();
    match kind {
        RotationKind::Quat => {
            let length = length(&numbers[..4]);
            (length < SHORTEST).then(|| {
                format!("a quaternion of length {length:e} (zero or too small to normalise)")
            })
        }
        RotationKind::Matrix => {
            let m = |r: usize, c: usize| f64::from(numbers[r * 3 + c]);
            let mut worst: f64 = 0.0;
            for a in 0..3 {
                for b in 0..3 {
                    let dot: f64 = (0..3).map(|r| m(r, a) * m(r, b)).sum();
                    let want = if a == b { 1.0 } else { 0.0 };
                    worst = worst.max((dot - want).abs());
                }
            }
            let det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
                - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
                + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
            (worst > TOLERANCE || (det - 1.0).abs() > 3.0 * TOLERANCE).then(|| {
                format!(
                    "not a rotation matrix (determinant {det:.6}, columns orthonormal only \
                     within {worst:.2e}; a rotation's are within {TOLERANCE})"
                )
            })
        }
        RotationKind::SixD => {
            let a = Vec3::new(numbers[0], numbers[1], numbers[2]).as_dvec3();
            let b = Vec3::new(numbers[3], numbers[4], numbers[5]).as_dvec3();
            let (la, lb) = (a.length(), b.length());
            let apart = if la > 0.0 && lb > 0.0 {
                a.cross(b).length() / (la * lb)
            } else {
                0.0
            };
            (la < SHORTEST || lb < SHORTEST || apart < SHORTEST).then(|| {
                format!(
                    "a 6D pair whose columns are zero or parallel (lengths {la:e} and {lb:e}): \
                     no rotation"
                )
            })
        }
        RotationKind::Euler | RotationKind::AxisAngle => None,
    }
}

/// `joint`'s local rotation ([`local_rotation`]) for its channel `values` as `kind` numbers, into
/// `out` (`kind.width()` long). No values (an End Site, the rest pose): the identity.
pub fn write_rotation(joint: &Joint, values: &[f32], kind: RotationKind, out: &mut [f32]) {
    if kind == RotationKind::Euler {
        out.fill(0.0);
        let angles = joint
            .channels
            .iter()
            .zip(values)
            .filter(|(c, _)| c.is_rotation())
            .map(|(_, &v)| v);
        for (slot, angle) in out.iter_mut().zip(angles) {
            *slot = angle;
        }
        return;
    }
    let rotation = if values.is_empty() {
        Mat4::IDENTITY
    } else {
        local_rotation(joint, values)
    };
    let m = glam::Mat3::from_mat4(rotation);
    match kind {
        RotationKind::Quat => {
            let q = glam::Quat::from_mat3(&m).normalize();
            let q = if q.w < 0.0 { -q } else { q };
            out.copy_from_slice(&[q.w, q.x, q.y, q.z]);
        }
        RotationKind::Matrix => out.copy_from_slice(&m.transpose().to_cols_array()),
        RotationKind::AxisAngle => {
            // w ≥ 0 keeps the angle in [0, π]: the shorter of the two ways round.
            let q = glam::Quat::from_mat3(&m).normalize();
            let q = if q.w < 0.0 { -q } else { q };
            out.copy_from_slice(&q.to_scaled_axis().to_array());
        }
        _ => {
            let (a, b) = (m.x_axis, m.y_axis);
            out.copy_from_slice(&[a.x, a.y, a.z, b.x, b.y, b.z]);
        }
    }
}

/// A local rotation given as a quaternion, as `kind` numbers (not Euler angles, whose meaning is
/// a joint's channel order), into `out`: the same numbers [`write_rotation`] writes for it.
pub fn write_quat(q: glam::Quat, kind: RotationKind, out: &mut [f32]) {
    // w ≥ 0: one of the two quaternions of each rotation, and an angle in [0, π].
    let q = q.normalize();
    let q = if q.w < 0.0 { -q } else { q };
    match kind {
        RotationKind::Quat => out.copy_from_slice(&[q.w, q.x, q.y, q.z]),
        RotationKind::AxisAngle => out.copy_from_slice(&q.to_scaled_axis().to_array()),
        RotationKind::Matrix => {
            out.copy_from_slice(&glam::Mat3::from_quat(q).transpose().to_cols_array())
        }
        RotationKind::SixD => {
            let m = glam::Mat3::from_quat(q);
            let (a, b) = (m.x_axis, m.y_axis);
            out.copy_from_slice(&[a.x, a.y, a.z, b.x, b.y, b.z]);
        }
        RotationKind::Euler => unreachable!("Euler angles need the joint's channel order"),
    }
}

/// Every joint's local rotation as `kind` numbers for the MOTION rows `frames` of `motion`, into
/// `out` (frames × joints × `kind.width()`): what [`write_rotation`] writes joint by joint, made
/// from the FK plan's quaternions eight frames at a time (Euler angles, which are the channel
/// values themselves, and a take without frames go joint by joint).
pub fn write_local_rotations(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    frames: &[usize],
    kind: RotationKind,
    out: &mut [f32],
) {
    let (joints, width) = (skeleton.joints.len(), kind.width());
    if joints == 0 {
        return;
    }
    if kind == RotationKind::Euler || motion.frame_count() == 0 {
        for (&frame, out) in frames.iter().zip(out.chunks_mut(joints * width)) {
            for (joint, slot) in skeleton.joints.iter().zip(out.chunks_exact_mut(width)) {
                let values = match motion.frame_count() {
                    0 => &[][..],
                    _ => joint.values(motion.frame(frame)),
                };
                write_rotation(joint, values, kind, slot);
            }
        }
        return;
    }
    let plan = FkPlan::new(skeleton, OffsetMode::Replace);
    let (mut rotations, mut translations) = (Vec::new(), Vec::new());
    let mut scratch = FkScratch::default();
    let mut rows: Vec<&[f32]> = Vec::with_capacity(LANES);
    for (batch, out) in frames
        .chunks(LANES)
        .zip(out.chunks_mut(LANES * joints * width))
    {
        rows.clear();
        rows.extend(batch.iter().map(|&frame| motion.frame(frame)));
        plan.locals_of_frames(&rows, &mut rotations, &mut translations, &mut scratch);
        for (&q, slot) in rotations.iter().zip(out.chunks_exact_mut(width)) {
            write_quat(q, kind, slot);
        }
    }
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
    use crate::model::skeleton::Channel::*;

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

/// `(sin, cos)` of an angle in degrees: reduced to a quadrant, then polynomials good to about
/// 1e-7 (a float's own precision), exact at multiples of 90°. Much faster than two libm calls.
#[inline]
pub fn sin_cos_degrees(degrees: f32) -> (f32, f32) {
    if degrees.abs() >= 1.0e6 {
        return degrees.to_radians().sin_cos();
    }
    sin_cos_lane(degrees)
}

/// The reduction and polynomials of `sin_cos_degrees`, without branches, so a loop over many
/// angles becomes SIMD code: rounding by the 1.5·2²³ trick and the quadrant picked with selects.
/// For |degrees| < 10⁶.
#[inline(always)]
fn sin_cos_lane(degrees: f32) -> (f32, f32) {
    const ROUND: f32 = 12_582_912.0;
    let quadrant = (degrees * (1.0 / 90.0) + ROUND) - ROUND;
    let r = (degrees - quadrant * 90.0) * (std::f32::consts::PI / 180.0);
    let r2 = r * r;
    let sin = r
        * (1.0
            + r2 * (-1.0 / 6.0
                + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 * (1.0 / 362_880.0)))));
    let cos = 1.0
        + r2 * (-0.5
            + r2 * (1.0 / 24.0
                + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40_320.0 + r2 * (-1.0 / 3_628_800.0)))));
    let k = (quadrant as i32) & 3;
    let (s1, c1) = if k & 1 != 0 { (cos, -sin) } else { (sin, cos) };
    if k & 2 != 0 { (-s1, -c1) } else { (s1, c1) }
}

#[inline(always)]
fn sin_cos_batch_impl(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    for ((&a, s), c) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
        (*s, *c) = sin_cos_lane(a);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn sin_cos_batch_avx2(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    sin_cos_batch_impl(angles, sin, cos)
}

/// `sin_cos_degrees` of every angle: eight at a time where the CPU has AVX2, four otherwise.
pub fn sin_cos_batch(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    if angles.iter().any(|a| a.abs() >= 1.0e6) {
        for ((&a, s), c) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
            (*s, *c) = sin_cos_degrees(a);
        }
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has just been found to support AVX2.
        unsafe { sin_cos_batch_avx2(angles, sin, cos) };
        return;
    }
    sin_cos_batch_impl(angles, sin, cos)
}

/// One joint, ready for fast FK: where its values are and what they do.
#[derive(Clone, Debug)]
struct PlannedJoint {
    parent: Option<usize>,
    offset: Vec3,
    /// (axis, column) of each position channel: a range of the plan's flat position list.
    positions: std::ops::Range<usize>,
    /// Its rotation channels: a range of the plan's flat rotation lists.
    rotations: std::ops::Range<usize>,
    axis: Option<glam::Quat>,
}

/// Forward kinematics compiled for one skeleton: the same products as [`world_matrices`], kept
/// as quaternion + translation, for exporting every frame of long takes fast.
#[derive(Clone, Debug)]
pub struct FkPlan {
    joints: Vec<PlannedJoint>,
    /// Every position channel, joint after joint: (axis, column).
    position_channels: Vec<(usize, usize)>,
    /// Every rotation channel, joint after joint: its column and axis.
    rotation_columns: Vec<usize>,
    rotation_axes: Vec<usize>,
    mode: OffsetMode,
}

/// Frames computed side by side: lane `l` of every value belongs to the batch's frame `l`.
pub const LANES: usize = 8;
type Lanes = [f32; LANES];

#[inline(always)]
fn lanes(f: impl FnMut(usize) -> f32) -> Lanes {
    std::array::from_fn(f)
}

/// A quaternion per lane.
#[derive(Clone, Copy, Debug)]
struct QuatLanes {
    x: Lanes,
    y: Lanes,
    z: Lanes,
    w: Lanes,
}

/// A point per lane.
#[derive(Clone, Copy, Debug)]
struct PointLanes {
    x: Lanes,
    y: Lanes,
    z: Lanes,
}

impl PointLanes {
    const ORIGIN: PointLanes = PointLanes {
        x: [0.0; LANES],
        y: [0.0; LANES],
        z: [0.0; LANES],
    };
}

impl QuatLanes {
    fn splat(q: glam::Quat) -> QuatLanes {
        QuatLanes {
            x: [q.x; LANES],
            y: [q.y; LANES],
            z: [q.z; LANES],
            w: [q.w; LANES],
        }
    }

    /// The rotation of `(s, c)` (sine and cosine of half the angle) about one axis.
    #[inline(always)]
    fn about_axis(axis: usize, s: &Lanes, c: &Lanes) -> QuatLanes {
        let zero = [0.0; LANES];
        match axis {
            0 => QuatLanes {
                x: *s,
                y: zero,
                z: zero,
                w: *c,
            },
            1 => QuatLanes {
                x: zero,
                y: *s,
                z: zero,
                w: *c,
            },
            _ => QuatLanes {
                x: zero,
                y: zero,
                z: *s,
                w: *c,
            },
        }
    }

    /// `self · (axis · s, c)`: half the work of a full product, the zeros of the axis left out.
    #[inline(always)]
    fn times_axis(self, axis: usize, s: &Lanes, c: &Lanes) -> QuatLanes {
        let QuatLanes { x, y, z, w } = self;
        match axis {
            0 => QuatLanes {
                x: lanes(|l| w[l] * s[l] + x[l] * c[l]),
                y: lanes(|l| y[l] * c[l] + z[l] * s[l]),
                z: lanes(|l| z[l] * c[l] - y[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - x[l] * s[l]),
            },
            1 => QuatLanes {
                x: lanes(|l| x[l] * c[l] - z[l] * s[l]),
                y: lanes(|l| w[l] * s[l] + y[l] * c[l]),
                z: lanes(|l| z[l] * c[l] + x[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - y[l] * s[l]),
            },
            _ => QuatLanes {
                x: lanes(|l| x[l] * c[l] + y[l] * s[l]),
                y: lanes(|l| y[l] * c[l] - x[l] * s[l]),
                z: lanes(|l| w[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - z[l] * s[l]),
            },
        }
    }

    /// The Hamilton product `self · b`.
    #[inline(always)]
    fn times(self, b: QuatLanes) -> QuatLanes {
        let a = self;
        QuatLanes {
            x: lanes(|l| a.w[l] * b.x[l] + a.x[l] * b.w[l] + a.y[l] * b.z[l] - a.z[l] * b.y[l]),
            y: lanes(|l| a.w[l] * b.y[l] - a.x[l] * b.z[l] + a.y[l] * b.w[l] + a.z[l] * b.x[l]),
            z: lanes(|l| a.w[l] * b.z[l] + a.x[l] * b.y[l] - a.y[l] * b.x[l] + a.z[l] * b.w[l]),
            w: lanes(|l| a.w[l] * b.w[l] - a.x[l] * b.x[l] - a.y[l] * b.y[l] - a.z[l] * b.z[l]),
        }
    }

    /// `v` turned by this (unit) quaternion: `v + w·t + q×t` with `t = 2·(q×v)`.
    #[inline(always)]
    fn rotate(self, v: PointLanes) -> PointLanes {
        let QuatLanes { x, y, z, w } = self;
        let tx = lanes(|l| 2.0 * (y[l] * v.z[l] - z[l] * v.y[l]));
        let ty = lanes(|l| 2.0 * (z[l] * v.x[l] - x[l] * v.z[l]));
        let tz = lanes(|l| 2.0 * (x[l] * v.y[l] - y[l] * v.x[l]));
        PointLanes {
            x: lanes(|l| v.x[l] + w[l] * tx[l] + (y[l] * tz[l] - z[l] * ty[l])),
            y: lanes(|l| v.y[l] + w[l] * ty[l] + (z[l] * tx[l] - x[l] * tz[l])),
            z: lanes(|l| v.z[l] + w[l] * tz[l] + (x[l] * ty[l] - y[l] * tx[l])),
        }
    }
}

/// Buffers one thread reuses from batch to batch.
#[derive(Clone, Debug, Default)]
pub struct FkScratch {
    half_angles: Vec<f32>,
    sin: Vec<f32>,
    cos: Vec<f32>,
    rotations: Vec<QuatLanes>,
    points: Vec<PointLanes>,
    local_rotations: Vec<QuatLanes>,
    local_points: Vec<PointLanes>,
}

impl FkPlan {
    pub fn new(skeleton: &Skeleton, mode: OffsetMode) -> FkPlan {
        let mut rotation_columns = Vec::new();
        let mut rotation_axes = Vec::new();
        let mut position_channels = Vec::new();
        let joints = skeleton
            .joints
            .iter()
            .map(|joint| {
                let columns: Vec<(Channel, usize)> = joint
                    .channels
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| (c, joint.first_channel + i))
                    .collect();
                let first = rotation_columns.len();
                for &(c, column) in columns.iter().filter(|(c, _)| c.is_rotation()) {
                    rotation_columns.push(column);
                    rotation_axes.push(c.axis());
                }
                let first_position = position_channels.len();
                position_channels.extend(
                    columns
                        .iter()
                        .filter(|(c, _)| c.is_position())
                        .map(|&(c, i)| (c.axis(), i)),
                );
                PlannedJoint {
                    parent: joint.parent,
                    offset: joint.offset,
                    positions: first_position..position_channels.len(),
                    rotations: first..rotation_columns.len(),
                    axis: joint.axis,
                }
            })
            .collect();
        FkPlan {
            joints,
            position_channels,
            rotation_columns,
            rotation_axes,
            mode,
        }
    }

    /// World position of every joint for one MOTION row, into `out` (one per joint).
    pub fn positions(&self, frame: &[f32], out: &mut Vec<Vec3>, scratch: &mut FkScratch) {
        self.positions_of_frames(&[frame], out, scratch);
    }

    /// World positions of every joint for up to [`LANES`] MOTION rows at once, into `out`
    /// (frame after frame, one point per joint). Each frame is a lane of the same vector
    /// operations, so a batch costs little more than one frame.
    pub fn positions_of_frames(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.lanes_avx2(frames, out, scratch) };
            return;
        }
        self.lanes_impl(frames, out, scratch)
    }

    /// [`FkPlan::positions_of_frames`] without AVX2 even where the CPU has it: the path every
    /// other CPU takes, so that tests check it on any machine.
    pub fn positions_of_frames_portable(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        self.lanes_impl(frames, out, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn lanes_avx2(&self, frames: &[&[f32]], out: &mut Vec<Vec3>, scratch: &mut FkScratch) {
        self.lanes_impl(frames, out, scratch)
    }

    #[inline(always)]
    fn lanes_impl(&self, frames: &[&[f32]], out: &mut Vec<Vec3>, scratch: &mut FkScratch) {
        self.local_lanes(frames, scratch);
        self.world_lanes(scratch, false);
        out.clear();
        let points = &scratch.points[..self.joints.len()];
        for l in 0..frames.len() {
            out.extend(points.iter().map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])));
        }
    }

    /// Each joint's local rotation and translation for up to [`LANES`] MOTION rows (the first
    /// half of [`FkPlan::positions_of_frames`]), into `rotations` and `translations`: frame after
    /// frame, one per joint, the identity where a joint has no rotation channel. A fixed axis C
    /// (ASF bones) is in the rotation already: `C · R1 · R2 · R3 · C⁻¹`.
    pub fn locals_of_frames(
        &self,
        frames: &[&[f32]],
        rotations: &mut Vec<glam::Quat>,
        translations: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.locals_avx2(frames, scratch) };
        } else {
            self.local_lanes(frames, scratch);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.local_lanes(frames, scratch);
        rotations.clear();
        translations.clear();
        let count = self.joints.len();
        for l in 0..frames.len() {
            rotations.extend(
                scratch.local_rotations[..count]
                    .iter()
                    .map(|q| glam::Quat::from_xyzw(q.x[l], q.y[l], q.z[l], q.w[l])),
            );
            translations.extend(
                scratch.local_points[..count]
                    .iter()
                    .map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])),
            );
        }
    }

    /// World positions from local rotations and translations (the second half of
    /// [`FkPlan::positions_of_frames`]): `rotations` and `translations` hold up to [`LANES`]
    /// frames, one per joint of this plan's skeleton each; `out` gets one point per joint, frame
    /// after frame. Every rotation given is applied, the identity included.
    pub fn positions_of_locals(
        &self,
        rotations: &[glam::Quat],
        translations: &[Vec3],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        let count = self.joints.len();
        let frames = rotations.len() / count.max(1);
        assert!(
            (1..=LANES).contains(&frames)
                && rotations.len() == frames * count
                && translations.len() == rotations.len(),
            "1 to {LANES} frames of every joint at a time"
        );
        // A short batch repeats its last frame in the spare lanes.
        let lane = |l: usize, j: usize| l.min(frames - 1) * count + j;
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.local_rotations.resize(count, identity);
        scratch.local_points.resize(count, PointLanes::ORIGIN);
        for j in 0..count {
            let q: [glam::Quat; LANES] = std::array::from_fn(|l| rotations[lane(l, j)]);
            scratch.local_rotations[j] = QuatLanes {
                x: q.map(|q| q.x),
                y: q.map(|q| q.y),
                z: q.map(|q| q.z),
                w: q.map(|q| q.w),
            };
            let t: [Vec3; LANES] = std::array::from_fn(|l| translations[lane(l, j)]);
            scratch.local_points[j] = PointLanes {
                x: t.map(|t| t.x),
                y: t.map(|t| t.y),
                z: t.map(|t| t.z),
            };
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.world_avx2(scratch) };
        } else {
            self.world_lanes(scratch, true);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.world_lanes(scratch, true);
        out.clear();
        let points = &scratch.points[..count];
        for l in 0..frames {
            out.extend(points.iter().map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])));
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn locals_avx2(&self, frames: &[&[f32]], scratch: &mut FkScratch) {
        self.local_lanes(frames, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn world_avx2(&self, scratch: &mut FkScratch) {
        self.world_lanes(scratch, true)
    }

    /// Every joint's local rotation and translation for the rows of one batch, into the
    /// scratch's `local_rotations` and `local_points`.
    #[inline(always)]
    fn local_lanes(&self, frames: &[&[f32]], scratch: &mut FkScratch) {
        // A short batch repeats its last frame in the spare lanes.
        let rows: [&[f32]; LANES] = std::array::from_fn(|l| frames[l.min(frames.len() - 1)]);
        let frame = |l: usize| rows[l];
        // Every rotation's half angle, then all their sines and cosines in one vector loop. The
        // angles are gathered into a buffer of the right size by index: extending it value by
        // value cost as much as the sines and cosines.
        let n = self.rotation_columns.len() * LANES;
        scratch.half_angles.resize(n, 0.0);
        for (lanes, &column) in scratch
            .half_angles
            .chunks_exact_mut(LANES)
            .zip(&self.rotation_columns)
        {
            for (value, row) in lanes.iter_mut().zip(&rows) {
                *value = row[column] * 0.5;
            }
        }
        scratch.sin.resize(n, 0.0);
        scratch.cos.resize(n, 0.0);
        sin_cos_batch(&scratch.half_angles, &mut scratch.sin, &mut scratch.cos);
        let count = self.joints.len();
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.local_rotations.resize(count, identity);
        scratch.local_points.resize(count, PointLanes::ORIGIN);
        let sines: &[Lanes] = as_lanes(&scratch.sin);
        let cosines: &[Lanes] = as_lanes(&scratch.cos);
        for (index, joint) in self.joints.iter().enumerate() {
            let mut t = [joint.offset.x, joint.offset.y, joint.offset.z].map(|v| [v; LANES]);
            for &(axis, column) in &self.position_channels[joint.positions.clone()] {
                for (l, value) in t[axis].iter_mut().enumerate() {
                    match self.mode {
                        OffsetMode::Replace => *value = frame(l)[column],
                        OffsetMode::Add => *value += frame(l)[column],
                    }
                }
            }
            scratch.local_points[index] = PointLanes {
                x: t[0],
                y: t[1],
                z: t[2],
            };
            // A rotation of θ about an axis is the quaternion (axis · sin θ/2, cos θ/2); each
            // later channel multiplies on the right.
            let mut rotation: Option<QuatLanes> = None;
            for i in joint.rotations.clone() {
                let (s, c, axis) = (&sines[i], &cosines[i], self.rotation_axes[i]);
                rotation = Some(match rotation {
                    None => QuatLanes::about_axis(axis, s, c),
                    Some(q) => q.times_axis(axis, s, c),
                });
            }
            if let (Some(axis), Some(r)) = (joint.axis, rotation) {
                rotation = Some(
                    QuatLanes::splat(axis)
                        .times(r)
                        .times(QuatLanes::splat(axis.conjugate())),
                );
            }
            scratch.local_rotations[index] = rotation.unwrap_or(identity);
        }
    }

    /// World rotations and points of every joint from the scratch's local ones, into its
    /// `rotations` and `points`. A joint without rotation channels takes its parent's rotation
    /// as it is, unless `every_rotation` says its local one (given from outside) counts too.
    #[inline(always)]
    fn world_lanes(&self, scratch: &mut FkScratch, every_rotation: bool) {
        let count = self.joints.len();
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.rotations.resize(count, identity);
        scratch.points.resize(count, PointLanes::ORIGIN);
        let (points, rotations) = (
            &mut scratch.points[..count],
            &mut scratch.rotations[..count],
        );
        let (local_points, local_rotations) = (
            &scratch.local_points[..count],
            &scratch.local_rotations[..count],
        );
        for (index, joint) in self.joints.iter().enumerate() {
            let (t, rotation) = (local_points[index], local_rotations[index]);
            let rotates = every_rotation || !joint.rotations.is_empty();
            let (world_rotation, world_point) = match joint.parent {
                Some(parent) => {
                    let (parent_rotation, parent_point) = (rotations[parent], points[parent]);
                    let moved = parent_rotation.rotate(t);
                    let point = PointLanes {
                        x: lanes(|l| parent_point.x[l] + moved.x[l]),
                        y: lanes(|l| parent_point.y[l] + moved.y[l]),
                        z: lanes(|l| parent_point.z[l] + moved.z[l]),
                    };
                    let rotation = match rotates {
                        true => parent_rotation.times(rotation),
                        false => parent_rotation,
                    };
                    (rotation, point)
                }
                None => (rotation, t),
            };
            rotations[index] = world_rotation;
            points[index] = world_point;
        }
    }
}

/// A flat list of values as lanes (its length is a multiple of [`LANES`]).
fn as_lanes(values: &[f32]) -> &[Lanes] {
    let (lanes, rest) = values.as_chunks::<LANES>();
    debug_assert!(rest.is_empty());
    lanes
}

/// Forward kinematics of every frame on every core; returns the sum of all coordinates (so the
/// work cannot be skipped, and as a checksum).
pub fn positions_all_frames(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    mode: OffsetMode,
) -> f64 {
    let plan = FkPlan::new(skeleton, mode);
    let frames = motion.frame_count();
    // Pieces of a few thousand frames, taken in turn by every core.
    const PIECE: usize = 4096;
    let mut total = 0.0f64;
    crate::io::parallel::map_in_order(
        frames.div_ceil(PIECE),
        crate::io::parallel::cores(),
        2 * crate::io::parallel::cores(),
        |piece| {
            let (mut out, mut scratch) = (Vec::new(), FkScratch::default());
            let mut sum = 0.0f64;
            let mine = piece * PIECE..((piece + 1) * PIECE).min(frames);
            let mut batch: Vec<&[f32]> = Vec::with_capacity(LANES);
            for first in mine.clone().step_by(LANES) {
                batch.clear();
                batch.extend((first..(first + LANES).min(mine.end)).map(|f| motion.frame(f)));
                plan.positions_of_frames(&batch, &mut out, &mut scratch);
                for points in out.chunks(plan.joints.len()) {
                    let sum_of_points: Vec3 = points.iter().copied().sum();
                    sum += f64::from(sum_of_points.x + sum_of_points.y + sum_of_points.z);
                }
            }
            sum
        },
        |_, sum| {
            total += sum;
            true
        },
    );
    total
}

#[cfg(test)]
mod fast_tests {
    use super::*;

    #[test]
    fn sin_cos_degrees_matches_libm() {
        let mut worst = 0.0f32;
        let mut degrees = -1000.0f32;
        while degrees < 1000.0 {
            let (s, c) = sin_cos_degrees(degrees);
            let (rs, rc) = (degrees as f64).to_radians().sin_cos();
            worst = worst
                .max((s as f64 - rs).abs() as f32)
                .max((c as f64 - rc).abs() as f32);
            degrees += 0.0137;
        }
        assert!(worst < 3e-7, "worst error {worst}");
        assert_eq!(sin_cos_degrees(90.0), (1.0, 0.0));
        let angles: Vec<f32> = (0..1000).map(|i| i as f32 * 0.731 - 365.0).collect();
        let (mut s, mut c) = (vec![0.0; 1000], vec![0.0; 1000]);
        sin_cos_batch(&angles, &mut s, &mut c);
        for (i, &a) in angles.iter().enumerate() {
            let (rs, rc) = (a as f64).to_radians().sin_cos();
            assert!(
                (s[i] as f64 - rs).abs() < 3e-7 && (c[i] as f64 - rc).abs() < 3e-7,
                "{a}"
            );
        }
        assert_eq!(sin_cos_degrees(-180.0), (0.0, -1.0));
    }

    #[test]
    fn local_rotations_by_the_plan_match_joint_by_joint_on_real_files() {
        let mut worst: f32 = 0.0;
        for entry in std::fs::read_dir("tests/data/bvh").unwrap() {
            let path = entry.unwrap().path();
            let Ok(bvh) = crate::bvh::load_file(&path, Default::default()) else {
                continue;
            };
            let (skeleton, motion) = (&bvh.skeleton, &bvh.motion);
            let frames: Vec<usize> = (0..motion.frame_count()).step_by(7).collect();
            for kind in [
                RotationKind::Quat,
                RotationKind::Matrix,
                RotationKind::SixD,
                RotationKind::AxisAngle,
                RotationKind::Euler,
            ] {
                let (joints, width) = (skeleton.joints.len(), kind.width());
                let mut fast = vec![0.0; frames.len() * joints * width];
                write_local_rotations(skeleton, motion, &frames, kind, &mut fast);
                let mut slot = vec![0.0; width];
                for (k, &frame) in frames.iter().enumerate() {
                    for (j, joint) in skeleton.joints.iter().enumerate() {
                        write_rotation(joint, joint.values(motion.frame(frame)), kind, &mut slot);
                        let got = &fast[(k * joints + j) * width..][..width];
                        if kind == RotationKind::Euler {
                            assert_eq!(got, &slot[..], "{}", path.display());
                            continue;
                        }
                        let (a, b) = (
                            rotation_of_numbers(kind, got).unwrap(),
                            rotation_of_numbers(kind, &slot).unwrap(),
                        );
                        for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
                            worst = worst.max((x - y).abs());
                        }
                    }
                }
            }
        }
        assert!(worst < 1e-5, "worst matrix element apart: {worst}");
    }

    #[test]
    fn plan_matches_world_matrices_on_real_files_on_both_paths() {
        // The repository's own corpus: mixed orders, position channels on 143 joints, CR endings,
        // and a CMU ASF/AMC pair whose bones turn about their own axes (the C·R·C⁻¹ step).
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let mut inputs: Vec<(String, Skeleton, crate::model::motion::Motion)> = [
            "bvh11_131_01.bvh",
            "makehuman_tpose.bvh",
            "opencollar_run.bvh",
        ]
        .iter()
        .map(|name| {
            let bvh =
                crate::bvh::load_file(&data.join("bvh").join(name), Default::default()).unwrap();
            (name.to_string(), bvh.skeleton, bvh.motion)
        })
        .collect();
        let asf = data.join("asf_amc/heiden_12.asf");
        let amc = data.join("asf_amc/heiden_12_02_01.amc");
        let cmu = crate::take::load(&asf, Some(&amc), None).unwrap();
        let turned = cmu.skeleton.joints.iter().filter(|j| {
            j.axis
                .is_some_and(|a| a.angle_between(glam::Quat::IDENTITY) > 0.1)
        });
        assert!(turned.count() >= 10, "bones with an axis of their own");
        inputs.push(("heiden_12_02_01.amc".to_string(), cmu.skeleton, cmu.motion));

        for (name, skeleton, motion) in &inputs {
            for mode in [OffsetMode::Replace, OffsetMode::Add] {
                let plan = FkPlan::new(skeleton, mode);
                let (mut out, mut scratch, mut matrices) =
                    (Vec::new(), FkScratch::default(), Vec::new());
                let last = motion.frame_count() - 1;
                // One frame, and a batch of eight (a lane each), on the dispatching and the
                // portable path.
                let batch: Vec<usize> = (0..LANES).map(|i| i * last / (LANES - 1)).collect();
                for (path, frames) in [("one", vec![last / 2]), ("eight", batch)] {
                    let rows: Vec<&[f32]> = frames.iter().map(|&f| motion.frame(f)).collect();
                    for portable in [false, true] {
                        if portable {
                            plan.positions_of_frames_portable(&rows, &mut out, &mut scratch);
                        } else {
                            plan.positions_of_frames(&rows, &mut out, &mut scratch);
                        }
                        for (lane, row) in rows.iter().enumerate() {
                            world_matrices(skeleton, row, mode, &mut matrices);
                            let points = &out[lane * matrices.len()..][..matrices.len()];
                            for (p, m) in points.iter().zip(&matrices) {
                                let q = m.w_axis.truncate();
                                assert!(
                                    p.distance(q) <= 1e-5 * q.length().max(10.0),
                                    "{name} {path} portable {portable} lane {lane}: {p} vs {q}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
