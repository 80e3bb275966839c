//! Joint positions to rotations (`bvhview solve`, Python `Motion.from_positions`): what a pose
//! estimator or a text-to-motion model outputs, frames × joints × 3, becomes a take on a
//! skeleton, in the skeleton's own channels and rotation orders.
//!
//! Each joint of the skeleton the data names turns so that the bones to its nearest named
//! joints below it point where the data's do: with one such bone (or several along one line),
//! by the smallest turn from where its parent carries it in the first frame, and after it by
//! the turn nearest the frame before's (the data leaves the twist about the bone free: it is
//! carried from frame to frame, so it never flips); with several (the hips: both thighs and
//! the spine; the chest: the neck and both clavicles), by the rotation that best lays them all
//! (Horn's quaternion method), which lays each exactly when the data's shape is the skeleton's.
//! Euler angles are unwrapped to the nearest equivalent of the frame before's. Joints the data
//! does not name keep their rest rotation. Bone lengths are the skeleton's (where the data's
//! differ, directions are kept), but for named joints with position channels, which are put
//! where the data says. The root moves the shallowest named joint to where the data puts it,
//! scaled by the skeleton's legs over the data's (as retargeting scales a path).

mod horn;
pub mod input;
pub mod layouts;
pub(crate) mod positions;
mod reach;

use horn::best_rotation;
pub use input::{
    MAX_NPY_HEADER_BYTES, MAX_NPY_HEADER_NESTING, joint_names, read_csv, read_npy, read_npy_file,
    read_npy_rows, read_positions,
};
pub use positions::{Positions, SMPL22_ORDER};
use reach::{hinge_twist, out_of_reach_deep, reach_twist, twist_axis, twist_search};

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::body::Body;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, UpAxis, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use glam::{DQuat, DVec3};

/// What [`solve`] did: which joints it matched, how it scaled, how near the solved take comes
/// to the data.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// use bvhview::solve::{Positions, joint_names, read_npy, solve};
///
/// // A CMU walk's 22 joints in SMPL's order, metres (tests/solve/walk_smpl22.npy), onto smpl22.
/// let bytes = std::fs::read("tests/solve/walk_smpl22.npy").expect("in the repository");
/// let (_, points) = read_npy(&bytes, "walk_smpl22.npy")?;
/// let positions = Positions::new(joint_names("smpl22"), points, 1.0 / 120.0)?;
/// let target = bvhview::retarget::Target::load("smpl22", u64::MAX)?;
/// let (motion, solved) = solve(&target.skeleton, target.up, &positions, None)?;
/// assert_eq!(motion.frame_count(), 120);
/// assert!((solved.scale - 100.0).abs() < 1e-3); // metres onto smpl22's centimetres
/// assert!(solved.unmatched.is_empty());
/// assert!(solved.off_the_data(&target.skeleton).is_empty()); // smpl22's own bones
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solved {
    /// The skeleton's legs over the data's (1 without legs in both): what the root's path is
    /// multiplied by.
    pub scale: f64,
    /// Per skeleton point the data names (joint or End Site, in skeleton order): the point, and
    /// the farthest the solved take puts it from where the data does (scaled, in the
    /// skeleton's units), over every frame.
    pub errors: Vec<(usize, f64)>,
    /// The largest turn of a joint between two frames: the joint, the first of the two frames,
    /// its turn from its parent (degrees), and how far the data's bones it lays turn there, seen
    /// from that parent (degrees). A twist about a bone is not in the data's figure: the
    /// positions do not show it.
    pub largest_turn: Option<(usize, usize, f64, f64)>,
    /// As [`Solved::largest_turn`], the turn farthest past twice the data's and 5° (a flip the
    /// data does not show), where one is; `None` where every turn is within.
    pub beyond_the_data: Option<(usize, usize, f64, f64)>,
    /// Data points the skeleton has no point of that name for, left out.
    pub unmatched: Vec<String>,
    /// What could not be done as asked (a root without position channels; a joint that turns
    /// about fewer than three axes).
    pub notes: Vec<String>,
}

