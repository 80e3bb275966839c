//! Retargeting: one take's motion on another skeleton (its names, hierarchy, bone lengths,
//! channel orders and rest pose).
//!
//! Three steps, each usable alone:
//! 1. **Roles.** [`Body::of`] reads which joint of a skeleton is the hips, the spine chain, the
//!    neck, the head and, per side, the clavicle, upper arm, forearm, hand, thigh, shin, foot and
//!    toe, from the names every common family uses (CMU, Mixamo `mixamorig:`, LaFAN1, Xsens/MVN,
//!    Bandai `UpperLeg_L`, MakeHuman, Daz/Poser/Second Life `lThigh`/`lShldr`, Rokoko,
//!    Perception Neuron, OptiTrack `LUArm`, SMPL `left_hip`, Rigify `thigh.L`), prefixes and case
//!    ignored, and from the tree where names say less (the hips are where legs and spine part).
//! 2. **A map.** [`Map::guess`] pairs target joints with source joints by role (spine chains of
//!    different lengths spread end to end), then by equal names for what has no role (fingers);
//!    [`Map::apply`] overrides it with `SRC = DST` pairs.
//! 3. **Rest alignment.** [`retarget`] gives each mapped target joint the source joint's world
//!    rotation relative to its rest pose, `W_t = W_s · W_s,rest⁻¹ · A · W_t,rest`, where A turns the
//!    target's rest bones onto the source's (so a T-pose take drives an A-pose rig with the arms
//!    where the source has them), then writes it into the target's own channels and orders.
//!    Unmapped joints keep their rest rotation; the hips' path is scaled by the ratio of hip
//!    heights and the feet are kept on the source's floor.
//!
//! Rotations are carried in 64-bit floats (see [`crate::model::pose::world_transforms_f64`]), so a take
//! retargeted onto its own skeleton gives back its own values. [`retarget`] runs eight frames side
//! by side (src/retarget/fast.rs); [`retarget_plain`] is the same work a joint and a frame at a
//! time, which a test holds it to (tests/retarget_fast.rs).

use crate::edit::{Side, channel_angles};
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, RotationKind, Up, world_transforms_f64};
use crate::model::skeleton::{Joint, Skeleton};
use glam::{DQuat, DVec3};
use std::fmt;

mod fast;

/// The part of a limb a joint moves (the joint at the start of that bone).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limb {
    Clavicle,
    UpperArm,
    ForeArm,
    Hand,
    Thigh,
    Shin,
    Foot,
    Toe,
}

const LIMBS: [Limb; 8] = [
    Limb::Clavicle,
    Limb::UpperArm,
    Limb::ForeArm,
    Limb::Hand,
    Limb::Thigh,
    Limb::Shin,
    Limb::Foot,
    Limb::Toe,
];

impl Limb {
    fn name(self) -> &'static str {
        match self {
            Limb::Clavicle => "clavicle",
            Limb::UpperArm => "upper arm",
            Limb::ForeArm => "forearm",
            Limb::Hand => "hand",
            Limb::Thigh => "thigh",
            Limb::Shin => "shin",
            Limb::Foot => "foot",
            Limb::Toe => "toe",
        }
    }
}

/// What a joint is in a human body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Hips,
    /// The n-th joint of the spine chain above the hips, from 0.
    Spine(usize),
    Neck,
    Head,
    Limb(Side, Limb),
}

impl Role {
    /// Whether the role lies on the chain hips → spine → neck → head.
    fn central(self) -> bool {
        matches!(self, Role::Spine(_) | Role::Neck | Role::Head)
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Role::Hips => f.write_str("hips"),
            Role::Spine(n) => write!(f, "spine {}", n + 1),
            Role::Neck => f.write_str("neck"),
            Role::Head => f.write_str("head"),
            Role::Limb(side, limb) => {
                let side = if *side == Side::Left { "left" } else { "right" };
                write!(f, "{side} {}", limb.name())
            }
        }
    }
}

/// What a name says, before the rest of the skeleton is looked at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Word {
    Hips,
    Spine,
    Neck,
    Head,
    Collar,
    /// A clavicle where the side also has an upper arm (Mixamo's `LeftShoulder`), the upper arm
    /// where it also has a collar (SMPL's `left_shoulder`, Second Life's `mShoulderLeft`).
    Shoulder,
    UpperArm,
    ForeArm,
    Hand,
    Wrist,
    Thigh,
    /// The shin where the side also has a thigh (Mixamo's `LeftLeg`), else the thigh.
    Leg,
    Shin,
    /// The toe where the side also has an ankle (SMPL's `left_foot`), else the foot.
    Foot,
    Ankle,
    Toe,
}

