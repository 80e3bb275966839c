//! Rest alignment: which bones drive which, the turn that puts the target's rest bones onto
//! the source's, and the heights the hips' path is scaled by.

use crate::model::body::{Body, Limb, is_ancestor};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use crate::retarget::map::{Map, mapped_below};
use glam::{DQuat, DVec3};

/// A source's width below this many of its legs' lengths is no pelvis or shoulders at all: its
/// reading of the body put both sides on one point (an ASF's pelvis bones read as thighs), and
/// nothing put on it can be stood behind.
pub const NO_WIDTH: f64 = 0.05;

/// The two skeletons' up axes, as their takes stand.
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::pose::{OffsetMode, Up};
/// use bvhview::model::stance::Stance;
/// use bvhview::retarget::{self, Map, Target, Ups};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..30);
/// let target = Target::load("smpl22", u64::MAX)?;
/// let source = Stance::guess(&take.skeleton, &take.motion, OffsetMode::Replace, None).up;
/// let ups = Ups { source, target: target.up };
/// assert_eq!(ups, Ups { source: Up::Y, target: Up::Y });
/// let map = Map::guess(&take.skeleton, &target.skeleton);
/// let (source, motion) = (&take.skeleton, &take.motion);
/// let (_, motion) = retarget::retarget(source, motion, &target.skeleton, &map, ups, 1)?;
/// assert_eq!(motion.frame_count(), 30);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ups {
    /// The up axis of the take being retargeted.
    pub source: Up,
    /// The up axis of the skeleton it is put on.
    pub target: Up,
}

/// [`Up::to_y_up`] in 64-bit floats (the 32-bit quaternion is not of unit length to 64 bits).
pub(super) fn to_y_up(up: Up) -> DQuat {
    match up {
        Up::Y => DQuat::IDENTITY,
        Up::Z => DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2),
    }
}

pub(super) fn subtree_size(skeleton: &Skeleton, joint: usize) -> usize {
    1 + skeleton.joints[joint]
        .children
        .iter()
        .map(|&c| subtree_size(skeleton, c))
        .sum::<usize>()
}

/// The bones both skeletons have, one per mapped target joint: to the next mapped joint down its
/// chain (the spine's way at the hips and chest, else the largest branch), where neither skeleton's
/// bone has zero length (CMU's `LowerBack` and `Neck` sit where their parents do: its hips and
/// chest have no bone there). `(target joint, target child)`; the source's are their map. The bones
/// [`direction_errors`](crate::retarget::direction_errors) measures.
pub fn bones(source: &Skeleton, target: &Skeleton, map: &Map) -> Vec<(usize, usize)> {
    main_bones(source, target, map)
        .into_iter()
        .filter(|&(_, _, direct)| direct)
        .map(|(t, d, _)| (t, d))
        .collect()
}

/// [`bones`], and where a bone has zero length on either skeleton, the chord to the next joint
/// down the chain that does not (`false`): what rest alignment turns onto the source's.
pub(super) fn main_bones(
    source: &Skeleton,
    target: &Skeleton,
    map: &Map,
) -> Vec<(usize, usize, bool)> {
    let (mut source_rest, mut target_rest) = (Vec::new(), Vec::new());
    world_transforms_f64(source, &[], OffsetMode::Replace, &mut source_rest);
    world_transforms_f64(target, &[], OffsetMode::Replace, &mut target_rest);
    let central: Vec<usize> = map
        .target_body
        .roles()
        .into_iter()
        .filter(|(r, _)| r.central())
        .map(|(_, j)| j)
        .collect();
    let primary = |t: usize, s: usize| {
        let below: Vec<usize> = mapped_below(target, &map.source_of, t)
            .into_iter()
            .filter(|&d| map.source_of[d] != Some(s))
            .collect();
        below
            .iter()
            .copied()
            .find(|d| central.contains(d))
            .or_else(|| {
                below
                    .iter()
                    .copied()
                    .max_by_key(|&d| (subtree_size(target, d), std::cmp::Reverse(d)))
            })
    };
    let mut bones = Vec::new();
    for (t, s) in map.source_of.iter().enumerate() {
        let Some(s) = *s else { continue };
        let mut d = primary(t, s);
        let mut direct = true;
        while let Some(next) = d {
            let Some(sd) = map.source_of[next] else { break };
            let short = (target_rest[next].1 - target_rest[t].1).length() < 1e-5
                || (source_rest[sd].1 - source_rest[s].1).length() < 1e-5;
            if !short {
                break;
            }
            direct = false;
            d = primary(next, s);
        }
        if let Some(d) = d {
            bones.push((t, d, direct));
        }
    }
    bones
}