impl Solved {
    /// Each point the data names that the solved take puts farther than 1e-4 of the skeleton's
    /// height from it (where the data's bones are not the skeleton's), farthest first, as
    /// `name by distance` (skeleton units); empty when every one is nearer.
    pub fn off_the_data(&self, skeleton: &Skeleton) -> Vec<String> {
        let mut rest = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
        let (low, high) = rest.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(low, high), (_, at)| (low.min(*at), high.max(*at)),
        );
        let size = (high - low).max_element().max(1e-9);
        let points = crate::positions::export_points(skeleton);
        let mut off: Vec<(usize, f64)> = self
            .errors
            .iter()
            .copied()
            .filter(|&(_, e)| e > 1e-4 * size)
            .collect();
        off.sort_by(|a, b| b.1.total_cmp(&a.1));
        off.into_iter()
            .map(|(j, e)| {
                let name = points.iter().find(|&&(_, point)| point == j).map_or_else(
                    || crate::model::skeleton::export_name(skeleton, j),
                    |(n, _)| n.clone(),
                );
                format!("{name} by {e:.4}")
            })
            .collect()
    }

    /// [`Solved::off_the_data`] as one line: the ten farthest, and how many more.
    pub fn off_the_data_line(&self, skeleton: &Skeleton) -> Option<String> {
        let off = self.off_the_data(skeleton);
        let shown = off.iter().take(10).cloned().collect::<Vec<_>>().join(", ");
        match off.len() {
            0 => None,
            1..=10 => Some(shown),
            n => Some(format!("{shown} and {} more", n - 10)),
        }
    }

    /// This report measured again on `motion`, a take of `skeleton` (as [`solve`] made it from
    /// `positions`, read along `up`, then perhaps smoothed): so what `bvhview solve` prints is
    /// measured on what it writes. The channels are measured as the take holds them, 32-bit
    /// floats, which is what BVH stores: it writes each as its shortest round-trip form, so the
    /// file reads back to these values exactly (glTF's quaternions are made from them, within
    /// 1e-7).
    ///
    /// ```
    /// # fn main() -> Result<(), bvhview::Error> {
    /// use bvhview::solve::{Positions, joint_names, read_npy, solve};
    ///
    /// let bytes = std::fs::read("tests/solve/walk_smpl22.npy").expect("in the repository");
    /// let (_, points) = read_npy(&bytes, "walk_smpl22.npy")?;
    /// let positions = Positions::new(joint_names("smpl22"), points, 1.0 / 120.0)?;
    /// let target = bvhview::retarget::Target::load("smpl22", u64::MAX)?;
    /// let (motion, solved) = solve(&target.skeleton, target.up, &positions, None)?;
    /// let smoothed = bvhview::edit::smooth(&target.skeleton, &motion, 6.0)?;
    /// let after = solved.measured_on(&target.skeleton, target.up, &positions, None, &smoothed);
    /// // Smoothing a clean walk moves its points off the data, a little.
    /// assert!(after.worst() > solved.worst());
    /// assert!(after.worse_than(&solved, &target.skeleton).is_some());
    /// // Unsmoothed, no joint turns past twice its bones' turn and 5° between two frames.
    /// assert!(solved.beyond_the_data.is_none() && solved.largest_turn.is_some());
    /// # Ok(())
    /// # }
    /// ```
    pub fn measured_on(
        &self,
        skeleton: &Skeleton,
        skeleton_up: Up,
        positions: &Positions,
        up: Option<UpAxis>,
        motion: &Motion,
    ) -> Solved {
        let count = skeleton.joints.len();
        let points = crate::positions::export_points(skeleton);
        let (data_of, _) = match_points(skeleton, &points, positions);
        let turn = up_turn(skeleton_up, up);
        let data = |frame: usize, joint: usize| -> Option<DVec3> {
            data_of[joint].map(|k| turn * positions.at(frame, k))
        };
        let mut rest = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
        // The bones each joint lays: to the nearest named joints below it.
        let laid: Vec<Vec<usize>> = (0..count)
            .map(|j| match data_of[j] {
                Some(_) if !skeleton.joints[j].end_site => targets_of(skeleton, j, &data_of, &rest)
                    .into_iter()
                    .map(|(d, _, _)| d)
                    .collect(),
                _ => Vec::new(),
            })
            .collect();
        let mut errors: Vec<(usize, f64)> = (0..count)
            .filter(|&j| data_of[j].is_some())
            .map(|j| (j, 0.0))
            .collect();
        let mut largest_turn: Option<(usize, usize, f64, f64)> = None;
        let mut beyond_the_data: Option<(usize, usize, f64, f64)> = None;
        let (mut posed, mut last) = (Vec::new(), Vec::new());
        let frames = positions.frames().min(motion.frame_count());
        for f in 0..frames {
            world_transforms_f64(skeleton, motion.frame(f), OffsetMode::Replace, &mut posed);
            for (j, error) in errors.iter_mut() {
                if let Some(at) = data(f, *j) {
                    *error = error.max((posed[*j].1 - at * self.scale).length());
                }
            }
            if f > 0 {
                let parent = |world: &[(DQuat, DVec3)], j: usize| {
                    skeleton.joints[j]
                        .parent
                        .map_or(DQuat::IDENTITY, |p| world[p].0)
                };
                for (j, below) in laid.iter().enumerate().filter(|(_, b)| !b.is_empty()) {
                    let (was, now) = (parent(&last, j), parent(&posed, j));
                    let local = |world: &[(DQuat, DVec3)], p: DQuat| p.inverse() * world[j].0;
                    let turned = local(&last, was)
                        .angle_between(local(&posed, now))
                        .to_degrees();
                    // The data's bones, each seen from the joint's parent as the take turns it.
                    let shown = below
                        .iter()
                        .filter_map(|&d| {
                            let then = was.inverse() * (data(f - 1, d)? - data(f - 1, j)?);
                            let here = now.inverse() * (data(f, d)? - data(f, j)?);
                            let (then, here) = (then.try_normalize()?, here.try_normalize()?);
                            Some(then.angle_between(here).to_degrees())
                        })
                        .fold(0.0, f64::max);
                    let figure = (j, f - 1, turned, shown);
                    if largest_turn.is_none_or(|(_, _, t, _)| turned > t) {
                        largest_turn = Some(figure);
                    }
                    let past = turned - (2.0 * shown + 5.0);
                    if past > 0.0
                        && beyond_the_data.is_none_or(|(_, _, t, s)| past > t - (2.0 * s + 5.0))
                    {
                        beyond_the_data = Some(figure);
                    }
                }
            }
            std::mem::swap(&mut posed, &mut last);
        }
        Solved {
            errors,
            largest_turn,
            beyond_the_data,
            ..self.clone()
        }
    }

    /// The farthest any point the data names stands from it (skeleton units; 0 without any).
    pub fn worst(&self) -> f64 {
        self.errors.iter().map(|&(_, e)| e).fold(0.0, f64::max)
    }

    /// What got worse in this report against `without` (the same take unsmoothed), as a clause
    /// of [`Solved::summary`]'s line, or `None` when nothing did: smoothing that moves the
    /// points farther from the data, or turns a joint farther past the data's turn, says so.
    pub fn worse_than(&self, without: &Solved, skeleton: &Skeleton) -> Option<String> {
        let mut worse = Vec::new();
        if self.worst() > without.worst() + 1e-9 {
            worse.push(format!(
                "farthest from the data {:.4} (without: {:.4})",
                self.worst(),
                without.worst()
            ));
        }
        let past = |s: &Solved| {
            s.beyond_the_data
                .map_or(0.0, |(_, _, t, d)| t - (2.0 * d + 5.0))
        };
        if past(self) > past(without) + 1e-9 {
            let name = |s: &Solved| {
                s.beyond_the_data
                    .map_or(String::from("none"), |(j, _, t, d)| {
                        format!("{} {t:.1}° ({d:.1}°)", skeleton.joints[j].name)
                    })
            };
            worse.push(format!(
                "turns past the data's {} (without: {})",
                name(self),
                name(without)
            ));
        }
        (!worse.is_empty()).then(|| worse.join(", "))
    }

    /// The figure `bvhview solve` prints: the matched joints, the scale, the worst one, and the
    /// largest turn between two frames against the data's (or the turn farthest past twice the
    /// data's and 5°, named, where one is).
    pub fn summary(&self, skeleton: &Skeleton) -> String {
        let worst = self.errors.iter().copied().fold(
            None,
            |worst: Option<(usize, f64)>, (j, e)| match worst {
                Some((_, w)) if w >= e => worst,
                _ => Some((j, e)),
            },
        );
        let mut text = format!(
            "{} joints matched, path ×{:.4}",
            self.errors.len(),
            self.scale
        );
        if let Some((j, e)) = worst {
            // Named as the data names it (an ASF point by the bone that ends there).
            let name = crate::positions::export_points(skeleton)
                .into_iter()
                .find(|&(_, point)| point == j)
                .map_or_else(
                    || crate::model::skeleton::export_name(skeleton, j),
                    |(n, _)| n,
                );
            text += &format!("; farthest from the data: {name} by {e:.4}");
        }
        if let Some((j, f, turned, shown)) = self.beyond_the_data {
            text += &format!(
                "; turns more than the data shows: {} by {turned:.1}° between frames {f} and {} \
                 (its bones: {shown:.1}°)",
                skeleton.joints[j].name,
                f + 1
            );
        } else if let Some((j, _, turned, shown)) = self.largest_turn {
            text += &format!(
                "; largest turn between frames: {} {turned:.1}° (its bones: {shown:.1}°)",
                skeleton.joints[j].name
            );
        }
        if !self.unmatched.is_empty() {
            text += &format!("; not in the skeleton: {}", self.unmatched.join(", "));
        }
        text
    }
}

