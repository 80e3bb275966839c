//! Foot locking: while a foot is planted, its ankle stays where it landed, by two-bone IK on the
//! thigh and shin the reading of the body finds; the foot keeps its world orientation, and no
//! bone changes length (only rotation channels are written).

use crate::edit::finite;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::body::contact::{Planting, sliding};
use crate::model::body::{Body, Limb};
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use glam::DQuat;
use glam::DVec3;
use std::ops::Range;

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
/// let options = LockFeet { catch_up: 0.5, ..LockFeet::default() };
/// let (locked, report) = lock_feet(
///     &take.skeleton,
///     &take.motion,
///     OffsetMode::Replace,
///     stance.up,
///     f64::from(stance.units.metres),
///     &options,
/// )?;
/// assert_eq!(locked.frame_count(), take.frame_count());
/// let left = &report.feet[0];
/// assert_eq!((take.skeleton.joints[left.ankle].name.as_str(), left.contacts), ("LeftAnkle", 12));
/// // Each contact is held within a millimetre or named with why (here: the leg does not reach).
/// assert_eq!((left.held, left.not_held.len()), (8, 4));
/// assert!(left.sliding_before > 0.4);
/// assert!(report.summary(&take.skeleton).starts_with("LeftAnkle: 12 contacts, 8 held, "));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockFeet {
    /// When an ankle is planted: the reading of the body's contacts
    /// ([`crate::model::body::contact`]), the same as the dataset's.
    pub planting: Planting,
    /// Out of a contact, the ankle comes back to where the take has it by at most this much of
    /// what the take's ankle moves each frame, so it is never more than `1 + catch_up` times as
    /// fast as the take's (a lock let go over a fixed number of frames snapped).
    pub catch_up: f64,
}

impl LockFeet {
    /// A contact is held when its ankle stays within this of where it landed (metres).
    pub const HELD: f64 = 0.001;
}

impl Default for LockFeet {
    fn default() -> LockFeet {
        LockFeet {
            planting: Planting::default(),
            catch_up: 0.5,
        }
    }
}

/// What locking did to one foot (the example on [`LockFeet`] reads one).
///
/// ```
/// let foot = bvhview::edit::FootLocked { ankle: 3, contacts: 2, held: 2, ..Default::default() };
/// assert_eq!((foot.sliding_before, foot.drift_after), (0.0, 0.0));
/// assert!(foot.not_held.is_empty());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FootLocked {
    /// The ankle joint.
    pub ankle: usize,
    /// How many contacts the reading found (on the take, or on a retarget's source).
    pub contacts: usize,
    /// How many of them the written ankle stays within [`LockFeet::HELD`] of where it landed.
    pub held: usize,
    /// The others, each with why.
    pub not_held: Vec<NotHeld>,
    /// How far the ankle slid along the floor during them all (metres, frame to frame), before…
    pub sliding_before: f64,
    /// …and after.
    pub sliding_after: f64,
    /// The farthest the ankle strays along the floor from where it landed, after (metres).
    pub drift_after: f64,
}

/// A contact whose ankle locking did not hold (measured on what it wrote).
///
/// ```
/// use bvhview::edit::NotHeld;
///
/// let missed = NotHeld { frames: 229..242, strayed: 0.027, why: "the leg does not reach".into() };
/// assert_eq!(missed.frames.len(), 13);
/// assert!(missed.strayed > bvhview::edit::LockFeet::HELD);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NotHeld {
    /// Its frames.
    pub frames: Range<usize>,
    /// The farthest the written ankle strays along the floor from where it landed (metres).
    pub strayed: f64,
    /// Why.
    pub why: String,
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

    /// The figure `convert --lock-feet` prints, measured on what it wrote: contacts, how many
    /// held, the sliding before and after, each contact not held with its frames and why; why a
    /// leg was not locked; never nothing.
    pub fn summary(&self, skeleton: &Skeleton) -> String {
        let mut parts: Vec<String> = self
            .feet
            .iter()
            .map(|foot| {
                let mut part = format!(
                    "{}: {}, {} held, sliding {:.1} cm → {:.1} cm, farthest from where it landed {:.1} cm",
                    skeleton.joints[foot.ankle].name,
                    crate::io::error::counted(foot.contacts, "contact"),
                    foot.held,
                    foot.sliding_before * 100.0,
                    foot.sliding_after * 100.0,
                    foot.drift_after * 100.0
                );
                let named: Vec<String> = foot
                    .not_held
                    .iter()
                    .map(|n| {
                        format!(
                            "frames {}..{} ({:.1} cm: {})",
                            n.frames.start,
                            n.frames.end,
                            n.strayed * 100.0,
                            n.why
                        )
                    })
                    .collect();
                if !named.is_empty() {
                    part.push_str(", not held: ");
                    part.push_str(&named.join(", "));
                }
                part
            })
            .collect();
        parts.extend(self.notes.iter().cloned());
        if parts.is_empty() {
            return "no foot locked".into();
        }
        parts.join("; ")
    }
}

