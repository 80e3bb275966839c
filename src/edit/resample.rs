//! Resampling a take to another frame rate: frames picked where the rates divide, rotations
//! interpolated on the sphere where they do not.

use crate::edit::finite;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// Rates closer than this (relatively) count as equal: frame times are written with few digits
/// (`0.033333` for 1/30, `.0083333` for 1/120).
pub const SAME_RATE: f64 = 1e-4;

/// How `resample` makes a take at `fps` from one of `frame_time` seconds a frame.
///
/// ```
/// use bvhview::edit::Resampling;
///
/// assert_eq!(Resampling::of(0.033333, 30.0), Resampling::Same); // 1/30 written with 6 digits
/// assert_eq!(Resampling::of(1.0 / 120.0, 30.0), Resampling::EveryKth(4));
/// assert_eq!(Resampling::of(1.0 / 30.0, 24.0), Resampling::Interpolated);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resampling {
    /// The rate is the file's (within [`SAME_RATE`]): every frame kept, bit for bit.
    Same,
    /// The file's rate is a whole multiple `k` ≥ 2 of `fps` (within [`SAME_RATE`]): frames 0,
    /// k, 2k, … kept as they are, `(frames - 1) / k + 1` of them.
    EveryKth(usize),
    /// Any other ratio: new frames interpolated between the file's.
    Interpolated,
}

impl Resampling {
    /// The way for a take of `frame_time` seconds a frame (finite, positive) to `fps`.
    pub fn of(frame_time: f64, fps: f64) -> Resampling {
        // Target frames per source frame: 1 when the rates agree, 1/k when every k-th is kept.
        let ratio = frame_time * fps;
        if (ratio - 1.0).abs() < SAME_RATE {
            return Resampling::Same;
        }
        let k = (1.0 / ratio).round();
        if (2.0..1e9).contains(&k) && (ratio * k - 1.0).abs() < SAME_RATE {
            return Resampling::EveryKth(k as usize);
        }
        Resampling::Interpolated
    }
}

/// Which of a take's frames make each frame of it resampled (see [`resample()`]).
///
/// ```
/// use bvhview::edit::{Picks, resample_picks};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // 5 frames at 120 fps to 60: every other frame, as it is.
/// assert_eq!(resample_picks(5, 1.0 / 120.0, 60.0, 3)?, Picks::Rows(vec![0, 2, 4]));
/// // 3 frames at 2 fps to 4: new frames halfway between.
/// let Picks::Between(between) = resample_picks(3, 0.5, 4.0, 3)? else { panic!() };
/// assert_eq!(between[1], (0, 1, 0.5));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Picks {
    /// Each new frame is the take's frame of that index, bit for bit.
    Rows(Vec<usize>),
    /// Each new frame lies between frames `a` and `b`, at `w` (0 to 1) of the way from `a`.
    Between(Vec<(usize, usize, f32)>),
}

/// The frames of a take of `frames` frames, `frame_time` seconds each, that make it at `fps`
/// ([`resample()`] says how): the rate checked by [`crate::limits::fps`], the number of new
/// frames (of `channels` values each) by [`crate::limits::resampled_frames`]. A take of fewer than two frames, or without
/// a usable frame time, keeps its frames.
pub fn resample_picks(
    frames: usize,
    frame_time: f64,
    fps: f64,
    channels: usize,
) -> Result<Picks, Error> {
    crate::limits::fps(fps, false)?;
    let timed = frame_time > 0.0 && frame_time.is_finite();
    if frames < 2 || !timed {
        return Ok(Picks::Rows((0..frames).collect()));
    }
    match Resampling::of(frame_time, fps) {
        Resampling::Same => return Ok(Picks::Rows((0..frames).collect())),
        Resampling::EveryKth(k) => return Ok(Picks::Rows((0..frames).step_by(k).collect())),
        Resampling::Interpolated => {}
    }
    crate::limits::resampled_frames(frames - 1, frame_time, fps, channels)?;
    let span = (frames - 1) as f64 * frame_time;
    // A little slack: frame times are written with few digits (.0083333 for 1/120).
    let count = (span * fps + 1e-3).floor() as usize + 1;
    let mut between = Vec::new();
    between.try_reserve_exact(count).map_err(|_| {
        Error::Memory(format!(
            "resampled to {} frames a second: {count} frames do not fit in memory",
            crate::limits::show(fps)
        ))
    })?;
    between.extend((0..count).map(|i| {
        let at = (i as f64 / fps) / frame_time;
        let a = (at.floor() as usize).min(frames - 1);
        let b = (a + 1).min(frames - 1);
        (a, b, (at - a as f64).clamp(0.0, 1.0) as f32)
    }));
    Ok(Picks::Between(between))
}