/// The take on `skeleton` (standing along `skeleton_up`, as [`crate::retarget::Target`] reads
/// it) whose joints stand where `positions` puts them (see the module docs), the positions'
/// `up` axis turned to the skeleton's (`None`: the skeleton's own). Refused when fewer than
/// two of the data's names are the skeleton's.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // A walk's own joint positions solved back onto its skeleton: the same positions.
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..20);
/// let names = take.point_names();
/// let mut points = Vec::new();
/// for f in 0..take.frame_count() {
///     points.extend(take.positions(f).unwrap().iter().map(|p| p.as_dvec3()));
/// }
/// let positions = bvhview::solve::Positions::new(names, points, take.motion.frame_time)?;
/// let up = take.stance(bvhview::model::pose::OffsetMode::Replace).up;
/// let (motion, solved) = bvhview::solve::solve(&take.skeleton, up, &positions, None)?;
/// assert_eq!(motion.frame_count(), 20);
/// assert!(solved.errors.iter().all(|&(_, e)| e < 1e-3), "{solved:?}");
/// # Ok(())
/// # }
/// ```
pub fn solve(
    skeleton: &Skeleton,
    skeleton_up: Up,
    positions: &Positions,
    up: Option<UpAxis>,
) -> Result<(Motion, Solved), Error> {
    let (data_of, unmatched) = matched_points(skeleton, positions)?;
    let mut rest = Vec::new();
    world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
    // The data turned to the skeleton's up axis.
    let turn = up_turn(skeleton_up, up);
    let (mut targets, free) = bones_to_lay(skeleton, &data_of, &rest);
    let from_parent = from_parent(skeleton, &rest);
    let scale = scale_of(skeleton, &rest, &data_of, positions, turn);
    let mut notes = fewer_axes_notes(skeleton, &targets);
    let (hips, carrier) = path_carrier(skeleton, &data_of);
    if carrier.is_none() {
        notes.push(format!(
            "no joint at or above {} has position channels: the take does not travel",
            hips.map_or("the hips", |h| skeleton.joints[h].name.as_str())
        ));
    }
    // Every other named joint with position channels takes its translation from the data too
    // (a Perception Neuron spine that stretches): the channels are there to move it.
    let placed: Vec<bool> = (0..skeleton.joints.len())
        .map(|j| moves(skeleton, j) && data_of[j].is_some() && Some(j) != carrier)
        .collect();
    // The carrier is put where the data says by its own channels, so a joint above it (Bandai's
    // `joint_Root`) need not turn towards it: turning would be a turn the data does not show.
    if let Some(c) = carrier {
        for above in targets.iter_mut() {
            above.retain(|&(d, _)| d != c);
        }
    }
    let frames = positions.frames();
    let channels = skeleton.channel_count();
    let values = (frames as u64).saturating_mul(channels as u64);
    if values > crate::io::limits::MAX_GENERATED_VALUES {
        return Err(Error::usage(format!(
            "positions: {frames} frames × {channels} channels are {values} values, more than the \
             {} bvhview makes in one take",
            crate::io::limits::MAX_GENERATED_VALUES
        )));
    }
    let plan = Plan {
        skeleton,
        positions,
        data_of,
        turn,
        rest,
        targets,
        free,
        from_parent,
        scale,
        hips,
        carrier,
        placed,
    };
    let data_out = plan.channels(frames, channels);
    let (skeleton_checked, motion) = crate::edit::finite(
        "solve",
        skeleton.clone(),
        Motion::new(positions.frame_time, channels, frames, data_out),
    )?;
    // How near the solved take comes to the data, and how it turns, measured on the take as
    // it stands (32-bit channels).
    let unmeasured = Solved {
        scale,
        errors: Vec::new(),
        largest_turn: None,
        beyond_the_data: None,
        unmatched,
        notes,
    };
    let solved = unmeasured.measured_on(&skeleton_checked, skeleton_up, positions, up, &motion);
    Ok((motion, solved))
}