/// One ankle, the contacts locking read on it, and why each it could not hold was let go.
type Read = (usize, Vec<Range<usize>>, Vec<Option<String>>);

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
        report
            .notes
            .extend(why_nothing_locked(legs.is_empty(), frames));
        return Ok((motion.clone(), report));
    }
    let up = match up {
        Up::Y => DVec3::Y,
        Up::Z => DVec3::Z,
    };
    let world: Vec<Vec<(DQuat, DVec3)>> = (0..frames)
        .map(|f| {
            let mut out = Vec::new();
            world_transforms_f64(skeleton, motion.frame(f), mode, &mut out);
            out
        })
        .collect();
    let channels = motion.channels;
    // Per leg: the contacts it locks on, and why each it could not hold was let go.
    let mut read: Vec<Read> = Vec::new();
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
        let contacts = Planting::contacts(&planted);
        let reach = Reach {
            world: &world,
            up,
            leg,
        };
        let (offsets, why) = reach.offsets(&contacts, options.catch_up);
        for (f, &offset) in offsets.iter().enumerate() {
            let row = &mut data[f * channels..(f + 1) * channels];
            write_leg(skeleton, motion.frame(f), &world[f], leg, offset, row);
        }
        read.push((leg.ankle, contacts, why));
    }
    let (_, locked) = finite(
        Message::of_argument("lock_feet", None),
        skeleton.clone(),
        Motion::new(motion.frame_time, channels, frames, data),
    )?;
    let track_of =
        |motion: &Motion, ankle: usize| ankle_track(skeleton, motion, mode, metres, ankle, frames);
    for (ankle, contacts, why) in read {
        let (before, after) = (track_of(motion, ankle), track_of(&locked, ankle));
        report
            .feet
            .push(foot_locked(ankle, &before, &after, up, contacts, why));
    }
    Ok((locked, report))
}

/// Why [`lock_feet_when`] locked nothing, where the legs' own notes do not say it: too few
/// frames, or (with legs to lock) the take's size in metres unknown.
fn why_nothing_locked(no_legs: bool, frames: usize) -> Option<String> {
    if frames < 2 {
        Some(format!(
            "nothing to lock in {} (a foot slides between frames)",
            crate::io::error::counted(frames, "frame")
        ))
    } else if !no_legs {
        Some("nothing locked: the take's size in metres is not known".into())
    } else {
        None
    }
}

/// One leg through the take: where its ankle can be put along the floor, frame by frame.
struct Reach<'a> {
    /// Every frame's world rotations and places.
    world: &'a [Vec<(DQuat, DVec3)>],
    /// The up axis.
    up: DVec3,
    leg: &'a Leg,
}

impl Reach<'_> {
    /// Frame `g`'s ankle as the take has it.
    fn at(&self, g: usize) -> DVec3 {
        self.world[g][self.leg.ankle].1
    }

    /// `v` along the floor (its height taken out).
    fn flat(&self, v: DVec3) -> DVec3 {
        v - self.up * v.dot(self.up)
    }

    /// Whether the leg reaches `flat_at` (along the floor) at frame `g`'s height, a little
    /// short of straight so that the knee keeps a bend to aim.
    fn reaches(&self, g: usize, flat_at: DVec3) -> bool {
        let (w, leg) = (&self.world[g], self.leg);
        let length =
            (w[leg.shin].1 - w[leg.thigh].1).length() + (w[leg.ankle].1 - w[leg.shin].1).length();
        let wanted = flat_at + self.up * self.at(g).dot(self.up);
        (wanted - w[leg.thigh].1).length() < 0.999 * length
    }

    /// Where the leg cannot reach the ankle moved by `offset` at frame `g`, the offset cut to
    /// what it reaches (the source's own ankle, no offset, is always reached; the points it
    /// reaches at a height are a disc, so one cut along the way finds the edge).
    fn within_reach(&self, g: usize, offset: DVec3) -> DVec3 {
        if self.reaches(g, self.flat(self.at(g)) + offset) {
            return offset;
        }
        let (mut low, mut high) = (0.0, 1.0);
        for _ in 0..30 {
            let mid = 0.5 * (low + high);
            match self.reaches(g, self.flat(self.at(g)) + offset * mid) {
                true => low = mid,
                false => high = mid,
            }
        }
        offset * low
    }

    /// Where each frame's ankle goes along the floor: the source's, moved by the offset
    /// returned per frame, and per contact why it could not be held (see inside).
    fn offsets(
        &self,
        contacts: &[Range<usize>],
        catch_up: f64,
    ) -> (Vec<DVec3>, Vec<Option<String>>) {
        // In a contact the offset keeps the ankle where it landed; out of one it shrinks by at
        // most half of what the source ankle moves that frame, so the written ankle is never
        // more than 1.5 times as fast as the source's (a lock let go over a fixed number of
        // frames snapped, 3.1 m/s where the source went 0.5 m/s on PyMO's walk).
        let frames = self.world.len();
        let mut offsets = Vec::with_capacity(frames);
        let mut why: Vec<Option<String>> = vec![None; contacts.len()];
        let mut offset = DVec3::ZERO;
        let mut next = 0;
        let mut landed = DVec3::ZERO;
        for f in 0..frames {
            while next < contacts.len() && contacts[next].end <= f {
                next += 1;
            }
            match contacts.get(next).filter(|c| c.contains(&f)) {
                Some(contact) => {
                    if f == contact.start {
                        // It lands where the written ankle is (the source's, moved as it was
                        // the frame before), so the lock starts without a jump.
                        landed = self.flat(self.at(f)) + self.within_reach(f, offset);
                    }
                    offset = landed - self.flat(self.at(f));
                    let reached = self.within_reach(f, offset);
                    if reached != offset {
                        // The leg drags the foot only as far as it must, and holds it there.
                        why[next].get_or_insert_with(|| {
                            format!("the leg does not reach where it landed from frame {f}")
                        });
                        offset = reached;
                        landed = self.flat(self.at(f)) + offset;
                    }
                }
                None => {
                    if f > 0 {
                        let step = (self.at(f) - self.at(f - 1)).length() * catch_up;
                        offset -= offset.clamp_length_max(step);
                    }
                    offset = self.within_reach(f, offset);
                }
            }
            offsets.push(offset);
        }
        (offsets, why)
    }
}

