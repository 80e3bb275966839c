//! Measures of a retarget: how far limb directions are from the source's, how far the
//! followable joints are, and how the retargeted take stands and travels (the hips' path, the
//! floor, how far planted feet slide).

use crate::model::body::Limb;
use crate::model::body::contact::{Planting, sliding};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use crate::retarget::align::{Ups, bones, hip_height, source_offset_mode, to_y_up};
use crate::retarget::map::Map;
use glam::{DQuat, DVec3};

/// The angle in degrees between each bone's world direction in the source and in the
/// retargeted take: per bone of [`bones`] (in its order), one per frame: the check that the
/// rest alignment holds; [`quantile`] of them all gives the figures in the guide.
pub fn direction_errors(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    target_motion: &Motion,
    map: &Map,
    ups: Ups,
) -> Vec<Vec<f64>> {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let pairs = bones(source, target, map);
    let source_mode = source_offset_mode(source, source_motion);
    let mut errors = vec![Vec::new(); pairs.len()];
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    let frames = source_motion.frame_count().min(target_motion.frame_count());
    for frame in 0..frames {
        world_transforms_f64(source, source_motion.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            target_motion.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        for (bone, &(t, d)) in pairs.iter().enumerate() {
            let (Some(s), Some(sd)) = (map.source_of[t], map.source_of[d]) else {
                continue;
            };
            let a = us * (ws[sd].1 - ws[s].1);
            let b = ut * (wt[d].1 - wt[t].1);
            if a.length() > 1e-9 && b.length() > 1e-9 {
                errors[bone].push(a.angle_between(b).to_degrees());
            }
        }
    }
    errors
}

/// [`direction_errors`] of the part of each bone's direction its target joint can follow: the
/// whole direction where the joint has three rotation channels; where it has one or two (an ASF
/// hinge knee `dof rx`, a foot `dof rx rz`), the direction across its first channel's axis, in
/// the plane that axis turns the bone in (what is along the axis comes from the parent's
/// rotation and the rest pose, which the hinge cannot change); `None` for a bone whose joint has
/// no rotation channel (CMU's `lhipjoint`), which follows nothing.
pub fn followable_errors(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    target_motion: &Motion,
    map: &Map,
    ups: Ups,
) -> Vec<Option<Vec<f64>>> {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let pairs = bones(source, target, map);
    let source_mode = source_offset_mode(source, source_motion);
    // Per bone: the first rotation channel's axis in the joint's frame, for joints with fewer
    // than three; `Some(None)` for three.
    let axes: Vec<Option<Option<DVec3>>> = pairs
        .iter()
        .map(|&(t, _)| {
            let joint = &target.joints[t];
            if joint.rotation_order.is_some() {
                return Some(None);
            }
            let first = joint.channels.iter().find(|c| c.is_rotation())?;
            let c = joint
                .axis
                .map_or(DQuat::IDENTITY, |c| c.as_dquat().normalize());
            Some(Some(c * DVec3::AXES[first.axis()]))
        })
        .collect();
    let mut errors: Vec<Option<Vec<f64>>> = axes.iter().map(|a| a.map(|_| Vec::new())).collect();
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    let frames = source_motion.frame_count().min(target_motion.frame_count());
    for frame in 0..frames {
        world_transforms_f64(source, source_motion.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            target_motion.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        for (bone, &(t, d)) in pairs.iter().enumerate() {
            let (Some(s), Some(sd), Some(Some(out))) =
                (map.source_of[t], map.source_of[d], errors.get_mut(bone))
            else {
                continue;
            };
            let mut a = us * (ws[sd].1 - ws[s].1);
            let mut b = ut * (wt[d].1 - wt[t].1);
            if let Some(Some(axis)) = axes[bone] {
                let axis = (ut * (wt[t].0 * axis)).normalize();
                a -= axis * a.dot(axis);
                b -= axis * b.dot(axis);
            }
            if a.length() > 1e-9 && b.length() > 1e-9 {
                out.push(a.angle_between(b).to_degrees());
            }
        }
    }
    errors
}

/// How a retargeted take stands and travels beside its source, each take in its own file's
/// units turned y-up: what [`standing`] measures.
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::{self, Map, Ups};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..60);
/// let smpl = retarget::onto(&walk, "smpl22")?;
/// let map = Map::guess(&walk.skeleton, &smpl.skeleton);
/// // Metres per unit of the source: CMU's takes keep their ASF's unit, 1/0.45 inch.
/// let stand = retarget::standing(
///     &walk.skeleton, &walk.motion, &smpl.skeleton, &smpl.motion, &map, Ups::default(), 0.056,
/// );
/// assert!(stand.pelvis > 0.8, "the pelvis keeps its width");
/// let expected = stand.ratio * stand.source_path;
/// assert!((stand.target_path - expected).abs() <= 0.02 * expected, "the path scaled by the legs");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Standing {
    /// The target's legs over the source's (the retarget's scale of the hips' path and floor).
    pub ratio: f64,
    /// The hips' path along the floor in the source, summed frame to frame.
    pub source_path: f64,
    /// The same in the target ([`Standing::ratio`] times the source's, when it is right).
    pub target_path: f64,
    /// The lowest height of the source's foot points
    /// ([`Body::foot_points`](crate::model::body::Body::foot_points): its own ankles and toes,
    /// mapped or not) over the take.
    pub source_floor: f64,
    /// The same of the target's own foot points (the ratio times the source's: the target's
    /// feet on the source's floor).
    pub target_floor: f64,
    /// How far planted feet slide, each take in its own legs' lengths: for each target ankle
    /// the map carries, its path along the floor during the contacts the reading of the body
    /// finds on the source's ankle ([`crate::model::body::contact`]), summed over the feet. The
    /// same frames on both sides, and a figure a taller target does not inflate. (Ankles, not
    /// toes: what `--lock-feet` holds.)
    pub source_sliding: f64,
    /// The same of the target's foot points.
    pub target_sliding: f64,
    /// The contacts those figures are taken over.
    pub contacts: usize,
    /// The least, over the frames, of the target's thigh-to-thigh distance over its rest
    /// distance: 1 when the pelvis keeps its width (a map that put both thighs on one source
    /// joint collapsed it to 0); 1 without two thighs.
    pub pelvis: f64,
}

