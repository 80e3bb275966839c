//! ASF/AMC (Acclaim; the CMU motion database): an ASF file holds the skeleton, an AMC file the
//! frames. Both become the same [`Skeleton`] + [`Motion`] as a BVH file (seed 004, DESIGN.md
//! decision 7):
//!
//! - the root is a joint at `:root position` with the channels of its `order`;
//! - every bone is a joint at the *start* of the bone, offset from its parent joint by the parent
//!   bone's `direction × length` (zero under the root), turning about its fixed `axis` C:
//!   local = T · C · M · C⁻¹, where M applies the `dof` rotations in the order listed (`rx ry rz`
//!   gives M = Rz · Ry · Rx, seed 004's `cal_global_coord`);
//! - a bone without children ends in an End Site at its own `direction × length`.
//!
//! So the channels of a joint are the dof rotations in reverse (`Zrotation Yrotation Xrotation`
//! for `rx ry rz`), because a [`Skeleton`]'s channels multiply in file order.

pub mod amc;
pub mod asf;
mod text;

pub use amc::load_amc;
pub use asf::{Asf, load_asf};

use crate::motion::Motion;
use crate::pose::channel_rotations;
use crate::skeleton::{Channel, Joint, RotationOrder, Skeleton};
use glam::{EulerRot, Mat4, Quat};

/// CMU captures at 120 frames per second; AMC files do not say.
pub const DEFAULT_FRAME_TIME: f64 = 1.0 / 120.0;

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
                let mut rotation = channel_rotations(joint, values);
                if let Some(axis) = joint.axis {
                    rotation = Mat4::from_quat(axis) * rotation * Mat4::from_quat(axis.inverse());
                }
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

/// C for an `axis a b c ORDER` (or the root's `orientation` with its `axis ORDER`): the
/// rotations applied in the order the letters say, so `XYZ` gives Rz · Ry · Rx (seed 004).
pub fn axis_rotation(degrees: [f64; 3], order: [usize; 3]) -> Quat {
    let mut rotation = Quat::IDENTITY;
    for &axis in &order {
        let angle = (degrees[axis] as f32).to_radians();
        let step = match axis {
            0 => Quat::from_rotation_x(angle),
            1 => Quat::from_rotation_y(angle),
            _ => Quat::from_rotation_z(angle),
        };
        // Each later rotation is applied after (outside) the earlier ones.
        rotation = step * rotation;
    }
    rotation
}

/// The joint a bone becomes (without its place in the tree).
pub(crate) fn bone_joint(name: &str, axis: Option<Quat>) -> Joint {
    let mut joint = Joint::new(name.to_string(), None);
    joint.axis = axis.filter(|q| !q.abs_diff_eq(Quat::IDENTITY, 1e-7));
    joint
}
