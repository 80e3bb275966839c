//! Animation tracks and the frame rate: each channel's keys decoded and bounded by the input's
//! size, and the key step that fits the most keys.

use crate::gltf::read::file::{File, accessor_values};
use crate::model::baked;
use glam::DQuat;
use gltf::animation::{Interpolation, Property};
use std::collections::HashMap;
use std::rc::Rc;

/// One animated property of one node, read.
pub(super) struct Track {
    pub(super) node: usize,
    pub(super) property: Property,
    pub(super) interpolation: Interpolation,
    /// Key times, shared by every track whose sampler reads the same accessor.
    pub(super) times: Rc<Vec<f32>>,
    /// `width` values per key (three per key for CUBICSPLINE: in-tangent, value, out-tangent),
    /// shared likewise.
    pub(super) values: Rc<Vec<f32>>,
    pub(super) width: usize,
}

impl Track {
    /// The value at `time`, `width` numbers. `hint` is the key found by the call before, where
    /// the search for this one starts: frames are sampled in order, so the key is that one or
    /// a little after it, and a take is read in one pass over each track's keys.
    pub(super) fn sample(&self, time: f64, hint: &mut usize, out: &mut [f64]) {
        let w = self.width;
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize, i: usize| -> f64 {
            let at = if cubic { (3 * k + 1) * w } else { k * w };
            self.values[at + i] as f64
        };
        let n = self.times.len();
        let t = |k: usize| self.times[k] as f64;
        if time <= t(0) || n == 1 {
            (0..w).for_each(|i| out[i] = value(0, i));
            return;
        }
        if time >= t(n - 1) {
            (0..w).for_each(|i| out[i] = value(n - 1, i));
            return;
        }
        // The last key at or before `time` (n − 2 at most): from the hint on where it is not
        // past `time`, else by a binary search.
        let mut k = (*hint).min(n - 2);
        if t(k) <= time {
            while k < n - 2 && t(k + 1) <= time {
                k += 1;
            }
        } else {
            k = self
                .times
                .partition_point(|&x| (x as f64) <= time)
                .saturating_sub(1)
                .min(n - 2);
        }
        *hint = k;
        let (t0, t1) = (t(k), t(k + 1));
        let dt = t1 - t0;
        let s = if dt > 0.0 {
            ((time - t0) / dt).clamp(0.0, 1.0)
        } else {
            0.0
        };
        match self.interpolation {
            Interpolation::Step => (0..w).for_each(|i| out[i] = value(k, i)),
            Interpolation::Linear if self.property == Property::Rotation => {
                let q =
                    |k: usize| DQuat::from_xyzw(value(k, 0), value(k, 1), value(k, 2), value(k, 3));
                let r = q(k).slerp(q(k + 1), s);
                out[..4].copy_from_slice(&r.to_array());
            }
            Interpolation::Linear => {
                (0..w).for_each(|i| out[i] = value(k, i) * (1.0 - s) + value(k + 1, i) * s)
            }
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let (h00, h10, h01, h11) = (
                    2.0 * s3 - 3.0 * s2 + 1.0,
                    s3 - 2.0 * s2 + s,
                    -2.0 * s3 + 3.0 * s2,
                    s3 - s2,
                );
                for (i, o) in out.iter_mut().enumerate().take(w) {
                    let out_tangent = self.values[(3 * k + 2) * w + i] as f64;
                    let in_tangent = self.values[(3 * (k + 1)) * w + i] as f64;
                    *o = h00 * value(k, i)
                        + h10 * dt * out_tangent
                        + h01 * value(k + 1, i)
                        + h11 * dt * in_tangent;
                }
            }
        }
    }
}

/// Key values (times and outputs, each key's numbers) that one byte of input may ask the
/// channels of an animation to read, above [`KEY_VALUES_FLOOR`]. A channel of its own stores each
/// key in at least 4 bytes; channels that share a sampler read its keys again, each (3,600
/// channels on one sampler of 56,000 keys: 1e9 values from a 437 KB file).
pub const KEY_VALUES_PER_BYTE: u64 = 16;

/// Key values any file may ask for, whatever its size.
pub const KEY_VALUES_FLOOR: u64 = 1 << 20;

/// The values of accessor `index` as f32s, `width` per element, decoded once per reader and
/// shared by every channel that reads it.
pub(super) type Decoded = HashMap<(usize, usize), Rc<Vec<f32>>>;