/// The words of a name in lower case: split at separators, at lower-to-upper case changes, at
/// letters next to digits, and before the last capital of a run of capitals (`LFArm` → `lf`,
/// `arm`); the part before the last `:` or `|` (`mixamorig:`) left out.
fn tokens(name: &str) -> Vec<String> {
    let name = name.rsplit([':', '|']).next().unwrap_or(name);
    let chars: Vec<char> = name.chars().collect();
    let mut out = Vec::new();
    let mut current = String::new();
    for (i, &c) in chars.iter().enumerate() {
        if !c.is_ascii_alphanumeric() {
            if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
            continue;
        }
        if !current.is_empty() {
            let previous = chars[i - 1];
            let next_lower = chars.get(i + 1).is_some_and(|n| n.is_ascii_lowercase());
            let boundary = (previous.is_ascii_lowercase() && c.is_ascii_uppercase())
                || (previous.is_ascii_alphabetic() != c.is_ascii_alphabetic())
                || (previous.is_ascii_uppercase() && c.is_ascii_uppercase() && next_lower);
            if boundary {
                out.push(std::mem::take(&mut current));
            }
        }
        current.push(c.to_ascii_lowercase());
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// Words a rig puts before its joints' names (Rigify's `DEF-`, Bandai's `joint_`, 3ds Max's
/// `Bip01`, Second Life's `m`, OptiTrack's `Skeleton1_`).
const PREFIXES: [&str; 13] = [
    "def",
    "org",
    "mch",
    "mixamorig",
    "bip",
    "bip01",
    "bip001",
    "skeleton",
    "skel",
    "joint",
    "jnt",
    "m",
    "bn",
];

/// Words that mark a helper or an end rather than a body part.
const NOT_PARTS: [&str; 12] = [
    "end", "top", "nub", "site", "tip", "twist", "roll", "ik", "pole", "ctrl", "helper", "share",
];

/// Body-part words CMU's ASF glues to a side letter (`lhumerus`, `rfemur`).
const GLUED: [&str; 22] = [
    "femur", "tibia", "foot", "toes", "toe", "clavicle", "humerus", "radius", "wrist", "hand",
    "hipjoint", "shldr", "thigh", "shin", "collar", "forearm", "uparm", "upleg", "loarm", "loleg",
    "shoulder", "hip",
];

/// The side and word a joint's name says, if it names a body part.
fn word_of(name: &str) -> Option<(Option<Side>, Word)> {
    let bare = name.rsplit([':', '|']).next().unwrap_or(name);
    // Xsens's vertebrae: L5, L3, T12, T8.
    if bare.len() >= 2
        && matches!(bare.as_bytes()[0], b'L' | b'T' | b'C')
        && bare[1..].bytes().all(|b| b.is_ascii_digit())
    {
        return Some((None, Word::Spine));
    }
    let mut words = tokens(name);
    // Leading prefixes, and the numbers after them (`Skeleton1_Hip`).
    while words.len() > 1 && PREFIXES.contains(&words[0].as_str()) {
        words.remove(0);
        while words.len() > 1 && words[0].bytes().all(|b| b.is_ascii_digit()) {
            words.remove(0);
        }
    }
    if words.iter().any(|w| NOT_PARTS.contains(&w.as_str())) {
        return None;
    }
    let mut side = None;
    let mut stem = String::new();
    for (i, word) in words.iter().enumerate() {
        let next = words.get(i + 1).map(String::as_str);
        let found = match word.as_str() {
            "l" | "left" => Some(Side::Left),
            "r" | "right" => Some(Side::Right),
            // OptiTrack's LUArm, LFArm.
            "lu" | "lf" | "ru" | "rf" if next == Some("arm") => {
                stem.push_str(&word[1..]);
                Some(if word.starts_with('l') {
                    Side::Left
                } else {
                    Side::Right
                })
            }
            w if w.bytes().all(|b| b.is_ascii_digit()) => continue,
            w => {
                let glued = [("left", Side::Left), ("right", Side::Right)]
                    .into_iter()
                    .find_map(|(mark, side)| Some((w.strip_prefix(mark)?, side)))
                    .filter(|(rest, _)| !rest.is_empty())
                    .or_else(|| {
                        let rest = w.get(1..)?;
                        let side = match w.as_bytes()[0] {
                            b'l' => Side::Left,
                            b'r' => Side::Right,
                            _ => return None,
                        };
                        (words.len() == 1 && GLUED.contains(&rest)).then_some((rest, side))
                    });
                match glued {
                    Some((rest, found)) if side.is_none() => {
                        stem.push_str(rest);
                        Some(found)
                    }
                    _ => {
                        stem.push_str(w);
                        None
                    }
                }
            }
        };
        if found.is_some() && side.is_none() {
            side = found;
        }
    }
    // Daz's ThighBend, ShldrBend, ForearmBend.
    let stem = stem.strip_suffix("bend").unwrap_or(&stem);
    let central = match stem {
        "hips" | "pelvis" | "root" => Some(Word::Hips),
        "hip" if side.is_none() => Some(Word::Hips),
        "spine" | "chest" | "upperchest" | "abdomen" | "abdomenlower" | "abdomenupper"
        | "chestlower" | "chestupper" | "lowerback" | "upperback" | "thorax" | "torso" | "back"
        | "ab" | "waist" | "lowerspine" | "upperspine" | "midspine" => Some(Word::Spine),
        "neck" | "lowerneck" | "upperneck" | "necklower" | "neckupper" => Some(Word::Neck),
        "head" => Some(Word::Head),
        _ => None,
    };
    if let Some(word) = central {
        return side.is_none().then_some((None, word));
    }
    let word = match stem {
        "clavicle" | "collar" | "collarbone" => Word::Collar,
        "shoulder" => Word::Shoulder,
        "arm" | "uparm" | "upperarm" | "uarm" | "humerus" | "shldr" => Word::UpperArm,
        "forearm" | "loarm" | "lowarm" | "lowerarm" | "radius" | "farm" | "elbow" => Word::ForeArm,
        "hand" => Word::Hand,
        "wrist" => Word::Wrist,
        "upleg" | "upperleg" | "thigh" | "femur" | "hip" => Word::Thigh,
        "leg" => Word::Leg,
        "loleg" | "lowleg" | "lowerleg" | "shin" | "tibia" | "knee" | "calf" => Word::Shin,
        "foot" => Word::Foot,
        "ankle" => Word::Ankle,
        "toe" | "toes" | "toebase" | "ball" => Word::Toe,
        _ => return None,
    };
    side.map(|side| (Some(side), word))
}

/// A skeleton's joints by role: what [`Map::guess`] pairs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Body {
    pub hips: Option<usize>,
    /// From the hips up.
    pub spine: Vec<usize>,
    pub neck: Option<usize>,
    pub head: Option<usize>,
    /// `[left, right]`, each in [`Limb`] order: clavicle, upper arm, forearm, hand, thigh, shin,
    /// foot, toe.
    pub limbs: [[Option<usize>; 8]; 2],
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

fn depth(skeleton: &Skeleton, mut joint: usize) -> usize {
    let mut depth = 0;
    while let Some(parent) = skeleton.joints[joint].parent {
        joint = parent;
        depth += 1;
    }
    depth
}

fn is_ancestor(skeleton: &Skeleton, ancestor: usize, mut joint: usize) -> bool {
    loop {
        if joint == ancestor {
            return true;
        }
        match skeleton.joints[joint].parent {
            Some(parent) => joint = parent,
            None => return false,
        }
    }
}

fn common_ancestor(skeleton: &Skeleton, a: usize, b: usize) -> Option<usize> {
    let mut joint = a;
    loop {
        if is_ancestor(skeleton, joint, b) {
            return Some(joint);
        }
        joint = skeleton.joints[joint].parent?;
    }
}

/// Joints from `from` (left out) down to `to` (left out), in order; empty unless `from` is an
/// ancestor of `to`.
fn path_between(skeleton: &Skeleton, from: usize, to: usize) -> Vec<usize> {
    let mut path = Vec::new();
    let mut joint = to;
    while let Some(parent) = skeleton.joints[joint].parent {
        if parent == from {
            path.reverse();
            return path;
        }
        path.push(parent);
        joint = parent;
    }
    Vec::new()
}

/// Limbs, neck and head from the tree alone, for a skeleton whose names say nothing: the hips
/// are the first joint with three branches at least three joints long (the largest the spine,
/// the other two the legs); the chest the first joint up the spine with two such branches (the
/// arms; the one that goes on upward from the hips, the neck). Down each arm, the hand is the
/// first joint with two children or more (fingers), else the last; down each leg the last four
/// joints are thigh, shin, foot and toe (three: no toe). Sides by the rest pose, as BVH faces
/// +z: left at +x.
#[allow(clippy::type_complexity)]
fn limbs_by_tree(
    skeleton: &Skeleton,
) -> Option<([[Option<usize>; 8]; 2], Option<usize>, Option<usize>)> {
    let joints = &skeleton.joints;
    let count = joints.len();
    let (mut height, mut size) = (vec![0usize; count], vec![0usize; count]);
    for j in (0..count).rev() {
        if joints[j].end_site {
            continue;
        }
        height[j] = 1 + joints[j]
            .children
            .iter()
            .map(|&c| height[c])
            .max()
            .unwrap_or(0);
        size[j] = 1 + joints[j].children.iter().map(|&c| size[c]).sum::<usize>();
    }
    let long = |j: usize| -> Vec<usize> {
        let mut branches: Vec<usize> = joints[j]
            .children
            .iter()
            .copied()
            .filter(|&c| height[c] >= 3)
            .collect();
        branches.sort_by_key(|&c| std::cmp::Reverse(size[c]));
        branches
    };
    let main_path = |from: usize| -> Vec<usize> {
        let mut path = vec![from];
        let mut j = from;
        while let Some(&next) = joints[j]
            .children
            .iter()
            .filter(|&&c| !joints[c].end_site)
            .max_by_key(|&&c| (size[c], std::cmp::Reverse(c)))
        {
            path.push(next);
            j = next;
        }
        path
    };
    let mut rest = Vec::new();
    world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
    let hips = (0..count).find(|&j| !joints[j].end_site && long(j).len() >= 3)?;
    let branches = long(hips);
    let (spine, legs) = (branches[0], [branches[1], branches[2]]);
    let mut chest = spine;
    while long(chest).len() < 2 {
        chest = *main_path(chest).get(1)?;
    }
    let up = (rest[chest].1 - rest[hips].1).normalize_or_zero();
    let mut arms = long(chest);
    let others: Vec<usize> = joints[chest]
        .children
        .iter()
        .copied()
        .filter(|c| !joints[*c].end_site)
        .collect();
    // The branch that goes on upward is the neck, not an arm.
    let upward = others.iter().copied().max_by(|&a, &b| {
        let rise = |c: usize| {
            let end = *main_path(c).last().unwrap_or(&c);
            (rest[end].1 - rest[chest].1).normalize_or_zero().dot(up)
        };
        rise(a).total_cmp(&rise(b))
    });
    if arms.len() > 2 {
        arms.retain(|&a| Some(a) != upward);
    }
    arms.truncate(2);
    if arms.len() < 2 {
        return None;
    }
    let side_of = |j: usize, of: usize| {
        if rest[j].1.x - rest[of].1.x >= 0.0 {
            0
        } else {
            1
        }
    };
    let mut limbs = [[None; 8]; 2];
    for &arm in &arms {
        let path = main_path(arm);
        let at = (2..path.len())
            .find(|&i| {
                joints[path[i]]
                    .children
                    .iter()
                    .filter(|&&c| !joints[c].end_site)
                    .count()
                    >= 2
            })
            .unwrap_or(path.len() - 1);
        if at < 2 {
            return None;
        }
        let side = side_of(path[at], chest);
        limbs[side][Limb::Hand as usize] = Some(path[at]);
        limbs[side][Limb::ForeArm as usize] = Some(path[at - 1]);
        limbs[side][Limb::UpperArm as usize] = Some(path[at - 2]);
        if at >= 3 {
            limbs[side][Limb::Clavicle as usize] = Some(path[at - 3]);
        }
    }
    for &leg in &legs {
        let path = main_path(leg);
        let n = path.len();
        let side = side_of(path[n - 1], hips);
        let (thigh, toe) = if n >= 4 {
            (n - 4, Some(n - 1))
        } else {
            (0, None)
        };
        limbs[side][Limb::Thigh as usize] = Some(path[thigh]);
        limbs[side][Limb::Shin as usize] = Some(path[thigh + 1]);
        limbs[side][Limb::Foot as usize] = Some(path[thigh + 2]);
        limbs[side][Limb::Toe as usize] = toe.map(|i| path[i]);
    }
    if limbs[0][Limb::Thigh as usize].is_none() || limbs[1][Limb::Thigh as usize].is_none() {
        return None;
    }
    let (neck, head) = match upward.filter(|u| !arms.contains(u)) {
        Some(u) => {
            let path = main_path(u);
            if path.len() >= 2 {
                (Some(path[0]), path.last().copied())
            } else {
                (None, Some(path[0]))
            }
        }
        None => (None, None),
    };
    Some((limbs, neck, head))
}

impl Body {
    /// The roles of a skeleton's joints, from their names and the tree.
    pub fn of(skeleton: &Skeleton) -> Body {
        let joints = &skeleton.joints;
        let words: Vec<Option<(Option<Side>, Word)>> = joints
            .iter()
            .map(|j| if j.end_site { None } else { word_of(&j.name) })
            .collect();
        let has = |side: Side, want: &[Word]| {
            words
                .iter()
                .flatten()
                .any(|&(s, w)| s == Some(side) && want.contains(&w))
        };
        // The shallowest joint of each role, words read in the light of the rest of the side.
        let mut body = Body::default();
        let shallowest = |candidates: Vec<usize>| {
            candidates
                .into_iter()
                .min_by_key(|&j| (depth(skeleton, j), j))
        };
        for side in [Side::Left, Side::Right] {
            let limb_of = |word: Word| -> Option<Limb> {
                Some(match word {
                    Word::Collar => Limb::Clavicle,
                    Word::Shoulder => {
                        if has(side, &[Word::Collar]) || !has(side, &[Word::UpperArm]) {
                            Limb::UpperArm
                        } else {
                            Limb::Clavicle
                        }
                    }
                    Word::UpperArm => Limb::UpperArm,
                    Word::ForeArm => Limb::ForeArm,
                    Word::Hand | Word::Wrist => Limb::Hand,
                    Word::Thigh => Limb::Thigh,
                    Word::Leg => {
                        if has(side, &[Word::Thigh]) {
                            Limb::Shin
                        } else {
                            Limb::Thigh
                        }
                    }
                    Word::Shin => Limb::Shin,
                    Word::Foot => {
                        if has(side, &[Word::Ankle]) {
                            Limb::Toe
                        } else {
                            Limb::Foot
                        }
                    }
                    Word::Ankle => Limb::Foot,
                    Word::Toe => Limb::Toe,
                    _ => return None,
                })
            };
            for (slot, limb) in LIMBS.iter().enumerate() {
                let candidates = (0..joints.len())
                    .filter(|&j| {
                        words[j].is_some_and(|(s, w)| s == Some(side) && limb_of(w) == Some(*limb))
                    })
                    .collect();
                body.limbs[side_index(side)][slot] = shallowest(candidates);
            }
        }
        let named = |word: Word| -> Vec<usize> {
            (0..joints.len())
                .filter(|&j| words[j].is_some_and(|(_, w)| w == word))
                .collect()
        };
        // Names that say nothing of any limb (`J1`, `bone_07`): the tree and the rest pose.
        let mut tree_neck_head = (None, None);
        if body
            .limbs
            .iter()
            .all(|side| side.iter().all(Option::is_none))
            && let Some((limbs, neck, head)) = limbs_by_tree(skeleton)
        {
            body.limbs = limbs;
            tree_neck_head = (neck, head);
        }
        let limb = |side: usize, limb: Limb| body.limbs[side][limb as usize];
        let pair_of = |a: Limb, b: Limb| {
            let left = limb(0, a).or(limb(0, b))?;
            let right = limb(1, a).or(limb(1, b))?;
            common_ancestor(skeleton, left, right)
        };
        // The chest carries both arms; the hips both legs and the spine.
        let chest = pair_of(Limb::Clavicle, Limb::UpperArm);
        let legs = pair_of(Limb::Thigh, Limb::Shin);
        let mut neck = shallowest(named(Word::Neck)).or(tree_neck_head.0);
        let head = shallowest(
            named(Word::Head)
                .into_iter()
                .filter(|&h| neck.is_none_or(|n| is_ancestor(skeleton, n, h)))
                .collect(),
        );
        let mut head = head.or(tree_neck_head.1);
        let hips = match (legs, chest.or(neck).or(head)) {
            (Some(legs), Some(top)) => common_ancestor(skeleton, legs, top),
            (Some(legs), None) => Some(legs),
            _ => shallowest(named(Word::Hips)).or(skeleton.roots().next()),
        };
        let Some(hips) = hips else {
            return body;
        };
        body.hips = Some(hips);
        // Rigify names no neck or head: the spine words above the chest are them.
        if head.is_none()
            && let Some(chest) = chest
        {
            let above: Vec<usize> = named(Word::Spine)
                .into_iter()
                .filter(|&j| j != chest && is_ancestor(skeleton, chest, j))
                .collect();
            if let Some(&last) = above.iter().max_by_key(|&&j| depth(skeleton, j)) {
                head = Some(last);
                if neck.is_none() {
                    neck = above
                        .iter()
                        .copied()
                        .filter(|&j| j != last)
                        .min_by_key(|&j| depth(skeleton, j));
                }
            }
        }
        body.neck = neck.filter(|&n| n != hips && is_ancestor(skeleton, hips, n));
        body.head = head.filter(|&h| h != hips && is_ancestor(skeleton, hips, h));
        let top = body.neck.or(body.head).or(chest.filter(|&c| c != hips));
        if let Some(top) = top {
            let mut path = path_between(skeleton, hips, top);
            if Some(top) == chest && body.neck.is_none() && body.head.is_none() {
                path.push(top);
            }
            let spine_words = named(Word::Spine);
            let named_path: Vec<usize> = path
                .iter()
                .copied()
                .filter(|j| spine_words.contains(j) || Some(*j) == chest)
                .collect();
            // No spine word on the way (names that say nothing): every joint on it.
            body.spine = if path.iter().any(|j| spine_words.contains(j)) {
                named_path
            } else {
                path
            };
        }
        body
    }

    /// Every role found, with its joint.
    pub fn roles(&self) -> Vec<(Role, usize)> {
        let mut roles = Vec::new();
        roles.extend(self.hips.map(|j| (Role::Hips, j)));
        roles.extend(
            self.spine
                .iter()
                .enumerate()
                .map(|(n, &j)| (Role::Spine(n), j)),
        );
        roles.extend(self.neck.map(|j| (Role::Neck, j)));
        roles.extend(self.head.map(|j| (Role::Head, j)));
        for side in [Side::Left, Side::Right] {
            for (slot, &limb) in LIMBS.iter().enumerate() {
                if let Some(j) = self.limbs[side_index(side)][slot] {
                    roles.push((Role::Limb(side, limb), j));
                }
            }
        }
        roles
    }

    /// The joint of `role`, if found.
    pub fn joint(&self, role: Role) -> Option<usize> {
        match role {
            Role::Hips => self.hips,
            Role::Spine(n) => self.spine.get(n).copied(),
            Role::Neck => self.neck,
            Role::Head => self.head,
            Role::Limb(side, limb) => self.limbs[side_index(side)][limb as usize],
        }
    }

    /// The feet and toes found, for the floor and the foot-skate figure.
    pub fn feet(&self) -> Vec<usize> {
        let mut feet = Vec::new();
        for side in 0..2 {
            for limb in [Limb::Foot, Limb::Toe] {
                feet.extend(self.limbs[side][limb as usize]);
            }
        }
        feet
    }
}

/// The roles a take must have on both skeletons for a guessed map to stand (the chain).
pub const REQUIRED: [Role; 9] = [
    Role::Hips,
    Role::Limb(Side::Left, Limb::UpperArm),
    Role::Limb(Side::Left, Limb::ForeArm),
    Role::Limb(Side::Right, Limb::UpperArm),
    Role::Limb(Side::Right, Limb::ForeArm),
    Role::Limb(Side::Left, Limb::Thigh),
    Role::Limb(Side::Left, Limb::Shin),
    Role::Limb(Side::Right, Limb::Thigh),
    Role::Limb(Side::Right, Limb::Shin),
];

/// How a target joint came to its source joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum How {
    Role(Role),
    /// The same name (prefixes and case aside) in both.
    Name,
    /// The one joint left between two mapped pairs, when the source has one there too (CMU's
    /// ASF `lhand` and its BVH's `LeftFingerBase`, `upperneck` and `Neck1`).
    Between,
    /// Given by the user (`--map`, `names=`).
    Given,
}

/// Which source joint drives each target joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Map {
    /// One entry per target joint: the source joint it takes its rotation from.
    pub source_of: Vec<Option<usize>>,
    pub how: Vec<Option<How>>,
    /// The roles of the two skeletons, as guessed.
    pub source_body: Body,
    pub target_body: Body,
}

