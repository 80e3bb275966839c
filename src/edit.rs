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

/// Only the frames in `range` (already checked against the take).
pub fn trim(motion: &Motion, range: std::ops::Range<usize>) -> Motion {
    let width = motion.channels;
    let data = motion.data[range.start * width..range.end * width].to_vec();
    Motion::new(motion.frame_time, width, range.len(), data)
}

/// Every length times `factor`: the OFFSETs and the position channels' values.
pub fn scale(skeleton: &Skeleton, motion: &Motion, factor: f32) -> (Skeleton, Motion) {
    let mut scaled = skeleton.clone();
    let mut data = motion.data.clone();
    for joint in &mut scaled.joints {
        joint.offset *= factor;
    }
    let positions: Vec<usize> = skeleton
        .joints
        .iter()
        .flat_map(|joint| {
            joint
                .channels
                .iter()
                .enumerate()
                .filter(|(_, c)| c.is_position())
                .map(move |(i, _)| joint.first_channel + i)
        })
        .collect();
    if motion.channels > 0 {
        for row in data.chunks_mut(motion.channels) {
            for &column in &positions {
                row[column] *= factor;
            }
        }
    }
    let frames = motion.frame_count();
    (
        scaled,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// The Euler order of glam that a joint's three rotation channels spell, in file order: the
/// channels multiply on the right in that order, as glam's intrinsic orders do.
fn euler_order(order: RotationOrder) -> EulerRot {
    match order {
        RotationOrder::Zyx => EulerRot::ZYX,
        RotationOrder::Yzx => EulerRot::YZX,
        RotationOrder::Zxy => EulerRot::ZXY,
        RotationOrder::Xzy => EulerRot::XZY,
        RotationOrder::Yxz => EulerRot::YXZ,
        RotationOrder::Xyz => EulerRot::XYZ,
    }
}

/// The take at `fps` frames per second: each new frame at time i / fps between the first and the
/// last frame, its rotations the spherical interpolation (slerp) of the two frames around it and
/// its positions their linear interpolation. Joints whose rotations are not three channels on
/// distinct axes (an ASF bone with one or two dof) have their angles interpolated linearly.
pub fn resample(skeleton: &Skeleton, motion: &Motion, fps: f64) -> Motion {
    let frames = motion.frame_count();
    let width = motion.channels;
    let timed = motion.frame_time > 0.0 && motion.frame_time.is_finite();
    if frames < 2 || !timed || fps.is_nan() || fps <= 0.0 {
        return Motion::new(1.0 / fps, width, frames, motion.data.clone());
    }
    let span = (frames - 1) as f64 * motion.frame_time;
    // A little slack: frame times are written with few digits (.0083333 for 1/120).
    let count = (span * fps + 1e-3).floor() as usize + 1;
    let mut data = Vec::with_capacity(count * width);
    for i in 0..count {
        let at = (i as f64 / fps) / motion.frame_time;
        let a = (at.floor() as usize).min(frames - 1);
        let b = (a + 1).min(frames - 1);
        let w = (at - a as f64).clamp(0.0, 1.0) as f32;
        let (row_a, row_b) = (motion.frame(a), motion.frame(b));
        let start = data.len();
        // Linear first (positions, and angles without a rotation order); slerp replaces the rest.
        data.extend(row_a.iter().zip(row_b).map(|(&x, &y)| x + (y - x) * w));
        for joint in &skeleton.joints {
            let Some(order) = joint.rotation_order else {
                continue;
            };
            let quat = |row: &[f32]| {
                Quat::from_mat4(&crate::pose::channel_rotations(joint, joint.values(row)))
            };
            let q = quat(row_a).slerp(quat(row_b), w);
            let (first, second, third) = q.to_euler(euler_order(order));
            let angles = [first, second, third].map(f32::to_degrees);
            let rotations = joint
                .channels
                .iter()
                .enumerate()
                .filter(|(_, c)| c.is_rotation())
                .map(|(k, _)| start + joint.first_channel + k);
            for (column, angle) in rotations.zip(angles) {
                data[column] = angle;
            }
        }
    }
    Motion::new(1.0 / fps, width, count, data)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn take(text: &str) -> crate::bvh::Bvh {
        crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap()
    }

    const TWO_FRAMES: &str = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition \
        Zposition Zrotation Xrotation Yrotation\nJOINT Chest\n{\nOFFSET 0 10 0\nCHANNELS 3 \
        Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 5 0\n}\n}\n}\nMOTION\nFrames: 3\n\
        Frame Time: 0.5\n0 0 0 0 0 0 0 0 0\n4 2 -2 0 0 0 40 0 0\n8 4 -4 0 0 0 80 0 0\n";

    #[test]
    fn resampling_interpolates_by_hand_worked_values() {
        let bvh = take(TWO_FRAMES);
        // 2 fps to 4: a frame halfway between each pair.
        let doubled = resample(&bvh.skeleton, &bvh.motion, 4.0);
        assert_eq!(doubled.frame_count(), 5);
        assert_eq!(doubled.frame_time, 0.25);
        let middle = doubled.frame(1);
        assert_eq!(&middle[..3], [2.0, 1.0, -1.0]);
        // Chest turns about Z only: the slerp halfway is 20°, Z first in its ZXY order.
        assert!(
            (middle[6] - 20.0).abs() < 1e-4 && middle[7].abs() < 1e-4 && middle[8].abs() < 1e-4
        );
        assert_eq!(doubled.frame(4), bvh.motion.frame(2));
        // 2 fps to 1.6 (a ratio of 0.8): frames at 0, 0.625 and 1.25 s.
        let slower = resample(&bvh.skeleton, &bvh.motion, 1.6);
        assert_eq!(slower.frame_count(), 2);
        let second = slower.frame(1);
        assert!((second[0] - 5.0).abs() < 1e-5, "{second:?}");
        assert!((second[6] - 50.0).abs() < 1e-3, "{second:?}");
    }

    #[test]
    fn trimming_and_scaling_are_exact() {
        let bvh = take(TWO_FRAMES);
        let trimmed = trim(&bvh.motion, 1..3);
        assert_eq!(trimmed.frame_count(), 2);
        assert_eq!(trimmed.frame(0), bvh.motion.frame(1));
        let (skeleton, motion) = scale(&bvh.skeleton, &bvh.motion, 0.5);
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 5.0, 0.0));
        assert_eq!(&motion.frame(2)[..6], [4.0, 2.0, -2.0, 0.0, 0.0, 0.0]);
        assert_eq!(motion.frame(2)[6], 80.0);
    }
}