/// Each skeleton joint's data point and the data's names the skeleton has no point of (see
/// [`match_points`]); refused when fewer than two joints are matched.
fn matched_points(
    skeleton: &Skeleton,
    positions: &Positions,
) -> Result<(Vec<Option<usize>>, Vec<String>), Error> {
    // The points as every export names them (`positions`, `Take::point_names`, Python):
    // `LeftToeBase_End` for an End Site; an ASF bone's name for the point where it ends.
    let points = crate::positions::export_points(skeleton);
    let names: Vec<&str> = points.iter().map(|(n, _)| n.as_str()).collect();
    let (data_of, unmatched) = match_points(skeleton, &points, positions);
    let matched = data_of.iter().flatten().count();
    if matched < 2 {
        return Err(Error::usage(
            Message::from(format!(
                "positions: {matched} of their {} joints are joints of the skeleton (its \
                 joints: {}); name them as the skeleton does, or give the layout (",
                positions.names.len(),
                names.iter().take(8).copied().collect::<Vec<_>>().join(", ")
            ))
            .argument("joints", Some("smpl22"))
            .text(")"),
        ));
    }
    Ok((data_of, unmatched))
}

/// Per joint, the named joints it turns towards with those bones at rest, and whether how it
/// turns is free (see inside).
fn bones_to_lay(
    skeleton: &Skeleton,
    data_of: &[Option<usize>],
    rest: &[(DQuat, DVec3)],
) -> (Vec<Vec<(usize, DVec3)>>, Vec<bool>) {
    // Per named joint, the named joints it turns towards and those bones at rest: the nearest
    // named joints below it, past any that stand where it stands at rest (CMU's `LHipJoint`
    // at the hips: the hips then turn towards the thighs beyond).
    let gathered: Vec<Vec<(usize, DVec3, usize)>> = (0..skeleton.joints.len())
        .map(|j| match data_of[j] {
            Some(_) => targets_of(skeleton, j, data_of, rest),
            None => Vec::new(),
        })
        .collect();
    // A joint whose every bone reaches its named joint past another named joint that turns
    // (CMU's hips: the thighs past `LHipJoint` and `RHipJoint`, the chest past `lowerback`; its
    // wrist: the fingers past `lhand`, the thumb's end past `LThumb`) puts nothing out of place
    // whichever way it turns: the joints between lay those bones. How it turns is then a choice,
    // and in it, each bone's direction from its parent's at rest (the one the joint continues).
    let free: Vec<bool> = gathered
        .iter()
        .map(|found| found.len() > 1 && found.iter().all(|t| t.2 > 0))
        .collect();
    let targets = gathered
        .iter()
        .map(|found| found.iter().map(|&(d, bone, _)| (d, bone)).collect())
        .collect();
    (targets, free)
}

/// Per joint, the direction of its bone from its parent at rest (`None` at a root or where
/// the bone has no length).
fn from_parent(skeleton: &Skeleton, rest: &[(DQuat, DVec3)]) -> Vec<Option<DVec3>> {
    skeleton
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            joint
                .parent
                .and_then(|p| (rest[j].1 - rest[p].1).try_normalize())
        })
        .collect()
}

/// A note per joint that turns towards the data about fewer than three axes (ASF's limited
/// joints).
fn fewer_axes_notes(skeleton: &Skeleton, targets: &[Vec<(usize, DVec3)>]) -> Vec<String> {
    let mut notes = Vec::new();
    let limited: Vec<bool> = skeleton
        .joints
        .iter()
        .map(|j| !j.end_site && j.rotation_order.is_none())
        .collect();
    for (j, joint) in skeleton.joints.iter().enumerate() {
        if limited[j] && joint.channels.iter().any(|c| c.is_rotation()) && !targets[j].is_empty() {
            notes.push(format!(
                "{} turns about fewer than three axes: its bones lie as near the data's as it can",
                joint.name
            ));
        }
    }
    notes
}

/// Whether joint `j` has position channels.
fn moves(skeleton: &Skeleton, j: usize) -> bool {
    skeleton.joints[j].channels.iter().any(|c| c.is_position())
}

/// The hips the path is measured at and the joint that carries the path (see inside).
fn path_carrier(skeleton: &Skeleton, data_of: &[Option<usize>]) -> (Option<usize>, Option<usize>) {
    // What carries the path: the joint with position channels nearest above the hips (or the
    // shallowest named joint), which moves that joint to where the data puts it, scaled.
    // Other joints with position channels that the data names are put where it says (a root
    // above the hips, Bandai's `joint_Root`, a translating spine); every other keeps its OFFSET,
    // so those bones keep the skeleton's lengths.
    let hips = Body::of(skeleton)
        .hips
        .filter(|&h| data_of[h].is_some())
        .or_else(|| {
            skeleton
                .roots()
                .find_map(|root| shallowest_named(skeleton, root, data_of))
        });
    let carrier = hips.and_then(|h| {
        let mut at = Some(h);
        while let Some(j) = at {
            if moves(skeleton, j) {
                return Some(j);
            }
            at = skeleton.joints[j].parent;
        }
        None
    });
    (hips, carrier)
}

