//! Mirroring a take: left and right swapped (or each joint reflected where it is), across the
//! axis the figure's sides lie along.

use crate::io::error::Error;
use crate::model::body::mirrored_name;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::skeleton::{Channel, RotationOrder, Skeleton};
use glam::DQuat;

/// How [`mirror()`] makes the mirror image.
///
/// ```
/// use bvhview::{Take, edit::{MirrorOptions, mirror}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = MirrorOptions { rename: true, ..MirrorOptions::default() };
/// let (skeleton, _motion) = mirror(&take.skeleton, &take.motion, &options)?;
/// let arm = take.skeleton.joints.iter().position(|j| j.name == "LeftArm").unwrap();
/// assert_eq!(skeleton.joints[arm].name, "RightArm"); // reflected where it is, renamed
/// // The default swaps: every name kept, left and right exchange their motion.
/// let (swapped, _) = mirror(&take.skeleton, &take.motion, &MirrorOptions::default())?;
/// assert_eq!(swapped.joints[arm].name, "LeftArm");
/// # Ok(())
/// # }
/// ```
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
/// for joints whose counterpart cannot take their motion): the pairs [`crate::model::body::name_side`] (or `names`)
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
                Error::usage(format!(
                    "mirror names: '{name}' is not a joint of the skeleton (a swap pairs joints \
                     the skeleton has)"
                ))
            })
        };
        let (a, b) = (find(from)?, find(to)?);
        for (x, y) in [(a, b), (b, a)] {
            if given.get(&x).is_some_and(|&other| other != y) {
                return Err(Error::usage(format!(
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
            return Err(Error::usage(format!(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::testing::*;

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
}