/// A name for matching: the part after the last `:` or `|`, in lower case.
fn bare_name(name: &str) -> String {
    name.rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .to_ascii_lowercase()
}

impl Map {
    /// The guess: every role both skeletons have (the spine chains spread end to end over each
    /// other when their lengths differ), then joints of the same name among the rest.
    pub fn guess(source: &Skeleton, target: &Skeleton) -> Map {
        let source_body = Body::of(source);
        let target_body = Body::of(target);
        let count = target.joints.len();
        let mut map = Map {
            source_of: vec![None; count],
            how: vec![None; count],
            source_body,
            target_body,
        };
        for (role, t) in map.target_body.roles() {
            if matches!(role, Role::Spine(_)) {
                continue;
            }
            if let Some(s) = map.source_body.joint(role) {
                map.source_of[t] = Some(s);
                map.how[t] = Some(How::Role(role));
            }
        }
        // Spine chains: first to first, last to last, the others at the same fraction up.
        let (ts, ss) = (&map.target_body.spine, &map.source_body.spine);
        let pairs: Vec<(usize, usize)> = match (ts.len(), ss.len()) {
            (0, _) | (_, 0) => Vec::new(),
            (1, _) => vec![(0, 0)],
            (_, 1) => vec![(0, 0)],
            (t, s) if t <= s => (0..t)
                .map(|k| (k, (k * (s - 1) + (t - 1) / 2) / (t - 1)))
                .collect(),
            (t, s) => (0..s)
                .map(|k| ((k * (t - 1) + (s - 1) / 2) / (s - 1), k))
                .collect(),
        };
        for (k, i) in pairs {
            let t = map.target_body.spine[k];
            map.source_of[t] = Some(map.source_body.spine[i]);
            map.how[t] = Some(How::Role(Role::Spine(k)));
        }
        // The rest by name.
        let mut used = vec![false; source.joints.len()];
        for s in map.source_of.iter().flatten() {
            used[*s] = true;
        }
        let mut by_name = std::collections::HashMap::new();
        for (s, joint) in source.joints.iter().enumerate() {
            if !joint.end_site && !used[s] {
                by_name.entry(bare_name(&joint.name)).or_insert(s);
            }
        }
        for (t, joint) in target.joints.iter().enumerate() {
            if joint.end_site || map.source_of[t].is_some() {
                continue;
            }
            if let Some(s) = by_name.remove(&bare_name(&joint.name)) {
                map.source_of[t] = Some(s);
                map.how[t] = Some(How::Name);
                used[s] = true;
            }
        }
        // A joint left alone between two mapped pairs takes the one unused source joint
        // between their sources: the bone it moves is the bone that one moves.
        for (t, joint) in target.joints.iter().enumerate() {
            let Some(p) = joint.parent else { continue };
            if joint.end_site || map.source_of[t].is_some() {
                continue;
            }
            let Some(sp) = map.source_of[p] else { continue };
            for d in mapped_below(target, &map.source_of, t) {
                let Some(sd) = map.source_of[d] else { continue };
                if path_between(target, p, d) != [t] {
                    continue;
                }
                if let [x] = path_between(source, sp, sd)[..]
                    && !used[x]
                    && !source.joints[x].end_site
                {
                    map.source_of[t] = Some(x);
                    map.how[t] = Some(How::Between);
                    used[x] = true;
                    break;
                }
            }
        }
        map
    }