/// One frame's `leg` turned so that its ankle stands `offset` from where the take has it
/// (`w`, the frame's world rotations and places; `values`, its channels), written into `row`;
/// nothing where the offset is zero or the leg has no direction or bend to aim by.
fn write_leg(
    skeleton: &Skeleton,
    values: &[f32],
    w: &[(DQuat, DVec3)],
    leg: &Leg,
    offset: DVec3,
    row: &mut [f32],
) {
    if offset == DVec3::ZERO {
        return;
    }
    let Some(turned) = leg_turned(skeleton, w, leg, offset) else {
        return;
    };
    for (joint, local) in turned {
        let joint = &skeleton.joints[joint];
        let Some(order) = joint.rotation_order else {
            continue;
        };
        let values = joint.values(values);
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

/// The thigh's, shin's and ankle's rotations from their parents that put the ankle `offset`
/// from where it stands in `w` (one frame's world rotations and places), the knee in the
/// plane it bends in; `None` where the leg has no direction or bend to aim by.
fn leg_turned(
    skeleton: &Skeleton,
    w: &[(DQuat, DVec3)],
    leg: &Leg,
    offset: DVec3,
) -> Option<[(usize, DQuat); 3]> {
    let (hip, knee, ankle) = (w[leg.thigh].1, w[leg.shin].1, w[leg.ankle].1);
    let wanted = ankle + offset;
    let (l1, l2) = ((knee - hip).length(), (ankle - knee).length());
    let reach_to = wanted - hip;
    let direction = reach_to.try_normalize()?;
    let d = reach_to
        .length()
        .clamp((l1 - l2).abs() + 1e-9, l1 + l2 - 1e-9);
    // The knee stays in the plane it bends in now.
    let bend = (knee - hip) - direction * (knee - hip).dot(direction);
    let pole = bend.try_normalize()?;
    let along = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
    let new_knee = hip + direction * along + pole * (l1 * l1 - along * along).max(0.0).sqrt();
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
    Some([
        (leg.thigh, parent(leg.thigh).inverse() * thigh_world),
        (leg.shin, shin_parent.inverse() * shin_world),
        (leg.ankle, ankle_parent.inverse() * w[leg.ankle].0),
    ])
}

/// Joint `ankle`'s place in each of `motion`'s first `frames` frames, in metres.
fn ankle_track(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    metres: f64,
    ankle: usize,
    frames: usize,
) -> Vec<DVec3> {
    let mut world = Vec::new();
    (0..frames)
        .map(|f| {
            world_transforms_f64(skeleton, motion.frame(f), mode, &mut world);
            world[ankle].1 * metres
        })
        .collect()
}

/// What locking did to one foot, measured on what it wrote: the ankle's path along the floor
/// during the `contacts` `before` and `after` (its tracks), and each contact whose ankle
/// strayed from where it landed, with `why` (per contact, where locking said).
fn foot_locked(
    ankle: usize,
    before: &[DVec3],
    after: &[DVec3],
    up: DVec3,
    contacts: Vec<Range<usize>>,
    why: Vec<Option<String>>,
) -> FootLocked {
    let (sliding_before, _) = sliding(before, up, &contacts);
    let (sliding_after, drift_after) = sliding(after, up, &contacts);
    let mut not_held = Vec::new();
    for (contact, why) in contacts.iter().zip(why) {
        let (_, strayed) = sliding(after, up, std::slice::from_ref(contact));
        if strayed <= LockFeet::HELD {
            continue;
        }
        let why = why.unwrap_or_else(|| {
            format!(
                "the legs' turns left it {:.1} mm from where it landed",
                strayed * 1000.0
            )
        });
        not_held.push(NotHeld {
            frames: contact.clone(),
            strayed,
            why,
        });
    }
    FootLocked {
        ankle,
        contacts: contacts.len(),
        held: contacts.len() - not_held.len(),
        not_held,
        sliding_before,
        sliding_after,
        drift_after,
    }
}
