//! A canonical layout on request (`convert --channels root6,rot3 --order ZYX --strip-prefix`):
//! one channel layout, one Euler order, names without their exporter's prefixes. Every joint's
//! world position stays where it was on every frame.

use crate::edit::finite;
use crate::io::error::Error;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, joint_translation, local_rotation_f64};
use crate::model::skeleton::{Channel, RotationOrder, Skeleton};

/// What the canonical form asks for; each part alone or together.
///
/// ```
/// use bvhview::edit::Canonical;
/// use bvhview::model::skeleton::RotationOrder;
///
/// let engine = Canonical { root6_rot3: true, order: Some(RotationOrder::Zyx), ..Default::default() };
/// assert!(!engine.strip_prefix);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Canonical {
    /// One channel layout: every root three positions then three rotations, every other joint
    /// three rotations. A position channel of another joint that never moves goes into its
    /// OFFSET; one that moves is refused by name, with how far it moves.
    pub root6_rot3: bool,
    /// One Euler order for every joint's three rotation channels (split once from the rotation
    /// they make; a joint already in that order keeps its values as they are).
    pub order: Option<RotationOrder>,
    /// Names without an exporter's prefix: a namespace (`mixamorig:Hips`, `Armature|Hips`) and
    /// a prefix every joint shares up to a separator (`Bip01 `, `CC_Base_`).
    pub strip_prefix: bool,
}

impl Canonical {
    /// Whether it asks for anything.
    pub fn any(&self) -> bool {
        self.root6_rot3 || self.order.is_some() || self.strip_prefix
    }
}

/// The take in the canonical form `wanted` asks for, its position channels read in `mode`; and
/// what was done that a user should hear of (OFFSETs that took a still position channel, names
/// changed). With `root6_rot3` the result's position channels replace OFFSETs (read it in
/// [`OffsetMode::Replace`]); without it, in `mode` as before.
///
/// ```
/// use bvhview::Take;
/// use bvhview::edit::{Canonical, canonical};
/// use bvhview::model::pose::{OffsetMode, world_positions};
/// use bvhview::model::skeleton::RotationOrder;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhpython_test_freebvh.bvh")?;
/// let wanted = Canonical { root6_rot3: true, order: Some(RotationOrder::Xyz), strip_prefix: true };
/// let (skeleton, motion, said) = canonical(&take.skeleton, &take.motion, OffsetMode::Replace, &wanted)?;
/// assert_eq!(skeleton.joints[0].name, "Hips"); // was mixamorig:Hips
/// assert!(said.iter().any(|line| line.contains("mixamorig:")));
/// let before = world_positions(&take.skeleton, take.motion.frame(20), OffsetMode::Replace);
/// let after = world_positions(&skeleton, motion.frame(20), OffsetMode::Replace);
/// assert!(before.iter().zip(&after).all(|(a, b)| a.distance(*b) < 1e-3));
/// # Ok(())
/// # }
/// ```
pub fn canonical(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    wanted: &Canonical,
) -> Result<(Skeleton, Motion, Vec<String>), Error> {
    let mut said = Vec::new();
    let mut out = skeleton.clone();
    let frames = motion.frame_count();
    let rows = || (0..frames).map(|f| motion.frame(f));
    // The layout of each joint, and where its values come from.
    let mut plans = Vec::with_capacity(skeleton.joints.len());
    let mut column = 0;
    for (j, joint) in skeleton.joints.iter().enumerate() {
        let copy = &mut out.joints[j];
        let positions: Vec<Channel> = joint
            .channels
            .iter()
            .copied()
            .filter(|c| c.is_position())
            .collect();
        let rotations = joint.rotation_axes();
        let mut plan = Plan {
            positions: Positions::Kept(positions.clone()),
            rotations: Rotations::Kept,
        };
        if wanted.root6_rot3 && !joint.end_site {
            plan.positions = if joint.parent.is_none() {
                Positions::Translation
            } else if positions.is_empty() {
                Positions::Kept(Vec::new())
            } else {
                still_translation(skeleton, motion, j, mode, &mut said)?;
                copy.offset = match frames {
                    0 => joint.offset,
                    _ => joint_translation(joint, joint.values(motion.frame(0)), mode),
                };
                Positions::Kept(Vec::new())
            };
        }
        let needs_three = wanted.root6_rot3 && !joint.end_site;
        let order = wanted
            .order
            .or(joint.rotation_order)
            .unwrap_or(RotationOrder::Zyx);
        if needs_three || (wanted.order.is_some() && !rotations.is_empty()) {
            let same = joint.rotation_order == Some(order) && joint.axis.is_none();
            plan.rotations = if same {
                Rotations::Kept
            } else {
                Rotations::Split(order)
            };
        }
        copy.channels = match &plan.positions {
            Positions::Kept(kept) => kept.clone(),
            Positions::Translation => {
                vec![Channel::Xposition, Channel::Yposition, Channel::Zposition]
            }
        };
        match plan.rotations {
            Rotations::Kept => copy
                .channels
                .extend(joint.channels.iter().copied().filter(|c| c.is_rotation())),
            Rotations::Split(order) => {
                copy.channels
                    .extend(order.letters().bytes().map(|letter| match letter {
                        b'x' => Channel::Xrotation,
                        b'y' => Channel::Yrotation,
                        _ => Channel::Zrotation,
                    }));
                copy.axis = None;
            }
        }
        copy.rotation_order = RotationOrder::get_flags(&copy.channels);
        copy.first_channel = column;
        column += copy.channels.len();
        plans.push(plan);
    }
    let channels = column;
    let mut data = Vec::with_capacity(frames * channels);
    let mut previous: Vec<Option<[f64; 3]>> = vec![None; skeleton.joints.len()];
    for row in rows() {
        for ((joint, plan), previous) in skeleton.joints.iter().zip(&plans).zip(&mut previous) {
            let values = joint.values(row);
            match &plan.positions {
                Positions::Kept(kept) => {
                    for (channel, &value) in joint.channels.iter().zip(values) {
                        if kept.contains(channel) {
                            data.push(value);
                        }
                    }
                }
                Positions::Translation => {
                    data.extend(joint_translation(joint, values, mode).to_array());
                }
            }
            match plan.rotations {
                Rotations::Kept => data.extend(
                    joint
                        .channels
                        .iter()
                        .zip(values)
                        .filter(|(c, _)| c.is_rotation())
                        .map(|(_, &v)| v),
                ),
                Rotations::Split(order) => {
                    let angles = euler::split(local_rotation_f64(joint, values), order, *previous);
                    *previous = Some(angles);
                    data.extend(angles.map(|a| a.to_degrees() as f32));
                }
            }
        }
    }
    if wanted.strip_prefix {
        said.extend(strip_prefixes(&mut out)?);
    }
    let motion = Motion::new(motion.frame_time, channels, frames, data);
    let (skeleton, motion) = finite("the canonical layout", out, motion)?;
    Ok((skeleton, motion, said))
}