/// What [`solve`] lays every frame by, worked out once from the skeleton and the data.
struct Plan<'a> {
    skeleton: &'a Skeleton,
    positions: &'a Positions,
    /// Each joint's data point.
    data_of: Vec<Option<usize>>,
    /// The turn from the data's up axis to the skeleton's.
    turn: DQuat,
    /// Each joint's world rotation and place at rest.
    rest: Vec<(DQuat, DVec3)>,
    /// Per joint, the named joints it turns towards and those bones at rest.
    targets: Vec<Vec<(usize, DVec3)>>,
    /// Per joint, whether how it turns is a choice ([`fit_or_carry`]).
    free: Vec<bool>,
    /// Per joint, its bone's direction from its parent at rest.
    from_parent: Vec<Option<DVec3>>,
    /// The skeleton's legs over the data's.
    scale: f64,
    /// The joint the path is put at.
    hips: Option<usize>,
    /// The joint whose position channels carry the path.
    carrier: Option<usize>,
    /// Per joint, whether the data puts it by its own position channels.
    placed: Vec<bool>,
}

/// What [`solve`] carries from joint to joint and frame to frame.
struct Carried {
    /// Each joint's world rotation, this frame as far as laid, else the frame before's.
    world: Vec<DQuat>,
    /// Each joint's world place this frame.
    at: Vec<DVec3>,
    /// One joint's bones and the data's, reused from joint to joint.
    pairs: Vec<(DVec3, DVec3)>,
    /// Each joint's angles in the frame before, to unwrap to.
    previous: Vec<Option<[f64; 3]>>,
    /// Each joint's rotation in the frame before, from its parent: where the data leaves a turn
    /// free (the twist about a lone bone), the one nearest it, so nothing flips between frames.
    before: Vec<Option<DQuat>>,
    /// Per joint laid by [`fit_or_carry`], whether it follows its fit (see there).
    following: Vec<bool>,
}