    /// Overrides the map with `(source joint, target joint)` pairs, by exact name; an empty
    /// target name unmaps the source joint. A source joint given a target loses the targets
    /// the guess gave it. Errors name the joint: one neither skeleton has, or two source
    /// joints given one target joint.
    pub fn apply(
        &mut self,
        pairs: &[(String, String)],
        source: &Skeleton,
        target: &Skeleton,
    ) -> Result<(), Error> {
        let find = |skeleton: &Skeleton, name: &str| {
            skeleton
                .joints
                .iter()
                .position(|j| !j.end_site && j.name == name)
        };
        let mut given: Vec<(usize, usize)> = Vec::new();
        for (src, dst) in pairs {
            let s = find(source, src).ok_or_else(|| {
                Error::Usage(format!(
                    "map: the source has no joint named {src:?} (it has {})",
                    some_names(source)
                ))
            })?;
            if dst.is_empty() {
                // A later "leave out" wins over an earlier pair of the same joint.
                given.retain(|&(o, _)| o != s);
                for t in 0..self.source_of.len() {
                    if self.source_of[t] == Some(s) {
                        self.source_of[t] = None;
                        self.how[t] = None;
                    }
                }
                continue;
            }
            let t = find(target, dst).ok_or_else(|| {
                Error::Usage(format!(
                    "map: the target has no joint named {dst:?} (it has {})",
                    some_names(target)
                ))
            })?;
            if let Some(&(other, _)) = given.iter().find(|&&(o, tt)| tt == t && o != s) {
                return Err(Error::Usage(format!(
                    "map: two source joints, {:?} and {src:?}, mapped to one target joint {dst:?}",
                    source.joints[other].name
                )));
            }
            given.push((s, t));
        }
        for &(s, t) in &given {
            for other in 0..self.source_of.len() {
                if self.source_of[other] == Some(s) && self.how[other] != Some(How::Given) {
                    self.source_of[other] = None;
                    self.how[other] = None;
                }
            }
            self.source_of[t] = Some(s);
            self.how[t] = Some(How::Given);
        }
        Ok(())
    }

    /// Fails unless the chain is mapped: every [`REQUIRED`] role of the target has a source
    /// joint. A map the user gave joints to needs only two mapped joints.
    pub fn check(&self, source_name: &str, target_name: &str) -> Result<(), Error> {
        if self.how.contains(&Some(How::Given)) {
            if self.source_of.iter().flatten().count() >= 2 {
                return Ok(());
            }
            return Err(Error::Usage(format!(
                "{target_name}: fewer than two joints mapped; nothing to retarget"
            )));
        }
        let missing = |body: &Body| -> Vec<String> {
            REQUIRED
                .iter()
                .filter(|&&r| body.joint(r).is_none())
                .map(|r| r.to_string())
                .collect()
        };
        for (name, body, what) in [
            (target_name, &self.target_body, "target"),
            (source_name, &self.source_body, "source"),
        ] {
            let missing = missing(body);
            if !missing.is_empty() {
                return Err(Error::Usage(format!(
                    "{name}: the {what} has no mappable chain: no joint found for {} \
                     (name them with --map SRC=DST or a map file)",
                    missing.join(", ")
                )));
            }
        }
        Ok(())
    }

    /// The map as text: TOML that `--map FILE` reads back (`"source" = "target"  # role`),
    /// then what stays unmapped on either side, as comments.
    pub fn show(&self, source: &Skeleton, target: &Skeleton) -> String {
        let quote = |s: &str| serde_json::to_string(s).unwrap_or_default();
        let mut text =
            String::from("# bvhview retarget map: \"source joint\" = \"target joint\"\n");
        for (t, s) in self.source_of.iter().enumerate() {
            let Some(s) = s else { continue };
            let how = match self.how[t] {
                Some(How::Role(role)) => role.to_string(),
                Some(How::Name) => "same name".to_string(),
                Some(How::Between) => "between".to_string(),
                Some(How::Given) => "given".to_string(),
                None => String::new(),
            };
            text.push_str(&format!(
                "{} = {}  # {how}\n",
                quote(&source.joints[*s].name),
                quote(&target.joints[t].name)
            ));
        }
        let unmapped: Vec<String> = target
            .joints
            .iter()
            .enumerate()
            .filter(|(t, j)| !j.end_site && self.source_of[*t].is_none())
            .map(|(_, j)| j.name.clone())
            .collect();
        let mut used = vec![false; source.joints.len()];
        for s in self.source_of.iter().flatten() {
            used[*s] = true;
        }
        let unused: Vec<String> = source
            .joints
            .iter()
            .enumerate()
            .filter(|(s, j)| !j.end_site && !used[*s])
            .map(|(_, j)| j.name.clone())
            .collect();
        text.push_str(&format!(
            "# target joints left at rest ({}): {}\n",
            unmapped.len(),
            if unmapped.is_empty() {
                "none".into()
            } else {
                unmapped.join(" ")
            }
        ));
        text.push_str(&format!(
            "# source joints not used ({}): {}\n",
            unused.len(),
            if unused.is_empty() {
                "none".into()
            } else {
                unused.join(" ")
            }
        ));
        text
    }
}

/// The first few joint names, for an error.
fn some_names(skeleton: &Skeleton) -> String {
    let names: Vec<&str> = skeleton
        .joints
        .iter()
        .filter(|j| !j.end_site)
        .map(|j| j.name.as_str())
        .collect();
    let shown: Vec<String> = names.iter().take(8).map(|n| format!("{n:?}")).collect();
    if names.len() > 8 {
        format!("{} … ({} joints)", shown.join(", "), names.len())
    } else {
        shown.join(", ")
    }
}