/// The take at `fps` frames per second. When the rate is the file's within [`SAME_RATE`]
/// (relatively: `|frame_time × fps − 1| < 1e-4`), every frame is kept bit for bit; when the
/// file's rate is a whole multiple k of `fps` (60 → 30, 240 → 30), frames 0, k, 2k, … are kept
/// bit for bit, `(frames − 1) / k + 1` of them (see [`Resampling`]). Otherwise each new frame
/// is at time i / fps between the first and the last frame, its rotations the spherical
/// interpolation (slerp) of the two frames around it and its positions their linear
/// interpolation; joints whose rotations are not three channels on distinct axes (an ASF bone
/// with one or two dof) have their angles interpolated linearly. The new take's frame time is
/// 1 / fps. The rate is checked by [`crate::limits::fps`], the number of frames made by
/// [`crate::limits::resampled_frames`]. `convert --fps`, Python's `Motion.resample` and
/// `dataset` all resample here.
pub fn resample(skeleton: &Skeleton, motion: &Motion, fps: f64) -> Result<Motion, Error> {
    let width = motion.channels;
    let between = match resample_picks(motion.frame_count(), motion.frame_time, fps, width)? {
        Picks::Rows(rows) => {
            let mut data = Vec::with_capacity(rows.len() * width);
            for &row in &rows {
                data.extend_from_slice(motion.frame(row));
            }
            return Ok(Motion::new(1.0 / fps, width, rows.len(), data));
        }
        Picks::Between(between) => between,
    };
    let count = between.len();
    let mut data = Vec::new();
    data.try_reserve_exact(count * width).map_err(|_| {
        Error::Memory(format!(
            "resampled to {} frames a second: {count} frames of {width} values do not fit in \
             memory",
            crate::limits::show(fps)
        ))
    })?;
    for &(a, b, w) in &between {
        let (row_a, row_b) = (motion.frame(a), motion.frame(b));
        let start = data.len();
        // Linear first (positions, and angles without a rotation order); slerp replaces the rest.
        // In f64, so that values near the f32 limit do not overflow on the way (inf · 0).
        let w64 = f64::from(w);
        data.extend(
            row_a
                .iter()
                .zip(row_b)
                .map(|(&x, &y)| (f64::from(x) * (1.0 - w64) + f64::from(y) * w64) as f32),
        );
        for joint in &skeleton.joints {
            let Some(order) = joint.rotation_order else {
                continue;
            };
            let quat =
                |row: &[f32]| crate::model::pose::channel_rotations_f64(joint, joint.values(row));
            let q = quat(row_a).slerp(quat(row_b), w64);
            let angles = euler::split_degrees(q, order);
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
    let motion = Motion::new(1.0 / fps, width, count, data);
    finite(
        Message::of_argument("fps", Some(&crate::limits::show(fps))),
        skeleton.clone(),
        motion,
    )
    .map(|(_, m)| m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::testing::*;

    #[test]
    fn resampling_interpolates_by_hand_worked_values() {
        let bvh = take(TWO_FRAMES);
        // 2 fps to 4: a frame halfway between each pair.
        let doubled = resample(&bvh.skeleton, &bvh.motion, 4.0).unwrap();
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
        let slower = resample(&bvh.skeleton, &bvh.motion, 1.6).unwrap();
        assert_eq!(slower.frame_count(), 2);
        let second = slower.frame(1);
        assert!((second[0] - 5.0).abs() < 1e-5, "{second:?}");
        assert!((second[6] - 50.0).abs() < 1e-3, "{second:?}");
    }

    /// A take of `frames` frames of `frame_time` seconds (written as `time`), its values made
    /// up so that no two frames are alike.
    fn generated(frames: usize, time: &str) -> crate::bvh::Bvh {
        let mut text = TWO_FRAMES.split("MOTION").next().unwrap().to_string();
        text.push_str(&format!("MOTION\nFrames: {frames}\nFrame Time: {time}\n"));
        for frame in 0..frames {
            let row: Vec<String> = (0..9)
                .map(|c| format!("{:.4}", ((frame * 9 + c) as f64 * 0.37).sin() * 90.0))
                .collect();
            text.push_str(&row.join(" "));
            text.push('\n');
        }
        take(&text)
    }

    #[test]
    fn resampling_to_the_files_rate_keeps_every_frame_bit_for_bit() {
        // Frame Time 0.033333 to 30: |0.033333 × 30 − 1| = 1e-5, the file's rate.
        let bvh = generated(7184, "0.033333");
        let same = resample(&bvh.skeleton, &bvh.motion, 30.0).unwrap();
        assert_eq!(same.frame_count(), 7184);
        assert_eq!(same.data, bvh.motion.data);
        assert_eq!(same.frame_time, 1.0 / 30.0);
        // A real take at its own rate (.0083333, 120 per second).
        let walk = crate::bvh::load_file(
            std::path::Path::new("tests/data/bvh/bvhparser_walk_01.bvh"),
            Default::default(),
        )
        .unwrap();
        let same = resample(&walk.skeleton, &walk.motion, 120.0).unwrap();
        assert_eq!(same.data, walk.motion.data);
        // Just past 1e-4 is another rate: interpolated.
        assert_eq!(
            Resampling::of(0.033333, 30.003_31),
            Resampling::Interpolated
        );
        assert_eq!(Resampling::of(0.033333, 30.0029), Resampling::Same);
    }

    #[test]
    fn resampling_by_a_whole_ratio_keeps_every_kth_frame_bit_for_bit() {
        for (time, fps, k) in [
            ("0.016667", 30.0, 2),
            ("0.0041667", 30.0, 8),
            (".0083333", 30.0, 4),
            ("0.008333", 30.0, 4),
            ("0.01", 50.0, 2),
            ("0.033333", 10.0, 3),
        ] {
            assert_eq!(
                Resampling::of(time.parse().unwrap(), fps),
                Resampling::EveryKth(k),
                "{time} to {fps}"
            );
            // Every frame count modulo k: the last frame is kept only when k divides n − 1.
            for frames in [2, k, k + 1, 5 * k, 5 * k + 1, 5 * k + 2, 7 * k - 1] {
                let bvh = generated(frames, time);
                let fewer = resample(&bvh.skeleton, &bvh.motion, fps).unwrap();
                assert_eq!(fewer.frame_count(), (frames - 1) / k + 1, "{time} {frames}");
                assert_eq!(fewer.frame_time, 1.0 / fps);
                for i in 0..fewer.frame_count() {
                    assert_eq!(
                        fewer.frame(i),
                        bvh.motion.frame(i * k),
                        "{time} {frames} {i}"
                    );
                }
            }
        }
        // A real 120-per-second take to 30: 344 frames give frames 0, 4, …, 340.
        let walk = crate::bvh::load_file(
            std::path::Path::new("tests/data/bvh/bvhparser_walk_01.bvh"),
            Default::default(),
        )
        .unwrap();
        let quarter = resample(&walk.skeleton, &walk.motion, 30.0).unwrap();
        assert_eq!(quarter.frame_count(), 86);
        for i in 0..86 {
            assert_eq!(quarter.frame(i), walk.motion.frame(4 * i));
        }
        // Not whole ratios: interpolated, as before.
        for (time, fps) in [(0.01, 30.0), (1.0 / 120.0, 100.0), (1.0 / 30.0, 60.0)] {
            assert_eq!(Resampling::of(time, fps), Resampling::Interpolated);
        }
    }
}