impl Plan<'_> {
    /// Where the data puts joint `joint` in `frame`, turned to the skeleton's up axis.
    fn data(&self, frame: usize, joint: usize) -> Option<DVec3> {
        self.data_of[joint].map(|k| self.turn * self.positions.at(frame, k))
    }

    /// Every frame's channels, frame after frame.
    fn channels(&self, frames: usize, channels: usize) -> Vec<f32> {
        let count = self.skeleton.joints.len();
        let mut data_out = vec![0.0f32; frames * channels];
        let mut carried = Carried {
            world: vec![DQuat::IDENTITY; count],
            at: vec![DVec3::ZERO; count],
            pairs: Vec::new(),
            previous: vec![None; count],
            before: vec![None; count],
            following: vec![true; count],
        };
        for f in 0..frames {
            let row = &mut data_out[f * channels..(f + 1) * channels];
            self.turn_joints(f, &mut carried, row);
            self.place_joints(f, &mut carried, row);
        }
        data_out
    }

    /// Frame `f`'s rotations, top down, written into `row`.
    fn turn_joints(&self, f: usize, carried: &mut Carried, row: &mut [f32]) {
        for (j, joint) in self.skeleton.joints.iter().enumerate() {
            let parent = joint.parent.map_or(DQuat::IDENTITY, |p| carried.world[p]);
            let wanted = self.wanted(f, j, parent, carried);
            let mut local = (parent.inverse() * wanted).normalize();
            if !joint.end_site {
                let angles;
                (angles, local) = self.angles(f, j, parent, local, &mut carried.previous[j]);
                let mut rotations = angles.into_iter();
                for (i, channel) in joint.channels.iter().enumerate() {
                    row[joint.first_channel + i] = if channel.is_position() {
                        joint.offset[channel.axis()]
                    } else {
                        rotations.next().unwrap_or(0.0).to_degrees() as f32
                    };
                }
            }
            carried.before[j] = Some(local);
            carried.world[j] = parent * local;
        }
    }

    /// Joint `j`'s world rotation in frame `f`, its parent's being `parent`: its bones laid
    /// where the data's are, or where its parent carries it when the data lays none.
    fn wanted(&self, f: usize, j: usize, parent: DQuat, carried: &mut Carried) -> DQuat {
        let at = match self.data(f, j) {
            Some(at) if !self.targets[j].is_empty() => at,
            _ => return parent,
        };
        carried.pairs.clear();
        carried
            .pairs
            .extend(self.targets[j].iter().filter_map(|&(d, bone)| {
                let to = self.data(f, d)? - at;
                (to.length() > 1e-9 && bone.length() > 1e-9).then_some((bone, to))
            }));
        let pairs = &carried.pairs;
        let laid = self.laid(
            f,
            j,
            parent,
            pairs,
            carried.before[j],
            &mut carried.following[j],
        );
        // Bones all along one line leave the twist about it free: it is the one
        // that lets the joints below that turn about two axes reach their bones.
        match pairs.first() {
            Some(&(_, to))
                if self.skeleton.joints[j].rotation_order.is_some()
                    && pairs
                        .iter()
                        .all(|(_, t)| t.normalize().cross(to.normalize()).length() < 1e-9) =>
            {
                let data = |d| self.data(f, d);
                reach_twist(
                    self.skeleton,
                    &self.targets,
                    j,
                    laid,
                    to,
                    carried.world[j],
                    data,
                )
            }
            _ => laid,
        }
    }

    /// The world rotation that lays joint `j`'s bones along the data's `pairs` (rest bone,
    /// data's bone) in frame `f`: by the smallest swing and the twist nearest the frame
    /// before's (`before`, from `parent`) with one bone or several along one line; else by
    /// [`fit_or_carry`] where how it turns is free, else by the best rigid fit (Horn's).
    fn laid(
        &self,
        f: usize,
        j: usize,
        parent: DQuat,
        pairs: &[(DVec3, DVec3)],
        before: Option<DQuat>,
        following: &mut bool,
    ) -> DQuat {
        match pairs[..] {
            [] => before.map_or(parent, |b| parent * b),
            [(bone, to)] => {
                let swung =
                    DQuat::from_rotation_arc((parent * bone).normalize(), to.normalize()) * parent;
                let swung = match before {
                    Some(b) => nearest_twist(swung, to, parent * b),
                    None => swung,
                };
                hinge_twist(self.skeleton, &self.targets, j, swung, to, |d| {
                    self.data(f, d)
                })
            }
            // Bones all along one line at rest (twins: MakeHuman's `Spine1` and
            // `Hips` from its `Root`) leave Horn's twist about them arbitrary: the
            // smallest swing onto the data's mean direction, twisted as before.
            [(first, _), ..] if along_one_line(pairs.iter().map(|p| p.0)) => {
                let first = first.normalize();
                let mean: DVec3 = pairs
                    .iter()
                    .map(|&(b, t)| b.normalize().dot(first).signum() * t.normalize())
                    .sum();
                match mean.try_normalize() {
                    Some(mean) => {
                        let swung = DQuat::from_rotation_arc(parent * first, mean) * parent;
                        match before {
                            Some(b) => nearest_twist(swung, mean, parent * b),
                            None => swung,
                        }
                    }
                    None => best_rotation(pairs),
                }
            }
            _ if self.free[j] => {
                fit_or_carry(pairs, self.from_parent[j], parent, before, following)
            }
            _ => best_rotation(pairs),
        }
    }

    /// Joint `j`'s rotation channels (radians, file order) for `local` (its rotation from
    /// `parent`) in frame `f`, and the rotation they make: unwrapped to `previous` (the frame
    /// before's, updated) with three axes; with fewer, the nearest they reach.
    fn angles(
        &self,
        f: usize,
        j: usize,
        parent: DQuat,
        local: DQuat,
        previous: &mut Option<[f64; 3]>,
    ) -> ([f64; 3], DQuat) {
        let joint = &self.skeleton.joints[j];
        if let Some(order) = joint.rotation_order {
            let channel = match joint.axis {
                Some(c) => {
                    let c = c.as_dquat().normalize();
                    c.inverse() * local * c
                }
                None => local,
            };
            let angles = crate::model::euler::split(channel, order, *previous);
            *previous = Some(angles);
            return (angles, local);
        }
        let bone = self.targets[j].first().map(|&(_, b)| b);
        // In degrees already, as the channels take them: back to radians here.
        let cost = |turned: DQuat| {
            out_of_reach_deep(self.skeleton, &self.targets, j, parent * turned, |d| {
                self.data(f, d)
            })
        };
        let (angles, realized) = match bone.and_then(|b| twist_axis(joint, b)) {
            // A bone turning about itself (ASF's wrists): the turn that lets
            // the joints below reach.
            Some(axis) => {
                let turn = twist_search(&cost, previous.map(|a| a[0]), |t| {
                    axis.1 * DQuat::from_axis_angle(axis.0, t) * axis.1.inverse()
                });
                *previous = Some([turn.to_degrees(), 0.0, 0.0]);
                crate::retarget::limited_angles(
                    joint,
                    axis.1 * DQuat::from_axis_angle(axis.0, turn) * axis.1.inverse(),
                    None,
                )
            }
            None => crate::retarget::limited_angles_by(joint, local, bone, cost),
        };
        (angles.map(f64::to_radians), realized)
    }

    /// Frame `f`'s translations, top down, written into `row`: the carrier's and those of the
    /// other named joints with position channels; the unnamed ones' position channels keep
    /// their OFFSET.
    fn place_joints(&self, f: usize, carried: &mut Carried, row: &mut [f32]) {
        let (world, at) = (&carried.world, &mut carried.at);
        for (j, joint) in self.skeleton.joints.iter().enumerate() {
            let (parent_rotation, parent_at) = joint
                .parent
                .map_or((DQuat::IDENTITY, DVec3::ZERO), |p| (world[p], at[p]));
            let rest_translation = match joint.parent {
                Some(p) => self.rest[j].1 - self.rest[p].1,
                None => self.rest[j].1,
            };
            let translation = if self.placed[j] {
                self.data(f, j)
                    .map(|to| parent_rotation.inverse() * (to * self.scale - parent_at))
            } else if Some(j) == self.carrier {
                self.carried_path(f, j, world, parent_rotation, parent_at)
            } else {
                None
            };
            at[j] = parent_at + parent_rotation * translation.unwrap_or(rest_translation);
            if let Some(translation) = translation {
                for (i, channel) in joint.channels.iter().enumerate() {
                    if channel.is_position() {
                        row[joint.first_channel + i] = translation[channel.axis()] as f32;
                    }
                }
            }
        }
    }

    /// The carrier `j`'s translation in frame `f` that puts the hips where the data does,
    /// scaled, its parent turned by `parent_rotation` and standing at `parent_at`.
    fn carried_path(
        &self,
        f: usize,
        j: usize,
        world: &[DQuat],
        parent_rotation: DQuat,
        parent_at: DVec3,
    ) -> Option<DVec3> {
        let h = self.hips?;
        let to = self.data(f, h)?;
        // Where the hips stand from the carrier: the bones between, turned.
        let mut below = DVec3::ZERO;
        let mut k = h;
        while k != j {
            let p = self.skeleton.joints[k].parent?;
            below += world[p] * (self.rest[k].1 - self.rest[p].1);
            k = p;
        }
        Some(parent_rotation.inverse() * (to * self.scale - below - parent_at))
    }
}