pub(super) fn decoded(
    file: &File,
    cache: &mut Decoded,
    accessor: &gltf::Accessor,
    width: usize,
) -> Result<Rc<Vec<f32>>, String> {
    let key = (accessor.index(), width);
    if let Some(values) = cache.get(&key) {
        return Ok(values.clone());
    }
    let values = Rc::new(accessor_values(file, accessor, width)?);
    cache.insert(key, values.clone());
    Ok(values)
}

/// The name a message gives node `index`: `node 3 'Hips'`.
pub(super) fn node_label(document: &gltf::Document, index: usize) -> String {
    match document.nodes().nth(index).and_then(|n| n.name()) {
        Some(name) => format!("node {index} '{}'", crate::limits::quoted(name)),
        None => format!("node {index}"),
    }
}

pub(super) fn tracks(file: &File, animation: &gltf::Animation) -> Result<Vec<Track>, String> {
    let a = animation.index();
    // The budget first, from the accessors' counts alone: nothing is decoded for a file that
    // asks for more than its size allows.
    let mut asked: u64 = 0;
    for channel in animation.channels() {
        let width = match channel.target().property() {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => continue,
        };
        let sampler = channel.sampler();
        let keys = sampler.input().count() as u64;
        let outputs = (sampler.output().count() as u64).saturating_mul(width);
        asked = asked.saturating_add(keys.saturating_add(outputs));
    }
    let budget = KEY_VALUES_FLOOR.saturating_add(KEY_VALUES_PER_BYTE.saturating_mul(file.bytes));
    if asked > budget {
        return Err(format!(
            "animation {a}: its {} channels ask for {} key values (keys × channels), more than \
             a file of {} bytes is read for ({budget}: {KEY_VALUES_PER_BYTE} a byte); refused as \
             damaged or hostile",
            animation.channels().count(),
            crate::limits::show(asked as f64),
            file.bytes
        ));
    }
    let document = &file.gltf.document;
    let mut cache = Decoded::new();
    // Input accessors whose times were checked, and output accessors whose values were.
    let mut times_checked = std::collections::HashSet::new();
    let mut values_checked = std::collections::HashSet::new();
    let mut tracks = Vec::new();
    for channel in animation.channels() {
        let property = channel.target().property();
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::MorphTargetWeights => continue,
        };
        let sampler = channel.sampler();
        let times = decoded(file, &mut cache, &sampler.input(), 1)?;
        let values = decoded(file, &mut cache, &sampler.output(), width)?;
        let interpolation = sampler.interpolation();
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if times.is_empty() || values.len() != times.len() * per_key * width {
            return Err(format!(
                "animation {a}: a sampler with {} keys and {} values",
                times.len(),
                values.len() / width
            ));
        }
        if times_checked.insert(sampler.input().index()) {
            if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|p| p[1] < p[0]) {
                return Err(format!(
                    "animation {a}: key times that are not finite and increasing"
                ));
            }
            // glTF 2.0 (animation.sampler.input): `time[0] >= 0`, an error for the Khronos
            // validator. A key before 0 is a damaged file; read, it would stretch the take back
            // to it (fuzzing flipped the sign of a 0.5 s take's first key: 495 s, 59,469 frames
            // to evaluate).
            if times[0] < 0.0 {
                return Err(format!(
                    "animation {a}: a key at {} s, before 0 (glTF's key times start at 0 or later)",
                    times[0]
                ));
            }
        }
        // A key that is not a number is refused, as a translation's always was by the take's
        // final check; a rotation's was read as no rotation.
        let node = channel.target().node().index();
        if values_checked.insert((sampler.output().index(), sampler.input().index()))
            && let Some(at) = crate::edit::first_non_finite(&values)
        {
            let key = at / width / per_key;
            let what = match property {
                Property::Translation => "translation",
                Property::Rotation => "rotation",
                _ => "scale",
            };
            return Err(format!(
                "animation {a}: {}: {what} key {key} (at {} s) is not a finite number",
                node_label(document, node),
                crate::limits::brief(times[key.min(times.len() - 1)] as f64)
            ));
        }
        tracks.push(Track {
            node,
            property,
            interpolation,
            times,
            values,
            width,
        });
    }
    Ok(tracks)
}