/// Reads a map file: JSON (`{"source": "target", …}`) or TOML (`"source" = "target"` lines,
/// what `--show-map` prints). An error names the file, line and column.
pub fn parse_map(text: &str, name: &str) -> Result<Vec<(String, String)>, Error> {
    let bad = |line: usize, column: usize, message: String| Error::Parse {
        path: name.to_string(),
        line,
        column,
        message,
    };
    let table: Vec<(String, String)> = if text.trim_start().starts_with('{') {
        let value: JsonEntries = serde_json::from_str(text)
            .map_err(|e| bad(e.line(), e.column(), format!("not a JSON map: {e}")))?;
        let mut pairs = Vec::new();
        for (key, value) in value.0 {
            match value {
                serde_json::Value::String(target) => pairs.push((key, target)),
                serde_json::Value::Null => pairs.push((key, String::new())),
                other => {
                    return Err(bad(
                        line_of(text, &key),
                        1,
                        format!("{key:?}: expected a target joint's name, found {other}"),
                    ));
                }
            }
        }
        pairs
    } else {
        let value: toml::Table = toml::from_str(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|span| position_of(text, span.start))
                .unwrap_or((1, 1));
            bad(line, column, format!("not a TOML map: {}", e.message()))
        })?;
        let mut pairs = Vec::new();
        for (key, value) in value {
            match value {
                toml::Value::String(target) => pairs.push((key, target)),
                other => {
                    return Err(bad(
                        line_of(text, &key),
                        1,
                        format!(
                            "{key:?}: expected a target joint's name in quotes, found {}",
                            other.type_str()
                        ),
                    ));
                }
            }
        }
        pairs
    };
    Ok(table)
}

/// A JSON map's entries in file order. A key given twice is refused where the second one is
/// (serde_json's own map would keep the last silently; TOML refuses it too).
struct JsonEntries(Vec<(String, serde_json::Value)>);

impl<'de> serde::Deserialize<'de> for JsonEntries {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Entries;
        impl<'de> serde::de::Visitor<'de> for Entries {
            type Value = JsonEntries;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object of source and target joint names")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<JsonEntries, A::Error> {
                let mut entries: Vec<(String, serde_json::Value)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if entries.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!("{key:?} is given twice")));
                    }
                    let value = map.next_value()?;
                    entries.push((key, value));
                }
                Ok(JsonEntries(entries))
            }
        }
        deserializer.deserialize_map(Entries)
    }
}

fn position_of(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

fn line_of(text: &str, key: &str) -> usize {
    text.lines()
        .position(|l| l.contains(key))
        .map_or(1, |i| i + 1)
}

/// Reads `SRC=DST`.
pub fn parse_pair(text: &str) -> Option<(String, String)> {
    let (src, dst) = text.split_once('=')?;
    let unquote = |s: &str| s.trim().trim_matches('"').to_string();
    let src = unquote(src);
    (!src.is_empty()).then(|| (src, unquote(dst)))
}

/// The built-in target skeletons: `smpl22`, the 22 body joints of SMPL in the layout of
/// HumanML3D, AMASS and most text-to-motion models, in centimetres, T-pose, Y up, facing +z.
pub const BUILT_IN: &[(&str, &[u8])] = &[("smpl22", include_bytes!("../../assets/smpl22.bvh"))];

/// A built-in skeleton by name (see [`BUILT_IN`]), with its one rest frame.
pub fn built_in(name: &str) -> Option<(Skeleton, Motion)> {
    let (_, bytes) = BUILT_IN
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))?;
    let file = crate::bvh::load_bytes(bytes, name).ok()?;
    Some((file.skeleton, file.motion))
}

/// A skeleton to retarget onto: a file's or a built-in one, with its up axis and the name to
/// show in messages (`bvhview retarget --onto`, `dataset --onto`).
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    pub name: String,
    pub skeleton: Skeleton,
    pub up: Up,
}

impl Target {
    /// `onto` as a file (.bvh, or .asf: only the skeleton is used) when it exists, else a
    /// built-in skeleton's name (see [`BUILT_IN`]).
    pub fn load(onto: &str, max_size: u64) -> Result<Target, Error> {
        let path = std::path::Path::new(onto);
        if !path.exists() {
            if let Some((skeleton, motion)) = built_in(onto) {
                return Ok(Target::new(onto.to_string(), skeleton, &motion));
            }
            if crate::take::extension(path).is_empty() {
                let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
                return Err(Error::Usage(format!(
                    "--onto {onto}: neither a file nor a built-in skeleton ({})",
                    names.join(", ")
                )));
            }
        }
        let loaded =
            crate::take::load_checked(path, None, None, crate::io::parallel::cores(), max_size)?;
        Ok(Target::new(
            path.display().to_string(),
            loaded.skeleton,
            &loaded.motion,
        ))
    }

    /// A target whose up axis is its take's, or its rest pose's when it has one frame or none.
    pub fn new(name: String, skeleton: Skeleton, motion: &Motion) -> Target {
        let up = if motion.frame_count() > 1 {
            crate::model::stance::Stance::guess(&skeleton, motion, OffsetMode::Replace, None).up
        } else {
            Up::guess(&skeleton)
        };
        Target { name, skeleton, up }
    }

    /// A take on this skeleton by the guessed map (`pairs` override it), refused with the
    /// reason when the map cannot stand, on up to `threads` threads. `source_name` names the
    /// take in messages.
    pub fn apply(
        &self,
        source_name: &str,
        skeleton: &Skeleton,
        motion: &Motion,
        pairs: &[(String, String)],
        threads: usize,
    ) -> Result<(Skeleton, Motion), Error> {
        let mut map = Map::guess(skeleton, &self.skeleton);
        map.apply(pairs, skeleton, &self.skeleton)?;
        map.check(source_name, &self.name)?;
        let ups = Ups {
            source: crate::model::stance::Stance::guess(
                skeleton,
                motion,
                OffsetMode::Replace,
                None,
            )
            .up,
            target: self.up,
        };
        retarget(skeleton, motion, &self.skeleton, &map, ups, threads)
    }
}

/// The two skeletons' up axes, as their takes stand.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Ups {
    pub source: Up,
    pub target: Up,
}

/// [`Up::to_y_up`] in 64-bit floats (the 32-bit quaternion is not of unit length to 64 bits).
fn to_y_up(up: Up) -> DQuat {
    match up {
        Up::Y => DQuat::IDENTITY,
        Up::Z => DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2),
    }
}

/// Nearest mapped joints below `joint`: down each branch to the first mapped one.
fn mapped_below(skeleton: &Skeleton, map: &[Option<usize>], joint: usize) -> Vec<usize> {
    let mut found = Vec::new();
    let mut stack: Vec<usize> = skeleton.joints[joint].children.clone();
    while let Some(j) = stack.pop() {
        if map[j].is_some() {
            found.push(j);
        } else {
            stack.extend(skeleton.joints[j].children.iter().copied());
        }
    }
    found.sort_unstable();
    found
}

fn subtree_size(skeleton: &Skeleton, joint: usize) -> usize {
    1 + skeleton.joints[joint]
        .children
        .iter()
        .map(|&c| subtree_size(skeleton, c))
        .sum::<usize>()
}

/// The bones both skeletons have, one per mapped target joint: to the next mapped joint down
/// its chain (the spine's way at the hips and chest, else the largest branch), where neither
/// skeleton's bone has zero length (CMU's `LowerBack` and `Neck` sit where their parents do: its
/// hips and chest have no bone there). `(target joint, target child)`; the source's are their
/// map. The bones [`direction_errors`] measures.
pub fn bones(source: &Skeleton, target: &Skeleton, map: &Map) -> Vec<(usize, usize)> {
    main_bones(source, target, map)
        .into_iter()
        .filter(|&(_, _, direct)| direct)
        .map(|(t, d, _)| (t, d))
        .collect()
}