/// [`solve`], then, with a `smooth` cutoff (Hz), [`crate::edit::smooth`]: the motion as it is
/// written, its [`Solved`] measured on it, and what smoothing made worse than the unsmoothed
/// solution ([`Solved::worse_than`]). The one way `bvhview solve` and Python's
/// `from_positions` make a take, so that what each says is measured on what it gives.
pub fn solve_smoothed(
    skeleton: &Skeleton,
    skeleton_up: Up,
    positions: &Positions,
    up: Option<UpAxis>,
    smooth: Option<f64>,
) -> Result<(Motion, Solved, Option<String>), Error> {
    let (motion, solved) = solve(skeleton, skeleton_up, positions, up)?;
    let Some(cutoff) = smooth else {
        return Ok((motion, solved, None));
    };
    let smoothed = crate::edit::smooth(skeleton, &motion, cutoff)?;
    let measured = solved.measured_on(skeleton, skeleton_up, positions, up, &smoothed);
    let worse = measured.worse_than(&solved, skeleton);
    Ok((smoothed, measured, worse))
}

/// Each skeleton point's data point (by the name every export gives it, else case aside; see
/// [`solve`]), and the data's names the skeleton has no point of.
fn match_points(
    skeleton: &Skeleton,
    points: &[(String, usize)],
    positions: &Positions,
) -> (Vec<Option<usize>>, Vec<String>) {
    // Each skeleton point's data point: by that name, else case aside.
    let count = skeleton.joints.len();
    let mut data_of: Vec<Option<usize>> = vec![None; count];
    let mut unmatched = Vec::new();
    for (k, name) in positions.names.iter().enumerate() {
        let found = points
            .iter()
            .find(|(n, _)| n == name)
            .or_else(|| {
                points
                    .iter()
                    .find(|(n, j)| n.eq_ignore_ascii_case(name) && data_of[*j].is_none())
            })
            .map(|&(_, j)| j);
        match found {
            Some(j) if data_of[j].is_none() => data_of[j] = Some(k),
            _ => unmatched.push(name.clone()),
        }
    }
    // A joint that starts where a named sibling starts is where that sibling is, always: it
    // takes the same data (ASF: every bone below a bone's end, which the export names once);
    // so does one that starts where its named parent is (ASF's `lowerback` at the root).
    for j in 0..count {
        let Some(p) = skeleton.joints[j].parent.filter(|_| data_of[j].is_none()) else {
            continue;
        };
        let twin = skeleton.joints[p].children.iter().find(|&&c| {
            c != j && data_of[c].is_some() && skeleton.joints[c].offset == skeleton.joints[j].offset
        });
        if let Some(&c) = twin {
            data_of[j] = data_of[c];
        } else if data_of[p].is_some() && skeleton.joints[j].offset.length() < 1e-9 {
            data_of[j] = data_of[p];
        }
    }
    (data_of, unmatched)
}

/// The turn that brings positions standing along `up` to the skeleton's `skeleton_up`.
fn up_turn(skeleton_up: Up, up: Option<UpAxis>) -> DQuat {
    match up {
        Some(up) if up != UpAxis::from(skeleton_up) => {
            skeleton_up.to_y_up().as_dquat().inverse() * up.to_y_up().as_dquat()
        }
        _ => DQuat::IDENTITY,
    }
}

/// Whether every direction lies along the first's (either way), within rounding.
fn along_one_line(mut directions: impl Iterator<Item = DVec3>) -> bool {
    let Some(first) = directions.next().and_then(DVec3::try_normalize) else {
        return true;
    };
    directions.all(|d| d.normalize().cross(first).length() < 1e-9)
}

/// The rotation of a joint whose bones all reach past joints that turn (see where it is
/// called). The best rigid fit of them (Horn's) where the data fixes it: where their shape is
/// the skeleton's (the fit lays each within 5°) and they spread across the bone the joint
/// continues (the one most along its bone from its parent: the fingers after the forearm) by
/// 25° or more. Where not, the fit is the turn of a joint between (CMU's thumb turning on its
/// own, up to 90° from where it stands beside the fingers), or no turn at all about that bone
/// (the thumb's end passing along the fingers), and it flips: CMU's wrist turned 179.6° between
/// two frames where the source's turned 54.8°. There the joint lays only the bone it continues
/// and keeps the twist about it from the frame before (at the first frame, the fit's, or where
/// the data fixes nothing, the least turn from where its parent carries it); once the data
/// fixes the fit again, the joint turns towards it by at most 5° a frame (less while the fit is
/// trusted less: off by 5° to 15°, spread by 25° to 12°) and follows it again once there, so a
/// thumb that comes back beside the fingers turned about them does not swing the wrist at once.
/// `following` carries, from frame to frame, whether the joint follows its fit.
fn fit_or_carry(
    pairs: &[(DVec3, DVec3)],
    from_parent: Option<DVec3>,
    parent: DQuat,
    before: Option<DQuat>,
    following: &mut bool,
) -> DQuat {
    /// The most a joint turns towards its fit in a frame while it catches up (degrees).
    const CATCH_UP: f64 = 5.0;
    let fit = best_rotation(pairs);
    let along = |bone: DVec3| from_parent.map_or(0.0, |d| bone.normalize().dot(d));
    let Some(&(bone, to)) = pairs
        .iter()
        .max_by(|a, b| along(a.0).total_cmp(&along(b.0)))
    else {
        return fit;
    };
    let off = pairs
        .iter()
        .map(|&(bone, to)| (fit * bone).angle_between(to).to_degrees())
        .fold(0.0, f64::max);
    let spread = pairs
        .iter()
        .map(|&(_, other)| other.angle_between(to).to_degrees())
        .map(|a| a.min(180.0 - a))
        .fold(0.0, f64::max);
    let between = |x: f64, none: f64, all: f64| ((x - none) / (all - none)).clamp(0.0, 1.0);
    let trust = between(off, 15.0, 5.0) * between(spread, 12.0, 25.0);
    if trust >= 1.0 && (*following || before.is_none()) {
        *following = true;
        return fit;
    }
    *following = false;
    let swung = DQuat::from_rotation_arc((parent * bone).normalize(), to.normalize()) * parent;
    let carried = match before {
        Some(b) => nearest_twist(swung, to, parent * b),
        None if trust > 0.0 => return nearest_twist(swung, to, fit),
        None => return swung,
    };
    let apart = carried.angle_between(fit).to_degrees();
    let step = CATCH_UP * trust;
    if apart <= step {
        *following = trust >= 1.0;
        return fit;
    }
    carried.slerp(fit, step / apart).normalize()
}

