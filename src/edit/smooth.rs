//! Smoothing jittery motion (`--smooth HZ`): a zero-phase low-pass on every position channel
//! (the root's path) and on every joint's rotation, the latter on a sign-continuous quaternion
//! path, renormalised, then written back into the joint's own channels.
//!
//! The filter is a second-order Butterworth low-pass (bilinear transform, the cutoff prewarped)
//! run forward and then backward (as scipy's `filtfilt`), so nothing lags; each end is extended
//! by its odd reflection and the filter starts in its steady state for the first value, so a
//! still take stays exactly still and the ends do not ring.

use crate::edit::finite;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use glam::DQuat;

/// A second-order Butterworth low-pass at `cutoff` Hz for samples `frame_time` seconds apart:
/// `(b0, b1, b2, a1, a2)` of `y = b0 x + b1 x₋₁ + b2 x₋₂ − a1 y₋₁ − a2 y₋₂`.
fn butterworth(cutoff: f64, frame_time: f64) -> [f64; 5] {
    let k = (std::f64::consts::PI * cutoff * frame_time).tan();
    let norm = 1.0 / (1.0 + std::f64::consts::SQRT_2 * k + k * k);
    let b0 = k * k * norm;
    [
        b0,
        2.0 * b0,
        b0,
        2.0 * (k * k - 1.0) * norm,
        (1.0 - std::f64::consts::SQRT_2 * k + k * k) * norm,
    ]
}

/// One pass of the filter over `x`, starting in its steady state for `x[0]`.
fn pass(filter: &[f64; 5], x: &mut [f64]) {
    let [b0, b1, b2, a1, a2] = *filter;
    let Some(&first) = x.first() else { return };
    // Transposed direct form II; the states a constant input `first` leaves.
    let mut z2 = (b2 - a2) * first;
    let mut z1 = (b1 - a1) * first + z2;
    for value in x.iter_mut() {
        let input = *value;
        let output = b0 * input + z1;
        z1 = b1 * input - a1 * output + z2;
        z2 = b2 * input - a2 * output;
        *value = output;
    }
}

/// `values` low-passed forward and backward (zero phase), each end extended by its odd
/// reflection over two periods of the cutoff (fewer in a short take), so the filter has
/// settled before the take begins and the ends do not ring.
pub fn zero_phase(values: &[f64], cutoff: f64, frame_time: f64) -> Vec<f64> {
    let n = values.len();
    if n < 2 {
        return values.to_vec();
    }
    let filter = butterworth(cutoff, frame_time);
    let pad = ((2.0 / (cutoff * frame_time)).ceil() as usize)
        .max(6)
        .min(n - 1);
    let mut x = Vec::with_capacity(n + 2 * pad);
    x.extend((1..=pad).rev().map(|k| 2.0 * values[0] - values[k]));
    x.extend_from_slice(values);
    x.extend((1..=pad).map(|k| 2.0 * values[n - 1] - values[n - 1 - k]));
    pass(&filter, &mut x);
    x.reverse();
    pass(&filter, &mut x);
    x.reverse();
    x[pad..pad + n].to_vec()
}

