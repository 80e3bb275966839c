//! Foot locking: while a foot is planted, its ankle stays where it landed, by two-bone IK on the
//! thigh and shin the reading of the body finds; the foot keeps its world orientation, and no
//! bone changes length (only rotation channels are written).

use super::*;
use crate::model::body::contact::{Planting, sliding};
use crate::model::body::{Body, Limb};
use crate::model::pose::{OffsetMode, Up, world_transforms_f64};
use glam::DVec3;

/// How feet are locked: when a foot counts as planted, and how the lock lets go; what locking
/// did to one foot ([`FootLocked`]) and to the take ([`FeetLocked`]).
///
/// ```
/// use bvhview::edit::{LockFeet, lock_feet};
/// use bvhview::model::pose::OffsetMode;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let stance = take.stance(OffsetMode::Replace);
/// let options = LockFeet { blend_frames: 4, ..LockFeet::default() };
/// let (locked, report) = lock_feet(
///     &take.skeleton,
///     &take.motion,
///     OffsetMode::Replace,
///     stance.up,
///     f64::from(stance.units.metres),
///     &options,
/// )?;
/// assert_eq!(locked.frame_count(), take.frame_count());
/// let left = report.feet[0];
/// assert_eq!((take.skeleton.joints[left.ankle].name.as_str(), left.contacts), ("LeftAnkle", 10));
/// assert!(left.drift_after < 0.001 && left.sliding_before > 0.4);
/// assert!(report.summary(&take.skeleton).starts_with("LeftAnkle: 10 contacts, sliding 40.3 cm"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockFeet {
    /// When an ankle is planted: the reading of the body's contacts
    /// ([`crate::model::body::contact`]), the same as the dataset's.
    pub planting: Planting,
    /// Frames over which the lock lets go after a contact, so the ankle does not jump.
    pub blend_frames: usize,
}

impl Default for LockFeet {
    fn default() -> LockFeet {
        LockFeet {
            planting: Planting::default(),
            blend_frames: 4,
        }
    }
}

/// What locking did to one foot (the example on [`LockFeet`] reads one).
///
/// ```
/// let foot = bvhview::edit::FootLocked { ankle: 3, contacts: 2, ..Default::default() };
/// assert_eq!((foot.sliding_before, foot.drift_after), (0.0, 0.0));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootLocked {
    /// The ankle joint.
    pub ankle: usize,
    /// How many contacts were locked.
    pub contacts: usize,
    /// How far the ankle slid along the floor during them (metres, frame to frame), before…
    pub sliding_before: f64,
    /// …and after.
    pub sliding_after: f64,
    /// The farthest the ankle strays along the floor from where it landed, after (metres).
    pub drift_after: f64,
}

/// What locking did, per foot locked, and why a leg was not (the example on [`LockFeet`]
/// prints one).
///
/// ```
/// let none = bvhview::edit::FeetLocked::default();
/// let walk = bvhview::Take::open("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// assert_eq!(none.summary(&walk.skeleton), "no foot locked");
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FeetLocked {
    /// Each foot locked.
    pub feet: Vec<FootLocked>,
    /// Why a leg was left as it was (no thigh, shin and ankle in a chain, a hinge).
    pub notes: Vec<String>,
}

impl FeetLocked {
    /// What the CLI's line of the [`summary`](FeetLocked::summary) begins with: `feet locked`,
    /// or `feet not locked` when none was.
    pub fn heading(&self) -> &'static str {
        match self.feet.is_empty() {
            true => "feet not locked",
            false => "feet locked",
        }
    }

    /// The figure `convert --lock-feet` prints: contacts, and the sliding before and after;
    /// why a leg was not locked; never nothing.
    pub fn summary(&self, skeleton: &Skeleton) -> String {
        let mut parts: Vec<String> = self
            .feet
            .iter()
            .map(|foot| {
                format!(
                    "{}: {}, sliding {:.1} cm → {:.1} cm, farthest from where it landed {:.1} cm",
                    skeleton.joints[foot.ankle].name,
                    crate::io::error::counted(foot.contacts, "contact"),
                    foot.sliding_before * 100.0,
                    foot.sliding_after * 100.0,
                    foot.drift_after * 100.0
                )
            })
            .collect();
        parts.extend(self.notes.iter().cloned());
        if parts.is_empty() {
            return "no foot locked".into();
        }
        parts.join("; ")
    }
}

/// One leg: thigh, shin and ankle, each above the next. Joints between them (MakeHuman's
/// `upperleg02`, twist bones) keep their rotations: each stretch moves as one rigid bone.
struct Leg {
    /// 0 left, 1 right.
    side: usize,
    thigh: usize,
    shin: usize,
    ankle: usize,
}

