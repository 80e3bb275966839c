//! Edits that map a skeleton and its motion to new ones.

use crate::motion::Motion;
use crate::pose::local_rotation;
use crate::skeleton::{Channel, RotationOrder, Skeleton};
use glam::{EulerRot, Quat};

/// A BVH-ready copy: every fixed axis baked into the rotation channels, as BVH has no axis.
/// Each joint with an axis or with rotation channels gets `Zrotation Yrotation Xrotation` holding
/// the Euler angles of C · M · C⁻¹ (M for the root includes its orientation); position channels
/// stay as they are. World positions are unchanged up to float rounding.
pub fn bake_axes(skeleton: &Skeleton, motion: &Motion) -> (Skeleton, Motion) {
    let mut baked = Skeleton {
        joints: Vec::with_capacity(skeleton.joints.len()),
        source: skeleton.source,
    };
    let mut column = 0;
    for joint in &skeleton.joints {
        let mut copy = joint.clone();
        copy.axis = None;
        copy.first_channel = column;
        let rotates = joint.channels.iter().any(|c| c.is_rotation());
        copy.channels = joint
            .channels
            .iter()
            .copied()
            .filter(|c| c.is_position())
            .collect();
        if rotates && !joint.end_site {
            copy.channels
                .extend([Channel::Zrotation, Channel::Yrotation, Channel::Xrotation]);
        }
        copy.rotation_order = RotationOrder::get_flags(&copy.channels);
        column += copy.channels.len();
        baked.joints.push(copy);
    }
    let channels = column;
    let frames = motion.frame_count();
    let mut data = Vec::with_capacity(frames * channels);
    for frame in 0..frames {
        let row = motion.frame(frame);
        for (joint, copy) in skeleton.joints.iter().zip(&baked.joints) {
            let values = joint.values(row);
            for (channel, &value) in joint.channels.iter().zip(values) {
                if channel.is_position() {
                    data.push(value);
                }
            }
            if copy.channels.iter().any(|c| c.is_rotation()) {
                let rotation = local_rotation(joint, values);
                let (z, y, x) = Quat::from_mat4(&rotation).to_euler(EulerRot::ZYX);
                data.extend([z.to_degrees(), y.to_degrees(), x.to_degrees()]);
            }
        }
    }
    (
        baked,
        Motion::new(motion.frame_time, channels, frames, data),
    )
}
