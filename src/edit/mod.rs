//! Edits that map a skeleton and its motion to new ones. Every edit whose arithmetic can leave
//! the 32-bit range (a scale, a difference, a turn of huge values) checks its result with
//! [`finite`] and refuses it rather than hand on an infinity no file can hold.

use crate::io::error::Error;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, RotationOrder, Skeleton};
use glam::{DQuat, Quat};

/// A BVH-ready copy: every fixed axis baked into the rotation channels, as BVH has no axis.
/// Each joint with an axis or with rotation channels gets `Zrotation Yrotation Xrotation` holding
/// the Euler angles of C · M · C⁻¹ (M for the root includes its orientation); position channels
/// stay as they are. World positions are unchanged up to float rounding.
pub fn bake_axes(skeleton: &Skeleton, motion: &Motion) -> Result<(Skeleton, Motion), Error> {
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

/// The edited take, or an error naming the edit when a value in it is not finite (an OFFSET or
/// a MOTION value past ±3.4e38 as a 32-bit float).
pub fn finite(edit: &str, skeleton: Skeleton, motion: Motion) -> Result<(Skeleton, Motion), Error> {
    // A NaN was not made by the edit (no edit makes one of finite values): it came in with the
    // take, and the message says so rather than blame the edit (issue 44: `--scale 1`).
    let nan = |value: f32| value.is_nan();
    if let Some(joint) = skeleton.joints.iter().find(|j| !j.offset.is_finite()) {
        if joint.offset.to_array().into_iter().any(nan) {
            return Err(Error::Usage(format!(
                "the OFFSET of joint {:?} is not a number (NaN); nothing was written",
                joint.name
            )));
        }
    } else if let Some(at) = first_non_finite(&motion.data) {
        if nan(motion.data[at]) {
            let channels = motion.channels.max(1);
            return Err(Error::Usage(format!(
                "frame {}, value {} is not a number (NaN); nothing was written",
                at / channels,
                at % channels + 1
            )));
        }
    } else {
        return Ok((skeleton, motion));
    }
    Err(Error::Usage(format!(
        "{edit} gives values too large for a 32-bit float; nothing was written"
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
        &format!("--scale {}", crate::io::limits::show(factor)),
        scaled,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// Rates closer than this (relatively) count as equal: frame times are written with few digits
/// (`0.033333` for 1/30, `.0083333` for 1/120).
pub const SAME_RATE: f64 = 1e-4;

/// How `resample` makes a take at `fps` from one of `frame_time` seconds a frame.
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

/// Which of a take's frames make each frame of it resampled (see [`resample`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Picks {
    /// Each new frame is the take's frame of that index, bit for bit.
    Rows(Vec<usize>),
    /// Each new frame lies between frames `a` and `b`, at `w` (0 to 1) of the way from `a`.
    Between(Vec<(usize, usize, f32)>),
}

/// The frames of a take of `frames` frames, `frame_time` seconds each, that make it at `fps`
/// ([`resample`] says how): the rate checked by [`crate::io::limits::fps`], the number of new
/// frames (of `channels` values each) by [`crate::io::limits::resampled_frames`]. A take of fewer than two frames, or without
/// a usable frame time, keeps its frames.
pub fn resample_picks(
    frames: usize,
    frame_time: f64,
    fps: f64,
    channels: usize,
) -> Result<Picks, Error> {
    crate::io::limits::fps(fps, false)?;
    let timed = frame_time > 0.0 && frame_time.is_finite();
    if frames < 2 || !timed {
        return Ok(Picks::Rows((0..frames).collect()));
    }
    match Resampling::of(frame_time, fps) {
        Resampling::Same => return Ok(Picks::Rows((0..frames).collect())),
        Resampling::EveryKth(k) => return Ok(Picks::Rows((0..frames).step_by(k).collect())),
        Resampling::Interpolated => {}
    }
    crate::io::limits::resampled_frames(frames - 1, frame_time, fps, channels)?;
    let span = (frames - 1) as f64 * frame_time;
    // A little slack: frame times are written with few digits (.0083333 for 1/120).
    let count = (span * fps + 1e-3).floor() as usize + 1;
    let mut between = Vec::new();
    between.try_reserve_exact(count).map_err(|_| {
        Error::Memory(format!(
            "--fps {}: {count} frames do not fit in memory",
            crate::io::limits::show(fps)
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
/// 1 / fps. The rate is checked by [`crate::io::limits::fps`], the number of frames made by
/// [`crate::io::limits::resampled_frames`]. `convert --fps`, Python's `Motion.resample` and
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
            "--fps {}: {count} frames of {width} values do not fit in memory",
            crate::io::limits::show(fps)
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
        &format!("--fps {}", crate::io::limits::show(fps)),
        skeleton.clone(),
        motion,
    )
    .map(|(_, m)| m)
}

/// Which side of the body a joint is on, by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// Body parts a single `l` or `r` is written before in lower-case names (CMU's ASF bones
/// `lhumerus`, `rfemur`; cgspeed's `lhip`, `lknee`, `lelbow`), and that may follow a lower-case
/// `left`/`right` (`lefthand`).
const PARTS: [&str; 48] = [
    "hipjoint",
    "hip",
    "femur",
    "thigh",
    "upleg",
    "upperleg",
    "leg",
    "knee",
    "shin",
    "tibia",
    "lowerleg",
    "loleg",
    "ankle",
    "foot",
    "heel",
    "toes",
    "toe",
    "toebase",
    "ball",
    "clavicle",
    "collar",
    "shoulder",
    "shldr",
    "scapula",
    "humerus",
    "uparm",
    "upperarm",
    "arm",
    "forearm",
    "elbow",
    "radius",
    "lowerarm",
    "loarm",
    "wrist",
    "hand",
    "palm",
    "fingers",
    "finger",
    "thumb",
    "index",
    "middle",
    "ring",
    "pinky",
    "eye",
    "buttock",
    "pectoral",
    "breast",
    "metatarsals",
];

/// Whether `text` is one of [`PARTS`], maybe followed by digits (`lhand`, `rthumb1`).
fn is_part(text: &str) -> bool {
    let stem = text.trim_end_matches(|c: char| c.is_ascii_digit());
    PARTS.contains(&stem.to_ascii_lowercase().as_str())
}

/// Whether `text` starts with one of [`PARTS`] (`lefthand`, `RIGHTFOOT`).
fn starts_with_part(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    PARTS.iter().any(|part| lower.starts_with(part))
}

/// The characters that separate the words of a name: `mixamorig:LeftArm`, `UpperLeg_L`,
/// `thigh.L.001`, `Bip01 L Thigh`, `DEF-thigh.L`.
fn is_separator(c: char) -> bool {
    matches!(c, '_' | '.' | ':' | '-' | ' ' | '|' | '/')
}

/// The side a name marks, the byte range of the mark and what the other side writes there.
fn side_mark(name: &str) -> Option<(Side, std::ops::Range<usize>, String)> {
    // The words of the name between separators, with their byte offsets.
    let mut tokens: Vec<(usize, &str)> = Vec::new();
    let mut start = None;
    for (i, c) in name.char_indices().chain([(name.len(), '_')]) {
        match (is_separator(c), start) {
            (true, Some(s)) => {
                tokens.push((s, &name[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    // 1. The words Left and Right (`LeftUpLeg`, `mixamorig:LeftArm`, `left_hip`, `mHipLeft`,
    //    `RightUpperLeg`, `LEFT_ARM`), as a word of their own: at the start of a word or after a
    //    lower-case letter or digit when capitalised, and not running on into a lower-case word
    //    (`Leftover`, `upright`, `Bright` have no side) unless that word is a body part
    //    (`lefthand`).
    const WORDS: [(&str, &str, Side); 6] = [
        ("Left", "Right", Side::Left),
        ("left", "right", Side::Left),
        ("LEFT", "RIGHT", Side::Left),
        ("Right", "Left", Side::Right),
        ("right", "left", Side::Right),
        ("RIGHT", "LEFT", Side::Right),
    ];
    for &(at, token) in &tokens {
        for (word, other, side) in WORDS {
            for (i, _) in token.match_indices(word) {
                let before = token[..i].chars().next_back();
                let after = &token[i + word.len()..];
                let capital = word.starts_with(|c: char| c.is_ascii_uppercase());
                let starts = match before {
                    None => true,
                    Some(c) => capital && (c.is_ascii_lowercase() || c.is_ascii_digit()),
                };
                let last_lower = word.ends_with(|c: char| c.is_ascii_lowercase());
                let ends = match after.chars().next() {
                    None => true,
                    Some(c) if last_lower => !c.is_ascii_lowercase() || starts_with_part(after),
                    Some(c) => !c.is_ascii_uppercase() || starts_with_part(after),
                };
                if starts && ends {
                    return Some((side, at + i..at + i + word.len(), other.to_string()));
                }
            }
        }
    }
    // 2. A word that is a lone L or R (`L_Hip`, `UpperLeg_L`, `thigh.L`, `upperleg01.R`,
    //    `Bip01 L Thigh`, `Finger_l_01`).
    for &(at, token) in &tokens {
        let (side, other) = match token {
            "L" => (Side::Left, "R"),
            "l" => (Side::Left, "r"),
            "R" => (Side::Right, "L"),
            "r" => (Side::Right, "l"),
            _ => continue,
        };
        return Some((side, at..at + 1, other.to_string()));
    }
    // 3. A word that starts with its side's letter: lower case before a capital (Daz's, Poser's
    //    and Second Life's `lThigh`, `rCollar`, `lShldr`), upper case before a capitalised word
    //    (CMU's `LHipJoint`, `LThumb`; not `L5`, `LOWER`), or lower case before a body part
    //    (CMU's ASF `lhumerus`, `lhipjoint`; cgspeed's `lhip`, `lknee`, `lelbow`).
    for &(at, token) in &tokens {
        let bytes = token.as_bytes();
        let Some(&first) = bytes.first() else {
            continue;
        };
        let side = match first {
            b'l' | b'L' => Side::Left,
            b'r' | b'R' => Side::Right,
            _ => continue,
        };
        let rest = &token[1..];
        let marked = if first.is_ascii_lowercase() {
            (bytes.len() >= 2 && bytes[1].is_ascii_uppercase()) || is_part(rest)
        } else {
            bytes.len() >= 3 && bytes[1].is_ascii_uppercase() && bytes[2].is_ascii_lowercase()
        };
        if marked {
            let other = match (side, first.is_ascii_lowercase()) {
                (Side::Left, true) => "r",
                (Side::Left, false) => "R",
                (Side::Right, true) => "l",
                (Side::Right, false) => "L",
            };
            return Some((side, at..at + 1, other.to_string()));
        }
    }
    None
}

/// The side a name marks and the name with the other side's mark, as the common rigs write them:
/// CMU (`LHipJoint`, `LeftUpLeg`, `LThumb`; its ASF's `lhipjoint`, `lhumerus`), cgspeed (`lhip`,
/// `lknee`, `lelbow`, `rhipjoint`), Mixamo (`mixamorig:LeftUpLeg`), LaFAN1 (`LeftUpLeg`), Bandai
/// (`UpperLeg_L`), Xsens (`RightUpperLeg`), Daz, Poser and Second Life (`lThigh`, `lShldr`,
/// `rCollar`, `mHipLeft`), Rokoko (`LeftThigh`), SMPL (`left_hip`, `L_Hip`), MakeHuman and
/// Blender (`upperleg01.R`, `thigh.L`). `None` when the name marks no side (`Hips`, `Spine`,
/// `Head`, `Neck`, `lowerback`, `upperback`, Xsens's `L5`).
pub fn name_side(name: &str) -> Option<(Side, String)> {
    let (side, range, other) = side_mark(name)?;
    let mut mirrored = String::with_capacity(name.len() + 1);
    mirrored.push_str(&name[..range.start]);
    mirrored.push_str(&other);
    mirrored.push_str(&name[range.end..]);
    debug_assert!(side_mark(&mirrored).is_some_and(|(s, _, _)| s == side.other()));
    Some((side, mirrored))
}

/// The name a joint takes in the mirror image: Left and Right exchanged (see [`name_side`]);
/// `None` when the name has no side.
pub fn mirrored_name(name: &str) -> Option<String> {
    name_side(name).map(|(_, mirrored)| mirrored)
}

/// How [`mirror`] makes the mirror image.
#[derive(Clone, Debug, Default)]
pub struct MirrorOptions {
    /// Rename instead of swap: every joint reflected where it is, and the names with a side
    /// given the other side's (`LeftArm` becomes `RightArm`). The default keeps every name and
    /// the skeleton's topology, and swaps the motion of left and right joints.
    pub rename: bool,
    /// Joint name → the name of its other-side counterpart, over the guess for the joints it
    /// lists (in a swap, both must be joints of the skeleton; when renaming, the new name).
    pub names: std::collections::HashMap<String, String>,
}

/// Whether joint `k`'s channels can carry the reflection of joint `j`'s motion, and back:
/// the same position channels, rotations both of three distinct axes (or the same channels),
/// and both with or without a bone axis.
fn swappable(j: &crate::model::skeleton::Joint, k: &crate::model::skeleton::Joint) -> bool {
    let positions = |joint: &crate::model::skeleton::Joint| -> Vec<Channel> {
        joint
            .channels
            .iter()
            .copied()
            .filter(|c| c.is_position())
            .collect()
    };
    j.end_site == k.end_site
        && j.axis.is_some() == k.axis.is_some()
        && (j.channels == k.channels
            || (positions(j) == positions(k)
                && j.rotation_order.is_some()
                && k.rotation_order.is_some()
                && j.channels.len() == k.channels.len()))
}

/// Each joint's counterpart on the other side of the body (itself for joints on the middle, and
/// for joints whose counterpart cannot take their motion): the pairs [`name_side`] (or `names`)
/// guesses, kept when both joints exist, each names the other, their parents are counterparts
/// too and their channels can carry each other's motion (`swappable`). End Sites pair as
/// their parents do, in order. A name in `names` that is not a joint, or a pair it gives that
/// cannot swap, is an error.
pub fn mirror_partners(
    skeleton: &Skeleton,
    names: &std::collections::HashMap<String, String>,
) -> Result<Vec<usize>, Error> {
    let joints = &skeleton.joints;
    let mut index = std::collections::HashMap::new();
    for (i, joint) in joints.iter().enumerate().rev() {
        if !joint.end_site {
            index.insert(joint.name.as_str(), i);
        }
    }
    // The counterparts `names` gives, both ways.
    let mut given: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    for (from, to) in names {
        let find = |name: &str| {
            index.get(name).copied().ok_or_else(|| {
                Error::Usage(format!(
                    "mirror names: '{name}' is not a joint of the skeleton (a swap pairs joints \
                     the skeleton has)"
                ))
            })
        };
        let (a, b) = (find(from)?, find(to)?);
        for (x, y) in [(a, b), (b, a)] {
            if given.get(&x).is_some_and(|&other| other != y) {
                return Err(Error::Usage(format!(
                    "mirror names: '{}' is given two counterparts",
                    joints[x].name
                )));
            }
            given.insert(x, y);
        }
    }
    let guess = |j: usize| -> Option<usize> {
        if let Some(&k) = given.get(&j) {
            return Some(k);
        }
        let other = mirrored_name(&joints[j].name)?;
        let k = *index.get(other.as_str())?;
        // A joint `names` pairs is not anyone else's guess.
        (!given.contains_key(&k)).then_some(k)
    };
    let mut partners: Vec<usize> = (0..joints.len()).collect();
    for j in 0..joints.len() {
        if joints[j].end_site || partners[j] != j {
            continue;
        }
        let Some(k) = guess(j) else {
            continue;
        };
        let parents = match (joints[j].parent, joints[k].parent) {
            (Some(p), Some(q)) => partners[p] == q,
            (None, None) => true,
            _ => false,
        };
        let ok = k != j && partners[k] == k && guess(k) == Some(j) && parents;
        if ok && swappable(&joints[j], &joints[k]) {
            partners[j] = k;
            partners[k] = j;
        } else if given.contains_key(&j) {
            return Err(Error::Usage(format!(
                "mirror names: '{}' and '{}' cannot swap their motion (their parents are not \
                 counterparts, or their channels differ)",
                joints[j].name, joints[k].name
            )));
        }
    }
    // End Sites: the n-th of one joint's with the n-th of its counterpart's.
    for j in 0..joints.len() {
        let k = partners[j];
        if k <= j || joints[j].end_site {
            continue;
        }
        let ends = |joint: usize| -> Vec<usize> {
            joints[joint]
                .children
                .iter()
                .copied()
                .filter(|&c| joints[c].end_site)
                .collect()
        };
        let (a, b) = (ends(j), ends(k));
        if a.len() == b.len() {
            for (x, y) in a.into_iter().zip(b) {
                partners[x] = y;
                partners[y] = x;
            }
        }
    }
    Ok(partners)
}

/// The axis (0 = x, 1 = y, 2 = z) across which the body's left and right lie: of the two
/// axes across the ground (x and z for a take that stands along y as [`crate::model::stance`] guesses
/// it, x and y for one along z), the one along which the counterparts that hang from the body's
/// middle (hips, collars, shoulders: joints whose parent has no counterpart, so a swinging hand
/// or foot does not count) are further apart, summed over up to 64 frames spread through the
/// take (the rest pose without frames). X when no joint has a counterpart, or on a tie.
pub fn lateral_axis(skeleton: &Skeleton, motion: &Motion, partners: &[usize]) -> usize {
    let middle = |j: usize| {
        skeleton.joints[j]
            .parent
            .is_none_or(|parent| partners[parent] == parent)
    };
    let pairs: Vec<(usize, usize)> = partners
        .iter()
        .enumerate()
        .filter(|&(j, &k)| k > j && middle(j))
        .map(|(j, &k)| (j, k))
        .collect();
    if pairs.is_empty() {
        return 0;
    }
    let stance = crate::model::stance::Stance::guess(
        skeleton,
        motion,
        crate::model::pose::OffsetMode::Replace,
        None,
    );
    let across = match stance.up {
        crate::model::pose::Up::Y => 2,
        crate::model::pose::Up::Z => 1,
    };
    let frames = motion.frame_count();
    let sampled: Vec<Option<usize>> = match frames {
        0 => vec![None],
        1..=64 => (0..frames).map(Some).collect(),
        _ => (0..64).map(|i| Some(i * (frames - 1) / 63)).collect(),
    };
    let mut apart = glam::DVec3::ZERO;
    for frame in sampled {
        let row = frame.map_or(&[][..], |f| motion.frame(f));
        let points = crate::model::pose::world_positions(skeleton, row, stance.mode);
        for &(j, k) in &pairs {
            let d = (points[j] - points[k]).abs().as_dvec3();
            if d.is_finite() {
                apart += d;
            }
        }
    }
    if apart[across] > apart.x { across } else { 0 }
}

/// Whether reflecting across the plane normal to `axis` negates this channel's values:
/// a position along `axis`, a rotation about either other axis.
fn reflected(channel: Channel, axis: usize) -> bool {
    if channel.is_position() {
        channel.axis() == axis
    } else {
        channel.axis() != axis
    }
}

/// A rotation reflected across the plane normal to `axis`: its angle about `axis` kept, about
/// the other two negated.
fn reflect_quat(q: DQuat, axis: usize) -> DQuat {
    let mut v = glam::DVec3::new(q.x, q.y, q.z);
    for other in 0..3 {
        if other != axis {
            v[other] = -v[other];
        }
    }
    DQuat::from_xyzw(v.x, v.y, v.z, q.w)
}

/// The mirror image across the body's sagittal plane: the plane through the origin normal to
/// its [`lateral_axis`] (x for most takes). By default every joint keeps its name, parent and
/// channels (a mirrored clip has the topology of the original), its OFFSET becomes its
/// counterpart's reflected and its motion its counterpart's reflected ([`mirror_partners`]):
/// the left hand moves as the right one did, seen in a mirror, so every world position is the
/// counterpart's reflected and `mirror` twice gives the take back. A reflected rotation keeps
/// its angle about the lateral axis and negates the other two; a position negates its lateral
/// component. Counterparts whose rotation orders differ have the reflected rotation written in
/// the joint's own order. With `options.rename`, each joint is reflected where it is and the
/// names exchange sides instead (`convert --mirror-rename`).
pub fn mirror(
    skeleton: &Skeleton,
    motion: &Motion,
    options: &MirrorOptions,
) -> Result<(Skeleton, Motion), Error> {
    if options.rename {
        let pairs = mirror_partners(skeleton, &std::collections::HashMap::new())?;
        let axis = lateral_axis(skeleton, motion, &pairs);
        let mut renamed = skeleton.clone();
        for joint in &mut renamed.joints {
            let name = options
                .names
                .get(&joint.name)
                .cloned()
                .or_else(|| mirrored_name(&joint.name));
            if let Some(name) = name {
                joint.name = name;
            }
        }
        return Ok(reflect(skeleton, &renamed, motion, axis, None));
    }
    let partners = mirror_partners(skeleton, &options.names)?;
    let axis = lateral_axis(skeleton, motion, &partners);
    Ok(reflect(skeleton, skeleton, motion, axis, Some(&partners)))
}

/// `skeleton` and `motion` reflected across the plane normal to `axis`, with each joint taking
/// its partner's OFFSET, bone axis and motion (`partners`; each joint its own when `None`),
/// on `names`' names.
fn reflect(
    skeleton: &Skeleton,
    names: &Skeleton,
    motion: &Motion,
    axis: usize,
    partners: Option<&[usize]>,
) -> (Skeleton, Motion) {
    let partner = |j: usize| partners.map_or(j, |p| p[j]);
    let mut mirrored = names.clone();
    for (j, joint) in mirrored.joints.iter_mut().enumerate() {
        let source = &skeleton.joints[partner(j)];
        joint.offset = source.offset;
        joint.offset[axis] = -joint.offset[axis];
        joint.axis = source
            .axis
            .map(|q| reflect_quat(q.as_dquat(), axis).as_quat());
    }
    let width = motion.channels;
    let mut data = motion.data.clone();
    if width > 0 {
        for (row, out) in motion.data.chunks(width).zip(data.chunks_mut(width)) {
            for (j, joint) in skeleton.joints.iter().enumerate() {
                let source = &skeleton.joints[partner(j)];
                let values = source.values(row);
                let out = &mut out[joint.first_channel..joint.first_channel + joint.channels.len()];
                if joint.channels == source.channels {
                    for ((slot, &value), &channel) in
                        out.iter_mut().zip(values).zip(&joint.channels)
                    {
                        *slot = if reflected(channel, axis) {
                            -value
                        } else {
                            value
                        };
                    }
                    continue;
                }
                // Counterparts with the same positions and three rotations in another order.
                let mut positions = source
                    .channels
                    .iter()
                    .zip(values)
                    .filter(|(c, _)| c.is_position());
                let rotation = reflect_quat(
                    crate::model::pose::channel_rotations_f64(source, values),
                    axis,
                );
                let order = joint.rotation_order.unwrap_or(RotationOrder::Zyx);
                let mut angles = euler::split_degrees(rotation, order).into_iter();
                for (slot, &channel) in out.iter_mut().zip(&joint.channels) {
                    *slot = if channel.is_position() {
                        let value = positions.next().map_or(0.0, |(_, &v)| v);
                        if reflected(channel, axis) {
                            -value
                        } else {
                            value
                        }
                    } else {
                        angles.next().unwrap_or(0.0)
                    };
                }
            }
        }
    }
    let frames = motion.frame_count();
    (
        mirrored,
        Motion::new(motion.frame_time, width, frames, data),
    )
}

/// The ground plane's axes for an up axis: (the two across, the one up).
fn plane(up: crate::model::pose::Up) -> ([usize; 2], usize) {
    match up {
        crate::model::pose::Up::Y => ([0, 2], 1),
        crate::model::pose::Up::Z => ([0, 1], 2),
    }
}

/// The travel across the ground removed: the joint that carries it ([`travel_joint_of_take`],
/// the root in most files, `Hips` under a still root in others) keeps its first frame's place in
/// the ground plane, so the figure moves where it stands.
/// Only that joint's values change, to values the take already holds: nothing can overflow.
///
/// [`travel_joint_of_take`]: crate::model::pose::travel_joint_of_take
pub fn in_place(skeleton: &Skeleton, motion: &Motion, up: crate::model::pose::Up) -> Motion {
    let (across, _) = plane(up);
    let mut data = motion.data.clone();
    if motion.frame_count() == 0 || motion.channels == 0 {
        return motion.clone();
    }
    let travel = crate::model::pose::travel_joint_of_take(
        skeleton,
        motion,
        crate::model::pose::OffsetMode::Replace,
    );
    let joint = &skeleton.joints[travel];
    for (i, channel) in joint.channels.iter().enumerate() {
        if channel.is_position() && across.contains(&channel.axis()) {
            let column = joint.first_channel + i;
            let first = motion.frame(0)[column];
            for row in data.chunks_mut(motion.channels) {
                row[column] = first;
            }
        }
    }
    Motion::new(
        motion.frame_time,
        motion.channels,
        motion.frame_count(),
        data,
    )
}

/// The take moved up or down so that its lowest point, over every joint and frame, is at 0.
/// The roots' up position channel carries the move (their OFFSET when they have none).
pub fn ground(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: crate::model::pose::OffsetMode,
    up: crate::model::pose::Up,
) -> Result<(Skeleton, Motion), Error> {
    let (_, axis) = plane(up);
    let mut lowest = f32::INFINITY;
    let frames = motion.frame_count();
    for frame in 0..frames.max(1) {
        let row = if frames == 0 {
            &[][..]
        } else {
            motion.frame(frame)
        };
        for p in crate::model::pose::world_positions(skeleton, row, mode) {
            lowest = lowest.min(p[axis]);
        }
    }
    let mut grounded = skeleton.clone();
    let mut data = motion.data.clone();
    if !lowest.is_finite() {
        return finite("--ground", grounded, motion.clone());
    }
    for root in skeleton.roots() {
        let joint = &skeleton.joints[root];
        let channel = joint
            .channels
            .iter()
            .position(|c| c.is_position() && c.axis() == axis);
        match (channel, frames) {
            (Some(i), 1..) => {
                for row in data.chunks_mut(motion.channels) {
                    row[joint.first_channel + i] -= lowest;
                }
            }
            _ => grounded.joints[root].offset[axis] -= lowest,
        }
    }
    finite(
        "--ground",
        grounded,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// The turn from one up axis to another, `turn`, which moves each axis onto another (maybe
/// negated): [`QuarterTurn::apply`] turns a vector exactly, with no rounding and no overflow on
/// the way (a product with the quaternion does both).
#[derive(Clone, Copy, Debug)]
pub struct QuarterTurn {
    pub turn: Quat,
    /// Column k: where axis k goes, as signs of 0, 1 or −1.
    axes: [[f32; 3]; 3],
}

impl QuarterTurn {
    pub fn between(from: crate::model::pose::Up, to: crate::model::pose::Up) -> QuarterTurn {
        // Into Y-up from `from`, then out of Y-up into `to`.
        let turn = to.to_y_up().inverse() * from.to_y_up();
        let axes = glam::Mat3::from_quat(turn)
            .to_cols_array_2d()
            .map(|c| c.map(f32::round));
        QuarterTurn { turn, axes }
    }

    /// `v` turned.
    pub fn apply(&self, v: glam::Vec3) -> glam::Vec3 {
        let mut out = glam::Vec3::ZERO;
        for (column, &value) in self.axes.iter().zip(&v.to_array()) {
            for (row, &sign) in column.iter().enumerate() {
                if sign != 0.0 {
                    out[row] = sign * value;
                }
            }
        }
        out
    }

    /// `turn · q · turn⁻¹`: the rotation q as seen once everything is turned (its axis turned,
    /// its angle kept), exactly.
    pub fn conjugate(&self, q: Quat) -> Quat {
        let axis = self.apply(glam::Vec3::new(q.x, q.y, q.z));
        Quat::from_xyzw(axis.x, axis.y, axis.z, q.w)
    }
}

/// The take turned from one up axis to another, so that it loads the same way in the other
/// convention: every OFFSET and position turned by the rotation Q between them, every joint's
/// rotation R replaced by Q·R·Q⁻¹ in the joint's own channel order. The world positions come
/// out turned by Q.
pub fn reorient(
    skeleton: &Skeleton,
    motion: &Motion,
    from: crate::model::pose::Up,
    to: crate::model::pose::Up,
) -> Result<(Skeleton, Motion), Error> {
    if from == to {
        return Ok((skeleton.clone(), motion.clone()));
    }
    let quarter = QuarterTurn::between(from, to);
    let (turn, exactly) = (quarter.turn, |v| quarter.apply(v));
    let mut turned = skeleton.clone();
    for joint in &mut turned.joints {
        joint.offset = exactly(joint.offset);
        let positions = joint.channels.iter().filter(|c| c.is_position()).count();
        let rotations = joint.channels.iter().filter(|c| c.is_rotation()).count();
        if (positions != 0 && positions != 3) || (rotations != 0 && joint.rotation_order.is_none())
        {
            return Err(Error::Usage(format!(
                "--up: '{}' has channels that cannot be turned to another axis (it needs three \
                 position channels or none, and three rotations on distinct axes or none)",
                joint.name
            )));
        }
    }
    let mut data = motion.data.clone();
    if motion.channels > 0 {
        for row in data.chunks_mut(motion.channels) {
            let original = row.to_vec();
            for joint in &skeleton.joints {
                let values = joint.values(&original);
                let columns = |position: bool| {
                    joint
                        .channels
                        .iter()
                        .enumerate()
                        .filter(move |(_, c)| c.is_position() == position)
                        .map(|(i, &c)| (joint.first_channel + i, c.axis()))
                        .collect::<Vec<_>>()
                };
                let positions = columns(true);
                if !positions.is_empty() {
                    let mut p = glam::Vec3::ZERO;
                    for &(column, axis) in &positions {
                        p[axis] = original[column];
                    }
                    let p = exactly(p);
                    for &(column, axis) in &positions {
                        row[column] = p[axis];
                    }
                }
                if let Some(order) = joint.rotation_order {
                    let r = crate::model::pose::channel_rotations_f64(joint, values);
                    let turn = turn.as_dquat();
                    let angles = euler::split_degrees(turn * r * turn.inverse(), order);
                    for (&(column, _), angle) in columns(false).iter().zip(angles) {
                        row[column] = angle;
                    }
                }
            }
        }
    }
    let frames = motion.frame_count();
    finite(
        "--up",
        turned,
        Motion::new(motion.frame_time, motion.channels, frames, data),
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

    /// Every name of a rig's list that is not in `centre` marks a side, and its mirrored name
    /// is in the list and marks the other; the names in `centre` mark none; as many left as
    /// right.
    fn family(names: &[&str], centre: &[&str]) {
        let (mut left, mut right) = (0, 0);
        for &name in names {
            let guess = name_side(name);
            if centre.contains(&name) {
                assert_eq!(guess, None, "{name} has no side");
                continue;
            }
            let (side, other) = guess.unwrap_or_else(|| panic!("{name} has a side"));
            assert!(
                names.contains(&other.as_str()),
                "{name} → {other}: not in the rig"
            );
            let (back_side, back) = name_side(&other).unwrap();
            assert_eq!(
                (back_side, back.as_str()),
                (side.other(), name),
                "{name} → {other}"
            );
            match side {
                Side::Left => left += 1,
                Side::Right => right += 1,
            }
        }
        assert_eq!(left, right, "{names:?}");
        assert!(left > 0);
    }

    #[test]
    fn side_names_of_cmu_bvh() {
        // cgspeed's conversions of CMU's takes (the repository's assimp_01_01.bvh).
        family(
            &[
                "Hips",
                "LHipJoint",
                "LeftUpLeg",
                "LeftLeg",
                "LeftFoot",
                "LeftToeBase",
                "RHipJoint",
                "RightUpLeg",
                "RightLeg",
                "RightFoot",
                "RightToeBase",
                "LowerBack",
                "Spine",
                "Spine1",
                "Neck",
                "Neck1",
                "Head",
                "LeftShoulder",
                "LeftArm",
                "LeftForeArm",
                "LeftHand",
                "LeftFingerBase",
                "LeftHandIndex1",
                "LThumb",
                "RightShoulder",
                "RightArm",
                "RightForeArm",
                "RightHand",
                "RightFingerBase",
                "RightHandIndex1",
                "RThumb",
            ],
            &[
                "Hips",
                "LowerBack",
                "Spine",
                "Spine1",
                "Neck",
                "Neck1",
                "Head",
            ],
        );
    }

    #[test]
    fn side_names_of_cmu_asf() {
        family(
            &[
                "root",
                "lhipjoint",
                "lfemur",
                "ltibia",
                "lfoot",
                "ltoes",
                "rhipjoint",
                "rfemur",
                "rtibia",
                "rfoot",
                "rtoes",
                "lowerback",
                "upperback",
                "thorax",
                "lowerneck",
                "upperneck",
                "head",
                "lclavicle",
                "lhumerus",
                "lradius",
                "lwrist",
                "lhand",
                "lfingers",
                "lthumb",
                "rclavicle",
                "rhumerus",
                "rradius",
                "rwrist",
                "rhand",
                "rfingers",
                "rthumb",
            ],
            &[
                "root",
                "lowerback",
                "upperback",
                "thorax",
                "lowerneck",
                "upperneck",
                "head",
            ],
        );
    }

    #[test]
    fn side_names_of_cgspeed() {
        family(
            &[
                "hips",
                "lhipjoint",
                "lhip",
                "lknee",
                "lankle",
                "lfoot",
                "ltoe",
                "rhipjoint",
                "rhip",
                "rknee",
                "rankle",
                "rfoot",
                "rtoe",
                "lowerback",
                "upperback",
                "chest",
                "neck",
                "head",
                "lcollar",
                "lshoulder",
                "lelbow",
                "lwrist",
                "lhand",
                "rcollar",
                "rshoulder",
                "relbow",
                "rwrist",
                "rhand",
            ],
            &["hips", "lowerback", "upperback", "chest", "neck", "head"],
        );
        // cgspeed's Daz-friendly release.
        family(
            &[
                "hip", "abdomen", "chest", "neck", "head", "leftEye", "rightEye", "rCollar",
                "rShldr", "rForeArm", "rHand", "rThumb1", "rIndex1", "rMid1", "rRing1", "rPinky1",
                "lCollar", "lShldr", "lForeArm", "lHand", "lThumb1", "lIndex1", "lMid1", "lRing1",
                "lPinky1", "rButtock", "rThigh", "rShin", "rFoot", "lButtock", "lThigh", "lShin",
                "lFoot",
            ],
            &["hip", "abdomen", "chest", "neck", "head"],
        );
    }

    #[test]
    fn side_names_of_mixamo() {
        let names: Vec<String> = [
            "Hips",
            "Spine",
            "Spine1",
            "Spine2",
            "Neck",
            "Head",
            "HeadTop_End",
            "LeftShoulder",
            "LeftArm",
            "LeftForeArm",
            "LeftHand",
            "LeftHandThumb1",
            "LeftHandIndex1",
            "LeftHandIndex4",
            "LeftUpLeg",
            "LeftLeg",
            "LeftFoot",
            "LeftToeBase",
            "LeftToe_End",
            "RightShoulder",
            "RightArm",
            "RightForeArm",
            "RightHand",
            "RightHandThumb1",
            "RightHandIndex1",
            "RightHandIndex4",
            "RightUpLeg",
            "RightLeg",
            "RightFoot",
            "RightToeBase",
            "RightToe_End",
        ]
        .iter()
        .map(|n| format!("mixamorig:{n}"))
        .collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        family(
            &names,
            &[
                "mixamorig:Hips",
                "mixamorig:Spine",
                "mixamorig:Spine1",
                "mixamorig:Spine2",
                "mixamorig:Neck",
                "mixamorig:Head",
                "mixamorig:HeadTop_End",
            ],
        );
        assert_eq!(
            mirrored_name("mixamorig1:LeftHand").as_deref(),
            Some("mixamorig1:RightHand")
        );
        assert_eq!(
            mirrored_name("Beta:RightUpLeg").as_deref(),
            Some("Beta:LeftUpLeg")
        );
    }

    #[test]
    fn side_names_of_lafan1() {
        family(
            &[
                "Hips",
                "LeftUpLeg",
                "LeftLeg",
                "LeftFoot",
                "LeftToe",
                "RightUpLeg",
                "RightLeg",
                "RightFoot",
                "RightToe",
                "Spine",
                "Spine1",
                "Spine2",
                "Neck",
                "Head",
                "LeftShoulder",
                "LeftArm",
                "LeftForeArm",
                "LeftHand",
                "RightShoulder",
                "RightArm",
                "RightForeArm",
                "RightHand",
            ],
            &["Hips", "Spine", "Spine1", "Spine2", "Neck", "Head"],
        );
    }

    #[test]
    fn side_names_of_bandai() {
        family(
            &[
                "joint_Root",
                "Hips",
                "Spine",
                "Chest",
                "Neck",
                "Head",
                "Shoulder_L",
                "UpperArm_L",
                "LowerArm_L",
                "Hand_L",
                "Shoulder_R",
                "UpperArm_R",
                "LowerArm_R",
                "Hand_R",
                "UpperLeg_L",
                "LowerLeg_L",
                "Foot_L",
                "Toes_L",
                "UpperLeg_R",
                "LowerLeg_R",
                "Foot_R",
                "Toes_R",
            ],
            &["joint_Root", "Hips", "Spine", "Chest", "Neck", "Head"],
        );
    }

    #[test]
    fn side_names_of_xsens() {
        // L5, L3, T12 and T8 are vertebrae, not sides.
        family(
            &[
                "Pelvis",
                "L5",
                "L3",
                "T12",
                "T8",
                "Neck",
                "Head",
                "RightShoulder",
                "RightUpperArm",
                "RightForeArm",
                "RightHand",
                "LeftShoulder",
                "LeftUpperArm",
                "LeftForeArm",
                "LeftHand",
                "RightUpperLeg",
                "RightLowerLeg",
                "RightFoot",
                "RightToe",
                "LeftUpperLeg",
                "LeftLowerLeg",
                "LeftFoot",
                "LeftToe",
            ],
            &["Pelvis", "L5", "L3", "T12", "T8", "Neck", "Head"],
        );
    }

    #[test]
    fn side_names_of_daz_poser_and_second_life() {
        // Daz Genesis.
        family(
            &[
                "hip",
                "pelvis",
                "lThighBend",
                "lThighTwist",
                "lShin",
                "lFoot",
                "lMetatarsals",
                "lToe",
                "rThighBend",
                "rThighTwist",
                "rShin",
                "rFoot",
                "rMetatarsals",
                "rToe",
                "abdomenLower",
                "abdomenUpper",
                "chestLower",
                "chestUpper",
                "lPectoral",
                "rPectoral",
                "lCollar",
                "lShldrBend",
                "lShldrTwist",
                "lForearmBend",
                "lHand",
                "lThumb1",
                "rCollar",
                "rShldrBend",
                "rShldrTwist",
                "rForearmBend",
                "rHand",
                "rThumb1",
                "neckLower",
                "neckUpper",
                "head",
                "lEye",
                "rEye",
                "lowerJaw",
                "upperJaw",
                "lowerFaceRig",
            ],
            &[
                "hip",
                "pelvis",
                "abdomenLower",
                "abdomenUpper",
                "chestLower",
                "chestUpper",
                "neckLower",
                "neckUpper",
                "head",
                "lowerJaw",
                "upperJaw",
                "lowerFaceRig",
            ],
        );
        // Second Life (the repository's opencollar takes), Bento included.
        family(
            &[
                "hip",
                "abdomen",
                "chest",
                "neck",
                "head",
                "lCollar",
                "lShldr",
                "lForeArm",
                "lHand",
                "rCollar",
                "rShldr",
                "rForeArm",
                "rHand",
                "lThigh",
                "lShin",
                "lFoot",
                "rThigh",
                "rShin",
                "rFoot",
                "mPelvis",
                "mTorso",
                "mChest",
                "mNeck",
                "mHead",
                "mHipLeft",
                "mKneeLeft",
                "mAnkleLeft",
                "mHipRight",
                "mKneeRight",
                "mAnkleRight",
                "mCollarLeft",
                "mShoulderLeft",
                "mElbowLeft",
                "mWristLeft",
                "mCollarRight",
                "mShoulderRight",
                "mElbowRight",
                "mWristRight",
                "mEyeLeft",
                "mEyeRight",
                "mFaceEar1Left",
                "mFaceEar1Right",
                "mHandThumb1Left",
                "mHandThumb1Right",
                "mFaceNoseCenter",
                "mFaceJaw",
            ],
            &[
                "hip",
                "abdomen",
                "chest",
                "neck",
                "head",
                "mPelvis",
                "mTorso",
                "mChest",
                "mNeck",
                "mHead",
                "mFaceNoseCenter",
                "mFaceJaw",
            ],
        );
    }

    #[test]
    fn side_names_of_rokoko() {
        family(
            &[
                "Hips",
                "Spine1",
                "Spine2",
                "Spine3",
                "Spine4",
                "Neck",
                "Head",
                "LeftShoulder",
                "LeftArm",
                "LeftForeArm",
                "LeftHand",
                "LeftFinger1Metacarpal",
                "LeftThigh",
                "LeftShin",
                "LeftFoot",
                "LeftToe",
                "LeftToeEnd",
                "RightShoulder",
                "RightArm",
                "RightForeArm",
                "RightHand",
                "RightFinger1Metacarpal",
                "RightThigh",
                "RightShin",
                "RightFoot",
                "RightToe",
                "RightToeEnd",
                "LeftInHandIndex",
                "RightInHandIndex",
            ],
            &[
                "Hips", "Spine1", "Spine2", "Spine3", "Spine4", "Neck", "Head",
            ],
        );
    }

    #[test]
    fn side_names_of_smpl() {
        family(
            &[
                "pelvis",
                "left_hip",
                "right_hip",
                "spine1",
                "left_knee",
                "right_knee",
                "spine2",
                "left_ankle",
                "right_ankle",
                "spine3",
                "left_foot",
                "right_foot",
                "neck",
                "left_collar",
                "right_collar",
                "head",
                "left_shoulder",
                "right_shoulder",
                "left_elbow",
                "right_elbow",
                "left_wrist",
                "right_wrist",
                "left_hand",
                "right_hand",
            ],
            &["pelvis", "spine1", "spine2", "spine3", "neck", "head"],
        );
        family(
            &[
                "Pelvis",
                "L_Hip",
                "R_Hip",
                "Spine1",
                "L_Knee",
                "R_Knee",
                "Spine2",
                "L_Ankle",
                "R_Ankle",
                "Spine3",
                "L_Foot",
                "R_Foot",
                "Neck",
                "L_Collar",
                "R_Collar",
                "Head",
                "L_Shoulder",
                "R_Shoulder",
                "L_Elbow",
                "R_Elbow",
                "L_Wrist",
                "R_Wrist",
                "L_Hand",
                "R_Hand",
            ],
            &["Pelvis", "Spine1", "Spine2", "Spine3", "Neck", "Head"],
        );
    }

    #[test]
    fn side_names_of_makehuman_blender_unreal_and_3ds_max() {
        family(
            &[
                "root",
                "spine05",
                "pelvis.L",
                "pelvis.R",
                "upperleg01.L",
                "upperleg01.R",
                "toe1-1.L",
                "toe1-1.R",
                "__Eye_L",
                "__Eye_R",
                "Clavicle_L",
                "Clavicle_R",
                "DEF-thigh.L",
                "DEF-thigh.R",
                "thigh.L.001",
                "thigh.R.001",
                "thigh_l",
                "thigh_r",
                "calf_l",
                "calf_r",
                "spine_01",
                "neck_01",
                "Bip01 L Thigh",
                "Bip01 R Thigh",
                "Bip01 Pelvis",
                "Bip01 Spine",
                "LEFT_ARM",
                "RIGHT_ARM",
                "lefthand",
                "righthand",
            ],
            &[
                "root",
                "spine05",
                "spine_01",
                "neck_01",
                "Bip01 Pelvis",
                "Bip01 Spine",
            ],
        );
    }

    #[test]
    fn names_without_a_side() {
        for name in [
            "Hips",
            "Spine",
            "Head",
            "Neck",
            "lowerback",
            "upperback",
            "LowerBack",
            "Chest",
            "L5",
            "T8",
            "rotation",
            "Root",
            "ROOT",
            "RootNode",
            "Leftover",
            "upright",
            "Bright",
            "Light",
            "lowerneck",
            "hip",
            "ring",
            "rib",
            "lip",
            "Site",
            "Reference",
            "LOWER",
        ] {
            assert_eq!(name_side(name), None, "{name}");
        }
    }

    const ARMS: &str = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition \
        Zposition Zrotation Xrotation Yrotation\nJOINT LeftArm\n{\nOFFSET 3 10 0\nCHANNELS 3 \
        Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 2 0 0\n}\n}\nJOINT RightArm\n{\n\
        OFFSET -3.5 10 0\nCHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET -2 0.5 \
        0\n}\n}\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n0 0 0 0 0 0 10 20 30 40 50 60\n\
        4 2 -2 5 6 7 11 21 31 41 51 61\n";

    #[test]
    fn mirroring_swaps_the_motion_of_left_and_right_by_hand_worked_values() {
        let bvh = take(ARMS);
        let options = MirrorOptions::default();
        let (skeleton, motion) = mirror(&bvh.skeleton, &bvh.motion, &options).unwrap();
        // Names, parents and channels kept.
        for (a, b) in skeleton.joints.iter().zip(&bvh.skeleton.joints) {
            assert_eq!(
                (&a.name, a.parent, &a.channels),
                (&b.name, b.parent, &b.channels)
            );
        }
        // Each arm takes the other's OFFSET (and End Site), reflected across x.
        let offsets: Vec<glam::Vec3> = skeleton.joints.iter().map(|j| j.offset).collect();
        assert_eq!(
            offsets,
            [
                glam::Vec3::ZERO,
                glam::Vec3::new(3.5, 10.0, 0.0),
                glam::Vec3::new(2.0, 0.5, 0.0),
                glam::Vec3::new(-3.0, 10.0, 0.0),
                glam::Vec3::new(-2.0, 0.0, 0.0),
            ]
        );
        // The root: x position, Z and Y rotations negated. LeftArm: RightArm's angles with Z
        // and Y negated, and the other way round.
        assert_eq!(
            motion.frame(1),
            [
                -4.0, 2.0, -2.0, -5.0, 6.0, -7.0, -41.0, 51.0, -61.0, -11.0, 21.0, -31.0
            ]
        );
        // Every world position is its counterpart's reflected; twice gives the take back.
        let mode = crate::model::pose::OffsetMode::Replace;
        let partners = [0, 3, 4, 1, 2];
        for frame in 0..2 {
            let before =
                crate::model::pose::world_positions(&bvh.skeleton, bvh.motion.frame(frame), mode);
            let after = crate::model::pose::world_positions(&skeleton, motion.frame(frame), mode);
            for (j, a) in after.iter().enumerate() {
                let b = before[partners[j]];
                assert!(
                    glam::Vec3::new(-b.x, b.y, b.z).abs_diff_eq(*a, 1e-4),
                    "{b} {a}"
                );
            }
        }
        let (again, back) = mirror(&skeleton, &motion, &options).unwrap();
        assert_eq!(again, bvh.skeleton);
        assert_eq!(back, bvh.motion);
        assert_eq!(
            mirror_partners(&bvh.skeleton, &Default::default()).unwrap(),
            partners
        );
    }

    #[test]
    fn mirroring_by_renaming_reflects_each_joint_where_it_is() {
        let bvh = take(ARMS);
        let options = MirrorOptions {
            rename: true,
            ..Default::default()
        };
        let (skeleton, motion) = mirror(&bvh.skeleton, &bvh.motion, &options).unwrap();
        let names: Vec<&str> = skeleton.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, ["Hips", "RightArm", "Site", "LeftArm", "Site"]);
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(-3.0, 10.0, 0.0));
        assert_eq!(
            motion.frame(1),
            [
                -4.0, 2.0, -2.0, -5.0, 6.0, -7.0, -11.0, 21.0, -31.0, -41.0, 51.0, -61.0
            ]
        );
        // By name, the same world positions as the swap.
        let mode = crate::model::pose::OffsetMode::Replace;
        let (swapped, swapped_motion) =
            mirror(&bvh.skeleton, &bvh.motion, &MirrorOptions::default()).unwrap();
        let a = crate::model::pose::world_positions(&skeleton, motion.frame(1), mode);
        let b = crate::model::pose::world_positions(&swapped, swapped_motion.frame(1), mode);
        assert!(a[1].abs_diff_eq(b[3], 1e-5) && a[3].abs_diff_eq(b[1], 1e-5));
    }

    #[test]
    fn mirror_counterparts_can_be_given_and_mismatches_stay_in_place() {
        let bvh = take(&ARMS.replace("LeftArm", "ArmA").replace("RightArm", "ArmB"));
        let none = mirror_partners(&bvh.skeleton, &Default::default()).unwrap();
        assert_eq!(none, [0, 1, 2, 3, 4]);
        let names = [("ArmA".to_string(), "ArmB".to_string())].into();
        assert_eq!(
            mirror_partners(&bvh.skeleton, &names).unwrap(),
            [0, 3, 4, 1, 2]
        );
        let unknown = [("ArmA".to_string(), "Nobody".to_string())].into();
        assert!(mirror_partners(&bvh.skeleton, &unknown).is_err());
        let parent = [("Hips".to_string(), "ArmB".to_string())].into();
        assert!(mirror_partners(&bvh.skeleton, &parent).is_err());
        // A counterpart with other channels keeps its own side: nothing swaps.
        let odd = take(
            &ARMS
                .replacen(
                    "CHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site",
                    "CHANNELS 2 Zrotation Xrotation\nEnd Site",
                    1,
                )
                .replace("10 20 30 40", "10 20 40")
                .replace("11 21 31 41", "11 21 41"),
        );
        assert_eq!(
            mirror_partners(&odd.skeleton, &Default::default()).unwrap(),
            [0, 1, 2, 3, 4]
        );
        // Counterparts whose rotation orders differ: the reflected rotation in each one's own
        // order, the same world positions.
        let mixed = take(&ARMS.replacen(
            "CHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site",
            "CHANNELS 3 Xrotation Yrotation Zrotation\nEnd Site",
            1,
        ));
        let (skeleton, motion) =
            mirror(&mixed.skeleton, &mixed.motion, &MirrorOptions::default()).unwrap();
        let mode = crate::model::pose::OffsetMode::Replace;
        let before =
            crate::model::pose::world_positions(&mixed.skeleton, mixed.motion.frame(1), mode);
        let after = crate::model::pose::world_positions(&skeleton, motion.frame(1), mode);
        for (j, &k) in [0, 3, 4, 1, 2].iter().enumerate() {
            let b = before[k];
            assert!(glam::Vec3::new(-b.x, b.y, b.z).abs_diff_eq(after[j], 1e-4));
        }
    }

    #[test]
    fn in_place_and_ground_by_hand_worked_values() {
        let bvh = take(TWO_FRAMES);
        let still = in_place(&bvh.skeleton, &bvh.motion, crate::model::pose::Up::Y);
        // x and z stay at frame 0's (0, 0); y keeps moving.
        assert_eq!(&still.frame(2)[..3], [0.0, 4.0, 0.0]);
        // The lowest point is the root at frame 0 (y 0) once the chest bends down: lift the
        // chain so that its lowest joint sits at 0.
        let bent = take(&TWO_FRAMES.replace("8 4 -4 0 0 0 80 0 0", "8 4 -4 0 0 0 180 0 0"));
        let mode = crate::model::pose::OffsetMode::Replace;
        let (skeleton, motion) = ground(
            &bent.skeleton,
            &bent.motion,
            mode,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        // Frame 2: root at y 4, chest at 14, the site 5 below the chest (turned 180°): 9. Frame
        // 0: root at 0, the lowest anywhere. So nothing moves.
        assert_eq!(motion.frame(2)[1], 4.0);
        let lifted = take(&TWO_FRAMES.replace("0 0 0 0 0 0 0 0 0\n4", "0 -7 0 0 0 0 0 0 0\n4"));
        let (_, motion) = ground(
            &lifted.skeleton,
            &lifted.motion,
            mode,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        // The root at -7 on frame 0 is the lowest point: every frame's y rises by 7.
        assert_eq!([motion.frame(0)[1], motion.frame(1)[1]], [0.0, 9.0]);
        assert_eq!(skeleton.joints[0].offset, glam::Vec3::ZERO);
    }

    #[test]
    fn reorienting_turns_every_world_position() {
        let bvh = take(TWO_FRAMES);
        let (skeleton, motion) = reorient(
            &bvh.skeleton,
            &bvh.motion,
            crate::model::pose::Up::Y,
            crate::model::pose::Up::Z,
        )
        .unwrap();
        // Y-up to Z-up: (x, y, z) becomes (x, -z, y).
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 0.0, 10.0));
        let mode = crate::model::pose::OffsetMode::Replace;
        for frame in 0..3 {
            let before =
                crate::model::pose::world_positions(&bvh.skeleton, bvh.motion.frame(frame), mode);
            let after = crate::model::pose::world_positions(&skeleton, motion.frame(frame), mode);
            for (b, a) in before.iter().zip(&after) {
                assert!(
                    glam::Vec3::new(b.x, -b.z, b.y).abs_diff_eq(*a, 1e-4),
                    "{b} {a}"
                );
            }
        }
        let (back, motion_back) = reorient(
            &skeleton,
            &motion,
            crate::model::pose::Up::Z,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        let again = crate::model::pose::world_positions(&back, motion_back.frame(2), mode);
        let original =
            crate::model::pose::world_positions(&bvh.skeleton, bvh.motion.frame(2), mode);
        for (a, o) in again.iter().zip(&original) {
            assert!(a.abs_diff_eq(*o, 1e-4));
        }
    }
}

#[cfg(test)]
mod finite_tests {
    use super::{Motion, Skeleton, finite, first_non_finite};

    /// Issue 44: a NaN that came in with the take is named as one, where it is, not blamed on
    /// the edit ("--scale 1 gives values too large"); an overflow the edit made still is.
    #[test]
    fn a_nan_is_named_where_it_is_and_an_overflow_blames_the_edit() {
        let take = || {
            let mut root = crate::model::skeleton::Joint::new("root".into(), None);
            root.offset = glam::Vec3::ONE;
            let skeleton = Skeleton {
                joints: vec![root],
                source: Default::default(),
            };
            (skeleton, Motion::new(1.0 / 30.0, 2, 2, vec![1.0; 4]))
        };
        let (mut skeleton, motion) = take();
        skeleton.joints[0].offset.y = f32::NAN;
        let error = finite("--scale 1", skeleton, motion)
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "the OFFSET of joint \"root\" is not a number (NaN); nothing was written"
        );
        let (skeleton, mut motion) = take();
        motion.data[3] = f32::NAN;
        let error = finite("--scale 1", skeleton, motion)
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "frame 1, value 2 is not a number (NaN); nothing was written"
        );
        let (skeleton, mut motion) = take();
        motion.data[0] = f32::INFINITY;
        let error = finite("--scale 1e38", skeleton, motion)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("--scale 1e38 gives values too large"),
            "{error}"
        );
        let (skeleton, motion) = take();
        assert!(finite("--scale 1", skeleton, motion).is_ok());
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