/// The legs of `body` that can be locked, and why the others cannot.
fn legs(skeleton: &Skeleton, body: &Body) -> (Vec<Leg>, Vec<String>) {
    let (mut legs, mut notes) = (Vec::new(), Vec::new());
    for (side, word) in [(0, "left"), (1, "right")] {
        let limb = |l: Limb| body.limbs[side][l as usize];
        let (Some(thigh), Some(shin), Some(ankle)) =
            (limb(Limb::Thigh), limb(Limb::Shin), limb(Limb::Foot))
        else {
            notes.push(format!(
                "{word} leg not locked: no thigh, shin and ankle read"
            ));
            continue;
        };
        let joints = &skeleton.joints;
        let below = |joint: usize, ancestor: usize| {
            std::iter::successors(joints[joint].parent, |&p| joints[p].parent)
                .any(|p| p == ancestor)
        };
        if !below(shin, thigh) || !below(ankle, shin) {
            notes.push(format!(
                "{word} leg not locked: {}, {} and {} are not one chain",
                joints[thigh].name, joints[shin].name, joints[ankle].name
            ));
            continue;
        }
        let free = |j: usize| joints[j].rotation_order.is_some() && joints[j].axis.is_none();
        if ![thigh, shin, ankle].into_iter().all(free) {
            notes.push(format!(
                "{word} leg not locked: a joint without three rotation channels of its own (an ASF bone's axis or hinge)"
            ));
            continue;
        }
        legs.push(Leg {
            side,
            thigh,
            shin,
            ankle,
        });
    }
    (legs, notes)
}

/// The shortest rotation taking direction `from` onto `to` (identity for a zero vector).
fn turn_onto(from: DVec3, to: DVec3) -> DQuat {
    match (from.try_normalize(), to.try_normalize()) {
        (Some(a), Some(b)) => DQuat::from_rotation_arc(a, b),
        _ => DQuat::IDENTITY,
    }
}

/// `motion` with each planted ankle held where it landed (see the module docs). `up` and
/// `metres` (per unit) are the take's stance; `mode` its offset mode.
pub fn lock_feet(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    up: Up,
    metres: f64,
    options: &LockFeet,
) -> Result<(Motion, FeetLocked), Error> {
    lock_feet_when(skeleton, motion, mode, (up, metres), options, None)
}