/// `wanted` turned about `axis` (a world direction) to the turn nearest `goal`: of the
/// rotations that lay a bone along `axis` as `wanted` does, the one nearest `goal`.
fn nearest_twist(wanted: DQuat, axis: DVec3, goal: DQuat) -> DQuat {
    let Some(axis) = axis.try_normalize() else {
        return wanted;
    };
    // A twist T(θ) = (cos θ/2, sin θ/2 · axis) is nearest `goal` where T · wanted · goal⁻¹'s
    // distance from ±1 is least: where T's 4-vector is most along goal · wanted⁻¹'s.
    let m = goal * wanted.inverse();
    let half = axis.dot(m.xyz()).atan2(m.w);
    (DQuat::from_axis_angle(axis, 2.0 * half) * wanted).normalize()
}

/// The named joints `j` turns towards (see where it is called), in file order, each with how
/// many named joints that turn stand between (0 for `j`'s own bones).
fn targets_of(
    skeleton: &Skeleton,
    j: usize,
    data_of: &[Option<usize>],
    rest: &[(DQuat, DVec3)],
) -> Vec<(usize, DVec3, usize)> {
    let gather = |past_turning: bool| {
        let mut out = Vec::new();
        let mut stack: Vec<(usize, usize)> = skeleton.joints[j]
            .children
            .iter()
            .rev()
            .map(|&c| (c, 0))
            .collect();
        while let Some((c, passed)) = stack.pop() {
            let bone = rest[c].1 - rest[j].1;
            let turns = skeleton.joints[c]
                .channels
                .iter()
                .any(|ch| ch.is_rotation());
            if data_of[c].is_some() && bone.length() > 1e-9 {
                out.push((c, bone, passed));
            } else if past_turning || data_of[c].is_none() || !turns {
                // Past a named joint that turns, what lies beyond moves with that joint too.
                let passed = passed + usize::from(data_of[c].is_some() && turns);
                stack.extend(
                    skeleton.joints[c]
                        .children
                        .iter()
                        .rev()
                        .map(|&d| (d, passed)),
                );
            }
        }
        out
    };
    // The bones beyond a named joint that stands where this one does and turns (ASF's
    // `lowerback` at the root) are that joint's to lay: this joint is laid by the others when
    // they are enough (two bones not along one line: ASF's hips), else by all of them (CMU
    // BVH's `LHipJoint` and `RHipJoint` turn at the hips, which need the thighs beyond).
    let own = gather(false);
    let enough = own.iter().any(|(_, a, _)| {
        own.iter()
            .any(|(_, b, _)| a.normalize().cross(b.normalize()).length() > 1e-3)
    });
    if enough { own } else { gather(true) }
}

/// The shallowest joint the data names at or below `root` (breadth first).
fn shallowest_named(skeleton: &Skeleton, root: usize, data_of: &[Option<usize>]) -> Option<usize> {
    let mut level = vec![root];
    while !level.is_empty() {
        if let Some(&j) = level.iter().find(|&&j| data_of[j].is_some()) {
            return Some(j);
        }
        level = level
            .iter()
            .flat_map(|&j| skeleton.joints[j].children.iter().copied())
            .collect();
    }
    None
}

/// The skeleton's legs over the data's (the median over the frames), else over the named
/// bones' lengths summed; 1 when neither can be measured.
fn scale_of(
    skeleton: &Skeleton,
    rest: &[(DQuat, DVec3)],
    data_of: &[Option<usize>],
    positions: &Positions,
    turn: DQuat,
) -> f64 {
    let body = Body::of(skeleton);
    let frames = positions.frames();
    let at = |f: usize, j: usize| data_of[j].map(|k| turn * positions.at(f, k));
    if let Some(legs) = body.leg_length(rest) {
        let mut measured: Vec<f64> = (0..frames)
            .filter_map(|f| {
                let sides: Vec<f64> = body
                    .limbs
                    .iter()
                    .filter_map(|limb| {
                        use crate::model::body::Limb;
                        let (t, s, a) = (
                            at(f, limb[Limb::Thigh as usize]?)?,
                            at(f, limb[Limb::Shin as usize]?)?,
                            at(f, limb[Limb::Foot as usize]?)?,
                        );
                        Some((s - t).length() + (a - s).length())
                    })
                    .collect();
                (!sides.is_empty()).then(|| sides.iter().sum::<f64>() / sides.len() as f64)
            })
            .collect();
        if !measured.is_empty() {
            measured.sort_by(f64::total_cmp);
            let median = measured[measured.len() / 2];
            if median > 1e-9 {
                return legs / median;
            }
        }
    }
    // Without legs: every named bone (a joint to its nearest named ancestor) in the first frame.
    let (mut skeleton_total, mut data_total) = (0.0, 0.0);
    for j in 0..skeleton.joints.len() {
        let mut at_parent = skeleton.joints[j].parent;
        while let Some(p) = at_parent.filter(|&p| data_of[p].is_none()) {
            at_parent = skeleton.joints[p].parent;
        }
        if let (Some(p), Some(a), Some(b)) = (at_parent, at(0, j), at_parent.and_then(|p| at(0, p)))
        {
            skeleton_total += (rest[j].1 - rest[p].1).length();
            data_total += (a - b).length();
        }
    }
    if data_total > 1e-9 && skeleton_total > 1e-9 {
        skeleton_total / data_total
    } else {
        1.0
    }
}
