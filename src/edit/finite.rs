//! The check every edit ends with: a value past the 32-bit range is refused, and a NaN that came
//! in with the take is named where it is.

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// The edited take, or an error naming the edit when a value in it is not finite (an OFFSET or
/// a MOTION value past ±3.4e38 as a 32-bit float).
pub fn finite(
    edit: impl Into<Message>,
    skeleton: Skeleton,
    motion: Motion,
) -> Result<(Skeleton, Motion), Error> {
    // A NaN was not made by the edit (no edit makes one of finite values): it came in with the
    // take, and the message says so rather than blame the edit (`--scale 1` once
    // did).
    let nan = |value: f32| value.is_nan();
    if let Some(joint) = skeleton.joints.iter().find(|j| !j.offset.is_finite()) {
        if joint.offset.to_array().into_iter().any(nan) {
            return Err(Error::usage(format!(
                "the OFFSET of joint {:?} is not a number (NaN); nothing was written",
                joint.name
            )));
        }
    } else if let Some(at) = first_non_finite(&motion.data) {
        if nan(motion.data[at]) {
            let channels = motion.channels.max(1);
            return Err(Error::usage(format!(
                "frame {}, value {} is not a number (NaN); nothing was written",
                at / channels,
                at % channels + 1
            )));
        }
    } else {
        return Ok((skeleton, motion));
    }
    Err(Error::usage(edit.into().text(
        " gives values too large for a 32-bit float; nothing was written",
    )))
}

/// Where the first NaN or infinity is: blocks without one (nearly always all of them) are
/// passed over by a test the compiler runs on many floats at once.
pub fn first_non_finite(values: &[f32]) -> Option<usize> {
    const BLOCK: usize = 64;
    values.chunks(BLOCK).enumerate().find_map(|(k, block)| {
        if block.iter().fold(true, |finite, v| finite & v.is_finite()) {
            None
        } else {
            block
                .iter()
                .position(|v| !v.is_finite())
                .map(|at| k * BLOCK + at)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A NaN that came in with the take is named as one, where it is, not blamed on
    /// the edit ("--scale 1 gives values too large"); an overflow the edit made still is.
    #[test]
    fn a_nan_is_named_where_it_is_and_an_overflow_blames_the_edit() {
        let take = || {
            let mut root = crate::model::skeleton::Joint::new("root".into(), None);
            root.offset = glam::Vec3::ONE;
            let skeleton = Skeleton {
                joints: vec![root],
                ..Skeleton::default()
            };
            (skeleton, Motion::new(1.0 / 30.0, 2, 2, vec![1.0; 4]))
        };
        let (mut skeleton, motion) = take();
        skeleton.joints[0].offset.y = f32::NAN;
        let error = finite(Message::of_argument("scale", Some("1")), skeleton, motion)
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "the OFFSET of joint \"root\" is not a number (NaN); nothing was written"
        );
        let (skeleton, mut motion) = take();
        motion.data[3] = f32::NAN;
        let error = finite(Message::of_argument("scale", Some("1")), skeleton, motion)
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "frame 1, value 2 is not a number (NaN); nothing was written"
        );
        let (skeleton, mut motion) = take();
        motion.data[0] = f32::INFINITY;
        let error = finite(
            Message::of_argument("scale", Some("1e38")),
            skeleton,
            motion,
        )
        .unwrap_err()
        .to_string();
        assert!(
            error.starts_with("scale 1e38 gives values too large"),
            "{error}"
        );
        let (skeleton, motion) = take();
        assert!(finite(Message::of_argument("scale", Some("1")), skeleton, motion).is_ok());
    }

    #[test]
    fn the_first_non_finite_number_is_found_in_any_block() {
        assert_eq!(first_non_finite(&[]), None);
        let values = vec![1.5f32; 300];
        assert_eq!(first_non_finite(&values), None);
        for at in [0, 1, 63, 64, 65, 127, 128, 299] {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let mut with = values.clone();
                with[at] = bad;
                // A later one does not hide the first.
                with[299] = f32::NAN;
                assert_eq!(first_non_finite(&with), Some(at), "{bad} at {at}");
            }
        }
    }
}
