//! Trimming a take to a range of frames, and scaling every length.

use crate::edit::finite;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// Only the frames in `range` (already checked against the take).
pub fn trim(motion: &Motion, range: std::ops::Range<usize>) -> Motion {
    let width = motion.channels;
    let data = motion.data[range.start * width..range.end * width].to_vec();
    Motion::new(motion.frame_time, width, range.len(), data)
}

/// Every length times `factor`: the OFFSETs and the position channels' values.
pub fn scale(
    skeleton: &Skeleton,
    motion: &Motion,
    factor: f32,
) -> Result<(Skeleton, Motion), Error> {
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
    finite(
        Message::of_argument("scale", Some(&crate::limits::show(factor))),
        scaled,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::testing::*;

    #[test]
    fn trimming_and_scaling_are_exact() {
        let bvh = take(TWO_FRAMES);
        let trimmed = trim(&bvh.motion, 1..3);
        assert_eq!(trimmed.frame_count(), 2);
        assert_eq!(trimmed.frame(0), bvh.motion.frame(1));
        let (skeleton, motion) = scale(&bvh.skeleton, &bvh.motion, 0.5).unwrap();
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 5.0, 0.0));
        assert_eq!(&motion.frame(2)[..6], [4.0, 2.0, -2.0, 0.0, 0.0, 0.0]);
        assert_eq!(motion.frame(2)[6], 80.0);
    }
}
