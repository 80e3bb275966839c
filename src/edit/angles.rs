//! Rotations into channel angles: fixed bone axes baked into BVH channels, and the angles of
//! rotations given as numbers (quaternions, matrices, 6D) in a joint's own channel order.

use crate::edit::finite;
use crate::io::error::Error;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, RotationOrder, Skeleton};
use glam::DQuat;

/// A BVH-ready copy: every fixed axis baked into the rotation channels, as BVH has no axis.
/// Each joint with an axis or with rotation channels gets `Zrotation Yrotation Xrotation` holding
/// the Euler angles of C · M · C⁻¹ (M for the root includes its orientation); position channels
/// stay as they are. World positions are unchanged up to float rounding.
pub fn bake_axes(skeleton: &Skeleton, motion: &Motion) -> Result<(Skeleton, Motion), Error> {
    let mut baked = Skeleton {
        joints: Vec::with_capacity(skeleton.joints.len()),
        source: skeleton.source,
        y_up_stated: skeleton.y_up_stated,
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
                let rotation = crate::model::pose::local_rotation_f64(joint, values);
                data.extend(euler::split_degrees(rotation, RotationOrder::Zyx));
            }
        }
    }
    finite(
        "baking the bone axes",
        baked,
        Motion::new(motion.frame_time, channels, frames, data),
    )
}

/// The values of `joint`'s rotation channels, in file order and degrees, for a local rotation
/// given as `kind` (`numbers`: 4, 9, 6 or 3 of them; euler: the channel values themselves).
pub fn channel_angles(
    joint: &crate::Joint,
    kind: crate::model::pose::RotationKind,
    numbers: &[f32],
) -> Vec<f32> {
    let axes: Vec<usize> = joint
        .channels
        .iter()
        .filter(|c| c.is_rotation())
        .map(|c| c.axis())
        .collect();
    if axes.is_empty() {
        return Vec::new();
    }
    let Some(local) = crate::model::pose::rotation_of_numbers(kind, numbers) else {
        // Euler angles are the channel values themselves.
        return numbers.iter().copied().take(axes.len()).collect();
    };
    // An ASF bone turns about its own axis C: its channels' rotation is C⁻¹ · local · C.
    let local = DQuat::from_mat3(&local.as_dmat3());
    let rotation = match joint.axis {
        Some(c) => {
            let c = c.as_dquat().normalize();
            c.inverse() * local * c
        }
        None => local,
    };
    // The channels' axes, then any missing, as one intrinsic sequence: R1 · R2 · R3.
    let mut order = axes.clone();
    for axis in 0..3 {
        if !order.contains(&axis) {
            order.push(axis);
        }
    }
    let Some(order) = RotationOrder::from_axes([order[0], order[1], order[2]]) else {
        // The same axis twice: no sequence of three distinct axes; left at 0.
        return vec![0.0; axes.len()];
    };
    let [a, b, c] = euler::split(rotation, order, None);
    // The same rotation is also (a + π, π − b, c + π): with fewer than three channels the third
    // angle is dropped, so take the form whose third angle is the smaller (a joint bent past 90°
    // about its second axis needs the second form).
    let pi = std::f64::consts::PI;
    let wrap = |angle: f64| {
        if angle > pi {
            angle - 2.0 * pi
        } else if angle <= -pi {
            angle + 2.0 * pi
        } else {
            angle
        }
    };
    let other = [wrap(a + pi), wrap(pi - b), wrap(c + pi)];
    let angles = if axes.len() < 3 && other[2].abs() < c.abs() {
        other
    } else {
        [a, b, c]
    };
    angles
        .into_iter()
        .take(axes.len())
        .map(|angle| angle.to_degrees() as f32)
        .collect()
}

/// The take as BVH can hold it: `None` when no joint has a fixed bone axis (the take is
/// BVH-ready as it is), else [`bake_axes`]' copy. Every BVH writer goes through here.
pub fn baked_for_bvh(
    skeleton: &Skeleton,
    motion: &Motion,
) -> Result<Option<(Skeleton, Motion)>, Error> {
    skeleton
        .joints
        .iter()
        .any(|j| j.axis.is_some())
        .then(|| bake_axes(skeleton, motion))
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::resample;
    use crate::edit::testing::*;

    /// Every order, at exactly ±90° of its middle axis and at 89.99°: what an edit writes turns
    /// the joint as the file did (glam's 32-bit `to_euler` was 6e-4 rad off at 89.99°).
    #[test]
    fn edits_split_rotations_exactly_at_and_near_the_lock() {
        use crate::model::skeleton::RotationOrder as R;
        let turned = |joint: &crate::Joint, values: &[f32]| {
            crate::model::pose::channel_rotations_f64(joint, values)
        };
        for order in [R::Zyx, R::Yzx, R::Zxy, R::Xzy, R::Yxz, R::Xyz] {
            let names: Vec<String> = order
                .letters()
                .chars()
                .map(|c| format!("{}rotation", c.to_ascii_uppercase()))
                .collect();
            for middle in [90.0f32, -90.0, 89.99, -89.99] {
                let row = format!("0 0 0 37 {middle} -121");
                let text = format!(
                    "HIERARCHY\nROOT Hips\n{{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition \
                     Zposition {}\nEnd Site\n{{\nOFFSET 0 1 0\n}}\n}}\nMOTION\nFrames: 2\n\
                     Frame Time: 0.5\n{row}\n{row}\n",
                    names.join(" ")
                );
                let bvh = take(&text);
                let joint = &bvh.skeleton.joints[0];
                let want = turned(joint, bvh.motion.frame(0));
                let close = |got: DQuat, what: &str| {
                    let error = 2.0 * got.dot(want).abs().min(1.0).acos();
                    assert!(error < 2e-6, "{what} {order:?} at {middle}°: {error:e} rad");
                };
                let doubled = resample(&bvh.skeleton, &bvh.motion, 4.0).unwrap();
                close(turned(joint, doubled.frame(1)), "resample");
                let (w, x, y, z) = (want.w as f32, want.x as f32, want.y as f32, want.z as f32);
                let numbers = [w, x, y, z];
                let angles =
                    channel_angles(joint, crate::model::pose::RotationKind::Quat, &numbers);
                close(
                    turned(joint, &[0.0, 0.0, 0.0, angles[0], angles[1], angles[2]]),
                    "quaternion to angles",
                );
                let baked = bake_axes(&bvh.skeleton, &bvh.motion).unwrap();
                close(
                    turned(&baked.0.joints[0], baked.1.frame(0)),
                    "baking the axes",
                );
            }
        }
    }
}