/// [`Standing`] of `target_motion`, retargeted from `source_motion` by `map`. `source_metres`:
/// metres per unit of the source's file, for the contacts' thresholds.
pub fn standing(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    target_motion: &Motion,
    map: &Map,
    ups: Ups,
    source_metres: f64,
) -> Standing {
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let source_mode = source_offset_mode(source, source_motion);
    let (mut rest_s, mut rest_t) = (Vec::new(), Vec::new());
    world_transforms_f64(source, &[], OffsetMode::Replace, &mut rest_s);
    world_transforms_f64(target, &[], OffsetMode::Replace, &mut rest_t);
    let hips = map
        .target_body
        .hips
        .and_then(|t| Some((t, map.source_of[t]?)));
    // As the retarget scales: legs over legs, 1 where either cannot be measured (the sliding
    // figures are then in each file's own units).
    let (legs_s, legs_t) = match hips {
        Some((t, s)) => (
            hip_height(source, &map.source_body, s, &rest_s),
            hip_height(target, &map.target_body, t, &rest_t),
        ),
        None => (1.0, 1.0),
    };
    let (legs_s, legs_t) = if legs_s > 1e-9 && legs_t > 1e-9 {
        (legs_s, legs_t)
    } else {
        (1.0, 1.0)
    };
    let feet: Vec<(usize, usize)> = map
        .target_body
        .limbs
        .iter()
        .filter_map(|limb| limb[Limb::Foot as usize])
        .filter_map(|t| Some((map.source_of[t]?, t)))
        .collect();
    let thighs: Vec<usize> = map
        .target_body
        .limbs
        .iter()
        .filter_map(|limb| limb[Limb::Thigh as usize])
        .collect();
    let mut pelvis = 1.0f64;
    let rest_width = match thighs[..] {
        [a, b] => (rest_t[a].1 - rest_t[b].1).length(),
        _ => 0.0,
    };
    let (floor_s, floor_t) = (
        map.source_body.foot_points(source),
        map.target_body.foot_points(target),
    );
    let (mut source_floor, mut target_floor) = (f64::INFINITY, f64::INFINITY);
    let frames = source_motion.frame_count().min(target_motion.frame_count());
    let mut hips_s = Vec::with_capacity(frames);
    let mut hips_t = Vec::with_capacity(frames);
    let mut tracks_s = vec![Vec::with_capacity(frames); feet.len()];
    let mut tracks_t = vec![Vec::with_capacity(frames); feet.len()];
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    for frame in 0..frames {
        world_transforms_f64(source, source_motion.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            target_motion.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        if let Some((t, s)) = hips {
            hips_s.push(us * ws[s].1);
            hips_t.push(ut * wt[t].1);
        }
        if let ([a, b], true) = (&thighs[..], rest_width > 0.0) {
            let (a, b) = (*a, *b);
            pelvis = pelvis.min((wt[a].1 - wt[b].1).length() / rest_width);
        }
        for &s in &floor_s {
            source_floor = source_floor.min((us * ws[s].1).y);
        }
        for &t in &floor_t {
            target_floor = target_floor.min((ut * wt[t].1).y);
        }
        for (k, &(s, t)) in feet.iter().enumerate() {
            tracks_s[k].push(us * ws[s].1);
            tracks_t[k].push(ut * wt[t].1);
        }
    }
    let path = |track: &[DVec3]| {
        track
            .windows(2)
            .map(|w| DVec3::new(w[1].x - w[0].x, 0.0, w[1].z - w[0].z).length())
            .sum::<f64>()
    };
    let planting = Planting::default();
    let mut standing = Standing {
        ratio: legs_t / legs_s,
        source_path: path(&hips_s),
        target_path: path(&hips_t),
        source_floor,
        target_floor,
        pelvis,
        ..Standing::default()
    };
    let in_metres: Vec<Vec<DVec3>> = tracks_s
        .iter()
        .map(|track| track.iter().map(|&p| p * source_metres).collect())
        .collect();
    let planted_all = planting.frames_of(&in_metres, DVec3::Y, source_motion.frame_time);
    for ((track_s, track_t), planted) in tracks_s.iter().zip(&tracks_t).zip(&planted_all) {
        let contacts = Planting::contacts(planted);
        standing.contacts += contacts.len();
        standing.source_sliding += sliding(track_s, DVec3::Y, &contacts).0 / legs_s;
        standing.target_sliding += sliding(track_t, DVec3::Y, &contacts).0 / legs_t;
    }
    standing
}

/// The value at fraction `q` (0 to 1) of sorted `values`.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let index = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[index]
}