/// Turns `from` onto `to` by the smallest rotation (none when they already agree).
pub(super) fn arc(from: DVec3, to: DVec3) -> DQuat {
    let (from, to) = (from.normalize(), to.normalize());
    if from.dot(to) > 1.0 - 1e-15 {
        DQuat::IDENTITY
    } else {
        DQuat::from_rotation_arc(from, to)
    }
}

/// Per target joint, the rotation A (in a Y-up world) that turns the target's rest bones onto
/// the source's: the parent's, then the smallest turn of the main bone onto the source's, then
/// a twist about it that best lays the other bones (the hips' legs, the chest's clavicles) on
/// theirs.
pub(super) fn alignments(
    source: &Skeleton,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    source_rest: &[(DQuat, DVec3)],
    target_rest: &[(DQuat, DVec3)],
) -> Vec<DQuat> {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let main: std::collections::HashMap<usize, usize> = main_bones(source, target, map)
        .into_iter()
        .map(|(t, d, _)| (t, d))
        .collect();
    let mut aligned = vec![DQuat::IDENTITY; target.joints.len()];
    for t in 0..target.joints.len() {
        let base = target.joints[t]
            .parent
            .map_or(DQuat::IDENTITY, |p| aligned[p]);
        let Some(s) = map.source_of[t] else {
            aligned[t] = base;
            continue;
        };
        let vectors = |d: usize| {
            let ds = map.source_of[d]?;
            let tv = ut * (target_rest[d].1 - target_rest[t].1);
            let sv = us * (source_rest[ds].1 - source_rest[s].1);
            (tv.length() > 1e-9 && sv.length() > 1e-9).then_some((tv, sv))
        };
        let Some((tv, sv)) = main.get(&t).and_then(|&d| vectors(d)) else {
            aligned[t] = base;
            continue;
        };
        let swung = arc(base * tv, sv) * base;
        let axis = sv.normalize();
        let (main_tv, main_sv) = (tv, sv);
        let (mut sin, mut cos) = (0.0, 0.0);
        // Not the main bone's chain: what hangs off it further up (the arms off the chest,
        // seen from the hips) turns with other joints and says nothing of this one's facing.
        let main_end = main.get(&t).copied();
        let mut todo: Vec<usize> = mapped_below(target, &map.source_of, t)
            .into_iter()
            .filter(|&d| {
                map.source_of[d] != Some(s) && main_end.is_none_or(|m| !is_ancestor(target, d, m))
            })
            .collect();
        let mut descended = 0;
        while let Some(d) = todo.pop() {
            // A joint on the main bone's line, or where the joint is (CMU's collars start on
            // the chest), says nothing of the turn about it: their rounding picked the chest's
            // facing, and the collars crossed at the chest. The joints below it say it instead.
            let informative = vectors(d).and_then(|(tv, sv)| {
                let a = swung * tv;
                let a = a - axis * a.dot(axis);
                let b = sv - axis * sv.dot(axis);
                let across = |v: DVec3, of: DVec3, main: DVec3| {
                    v.length() >= 0.1 * of.length() && v.length() >= 0.02 * main.length()
                };
                (across(a, tv, main_tv) && across(b, sv, main_sv)).then_some((a, b))
            });
            let Some((a, b)) = informative else {
                if descended < 64 {
                    descended += 1;
                    todo.extend(mapped_below(target, &map.source_of, d));
                }
                continue;
            };
            sin += a.cross(b).dot(axis);
            cos += a.dot(b);
        }
        // Half a turn has no sine: the hips of a source that faces away from the target's rest
        // (a Z-up take facing +y, -z once turned Y up) turn by the cosine's sign alone (a test
        // of the sine alone left them unturned: the legs crossed at the pelvis).
        let twist = match sin == 0.0 && cos >= 0.0 {
            true => DQuat::IDENTITY,
            false => DQuat::from_axis_angle(axis, sin.atan2(cos)),
        };
        aligned[t] = twist * swung;
    }
    aligned
}