/// [`lock_feet()`] during contacts read elsewhere: `planted[side]` (0 left, 1 right) per frame,
/// as [`Body::planted_ankles`] reads them on a retarget's source (the retargeted take's own
/// feet may slide, so its own reading misses contacts). `None`: read on `motion` itself.
pub fn lock_feet_when(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    (up, metres): (Up, f64),
    options: &LockFeet,
    planted: Option<&[Vec<bool>; 2]>,
) -> Result<(Motion, FeetLocked), Error> {
    let body = Body::of(skeleton);
    let (legs, notes) = legs(skeleton, &body);
    let mut report = FeetLocked {
        feet: Vec::new(),
        notes,
    };
    let frames = motion.frame_count();
    let mut data = motion.data.clone();
    if legs.is_empty() || frames < 2 || !metres.is_finite() || metres <= 0.0 {
        // Said, so that the report is never empty (the legs' own notes say why they are not).
        if frames < 2 {
            report.notes.push(format!(
                "nothing to lock in {} (a foot slides between frames)",
                crate::io::error::counted(frames, "frame")
            ));
        } else if !legs.is_empty() {
            report
                .notes
                .push("nothing locked: the take's size in metres is not known".into());
        }
        return Ok((motion.clone(), report));
    }
    let up = match up {
        Up::Y => DVec3::Y,
        Up::Z => DVec3::Z,
    };
    let flat = |v: DVec3| v - up * v.dot(up);
    let world: Vec<Vec<(DQuat, DVec3)>> = (0..frames)
        .map(|f| {
            let mut out = Vec::new();
            world_transforms_f64(skeleton, motion.frame(f), mode, &mut out);
            out
        })
        .collect();
    let channels = motion.channels;
    let mut intervals: Vec<(usize, Vec<std::ops::Range<usize>>)> = Vec::new();
    // The ankles' own contacts, read together (each against the ground both stand on).
    let tracks: Vec<Vec<DVec3>> = legs
        .iter()
        .map(|leg| {
            (0..frames)
                .map(|f| world[f][leg.ankle].1 * metres)
                .collect()
        })
        .collect();
    let own = options.planting.frames_of(&tracks, up, motion.frame_time);
    for (k, leg) in legs.iter().enumerate() {
        let at = |f: usize| world[f][leg.ankle].1;
        let planted = match planted {
            Some(sides) if sides[leg.side].len() == frames => sides[leg.side].clone(),
            Some(_) => {
                // Asked to lock on contacts read elsewhere, which this side has none of.
                report.notes.push(format!(
                    "{} locked on its own contacts: none were read for its side elsewhere",
                    skeleton.joints[leg.ankle].name
                ));
                own[k].clone()
            }
            None => own[k].clone(),
        };
        // Where each frame's ankle is held, and how firmly (1 in a contact, less as it lets go).
        let mut hold: Vec<Option<(DVec3, f64)>> = vec![None; frames];
        let mut contacts = Vec::new();
        for run in Planting::contacts(&planted) {
            let (start, f) = (run.start, run.end);
            let landed = flat(at(start));
            // The lock lets go where the leg could no longer reach where the foot landed: the
            // foot is lifting (the contact's last frames, the hips already moving on).
            let reaches = |g: usize| {
                let w = &world[g];
                let length = (w[leg.shin].1 - w[leg.thigh].1).length()
                    + (w[leg.ankle].1 - w[leg.shin].1).length();
                let wanted = landed + up * at(g).dot(up);
                (wanted - w[leg.thigh].1).length() < 0.999 * length
            };
            let end = (start..f).find(|&g| !reaches(g)).unwrap_or(f);
            if end - start < 2 {
                continue;
            }
            contacts.push(start..end);
            for held in &mut hold[start..end] {
                *held = Some((landed, 1.0));
            }
            for k in 1..=options.blend_frames {
                let g = end + k - 1;
                if g >= frames || (g >= f && planted[g]) {
                    break;
                }
                let weight = 1.0 - k as f64 / (options.blend_frames + 1) as f64;
                hold[g] = Some((landed, weight));
            }
        }
        for f in 0..frames {
            let Some((landed, weight)) = hold[f] else {
                continue;
            };
            let w = &world[f];
            let (hip, knee, ankle) = (w[leg.thigh].1, w[leg.shin].1, w[leg.ankle].1);
            let wanted = ankle + (landed - flat(ankle)) * weight;
            let (l1, l2) = ((knee - hip).length(), (ankle - knee).length());
            let reach_to = wanted - hip;
            let Some(direction) = reach_to.try_normalize() else {
                continue;
            };
            let d = reach_to
                .length()
                .clamp((l1 - l2).abs() + 1e-9, l1 + l2 - 1e-9);
            // The knee stays in the plane it bends in now.
            let bend = (knee - hip) - direction * (knee - hip).dot(direction);
            let Some(pole) = bend.try_normalize() else {
                continue;
            };
            let along = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
            let new_knee =
                hip + direction * along + pole * (l1 * l1 - along * along).max(0.0).sqrt();
            let new_ankle = hip + direction * d;
            let thigh_turn = turn_onto(knee - hip, new_knee - hip);
            let moved_ankle = new_knee + thigh_turn * (ankle - knee);
            let shin_turn = turn_onto(moved_ankle - new_knee, new_ankle - new_knee);
            let thigh_world = thigh_turn * w[leg.thigh].0;
            let shin_world = shin_turn * thigh_turn * w[leg.shin].0;
            let parent = |j: usize| {
                skeleton.joints[j]
                    .parent
                    .map_or(DQuat::IDENTITY, |p| w[p].0)
            };
            // Each joint's parent as it stands after the turns above it (the thigh itself, or
            // the joints between, which turn with it).
            let shin_parent = thigh_turn * parent(leg.shin);
            let ankle_parent = shin_turn * thigh_turn * parent(leg.ankle);
            let row = &mut data[f * channels..(f + 1) * channels];
            for (joint, local) in [
                (leg.thigh, parent(leg.thigh).inverse() * thigh_world),
                (leg.shin, shin_parent.inverse() * shin_world),
                (leg.ankle, ankle_parent.inverse() * w[leg.ankle].0),
            ] {
                let joint = &skeleton.joints[joint];
                let Some(order) = joint.rotation_order else {
                    continue;
                };
                let values = joint.values(motion.frame(f));
                let rotations: Vec<usize> = joint
                    .channels
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.is_rotation())
                    .map(|(i, _)| i)
                    .collect();
                let previous = [0, 1, 2].map(|k| f64::from(values[rotations[k]]).to_radians());
                let angles = euler::split(local, order, Some(previous));
                for (k, &i) in rotations.iter().enumerate() {
                    row[joint.first_channel + i] = angles[k].to_degrees() as f32;
                }
            }
        }
        intervals.push((leg.ankle, contacts));
    }
    let (_, locked) = finite(
        "--lock-feet",
        skeleton.clone(),
        Motion::new(motion.frame_time, channels, frames, data),
    )?;
    // How far each ankle slides along the floor during its contacts, before and after, and
    // the farthest it strays from where it landed.
    let slid = |motion: &Motion, ankle: usize, contacts: &[std::ops::Range<usize>]| {
        let mut world = Vec::new();
        let track: Vec<DVec3> = (0..frames)
            .map(|f| {
                world_transforms_f64(skeleton, motion.frame(f), mode, &mut world);
                world[ankle].1 * metres
            })
            .collect();
        sliding(&track, up, contacts)
    };
    for (ankle, contacts) in &intervals {
        let (before, _) = slid(motion, *ankle, contacts);
        let (after, drift) = slid(&locked, *ankle, contacts);
        report.feet.push(FootLocked {
            ankle: *ankle,
            contacts: contacts.len(),
            sliding_before: before,
            sliding_after: after,
            drift_after: drift,
        });
    }
    Ok((locked, report))
}
