//! Edits that map a skeleton and its motion to new ones. Every edit whose arithmetic can leave
//! the 32-bit range (a scale, a difference, a turn of huge values) checks its result with
//! [`finite`] and refuses it rather than hand on an infinity no file can hold.

use crate::error::Error;
use crate::motion::Motion;
use crate::pose::local_rotation;
use crate::skeleton::{Channel, RotationOrder, Skeleton};
use glam::{EulerRot, Quat};

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
                let rotation = local_rotation(joint, values);
                let (z, y, x) = Quat::from_mat4(&rotation).to_euler(EulerRot::ZYX);
                data.extend([z.to_degrees(), y.to_degrees(), x.to_degrees()]);
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
    let offsets = skeleton.joints.iter().all(|j| j.offset.is_finite());
    if !offsets || !motion.data.iter().all(|v| v.is_finite()) {
        return Err(Error::Usage(format!(
            "{edit} gives values too large for a 32-bit float; nothing was written"
        )));
    }
    Ok((skeleton, motion))
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
        &format!("--scale {}", crate::limits::show(factor)),
        scaled,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// The Euler order of glam that a joint's three rotation channels spell, in file order: the
/// channels multiply on the right in that order, as glam's intrinsic orders do.
pub fn euler_order(order: RotationOrder) -> EulerRot {
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
/// The rate is checked by [`crate::limits::fps`], the number of frames made by
/// [`crate::limits::resampled_frames`].
pub fn resample(skeleton: &Skeleton, motion: &Motion, fps: f64) -> Result<Motion, Error> {
    crate::limits::fps(fps, false)?;
    let frames = motion.frame_count();
    let width = motion.channels;
    let timed = motion.frame_time > 0.0 && motion.frame_time.is_finite();
    if frames < 2 || !timed {
        return Ok(Motion::new(1.0 / fps, width, frames, motion.data.clone()));
    }
    crate::limits::resampled_frames(frames - 1, motion.frame_time, fps, width)?;
    let span = (frames - 1) as f64 * motion.frame_time;
    // A little slack: frame times are written with few digits (.0083333 for 1/120).
    let count = (span * fps + 1e-3).floor() as usize + 1;
    let mut data = Vec::new();
    data.try_reserve_exact(count * width).map_err(|_| {
        Error::Memory(format!(
            "--fps {}: {count} frames of {width} values do not fit in memory",
            crate::limits::show(fps)
        ))
    })?;
    for i in 0..count {
        let at = (i as f64 / fps) / motion.frame_time;
        let a = (at.floor() as usize).min(frames - 1);
        let b = (a + 1).min(frames - 1);
        let w = (at - a as f64).clamp(0.0, 1.0) as f32;
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
    let motion = Motion::new(1.0 / fps, width, count, data);
    finite(
        &format!("--fps {}", crate::limits::show(fps)),
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

/// The side a name marks and the name with the other side's mark, as the common rigs write them
/// (`LeftArm`, `leftArm`, `L_Arm`, `Arm_L`, `Arm.L`, `lhumerus`/`rhumerus` in CMU's ASF,
/// `lShldr`/`rShldr` in Daz's, Poser's and Second Life's, `mixamorig:LeftHand`); `None` when the
/// name has no side.
pub fn name_side(name: &str) -> Option<(Side, String)> {
    let sides = |left: bool| if left { Side::Left } else { Side::Right };
    for (left, right) in [("Left", "Right"), ("left", "right"), ("LEFT", "RIGHT")] {
        for (from, to, is_left) in [(left, right, true), (right, left, false)] {
            if name.contains(from) {
                return Some((sides(is_left), name.replacen(from, to, 1)));
            }
        }
    }
    for (left, right) in [("_L", "_R"), (".L", ".R"), ("_l", "_r"), (".l", ".r")] {
        for (from, to, is_left) in [(left, right, true), (right, left, false)] {
            if let Some(stem) = name.strip_suffix(from) {
                return Some((sides(is_left), format!("{stem}{to}")));
            }
        }
    }
    for (left, right) in [("L_", "R_"), ("l_", "r_")] {
        for (from, to, is_left) in [(left, right, true), (right, left, false)] {
            if let Some(rest) = name.strip_prefix(from) {
                return Some((sides(is_left), format!("{to}{rest}")));
            }
        }
    }
    // Daz's, Poser's and Second Life's: lShldr, rForeArm, lThigh … (a lower-case l or r before
    // a capital).
    if let [side @ (b'l' | b'r'), capital, ..] = name.as_bytes()
        && capital.is_ascii_uppercase()
    {
        let (side, other) = if *side == b'l' {
            (Side::Left, 'r')
        } else {
            (Side::Right, 'l')
        };
        return Some((side, format!("{other}{}", &name[1..])));
    }
    // CMU's ASF bones: lhumerus, rfemur, lclavicle … (a single l or r before a known part).
    const PARTS: [&str; 13] = [
        "hipjoint", "femur", "tibia", "foot", "toes", "clavicle", "humerus", "radius", "wrist",
        "hand", "fingers", "thumb", "shoulder",
    ];
    for part in PARTS {
        if name.len() == part.len() + 1 && name.ends_with(part) {
            match name.as_bytes()[0] {
                b'l' => return Some((Side::Left, format!("r{part}"))),
                b'r' => return Some((Side::Right, format!("l{part}"))),
                _ => {}
            }
        }
    }
    None
}

/// The name a joint takes in the mirror image: Left and Right exchanged (see [`name_side`]);
/// `None` when the name has no side.
pub fn mirrored_name(name: &str) -> Option<String> {
    name_side(name).map(|(_, mirrored)| mirrored)
}

/// The mirror image across the YZ plane (x → −x), with Left and Right exchanged in the names, so
/// a left-handed wave becomes a right-handed one on the same skeleton. OFFSETs and position
/// channels negate x; a rotation reflected through that plane keeps its angle about X and
/// negates its angles about Y and Z.
pub fn mirror(skeleton: &Skeleton, motion: &Motion) -> (Skeleton, Motion) {
    let mut mirrored = skeleton.clone();
    for joint in &mut mirrored.joints {
        joint.offset.x = -joint.offset.x;
        if let Some(name) = mirrored_name(&joint.name) {
            joint.name = name;
        }
    }
    let negated: Vec<usize> = skeleton
        .joints
        .iter()
        .flat_map(|joint| {
            joint
                .channels
                .iter()
                .enumerate()
                .filter(|(_, c)| {
                    matches!(
                        c,
                        Channel::Xposition | Channel::Yrotation | Channel::Zrotation
                    )
                })
                .map(move |(i, _)| joint.first_channel + i)
        })
        .collect();
    let mut data = motion.data.clone();
    if motion.channels > 0 {
        for row in data.chunks_mut(motion.channels) {
            for &column in &negated {
                row[column] = -row[column];
            }
        }
    }
    let frames = motion.frame_count();
    (
        mirrored,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// The ground plane's axes for an up axis: (the two across, the one up).
fn plane(up: crate::pose::Up) -> ([usize; 2], usize) {
    match up {
        crate::pose::Up::Y => ([0, 2], 1),
        crate::pose::Up::Z => ([0, 1], 2),
    }
}

/// The travel across the ground removed: the joint that carries it ([`travel_joint_of_take`],
/// the root in most files, `Hips` under a still root in others) keeps its first frame's place in
/// the ground plane, so the figure moves where it stands.
/// Only that joint's values change, to values the take already holds: nothing can overflow.
///
/// [`travel_joint_of_take`]: crate::pose::travel_joint_of_take
pub fn in_place(skeleton: &Skeleton, motion: &Motion, up: crate::pose::Up) -> Motion {
    let (across, _) = plane(up);
    let mut data = motion.data.clone();
    if motion.frame_count() == 0 || motion.channels == 0 {
        return motion.clone();
    }
    let travel =
        crate::pose::travel_joint_of_take(skeleton, motion, crate::pose::OffsetMode::Replace);
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
    mode: crate::pose::OffsetMode,
    up: crate::pose::Up,
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
        for p in crate::pose::world_positions(skeleton, row, mode) {
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

/// The take turned from one up axis to another, so that it loads the same way in the other
/// convention: every OFFSET and position turned by the rotation Q between them, every joint's
/// rotation R replaced by Q·R·Q⁻¹ in the joint's own channel order. The world positions come
/// out turned by Q.
pub fn reorient(
    skeleton: &Skeleton,
    motion: &Motion,
    from: crate::pose::Up,
    to: crate::pose::Up,
) -> Result<(Skeleton, Motion), Error> {
    if from == to {
        return Ok((skeleton.clone(), motion.clone()));
    }
    // Into Y-up from `from`, then out of Y-up into `to`.
    let turn = to.to_y_up().inverse() * from.to_y_up();
    // A quarter turn moves each axis onto another, maybe negated: exactly, with no rounding
    // and no overflow on the way (a product with the quaternion does both).
    let axes = glam::Mat3::from_quat(turn)
        .to_cols_array_2d()
        .map(|c| c.map(f32::round));
    let exactly = |v: glam::Vec3| {
        let mut out = glam::Vec3::ZERO;
        for (column, &value) in axes.iter().zip(&v.to_array()) {
            for (row, &sign) in column.iter().enumerate() {
                if sign != 0.0 {
                    out[row] = sign * value;
                }
            }
        }
        out
    };
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
                    let r = Quat::from_mat4(&crate::pose::channel_rotations(joint, values));
                    let (a, b, c) = (turn * r * turn.inverse()).to_euler(euler_order(order));
                    for (&(column, _), angle) in columns(false).iter().zip([a, b, c]) {
                        row[column] = angle.to_degrees();
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
    kind: crate::pose::RotationKind,
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
    let Some(local) = crate::pose::rotation_of_numbers(kind, numbers) else {
        // Euler angles are the channel values themselves.
        return numbers.iter().copied().take(axes.len()).collect();
    };
    // An ASF bone turns about its own axis C: its channels' rotation is C⁻¹ · local · C.
    let rotation = match joint.axis {
        Some(c) => glam::Mat3::from_quat(c.inverse()) * local * glam::Mat3::from_quat(c),
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
    let sequence = euler_order(order);
    let (a, b, c) = rotation.to_euler(sequence);
    // The same rotation is also (a + π, π − b, c + π): with fewer than three channels the third
    // angle is dropped, so take the form whose third angle is the smaller (a joint bent past 90°
    // about its second axis needs the second form).
    let wrap = |angle: f32| {
        let pi = std::f32::consts::PI;
        if angle > pi {
            angle - 2.0 * pi
        } else if angle <= -pi {
            angle + 2.0 * pi
        } else {
            angle
        }
    };
    let pi = std::f32::consts::PI;
    let other = (wrap(a + pi), wrap(pi - b), wrap(c + pi));
    let (a, b, c) = if axes.len() < 3 && other.2.abs() < c.abs() {
        other
    } else {
        (a, b, c)
    };
    [a, b, c]
        .into_iter()
        .take(axes.len())
        .map(f32::to_degrees)
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

    #[test]
    fn mirroring_swaps_sides_and_reflects_by_hand_worked_values() {
        for (name, want) in [
            ("LeftArm", Some("RightArm")),
            ("mixamorig:RightHand", Some("mixamorig:LeftHand")),
            ("upperarm_l", Some("upperarm_r")),
            ("Arm.R", Some("Arm.L")),
            ("L_Knee", Some("R_Knee")),
            ("lhumerus", Some("rhumerus")),
            ("lShldr", Some("rShldr")),
            ("rForeArm", Some("lForeArm")),
            ("Hips", None),
            ("lowerback", None),
            ("rotation", None),
        ] {
            assert_eq!(mirrored_name(name).as_deref(), want, "{name}");
        }
        let text = TWO_FRAMES
            .replace("JOINT Chest", "JOINT LeftArm")
            .replace("OFFSET 0 10 0", "OFFSET 3 10 0");
        let bvh = take(&text);
        let (skeleton, motion) = mirror(&bvh.skeleton, &bvh.motion);
        assert_eq!(skeleton.joints[1].name, "RightArm");
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(-3.0, 10.0, 0.0));
        // Root position x negated; Z and Y rotations negated, X kept.
        assert_eq!(
            motion.frame(1),
            [-4.0, 2.0, -2.0, -0.0, 0.0, -0.0, -40.0, 0.0, -0.0]
        );
        // The mirror image: every world position with x negated.
        let mode = crate::pose::OffsetMode::Replace;
        let before = crate::pose::world_positions(&bvh.skeleton, bvh.motion.frame(2), mode);
        let after = crate::pose::world_positions(&skeleton, motion.frame(2), mode);
        for (b, a) in before.iter().zip(&after) {
            assert!(
                glam::Vec3::new(-b.x, b.y, b.z).abs_diff_eq(*a, 1e-4),
                "{b} {a}"
            );
        }
    }

    #[test]
    fn in_place_and_ground_by_hand_worked_values() {
        let bvh = take(TWO_FRAMES);
        let still = in_place(&bvh.skeleton, &bvh.motion, crate::pose::Up::Y);
        // x and z stay at frame 0's (0, 0); y keeps moving.
        assert_eq!(&still.frame(2)[..3], [0.0, 4.0, 0.0]);
        // The lowest point is the root at frame 0 (y 0) once the chest bends down: lift the
        // chain so that its lowest joint sits at 0.
        let bent = take(&TWO_FRAMES.replace("8 4 -4 0 0 0 80 0 0", "8 4 -4 0 0 0 180 0 0"));
        let mode = crate::pose::OffsetMode::Replace;
        let (skeleton, motion) =
            ground(&bent.skeleton, &bent.motion, mode, crate::pose::Up::Y).unwrap();
        // Frame 2: root at y 4, chest at 14, the site 5 below the chest (turned 180°): 9. Frame
        // 0: root at 0, the lowest anywhere. So nothing moves.
        assert_eq!(motion.frame(2)[1], 4.0);
        let lifted = take(&TWO_FRAMES.replace("0 0 0 0 0 0 0 0 0\n4", "0 -7 0 0 0 0 0 0 0\n4"));
        let (_, motion) =
            ground(&lifted.skeleton, &lifted.motion, mode, crate::pose::Up::Y).unwrap();
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
            crate::pose::Up::Y,
            crate::pose::Up::Z,
        )
        .unwrap();
        // Y-up to Z-up: (x, y, z) becomes (x, -z, y).
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 0.0, 10.0));
        let mode = crate::pose::OffsetMode::Replace;
        for frame in 0..3 {
            let before = crate::pose::world_positions(&bvh.skeleton, bvh.motion.frame(frame), mode);
            let after = crate::pose::world_positions(&skeleton, motion.frame(frame), mode);
            for (b, a) in before.iter().zip(&after) {
                assert!(
                    glam::Vec3::new(b.x, -b.z, b.y).abs_diff_eq(*a, 1e-4),
                    "{b} {a}"
                );
            }
        }
        let (back, motion_back) =
            reorient(&skeleton, &motion, crate::pose::Up::Z, crate::pose::Up::Y).unwrap();
        let again = crate::pose::world_positions(&back, motion_back.frame(2), mode);
        let original = crate::pose::world_positions(&bvh.skeleton, bvh.motion.frame(2), mode);
        for (a, o) in again.iter().zip(&original) {
            assert!(a.abs_diff_eq(*o, 1e-4));
        }
    }
}