/// How one joint's channels are made.
struct Plan {
    positions: Positions,
    rotations: Rotations,
}

/// Where a joint's position channels come from.
enum Positions {
    /// These of its own channels, as they are (none: the OFFSET alone).
    Kept(Vec<Channel>),
    /// Its whole translation (a root's X, Y and Z positions).
    Translation,
}

/// Where a joint's rotation channels come from.
enum Rotations {
    /// Its own, as they are.
    Kept,
    /// Split from the rotation they make, into this order, continuous from frame to frame.
    Split(RotationOrder),
}

/// Refuses a non-root joint whose position channels move it: canonical BVH has none there, and
/// dropping them would move its bones (bvhio#15). Still ones are said as they go into the
/// OFFSET.
fn still_translation(
    skeleton: &Skeleton,
    motion: &Motion,
    j: usize,
    mode: OffsetMode,
    said: &mut Vec<String>,
) -> Result<(), Error> {
    let joint = &skeleton.joints[j];
    let at = |f: usize| joint_translation(joint, joint.values(motion.frame(f)), mode);
    let frames = motion.frame_count();
    let (mut farthest, mut when) = (0.0f32, 0);
    for f in 1..frames {
        let distance = at(f).distance(at(0));
        if distance > farthest {
            (farthest, when) = (distance, f);
        }
    }
    if farthest > 0.0 {
        return Err(Error::usage(
            crate::io::message::Message::from(format!(
                "joint '{}' has position channels that move it {} from where frame 0 puts it \
                 (frame {when}): the canonical layout (root6,rot3) has position channels on the \
                 root only, and dropping these would move its bones; without ",
                crate::limits::quoted(&joint.name),
                crate::limits::show(f64::from(farthest))
            ))
            .argument("channels", None)
            .text(" they are kept"),
        ));
    }
    said.push(format!(
        "joint '{}': its position channels never move it; their value is its OFFSET now",
        crate::limits::quoted(&joint.name)
    ));
    Ok(())
}

/// Strips an exporter's prefixes from every joint's name: a namespace ending in `:` or `|`,
/// then a prefix every joint (End Sites aside) shares up to a separator (`_`, space, `.`, `-`).
/// Refused when two joints would share a name. What changed is said, once.
fn strip_prefixes(skeleton: &mut Skeleton) -> Result<Vec<String>, Error> {
    let original: Vec<String> = skeleton.joints.iter().map(|j| j.name.clone()).collect();
    let mut names: Vec<String> = original
        .iter()
        .map(|name| {
            name.rsplit([':', '|'])
                .next()
                .filter(|rest| !rest.is_empty())
                .unwrap_or(name)
                .to_string()
        })
        .collect();
    let body: Vec<usize> = (0..names.len())
        .filter(|&i| !skeleton.joints[i].end_site)
        .collect();
    if body.len() > 1 {
        let first = &names[body[0]];
        let mut common = first.len();
        for &i in &body[1..] {
            common = common.min(
                first
                    .bytes()
                    .zip(names[i].bytes())
                    .take_while(|(a, b)| a == b)
                    .count(),
            );
        }
        // Cut back to just after a separator, on a character boundary, leaving every name some.
        let shared = &first[..first.floor_char_boundary(common)];
        let cut = shared.rfind(['_', ' ', '.', '-']).map_or(0, |k| k + 1);
        if cut > 0 && body.iter().all(|&i| names[i].len() > cut) {
            for &i in &body {
                names[i] = names[i][cut..].to_string();
            }
        }
    }
    for (i, name) in names.iter().enumerate() {
        if let Some(k) = names[..i].iter().position(|other| other == name)
            && !skeleton.joints[i].end_site
        {
            return Err(Error::usage(
                crate::io::message::Message::from("")
                    .argument("strip_prefix", None)
                    .text(format!(
                        ": '{}' and '{}' would both be named '{}'",
                        crate::limits::quoted(&original[k]),
                        crate::limits::quoted(&original[i]),
                        crate::limits::quoted(name)
                    )),
            ));
        }
    }
    let changed: Vec<String> = original
        .iter()
        .zip(&names)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("{a} → {b}"))
        .collect();
    for (joint, name) in skeleton.joints.iter_mut().zip(names) {
        joint.name = name;
    }
    Ok(match changed.len() {
        0 => Vec::new(),
        n => vec![format!(
            "{n} names lost their prefix ({}{})",
            changed[..n.min(3)].join(", "),
            if n > 3 { ", …" } else { "" }
        )],
    })
}
