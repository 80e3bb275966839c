//! Forward kinematics: the one place where joint matrices and world positions are computed.
//!
//! A joint's local matrix is `T(t) · R1 · R2 · R3`: one translation, then its rotation channels in
//! the order the file lists them, in degrees. This is the product the article's `drawRecursive`
//! builds on the GL matrix stack (`glTranslatef`, then one `glRotatef` per channel), and the one
//! the renderer's draw issues call for call; the world matrix is the parent's world times local.

use crate::skeleton::{Channel, Joint, Skeleton};
use glam::{Mat4, Vec3};

/// How a joint's position channels combine with its OFFSET.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum OffsetMode {
    /// Position channels replace the matching OFFSET components (the article's
    /// `root->x = pFrame[0]`; Blender, bvhio).
    #[default]
    Replace,
    /// Position channels are added to the OFFSET (three.js; the paper's "OFFSET + translation").
    Add,
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

/// `T(t) · R1 · R2 · R3` for one joint, or `T(t) · C · R1 · R2 · R3 · C⁻¹` when the joint has a
/// fixed axis C (ASF bones); `values` are this joint's channel values.
pub fn local_matrix(joint: &Joint, values: &[f32], mode: OffsetMode) -> Mat4 {
    let translation = Mat4::from_translation(joint_translation(joint, values, mode));
    let rotation = channel_rotations(joint, values);
    match joint.axis {
        None => translation * rotation,
        Some(axis) => {
            translation * Mat4::from_quat(axis) * rotation * Mat4::from_quat(axis.inverse())
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::Channel::*;

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
