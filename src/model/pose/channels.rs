//! The rotation of one joint in one frame, as a matrix: each rotation channel, their product in
//! file order, and the joint's local rotation about its fixed axis.

use crate::model::skeleton::{Channel, Joint};
use glam::Mat4;

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