/// Common frame rates: a rate found from key steps within [`SNAP`] of one is taken as it.
pub(super) const COMMON_RATES: [f64; 24] = [
    10.0,
    12.0,
    15.0,
    20.0,
    24000.0 / 1001.0,
    24.0,
    25.0,
    30000.0 / 1001.0,
    30.0,
    48.0,
    50.0,
    60000.0 / 1001.0,
    60.0,
    72.0,
    90.0,
    100.0,
    120.0,
    144.0,
    180.0,
    200.0,
    240.0,
    250.0,
    480.0,
    1000.0,
];

/// How near (relative) a measured rate must be to a common one to be taken as it: 1e-6, the
/// spread of key times written as f32 at a rate, and less than bvhview's own BVH-to-glTF steps
/// are from a common rate (`Frame Time: 0.0083333` is 4e-6 from 1/120 s; kept as written, so
/// that sampling at its step lands on its keys).
pub(super) const SNAP: f64 = 1e-6;

/// Gaps within this (relative) of the shortest of their group are one step.
pub(super) const SAME_STEP: f64 = 5e-3;

/// How many of the most common steps are tried as the take's step.
pub(super) const CANDIDATES: usize = 8;

/// A take's sampling: its start and end, the frames per second, and what is said about them.
pub(super) struct Timing {
    pub(super) start: f64,
    pub(super) end: f64,
    pub(super) fps: f64,
    pub(super) warning: Option<String>,
}

/// How many of `times` (each list once) fall on a frame of `step` seconds from `start`: within
/// `slack` seconds, or the rounding of an f32 time.
pub(super) fn on_frames(times: &[&[f32]], start: f64, step: f64, slack: f64) -> usize {
    times
        .iter()
        .flat_map(|list| list.iter())
        .filter(|&&t| {
            let since = t as f64 - start;
            let frames = since / step;
            let slack = slack.max(4.0 * f32::EPSILON as f64 * (t as f64).abs());
            (frames - frames.round()).abs() * step <= slack
        })
        .count()
}