/// `motion` low-passed at `cutoff` Hz (see the module docs). Refused when the cutoff is not
/// below half the frame rate (the Nyquist frequency), where a low-pass means nothing.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let smooth = bvhview::edit::smooth(&take.skeleton, &take.motion, 6.0)?;
/// assert_eq!(smooth.frame_count(), take.frame_count());
/// // At 120 frames per second, 6 Hz keeps a walk's steps: the hips move as they did, to 3 mm.
/// let (a, b) = (take.motion.frame(100), smooth.frame(100));
/// assert!((a[0] - b[0]).abs() < 0.3);
/// assert!(bvhview::edit::smooth(&take.skeleton, &take.motion, 61.0).is_err());
/// # Ok(())
/// # }
/// ```
pub fn smooth(skeleton: &Skeleton, motion: &Motion, cutoff: f64) -> Result<Motion, Error> {
    let frames = motion.frame_count();
    if !(motion.frame_time > 0.0 && motion.frame_time.is_finite()) {
        return Err(Error::invalid(
            "smooth",
            "",
            format!("Frame Time {}: no rate to filter at", motion.frame_time),
        ));
    }
    let nyquist = 0.5 / motion.frame_time;
    if !(cutoff > 0.0 && cutoff < nyquist) {
        return Err(Error::invalid(
            "smooth",
            cutoff.to_string(),
            format!("a cutoff in Hz above 0 and below half the frame rate ({nyquist:.3})"),
        ));
    }
    let channels = motion.channels;
    let mut data = motion.data.clone();
    let column = |c: usize| -> Vec<f64> {
        (0..frames)
            .map(|f| f64::from(motion.data[f * channels + c]))
            .collect()
    };
    for joint in &skeleton.joints {
        let first = joint.first_channel;
        // Position channels, and the angles of a joint without a rotation order (an ASF bone
        // with one or two degrees of freedom), one by one.
        for (i, channel) in joint.channels.iter().enumerate() {
            if channel.is_position() || joint.rotation_order.is_none() {
                let mut values = column(first + i);
                if channel.is_rotation() {
                    // Unwrapped first: a hinge crossing ±180° is not averaged through 0.
                    for f in 1..values.len() {
                        let turns = ((values[f] - values[f - 1]) / 360.0).round();
                        values[f] -= 360.0 * turns;
                    }
                }
                let smooth = zero_phase(&values, cutoff, motion.frame_time);
                for (f, value) in smooth.into_iter().enumerate() {
                    data[f * channels + first + i] = value as f32;
                }
            }
        }
        let Some(order) = joint.rotation_order else {
            continue;
        };
        // The rotation as a quaternion path without sign flips, its four numbers low-passed.
        let mut path: Vec<DQuat> = Vec::with_capacity(frames);
        for f in 0..frames {
            let q = crate::model::pose::channel_rotations_f64(joint, joint.values(motion.frame(f)));
            let q = match path.last() {
                Some(last) if last.dot(q) < 0.0 => -q,
                _ => q,
            };
            path.push(q);
        }
        let parts: Vec<Vec<f64>> = (0..4)
            .map(|k| {
                let values: Vec<f64> = path.iter().map(|q| q.to_array()[k]).collect();
                zero_phase(&values, cutoff, motion.frame_time)
            })
            .collect();
        let rotations: Vec<usize> = joint
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.is_rotation())
            .map(|(i, _)| i)
            .collect();
        let mut previous: Option<[f64; 3]> = None;
        for f in 0..frames {
            let q = DQuat::from_xyzw(parts[0][f], parts[1][f], parts[2][f], parts[3][f]);
            let q = if q.length() > 1e-9 {
                q.normalize()
            } else {
                path[f]
            };
            // The first frame keeps the form of its own angles; the others follow the frame before.
            let before = (rotations.len() == 3).then(|| {
                [0, 1, 2].map(|k| f64::from(motion.frame(f)[first + rotations[k]]).to_radians())
            });
            let angles = euler::split(q, order, previous.or(before));
            previous = Some(angles);
            for (k, &i) in rotations.iter().enumerate() {
                data[f * channels + first + i] = angles[k].to_degrees() as f32;
            }
        }
    }
    let (_, smoothed) = finite(
        Message::of_argument("smooth", None),
        skeleton.clone(),
        Motion::new(motion.frame_time, channels, frames, data),
    )?;
    Ok(smoothed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_stays_constant_and_a_line_stays_a_line() {
        let constant = vec![3.5; 40];
        for v in zero_phase(&constant, 5.0, 1.0 / 30.0) {
            assert!((v - 3.5).abs() < 1e-12);
        }
        // The odd reflection at each end keeps a straight line straight there too (within
        // 1e-4 of a frame's step: the filter settles over the reflection).
        let line: Vec<f64> = (0..40).map(|f| 0.25 * f as f64).collect();
        for (a, b) in zero_phase(&line, 5.0, 1.0 / 30.0).iter().zip(&line) {
            assert!((a - b).abs() < 0.25e-4, "{a} {b}");
        }
        // A take of two frames is left as it is but for the filter's pull between them.
        assert_eq!(zero_phase(&[1.0], 5.0, 0.1), [1.0]);
        assert_eq!(zero_phase(&[2.0, 2.0], 5.0, 1.0 / 30.0).len(), 2);
    }

    #[test]
    fn a_fast_wiggle_is_cut_and_a_slow_wave_kept() {
        let frame_time = 1.0 / 100.0;
        let slow: Vec<f64> = (0..400)
            .map(|f| (2.0 * std::f64::consts::PI * 1.0 * f as f64 * frame_time).sin())
            .collect();
        let fast: Vec<f64> = (0..400)
            .map(|f| (2.0 * std::f64::consts::PI * 30.0 * f as f64 * frame_time).sin())
            .collect();
        let kept = zero_phase(&slow, 6.0, frame_time);
        let cut = zero_phase(&fast, 6.0, frame_time);
        // Away from the ends: the 1 Hz wave within 1 %, the 30 Hz one below 1 % (forward and
        // backward: the filter's gain squared, (6/30)^4 ≈ 0.16 %).
        for f in 50..350 {
            assert!((kept[f] - slow[f]).abs() < 0.01, "{f}");
            assert!(cut[f].abs() < 0.01, "{f}: {}", cut[f]);
        }
    }
}