/// How tall the hips stand: the legs' length ([`Body::leg_length`]). Without legs: the spread
/// of the rest pose along the body from the hips.
pub(super) fn hip_height(
    skeleton: &Skeleton,
    body: &Body,
    hips: usize,
    rest: &[(DQuat, DVec3)],
) -> f64 {
    body.leg_length(rest).unwrap_or_else(|| {
        (0..skeleton.joints.len())
            .map(|j| (rest[j].1 - rest[hips].1).length())
            .fold(0.0, f64::max)
    })
}

/// Where the floor is read: the foot points of the reading of the body (each leg's ankle and
/// toe), so that the target's own feet stand where the source's stood; a source's toe tip the
/// target does not have would sink the target's feet by its height. Without two feet: every
/// joint of the legs (everything under a thigh, End Sites too).
pub(super) fn floor_points(skeleton: &Skeleton, body: &Body) -> Vec<usize> {
    let feet = body.foot_points(skeleton);
    if !feet.is_empty() {
        return feet;
    }
    let thighs: Vec<usize> = [
        body.limbs[0][Limb::Thigh as usize],
        body.limbs[1][Limb::Thigh as usize],
    ]
    .into_iter()
    .flatten()
    .collect();
    (0..skeleton.joints.len())
        .filter(|&j| thighs.iter().any(|&t| is_ancestor(skeleton, t, j)))
        .collect()
}

/// How a source's position channels combine with its OFFSETs: as written (MakeHuman's files
/// mean "added to OFFSET", as the dataset compiler also reads them), else replacing them.
pub(super) fn source_offset_mode(source: &Skeleton, motion: &Motion) -> OffsetMode {
    match crate::model::pose::written_for_other_mode(source, motion, OffsetMode::Replace) {
        Some(_) => OffsetMode::Add,
        None => OffsetMode::Replace,
    }
}

/// The source pose rest alignment reads the source's bones in: `None` for its rest pose, or a
/// frame of its take where the rest pose says nothing of which way the body faces (its thighs,
/// or its upper arms, on one point: Blender's FBX rest, every bone along its parent's +y, which
/// left the hips and chest unturned and the sides crossed). The frame is the one of up to 64
/// spread over the take where the narrower of the two widths is widest.
pub(super) fn reference_frame(
    source: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    body: &Body,
    rest: &[(DQuat, DVec3)],
) -> Option<usize> {
    let pairs: Vec<(usize, usize)> = [Limb::Thigh, Limb::UpperArm]
        .into_iter()
        .filter_map(|limb| match body.limbs.map(|side| side[limb as usize]) {
            [Some(left), Some(right)] => Some((left, right)),
            _ => None,
        })
        .collect();
    let legs = body.leg_length(rest).filter(|&l| l > 1e-9)?;
    let narrowest = |world: &[(DQuat, DVec3)]| {
        pairs
            .iter()
            .map(|&(l, r)| (world[l].1 - world[r].1).length() / legs)
            .fold(f64::INFINITY, f64::min)
    };
    if pairs.is_empty() || narrowest(rest) >= NO_WIDTH || motion.frame_count() == 0 {
        return None;
    }
    let frames = motion.frame_count();
    let mut world = Vec::new();
    let mut best: Option<(usize, f64)> = None;
    let looked = frames.min(64);
    for k in 0..looked {
        let frame = match looked {
            1 => 0,
            _ => k * (frames - 1) / (looked - 1),
        };
        world_transforms_f64(source, motion.frame(frame), mode, &mut world);
        let width = narrowest(&world);
        if best.is_none_or(|(_, w)| width > w) {
            best = Some((frame, width));
        }
    }
    best.filter(|&(_, width)| width >= NO_WIDTH)
        .map(|(frame, _)| frame)
}