/// The take's start, end and frame rate from its keys.
///
/// The rate is found from the **key steps** of all the take's tracks (each input accessor
/// once): every gap between two keys (gaps under a microsecond, repeated keys, left out) is
/// grouped with the gaps within 0.5 % of it; the [`CANDIDATES`] largest groups are tried, each
/// at the mean of its gaps (a rate within 1e-6 of a common rate, 24, 30000/1001, 30, 60, 120 …,
/// taken as that rate); the step that puts the most keys on a frame wins, the longer step on a
/// tie. So one odd key (a key 1.5 ms after a take at 30 fps) does not set the rate, nor do the
/// long gaps of tracks with a key at each end only. When keys fall between the frames of the
/// chosen rate, the take is still sampled at it (between keys as the file interpolates) and a
/// warning says how many do not fit. A rate past [`crate::limits::MAX_FPS`] (keys 0.5 ms apart)
/// is sampled at 1000 fps with a warning, and one below [`crate::limits::MIN_FPS`] at that: a
/// file is never refused for a rate it does not state.
pub(super) fn timing(tracks: &[Track]) -> Timing {
    let mut start = f64::MAX;
    let mut end = f64::MIN;
    let mut seen: std::collections::HashSet<*const Vec<f32>> = Default::default();
    let mut lists: Vec<&[f32]> = Vec::new();
    for track in tracks {
        let n = track.times.len();
        start = start.min(track.times[0] as f64);
        end = end.max(track.times[n - 1] as f64);
        // Tracks sharing one input accessor count its keys once.
        if seen.insert(Rc::as_ptr(&track.times)) {
            lists.push(&track.times);
        }
    }
    let mut gaps: Vec<f64> = lists
        .iter()
        .flat_map(|list| list.windows(2).map(|p| p[1] as f64 - p[0] as f64))
        .filter(|&d| d > 1e-6)
        .collect();
    if start > end || gaps.is_empty() {
        return Timing {
            start: if start > end { 0.0 } else { start },
            end: if start > end { 0.0 } else { end },
            fps: 30.0,
            warning: None,
        };
    }
    gaps.sort_by(f64::total_cmp);
    // Groups of gaps within SAME_STEP of the group's shortest: (count, mean).
    let mut groups: Vec<(usize, f64)> = Vec::new();
    let mut i = 0;
    while i < gaps.len() {
        let first = gaps[i];
        let mut j = i;
        let mut sum = 0.0;
        while j < gaps.len() && gaps[j] <= first * (1.0 + SAME_STEP) {
            sum += gaps[j];
            j += 1;
        }
        groups.push((j - i, sum / (j - i) as f64));
        i = j;
    }
    groups.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.total_cmp(&a.1)));
    let keys: usize = lists.iter().map(|l| l.len()).sum();
    // A key fits a frame within a hundredth of the shortest step tried (a hundredth of the
    // step itself would let a step of minutes fit every key of its first seconds).
    let slack = 0.01
        * groups
            .iter()
            .take(CANDIDATES)
            .map(|g| g.1)
            .fold(f64::MAX, f64::min);
    let (mut step, mut fitting) = (groups[0].1, 0usize);
    for &(_, mean) in groups.iter().take(CANDIDATES) {
        let snapped = COMMON_RATES
            .iter()
            .find(|&&rate| (rate * mean - 1.0).abs() <= SNAP)
            .map_or(mean, |rate| 1.0 / rate);
        let fit = on_frames(&lists, start, snapped, slack);
        if fit > fitting || (fit == fitting && snapped > step) {
            (step, fitting) = (snapped, fit);
        }
    }
    let mut fps = COMMON_RATES
        .iter()
        .copied()
        .find(|&rate| (rate * step - 1.0).abs() <= SNAP)
        .unwrap_or(1.0 / step);
    let mut notes = Vec::new();
    if fps > crate::limits::MAX_FPS {
        notes.push(format!(
            "its keys are {} ms apart ({} fps); sampled at {} fps, the fastest bvhview reads",
            crate::limits::brief(1e3 * step),
            crate::limits::brief((fps * 10.0).round() / 10.0),
            crate::limits::MAX_FPS
        ));
        fps = crate::limits::MAX_FPS;
        fitting = keys;
    } else if fps < crate::limits::MIN_FPS {
        notes.push(format!(
            "its keys are {} s apart; sampled at {} fps, the slowest bvhview reads",
            crate::limits::brief(step),
            crate::limits::MIN_FPS
        ));
        fps = crate::limits::MIN_FPS;
        fitting = keys;
    }
    if fitting < keys {
        notes.push(format!(
            "{} of {keys} key times do not fall on a frame at {} fps (the key step that fits \
             the most keys); frames are sampled at that rate, between keys as the file \
             interpolates",
            keys - fitting,
            crate::limits::brief(fps)
        ));
    }
    Timing {
        start,
        end,
        fps,
        warning: (!notes.is_empty()).then(|| notes.join("; ")),
    }
}

/// The frames of a take of `joints` joints and `tracks` tracks sampled as `timing` says, or why
/// not: past [`baked::frame_count`]'s limits, or more frames × (nodes + tracks) than the file's
/// size allows ([`baked::FRAME_WORK_PER_BYTE`] a byte above [`baked::FRAME_WORK_FLOOR`]), where
/// `nodes` are the nodes posed in each frame: the joints and every node above them (a joint
/// under a chain of 999 nodes costs 1000 products a frame).
pub(super) fn frames_within(
    timing: &Timing,
    joints: usize,
    nodes: usize,
    tracks: usize,
    bytes: u64,
) -> Result<usize, String> {
    let frames = baked::frame_count(timing.start, timing.end, timing.fps, joints)?;
    let nodes = nodes.max(joints);
    let work = (frames as u64).saturating_mul((nodes + tracks) as u64);
    let budget = baked::frame_work_budget(bytes);
    if work > budget {
        return Err(format!(
            "the take lasts {} s at {} fps: {} of {}{} and {}, more than a file of {bytes} \
             bytes is read for (frames × (nodes + tracks) at most {}, {} a byte); refused as \
             damaged or hostile",
            crate::limits::brief(timing.end - timing.start),
            crate::limits::brief(timing.fps),
            crate::io::error::counted(frames, "frame"),
            crate::io::error::counted(joints, "joint"),
            if nodes > joints {
                format!(" ({nodes} nodes with those above them)")
            } else {
                String::new()
            },
            crate::io::error::counted(tracks, "track"),
            budget,
            baked::FRAME_WORK_PER_BYTE
        ));
    }
    Ok(frames)
}