/// [`bones`], and where a bone has zero length on either skeleton, the chord to the next joint
/// down the chain that does not (`false`): what rest alignment turns onto the source's.
fn main_bones(source: &Skeleton, target: &Skeleton, map: &Map) -> Vec<(usize, usize, bool)> {
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
fn arc(from: DVec3, to: DVec3) -> DQuat {
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
fn alignments(
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
        let (mut sin, mut cos) = (0.0, 0.0);
        for d in mapped_below(target, &map.source_of, t) {
            if Some(&d) == main.get(&t) || map.source_of[d] == Some(s) {
                continue;
            }
            let Some((tv, sv)) = vectors(d) else { continue };
            let a = swung * tv;
            let a = a - axis * a.dot(axis);
            let b = sv - axis * sv.dot(axis);
            sin += a.cross(b).dot(axis);
            cos += a.dot(b);
        }
        let twist = if sin.abs() > 1e-12 * cos.abs().max(1e-300) {
            DQuat::from_axis_angle(axis, sin.atan2(cos))
        } else {
            DQuat::IDENTITY
        };
        aligned[t] = twist * swung;
    }
    aligned
}

/// How tall the hips stand: the legs' length (thigh to shin to foot, the mean of the two sides
/// found), which a rest pose lying down or with its bones along x (Bandai's) measures the same
/// as one standing. Without legs: the spread of the rest pose along the body from the hips.
fn hip_height(skeleton: &Skeleton, body: &Body, hips: usize, rest: &[(DQuat, DVec3)]) -> f64 {
    let mut legs = Vec::new();
    for side in 0..2 {
        let joint = |limb: Limb| body.limbs[side][limb as usize];
        if let (Some(thigh), Some(shin), Some(foot)) =
            (joint(Limb::Thigh), joint(Limb::Shin), joint(Limb::Foot))
        {
            legs.push(
                (rest[shin].1 - rest[thigh].1).length() + (rest[foot].1 - rest[shin].1).length(),
            );
        }
    }
    if !legs.is_empty() {
        return legs.iter().sum::<f64>() / legs.len() as f64;
    }
    (0..skeleton.joints.len())
        .map(|j| (rest[j].1 - rest[hips].1).length())
        .fold(0.0, f64::max)
}

/// Joints of the legs (everything under a thigh, End Sites too): where the floor is read.
fn leg_points(skeleton: &Skeleton, body: &Body) -> Vec<usize> {
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
fn source_offset_mode(source: &Skeleton, motion: &Motion) -> OffsetMode {
    match crate::model::pose::written_for_other_mode(source, motion, OffsetMode::Replace) {
        Some(_) => OffsetMode::Add,
        None => OffsetMode::Replace,
    }
}

/// Of the two Euler forms of a rotation, and their turns by whole circles, the one nearest
/// `reference` (degrees).
fn nearest_form(angles: [f64; 3], reference: [f64; 3]) -> [f64; 3] {
    let near = |angle: f64, to: f64| angle + 360.0 * ((to - angle) / 360.0).round();
    let forms = [
        angles,
        [angles[0] + 180.0, 180.0 - angles[1], angles[2] + 180.0],
    ];
    let mut best = angles;
    let mut best_cost = f64::INFINITY;
    for form in forms {
        let fitted = [
            near(form[0], reference[0]),
            near(form[1], reference[1]),
            near(form[2], reference[2]),
        ];
        let cost: f64 = (0..3).map(|i| (fitted[i] - reference[i]).abs()).sum();
        if cost < best_cost {
            best_cost = cost;
            best = fitted;
        }
    }
    best
}

/// The turn about unit `axis` that best lays `from` on `to` (the angle between them projected on
/// the plane across the axis); `None` when either lies along the axis.
fn hinge_angle(axis: DVec3, from: DVec3, to: DVec3) -> Option<f64> {
    let from = from - axis * from.dot(axis);
    let to = to - axis * to.dot(axis);
    (from.length() > 1e-9 && to.length() > 1e-9)
        .then(|| axis.dot(from.cross(to)).atan2(from.dot(to)))
}

/// The channel values of a joint with fewer than three rotation channels (an ASF knee `dof rx`,
/// a foot `dof rx rz`, a bone without dof) for the local rotation `local` it cannot always take,
/// and the local rotation those values give. A hinge turns so that its bone (`bone`: at rest,
/// in the joint's frame) lies as near as it can to where `local` puts it: the bone's direction
/// projected on the plane the hinge turns in, which is the best a hinge can do. Two channels
/// `R1 · R2` lay the bone exactly where the direction is within their reach (the second angle
/// keeps the bone's component along the first axis, the first turns it into place), of the two
/// solutions the one nearer the Euler decomposition. Without a bone, or where the bone lies
/// along an axis, the Euler decomposition's angles ([`channel_angles`]).
fn limited_angles(joint: &Joint, local: DQuat, bone: Option<DVec3>) -> ([f64; 3], DQuat) {
    let axes: Vec<usize> = joint
        .channels
        .iter()
        .filter(|c| c.is_rotation())
        .map(|c| c.axis())
        .collect();
    let mut angles = [0.0; 3];
    let q = local.as_quat();
    for (angle, value) in angles.iter_mut().zip(channel_angles(
        joint,
        RotationKind::Quat,
        &[q.w, q.x, q.y, q.z],
    )) {
        *angle = f64::from(value);
    }
    let c = joint
        .axis
        .map_or(DQuat::IDENTITY, |c| c.as_dquat().normalize());
    if let Some(bone) = bone.filter(|b| b.length() > 1e-9) {
        // In the channels' frame: the bone at rest and where `local` puts it.
        let u = c.inverse() * bone;
        let w = c.inverse() * (local * bone);
        let unit = |axis: usize| DVec3::AXES[axis];
        let about =
            |axis: usize, degrees: f64| DQuat::from_axis_angle(unit(axis), degrees.to_radians());
        match axes[..] {
            [a] => {
                if let Some(theta) = hinge_angle(unit(a), u, w) {
                    angles[0] = theta.to_degrees();
                }
            }
            [a1, a2] if a1 != a2 => {
                let (x1, x2) = (unit(a1), unit(a2));
                // a1 · R2(β) u = A cos β + B sin β must equal a1 · w.
                let (along, across) = (x1.dot(u), x1.dot(x2.cross(u)));
                let reach = along.hypot(across);
                if reach > 1e-9 {
                    let phase = across.atan2(along);
                    let spread = (x1.dot(w) / reach).clamp(-1.0, 1.0).acos();
                    let near = |b: f64| {
                        let d = (b.to_degrees() - angles[1]).rem_euclid(360.0);
                        d.min(360.0 - d)
                    };
                    let beta = [phase + spread, phase - spread]
                        .into_iter()
                        .min_by(|&x, &y| near(x).total_cmp(&near(y)))
                        .unwrap_or(phase);
                    let mut beta = beta.to_degrees();
                    beta -= 360.0 * ((beta - angles[1]) / 360.0).round();
                    let turned = about(a2, beta) * u;
                    if let Some(alpha) = hinge_angle(x1, turned, w) {
                        angles[0] = alpha.to_degrees();
                        angles[1] = beta;
                    }
                }
            }
            _ => {}
        }
    }
    // The rotation the values give, as they are written (32-bit).
    let mut values = Vec::with_capacity(joint.channels.len());
    let mut rotations = angles.iter();
    for channel in &joint.channels {
        values.push(if channel.is_rotation() {
            rotations.next().copied().unwrap_or(0.0) as f32
        } else {
            0.0
        });
    }
    (
        angles,
        crate::model::pose::local_rotation_f64(joint, &values),
    )
}

/// The source's motion on the target skeleton: a take with the target's joints, offsets and
/// channels, and the source's frames and frame time, computed on up to `threads` threads (the
/// same values on any number). See the module's docs for the steps.
///
/// The fast path (eight frames at a time, src/retarget/fast.rs); [`retarget_plain`] is the same
/// work a joint and a frame at a time, which a test holds it to.
pub fn retarget(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
) -> Result<(Skeleton, Motion), Error> {
    let setup = Setup::new(source, motion, target, map, ups);
    let (data, finite) = fast::frames(&setup, source, motion, target, map, threads);
    if finite && target.joints.iter().all(|j| j.offset.is_finite()) {
        // What `finish` checks, checked already on the cores.
        let motion = Motion::new(
            motion.frame_time,
            target.channel_count(),
            motion.frame_count(),
            data,
        );
        return Ok((target.clone(), motion));
    }
    finish(target, motion, data)
}

/// [`retarget`] done plainly: glam's 64-bit quaternions and libm's `sin`, `cos` and `atan2`, a
/// joint and a frame at a time. What the fast path is checked against.
pub fn retarget_plain(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
) -> Result<(Skeleton, Motion), Error> {
    let setup = Setup::new(source, motion, target, map, ups);
    let values = plain_frames(&setup, source, motion, target, map, threads);
    finish(target, motion, values.iter().map(|&v| v as f32).collect())
}

/// The channel values [`retarget`] (`fast`) or [`retarget_plain`] computes, before they are
/// rounded to 32 bits: for the test that holds the two together.
#[doc(hidden)]
pub fn retargeted_values(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
    fast: bool,
) -> Vec<f64> {
    let setup = Setup::new(source, motion, target, map, ups);
    match fast {
        true => fast::frames(&setup, source, motion, target, map, threads).0,
        false => plain_frames(&setup, source, motion, target, map, threads),
    }
}

/// The take, refused when a value is not finite (too large for a 32-bit float).
fn finish(target: &Skeleton, motion: &Motion, data: Vec<f32>) -> Result<(Skeleton, Motion), Error> {
    crate::edit::finite(
        "retargeting",
        target.clone(),
        Motion::new(
            motion.frame_time,
            target.channel_count(),
            motion.frame_count(),
            data,
        ),
    )
}

/// What the pass over the frames needs, worked out once from the skeletons and the map: the
/// same for the plain and the fast path.
struct Setup {
    source_mode: OffsetMode,
    /// The source's and the target's turn to Y up, and the target's back.
    us: DQuat,
    ut: DQuat,
    ut_inv: DQuat,
    aligned: Vec<DQuat>,
    /// The hips pair that carries the path: (target, source).
    hips: Option<(usize, usize)>,
    /// The joint whose position channels move the hips there: the hips or an ancestor.
    carrier: Option<usize>,
    ratio: f64,
    /// Per target joint following a source chord: the chord's far source joint, and the bone at
    /// rest.
    follow: Vec<Option<(usize, DVec3)>>,
    source_legs: Vec<usize>,
    target_legs: Vec<usize>,
    under_carrier: Vec<bool>,
    reference_columns: Vec<Option<[usize; 3]>>,
    bone_of: Vec<Option<DVec3>>,
}

impl Setup {
    fn new(source: &Skeleton, motion: &Motion, target: &Skeleton, map: &Map, ups: Ups) -> Setup {
        let mode = OffsetMode::Replace;
        let source_mode = source_offset_mode(source, motion);
        let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
        let ut_inv = ut.inverse();
        let mut source_rest = Vec::new();
        let mut target_rest = Vec::new();
        world_transforms_f64(source, &[], mode, &mut source_rest);
        world_transforms_f64(target, &[], mode, &mut target_rest);
        let aligned = alignments(source, target, map, ups, &source_rest, &target_rest);
        // The hips pair that carries the path: the target's hips if mapped, else its first
        // mapped joint.
        let hips_t = map
            .target_body
            .hips
            .filter(|&h| map.source_of[h].is_some())
            .or_else(|| map.source_of.iter().position(Option::is_some));
        let hips = hips_t.and_then(|t| Some((t, map.source_of[t]?)));
        // The joint whose position channels move the hips there: the hips or an ancestor.
        let carrier = hips_t.and_then(|t| {
            let mut joint = t;
            loop {
                if target.joints[joint]
                    .channels
                    .iter()
                    .any(|c| c.is_position())
                {
                    return Some(joint);
                }
                joint = target.joints[joint].parent?;
            }
        });
        let ratio = match hips {
            Some((t, s)) => {
                let ht = hip_height(target, &map.target_body, t, &target_rest);
                let hs = hip_height(source, &map.source_body, s, &source_rest);
                if ht > 1e-9 && hs > 1e-9 { ht / hs } else { 1.0 }
            }
            None => 1.0,
        };
        // Bones whose source chord spans joints the target lacks (CMU's Neck1 between Neck and
        // Head): the target bone follows the chord each frame, by the smallest turn.
        let mut follow: Vec<Option<(usize, DVec3)>> = vec![None; target.joints.len()];
        for (t, d, _) in main_bones(source, target, map) {
            let (Some(s), Some(sd)) = (map.source_of[t], map.source_of[d]) else {
                continue;
            };
            let mut used = vec![false; source.joints.len()];
            for u in map.source_of.iter().flatten() {
                used[*u] = true;
            }
            if path_between(source, s, sd).iter().any(|&j| !used[j]) {
                follow[t] = Some((sd, target_rest[d].1 - target_rest[t].1));
            }
        }
        let source_legs = leg_points(source, &map.source_body);
        let target_legs = leg_points(target, &map.target_body);
        let joints = target.joints.len();
        let under_carrier: Vec<bool> = (0..joints)
            .map(|j| carrier.is_some_and(|c| is_ancestor(target, c, j)))
            .collect();
        // Of each target joint turning in the same order as its source joint, the source's
        // rotation columns: its values are the reference for the Euler form written.
        let reference_columns: Vec<Option<[usize; 3]>> = (0..joints)
            .map(|t| {
                let joint = &target.joints[t];
                let s = &source.joints[map.source_of[t]?];
                if joint.rotation_order.is_none()
                    || s.rotation_order != joint.rotation_order
                    || s.axis != joint.axis
                {
                    return None;
                }
                let columns: Vec<usize> = s
                    .channels
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.is_rotation())
                    .map(|(i, _)| s.first_channel + i)
                    .collect();
                Some([columns[0], columns[1], columns[2]])
            })
            .collect();
        // Each target joint's main bone at rest, in its own frame (every rest rotation is the
        // identity): what a joint with fewer than three rotation channels lays where it can.
        let mut bone_of: Vec<Option<DVec3>> = vec![None; joints];
        for (t, d, _) in main_bones(source, target, map) {
            bone_of[t] = Some(target_rest[d].1 - target_rest[t].1);
        }
        Setup {
            source_mode,
            us,
            ut,
            ut_inv,
            aligned,
            hips,
            carrier,
            ratio,
            follow,
            source_legs,
            target_legs,
            under_carrier,
            reference_columns,
            bone_of,
        }
    }

    /// Feet on the floor: the legs' lowest point over the take where the source's is, scaled.
    fn lift(&self, source_floor: f64, target_floor: f64) -> DVec3 {
        if source_floor.is_finite() && target_floor.is_finite() {
            self.ut_inv * DVec3::new(0.0, self.ratio * source_floor - target_floor, 0.0)
        } else {
            DVec3::ZERO
        }
    }
}

/// The plain pass over the frames: every frame's channel values, frame after frame.
fn plain_frames(
    setup: &Setup,
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    threads: usize,
) -> Vec<f64> {
    let Setup {
        source_mode,
        us,
        ut,
        ut_inv,
        ref aligned,
        hips,
        carrier,
        ratio,
        ref follow,
        ref source_legs,
        ref target_legs,
        ref under_carrier,
        ref reference_columns,
        ref bone_of,
    } = *setup;
    let frames = motion.frame_count();
    let joints = target.joints.len();
    // First, on the cores, a piece of frames at a time: each target joint's rotation channels
    // in one Euler form (radians turned to degrees), where the carrier moves the hips, and the
    // lowest leg points of source and target.
    struct Piece {
        angles: Vec<[f64; 3]>,
        moves: Vec<DVec3>,
        carrier_parent: Vec<DQuat>,
        source_floor: f64,
        target_floor: f64,
    }
    const PIECE: usize = 512;
    let compute = |piece: usize| -> Piece {
        let range = piece * PIECE..((piece + 1) * PIECE).min(frames);
        let mut out = Piece {
            angles: Vec::with_capacity(range.len() * joints),
            moves: Vec::with_capacity(range.len()),
            carrier_parent: Vec::with_capacity(range.len()),
            source_floor: f64::INFINITY,
            target_floor: f64::INFINITY,
        };
        let mut world_s = Vec::new();
        let mut world_t: Vec<(DQuat, DVec3)> = vec![(DQuat::IDENTITY, DVec3::ZERO); joints];
        for frame in range {
            world_transforms_f64(source, motion.frame(frame), source_mode, &mut world_s);
            for t in 0..joints {
                let joint = &target.joints[t];
                let parent = joint.parent.map(|p| world_t[p]);
                let parent_rotation = parent.map_or(DQuat::IDENTITY, |(r, _)| r);
                let rotation = match map.source_of[t] {
                    Some(s) => {
                        let carried = us * world_s[s].0 * us.inverse();
                        let rotation = ut_inv * carried * aligned[t] * ut;
                        match follow[t] {
                            Some((sd, rest)) => {
                                let chord = ut_inv * (us * (world_s[sd].1 - world_s[s].1));
                                if chord.length() > 1e-9 {
                                    arc(rotation * rest, chord) * rotation
                                } else {
                                    rotation
                                }
                            }
                            None => rotation,
                        }
                    }
                    None => parent_rotation,
                };
                let mut rotation = rotation;
                let local = parent_rotation.inverse() * rotation;
                out.angles.push(match joint.rotation_order {
                    Some(order) => {
                        let channel_rotation = match joint.axis {
                            Some(c) => {
                                let c = c.as_dquat().normalize();
                                c.inverse() * local * c
                            }
                            None => local,
                        };
                        crate::model::euler::split(channel_rotation, order, None)
                            .map(f64::to_degrees)
                    }
                    None => {
                        // Fewer than three rotation channels: the rotation the joint can take,
                        // and its children go on from that one, not from the one asked for.
                        let (angles, realized) = limited_angles(joint, local, bone_of[t]);
                        rotation = parent_rotation * realized;
                        angles
                    }
                });
                let position = match parent {
                    Some((r, p)) => p + r * joint.offset.as_dvec3(),
                    None => joint.offset.as_dvec3(),
                };
                world_t[t] = (rotation, position);
            }
            let (mut moved, mut turned) = (DVec3::ZERO, DQuat::IDENTITY);
            if let (Some((t, s)), Some(carrier)) = (hips, carrier) {
                let wanted = ut_inv * (ratio * (us * world_s[s].1));
                moved = wanted - world_t[t].1;
                turned = target.joints[carrier]
                    .parent
                    .map_or(DQuat::IDENTITY, |p| world_t[p].0);
                for (joint, &under) in world_t.iter_mut().zip(under_carrier) {
                    if under {
                        joint.1 += moved;
                    }
                }
            }
            out.moves.push(moved);
            out.carrier_parent.push(turned);
            for &j in source_legs {
                out.source_floor = out.source_floor.min((us * world_s[j].1).y);
            }
            for &j in target_legs {
                out.target_floor = out.target_floor.min((ut * world_t[j].1).y);
            }
        }
        out
    };
    let mut pieces: Vec<Piece> = Vec::with_capacity(frames.div_ceil(PIECE));
    crate::io::parallel::map_in_order(
        frames.div_ceil(PIECE),
        threads.max(1),
        threads.max(1) * 4,
        compute,
        |_, piece| {
            pieces.push(piece);
            true
        },
    );
    let source_floor = pieces
        .iter()
        .map(|p| p.source_floor)
        .fold(f64::INFINITY, f64::min);
    let target_floor = pieces
        .iter()
        .map(|p| p.target_floor)
        .fold(f64::INFINITY, f64::min);
    let lift = setup.lift(source_floor, target_floor);
    // Then, in frame order: of the two Euler forms of each rotation and their turns by whole
    // circles, the one nearest the source joint's own values when it turns in the same order,
    // else nearest this joint's previous frame; the carrier's translation.
    let channels = target.channel_count();
    let mut data = vec![0.0f64; frames * channels];
    let mut previous: Vec<[f64; 3]> = vec![[0.0; 3]; joints];
    let rows = pieces.iter().flat_map(|p| {
        p.angles
            .chunks(joints.max(1))
            .zip(p.moves.iter().zip(&p.carrier_parent))
    });
    for (frame, (angles, (moved, turned))) in rows.enumerate() {
        let row = &mut data[frame * channels..(frame + 1) * channels];
        let source_row = motion.frame(frame);
        for (t, joint) in target.joints.iter().enumerate() {
            let mut translation = joint.offset.as_dvec3();
            if Some(t) == carrier {
                translation += turned.inverse() * (*moved + lift);
            }
            let angles = match joint.rotation_order {
                Some(_) => {
                    let reference = reference_columns[t]
                        .map(|c| c.map(|column| f64::from(source_row[column])))
                        .unwrap_or(previous[t]);
                    let chosen = nearest_form(angles[t], reference);
                    previous[t] = chosen;
                    chosen
                }
                None => angles[t],
            };
            let mut rotations = angles.into_iter();
            for (i, channel) in joint.channels.iter().enumerate() {
                row[joint.first_channel + i] = if channel.is_position() {
                    translation[channel.axis()]
                } else {
                    rotations.next().unwrap_or(0.0)
                };
            }
        }
    }
    data
}

/// The angle in degrees between each bone's world direction in the source and in the
/// retargeted take: per bone of [`bones`] (in its order), one per frame. The issue's check of
/// rest alignment; [`quantile`] of them all gives the figures in the guide.
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

/// The foot-skate figure: of the frames where a foot or toe is within 5 cm of the floor (the
/// take's lowest foot point), the share in which it slides more than 2.5 cm along the floor to
/// the next frame. `feet`: the joints to follow (a retargeted take's mapped feet and toes, and
/// the source joints they come from, to compare like with like); `metres` per unit of the file.
pub fn foot_skate(
    skeleton: &Skeleton,
    motion: &Motion,
    feet: &[usize],
    up: Up,
    metres: f64,
) -> f64 {
    if feet.is_empty() || motion.frame_count() < 2 {
        return 0.0;
    }
    let turn = to_y_up(up);
    let mut world = Vec::new();
    let mut tracks: Vec<Vec<DVec3>> = vec![Vec::new(); feet.len()];
    for frame in 0..motion.frame_count() {
        world_transforms_f64(
            skeleton,
            motion.frame(frame),
            OffsetMode::Replace,
            &mut world,
        );
        for (track, &f) in tracks.iter_mut().zip(feet) {
            track.push(turn * world[f].1 * metres);
        }
    }
    let floor = tracks
        .iter()
        .flatten()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min);
    let (mut near, mut sliding) = (0usize, 0usize);
    for track in &tracks {
        for pair in track.windows(2) {
            if pair[0].y - floor < 0.05 {
                near += 1;
                let step = DVec3::new(pair[1].x - pair[0].x, 0.0, pair[1].z - pair[0].z);
                if step.length() > 0.025 {
                    sliding += 1;
                }
            }
        }
    }
    if near == 0 {
        0.0
    } else {
        sliding as f64 / near as f64
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn role_of(name: &str) -> Option<(Option<Side>, Word)> {
        word_of(name)
    }

    #[test]
    fn names_split_into_words() {
        assert_eq!(tokens("mixamorig:LeftUpLeg"), ["left", "up", "leg"]);
        assert_eq!(tokens("LFArm"), ["lf", "arm"]);
        assert_eq!(tokens("LHipJoint"), ["l", "hip", "joint"]);
        assert_eq!(
            tokens("DEF-upper_arm.L.001"),
            ["def", "upper", "arm", "l", "001"]
        );
        assert_eq!(tokens("spine.003"), ["spine", "003"]);
    }

    #[test]
    fn words_of_each_family() {
        use Side::*;
        for (name, want) in [
            ("LeftUpLeg", Some((Some(Left), Word::Thigh))),
            ("UpperLeg_L", Some((Some(Left), Word::Thigh))),
            ("RightUpperLeg", Some((Some(Right), Word::Thigh))),
            ("lThigh", Some((Some(Left), Word::Thigh))),
            ("lShldr", Some((Some(Left), Word::UpperArm))),
            ("lShldrBend", Some((Some(Left), Word::UpperArm))),
            ("lShldrTwist", None),
            ("left_hip", Some((Some(Left), Word::Thigh))),
            ("thigh.L", Some((Some(Left), Word::Thigh))),
            ("DEF-thigh.R", Some((Some(Right), Word::Thigh))),
            ("LUArm", Some((Some(Left), Word::UpperArm))),
            ("RFArm", Some((Some(Right), Word::ForeArm))),
            ("lfemur", Some((Some(Left), Word::Thigh))),
            ("lhipjoint", None),
            ("LHipJoint", None),
            ("lowerback", Some((None, Word::Spine))),
            ("T12", Some((None, Word::Spine))),
            ("L5", Some((None, Word::Spine))),
            ("mixamorig:HeadTop_End", None),
            ("LeftHandIndex1", None),
            ("mHipLeft", Some((Some(Left), Word::Thigh))),
            ("hip", Some((None, Word::Hips))),
            ("joint_Root", Some((None, Word::Hips))),
            ("Skeleton1_LShin", Some((Some(Left), Word::Shin))),
        ] {
            assert_eq!(role_of(name), want, "{name}");
        }
    }
}

#[cfg(test)]
mod limited {
    use super::*;
    use crate::model::skeleton::Channel;

    /// A joint turning about `axes` inside a fixed axis C (an ASF bone).
    fn joint(channels: Vec<Channel>, c: DQuat) -> Joint {
        let mut joint = Joint::new("j".into(), None);
        joint.channels = channels;
        joint.axis = Some(c.as_quat());
        joint
    }

    /// Rotations spread over the sphere, from a fixed sequence (no randomness in tests).
    fn rotations() -> impl Iterator<Item = DQuat> {
        (0..200).map(|k| {
            let k = f64::from(k);
            DQuat::from_euler(glam::EulerRot::ZXY, 0.37 * k, 0.61 * k, 0.23 * k)
        })
    }

    #[test]
    fn a_hinge_lays_its_bone_in_its_plane_as_near_as_it_can() {
        let c = DQuat::from_rotation_z(20f64.to_radians());
        let knee = joint(vec![Channel::Xrotation], c);
        let bone = c * DVec3::new(0.0, -1.0, 0.0);
        let hinge = c * DVec3::X;
        for local in rotations() {
            let (angles, realized) = limited_angles(&knee, local, Some(bone));
            assert_eq!(angles[1..], [0.0, 0.0]);
            let (got, want) = (realized * bone, local * bone);
            // In the hinge's plane, the bone points where it is asked to (within the 32-bit
            // rounding of the written angle).
            let across = |v: DVec3| (v - hinge * v.dot(hinge)).normalize();
            assert!(across(got).angle_between(across(want)).to_degrees() < 1e-4);
            // And no angle of the hinge lays it nearer.
            for step in 0..360 {
                let other = c * DQuat::from_rotation_x(f64::from(step).to_radians()) * c.inverse();
                assert!(
                    (other * bone).angle_between(want) >= got.angle_between(want) - 1e-6,
                    "{local:?}: {step}° is nearer"
                );
            }
        }
    }

    #[test]
    fn two_channels_lay_their_bone_exactly_where_it_is_within_reach() {
        // A clavicle: `dof ry rz` about its axis, the bone along the axis frame's x.
        let c = DQuat::from_rotation_z(-15f64.to_radians());
        let clavicle = joint(vec![Channel::Yrotation, Channel::Zrotation], c);
        let bone = c * DVec3::new(2.0, 0.0, 0.0);
        for local in rotations() {
            let (angles, realized) = limited_angles(&clavicle, local, Some(bone));
            assert_eq!(angles[2], 0.0);
            let error = (realized * bone).angle_between(local * bone).to_degrees();
            assert!(error < 1e-4, "{local:?}: {error}° off");
        }
    }

    #[test]
    fn a_bone_without_rotation_channels_keeps_its_rest() {
        let hip = joint(Vec::new(), DQuat::IDENTITY);
        let (angles, realized) = limited_angles(&hip, DQuat::from_rotation_y(1.0), Some(DVec3::X));
        assert_eq!(angles, [0.0; 3]);
        assert_eq!(realized, DQuat::IDENTITY);
    }
}
