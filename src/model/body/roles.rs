//! The roles of a skeleton's joints (hips, spine, neck, head, and per side the limbs), read
//! from their names and, where names say less, from the tree.

use super::names::{LIMBS, Limb, Role, Word, word_of};
use super::sides::Side;
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use glam::{DQuat, DVec3};

/// A skeleton's joints by role: what [`crate::retarget::Map::guess`] pairs.
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::Body;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/body/lafan1.bvh")?;
/// let body = Body::of(&take.skeleton);
/// let summary = body.summary(&take.skeleton);
/// assert!(summary.starts_with("from names; hips Hips; spine Spine Spine1 Spine2; neck Neck"));
/// let name = |&j: &usize| take.skeleton.joints[j].name.as_str();
/// let feet: Vec<&str> = body.foot_points(&take.skeleton).iter().map(name).collect();
/// assert_eq!(feet, ["LeftFoot", "LeftToe", "RightFoot", "RightToe"]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Body {
    /// The hips joint (where the legs and the spine part), if one was read.
    pub hips: Option<usize>,
    /// From the hips up.
    pub spine: Vec<usize>,
    /// The neck joint, if one was read.
    pub neck: Option<usize>,
    /// The head joint, if one was read.
    pub head: Option<usize>,
    /// `[left, right]`, each in [`Limb`] order: clavicle, upper arm, forearm, hand, thigh, shin,
    /// foot, toe.
    pub limbs: [[Option<usize>; 8]; 2],
    /// `[left, right]` × [`FINGERS`](crate::model::body::FINGERS) (thumb, index, middle, ring,
    /// pinky) × up to three bones from the hand out, read from names under each hand.
    pub fingers: [[[Option<usize>; 3]; 5]; 2],
    /// The limbs were read from the tree and the rest pose: the names said nothing of any.
    pub from_tree: bool,
    /// Where the names' left and right contradict where the limbs lie (the body's up from its
    /// feet to its hips, its facing from its feet to its toes), what the geometry moved, in
    /// words: the chains now sit on the side they lie on.
    pub sides_by_geometry: Option<String>,
}

pub(super) fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

pub(super) fn depth(skeleton: &Skeleton, mut joint: usize) -> usize {
    let mut depth = 0;
    while let Some(parent) = skeleton.joints[joint].parent {
        joint = parent;
        depth += 1;
    }
    depth
}

pub(crate) fn is_ancestor(skeleton: &Skeleton, ancestor: usize, mut joint: usize) -> bool {
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

pub(super) fn common_ancestor(skeleton: &Skeleton, a: usize, b: usize) -> Option<usize> {
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
pub(crate) fn path_between(skeleton: &Skeleton, from: usize, to: usize) -> Vec<usize> {
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

/// `[left, right]`, each in [`Limb`] order.
type Limbs = [[Option<usize>; 8]; 2];

/// Limbs, neck and head from the tree alone, for a skeleton whose names say nothing: the hips
/// are the first joint with three branches at least three joints long (the largest the spine,
/// the other two the legs); the chest the first joint up the spine with two such branches (the
/// arms; the one that goes on upward from the hips, the neck). Down each arm, the hand is the
/// first joint with two children or more (fingers), else the last; down each leg the last four
/// joints are thigh, shin, foot and toe (three: no toe). Sides by the rest pose, as BVH faces
/// +z: left at +x.
pub(super) fn limbs_by_tree(skeleton: &Skeleton) -> Option<(Limbs, Option<usize>, Option<usize>)> {
    let tree = Tree::new(skeleton);
    let joints = &skeleton.joints;
    let hips = (0..joints.len()).find(|&j| !joints[j].end_site && tree.long(j).len() >= 3)?;
    let branches = tree.long(hips);
    let (spine, legs) = (branches[0], [branches[1], branches[2]]);
    let mut chest = spine;
    while tree.long(chest).len() < 2 {
        chest = *tree.main_path(chest).get(1)?;
    }
    let mut arms = tree.long(chest);
    let upward = tree.upward(chest, hips);
    if arms.len() > 2 {
        arms.retain(|&a| Some(a) != upward);
    }
    arms.truncate(2);
    if arms.len() < 2 {
        return None;
    }
    let mut limbs = [[None; 8]; 2];
    for &arm in &arms {
        tree.place_arm(&mut limbs, arm, chest)?;
    }
    for &leg in &legs {
        tree.place_leg(&mut limbs, leg, hips);
    }
    if limbs[0][Limb::Thigh as usize].is_none() || limbs[1][Limb::Thigh as usize].is_none() {
        return None;
    }
    let (neck, head) = match upward.filter(|u| !arms.contains(u)) {
        Some(u) => {
            let path = tree.main_path(u);
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

/// A skeleton's tree as [`limbs_by_tree`] reads it: how tall and how large each joint's
/// subtree is, and the rest pose.
struct Tree<'a> {
    skeleton: &'a Skeleton,
    /// Per joint: the most joints on a way down from it, itself included (0 for an End Site).
    height: Vec<usize>,
    /// Per joint: the joints under it, itself included (0 for an End Site).
    size: Vec<usize>,
    /// World rotation and position of each joint at rest.
    rest: Vec<(DQuat, DVec3)>,
}

impl<'a> Tree<'a> {
    fn new(skeleton: &'a Skeleton) -> Self {
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
        let mut rest = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
        Tree {
            skeleton,
            height,
            size,
            rest,
        }
    }

    /// The branches under `j` at least three joints long, the largest first.
    fn long(&self, j: usize) -> Vec<usize> {
        let mut branches: Vec<usize> = self.skeleton.joints[j]
            .children
            .iter()
            .copied()
            .filter(|&c| self.height[c] >= 3)
            .collect();
        branches.sort_by_key(|&c| std::cmp::Reverse(self.size[c]));
        branches
    }

    /// The way down from `from` through the largest child at each joint.
    fn main_path(&self, from: usize) -> Vec<usize> {
        let joints = &self.skeleton.joints;
        let mut path = vec![from];
        let mut j = from;
        while let Some(&next) = joints[j]
            .children
            .iter()
            .filter(|&&c| !joints[c].end_site)
            .max_by_key(|&&c| (self.size[c], std::cmp::Reverse(c)))
        {
            path.push(next);
            j = next;
        }
        path
    }

    /// The branch of `chest` that goes on upward (from the hips to the chest): the neck, not an
    /// arm.
    fn upward(&self, chest: usize, hips: usize) -> Option<usize> {
        let (joints, rest) = (&self.skeleton.joints, &self.rest);
        let up = (rest[chest].1 - rest[hips].1).normalize_or_zero();
        let others: Vec<usize> = joints[chest]
            .children
            .iter()
            .copied()
            .filter(|c| !joints[*c].end_site)
            .collect();
        others.iter().copied().max_by(|&a, &b| {
            let rise = |c: usize| {
                let end = *self.main_path(c).last().unwrap_or(&c);
                (rest[end].1 - rest[chest].1).normalize_or_zero().dot(up)
            };
            rise(a).total_cmp(&rise(b))
        })
    }

    /// The side `j` is on seen from `of`: left (0) at +x, else right (1).
    fn side_of(&self, j: usize, of: usize) -> usize {
        if self.rest[j].1.x - self.rest[of].1.x >= 0.0 {
            0
        } else {
            1
        }
    }

    /// The arm down from `arm`: the hand the first joint with two children or more, then the
    /// forearm, the upper arm and the clavicle above it. `None` for an arm too short.
    fn place_arm(&self, limbs: &mut Limbs, arm: usize, chest: usize) -> Option<()> {
        let joints = &self.skeleton.joints;
        let path = self.main_path(arm);
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
        let side = self.side_of(path[at], chest);
        limbs[side][Limb::Hand as usize] = Some(path[at]);
        limbs[side][Limb::ForeArm as usize] = Some(path[at - 1]);
        limbs[side][Limb::UpperArm as usize] = Some(path[at - 2]);
        if at >= 3 {
            limbs[side][Limb::Clavicle as usize] = Some(path[at - 3]);
        }
        Some(())
    }

    /// The leg down from `leg`: its last four joints thigh, shin, foot and toe (three: no toe).
    fn place_leg(&self, limbs: &mut Limbs, leg: usize, hips: usize) {
        let path = self.main_path(leg);
        let n = path.len();
        let side = self.side_of(path[n - 1], hips);
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
}

/// The upper arm among the joints a side's names call one (`upper_arms`) that lie above the
/// elbow: the bone that reaches the elbow. A joint above another candidate is a shoulder piece,
/// not the upper arm, when its bone bends more than 10° from the line on to the elbow or its
/// name says shoulder where the next says upper arm (MakeHuman's `shoulder01.L` above
/// `upperarm01.L`); candidates in line with the next (an upper arm split for its twist,
/// `upperarm01`, `upperarm02`) are one bone, read from its first joint.
fn upper_arm_above(
    skeleton: &Skeleton,
    upper_arms: &[usize],
    elbow: usize,
    word: impl Fn(usize) -> Option<Word>,
) -> Option<usize> {
    let mut chain: Vec<usize> = upper_arms
        .iter()
        .copied()
        .filter(|&j| j != elbow && is_ancestor(skeleton, j, elbow))
        .collect();
    chain.sort_by_key(|&j| (depth(skeleton, j), j));
    chain.dedup();
    // Only one chain: every candidate must lie above the next.
    if chain.windows(2).any(|w| !is_ancestor(skeleton, w[0], w[1])) {
        return None;
    }
    let mut rest = Vec::new();
    world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
    let at = |j: usize| rest[j].1;
    let mut upper = *chain.first()?;
    for &next in &chain[1..] {
        let (bone, on) = (at(next) - at(upper), at(elbow) - at(next));
        let bent = match (bone.try_normalize(), on.try_normalize()) {
            (Some(a), Some(b)) => a.dot(b) < 10f64.to_radians().cos(),
            _ => false,
        };
        let named_apart = word(upper) == Some(Word::Shoulder) && word(next) == Some(Word::UpperArm);
        if bent || named_apart {
            upper = next;
        }
    }
    Some(upper)
}

/// A skeleton's joints as their names read: each joint's side and word (none for an End Site
/// or a name that says nothing).
struct Names<'a> {
    skeleton: &'a Skeleton,
    words: Vec<Option<(Option<Side>, Word)>>,
}

impl<'a> Names<'a> {
    fn new(skeleton: &'a Skeleton) -> Self {
        let words = skeleton
            .joints
            .iter()
            .map(|j| if j.end_site { None } else { word_of(&j.name) })
            .collect();
        Names { skeleton, words }
    }

    /// Whether a joint of `side` says one of `want`.
    fn has(&self, side: Side, want: &[Word]) -> bool {
        self.words
            .iter()
            .flatten()
            .any(|&(s, w)| s == Some(side) && want.contains(&w))
    }

    /// The limb `word` names on `side`, in the light of the rest of the side (a shoulder is the
    /// clavicle where the side names an upper arm and no collar; a leg the shin below a thigh).
    fn limb_of(&self, side: Side, word: Word) -> Option<Limb> {
        Some(match word {
            Word::Collar => Limb::Clavicle,
            Word::Shoulder => {
                if self.has(side, &[Word::Collar]) || !self.has(side, &[Word::UpperArm]) {
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
                if self.has(side, &[Word::Thigh]) {
                    Limb::Shin
                } else {
                    Limb::Thigh
                }
            }
            Word::Shin => Limb::Shin,
            Word::Foot => {
                if self.has(side, &[Word::Ankle]) {
                    Limb::Toe
                } else {
                    Limb::Foot
                }
            }
            Word::Ankle => Limb::Foot,
            Word::Buttock if self.has(side, &[Word::Thigh]) => return None,
            Word::Buttock => Limb::Thigh,
            Word::Toe => Limb::Toe,
            _ => return None,
        })
    }

    /// The shallowest of `candidates`; among joints at one depth, the first by name:
    /// MakeHuman's five toes give `toe1-1` on both sides, whatever order the file lists them in.
    fn shallowest(&self, candidates: Vec<usize>) -> Option<usize> {
        let joints = &self.skeleton.joints;
        candidates
            .into_iter()
            .min_by_key(|&j| (depth(self.skeleton, j), joints[j].name.as_str(), j))
    }

    /// The joints whose names say `word`, on either side or none.
    fn named(&self, word: Word) -> Vec<usize> {
        (0..self.skeleton.joints.len())
            .filter(|&j| self.words[j].is_some_and(|(_, w)| w == word))
            .collect()
    }

    /// The limbs of `side` by name, each the shallowest joint that names it, the upper arm the
    /// one that reaches the elbow.
    fn read_side(&self, body: &mut Body, side: Side) {
        let mut upper_arms = Vec::new();
        for (slot, limb) in LIMBS.iter().enumerate() {
            let candidates: Vec<usize> = (0..self.skeleton.joints.len())
                .filter(|&j| {
                    self.words[j].is_some_and(|(s, w)| {
                        s == Some(side) && self.limb_of(side, w) == Some(*limb)
                    })
                })
                .collect();
            if *limb == Limb::UpperArm {
                upper_arms.clone_from(&candidates);
            }
            body.limbs[side_index(side)][slot] = self.shallowest(candidates);
        }
        let arm = &mut body.limbs[side_index(side)];
        if let Some(elbow) = arm[Limb::ForeArm as usize] {
            let word = |j: usize| self.words[j].map(|(_, w)| w);
            if let Some(upper) = upper_arm_above(self.skeleton, &upper_arms, elbow, word) {
                arm[Limb::UpperArm as usize] = Some(upper);
            }
        }
    }
}

impl Body {
    /// The roles of a skeleton's joints, from their names and the tree.
    pub fn of(skeleton: &Skeleton) -> Body {
        let names = Names::new(skeleton);
        // The shallowest joint of each role, words read in the light of the rest of the side.
        let mut body = Body::default();
        for side in [Side::Left, Side::Right] {
            names.read_side(&mut body, side);
        }
        body.shift_chains_read_one_bone_up(skeleton);
        let named = |word: Word| names.named(word);
        // Names that say nothing of any limb (`J1`, `bone_07`): the tree and the rest pose.
        let mut tree_neck_head = (None, None);
        if body
            .limbs
            .iter()
            .all(|side| side.iter().all(Option::is_none))
            && let Some((limbs, neck, head)) = limbs_by_tree(skeleton)
        {
            body.limbs = limbs;
            body.from_tree = true;
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
        let neck = names.shallowest(named(Word::Neck)).or(tree_neck_head.0);
        let head = names.shallowest(
            named(Word::Head)
                .into_iter()
                .filter(|&h| neck.is_none_or(|n| is_ancestor(skeleton, n, h)))
                .collect(),
        );
        let head = head.or(tree_neck_head.1);
        // A root that is itself a limb (a hand alone, an arm alone) is no hips.
        let limb_joints: Vec<usize> = body.limbs.iter().flatten().flatten().copied().collect();
        let hips = match (legs, chest.or(neck).or(head)) {
            (Some(legs), Some(top)) => common_ancestor(skeleton, legs, top),
            (Some(legs), None) => Some(legs),
            _ => names
                .shallowest(named(Word::Hips))
                .or(skeleton.roots().next())
                .filter(|root| !limb_joints.contains(root)),
        };
        if let Some(hips) = hips {
            body.read_centre(skeleton, hips, chest, neck, head, &named);
        }
        body.settle_sides(skeleton);
        body.read_fingers(skeleton);
        body
    }

    /// The hips, spine, neck and head, the hips known: `chest` carries both arms, `neck` and
    /// `head` as their names say (either may be missing). `named` lists the joints a word names.
    fn read_centre(
        &mut self,
        skeleton: &Skeleton,
        hips: usize,
        chest: Option<usize>,
        mut neck: Option<usize>,
        mut head: Option<usize>,
        named: &dyn Fn(Word) -> Vec<usize>,
    ) {
        let body = self;
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
        // A face under the neck (Rigify's `ORG-face`; a rig's `face` hung from its `neck`): the
        // head is the joint it hangs from, or the face itself when it hangs from the neck.
        if head.is_none() {
            let under = neck.unwrap_or(hips);
            let face = named(Word::Face)
                .into_iter()
                .filter(|&f| f != under && is_ancestor(skeleton, under, f))
                .min_by_key(|&f| (depth(skeleton, f), f));
            head = face.map(|f| match skeleton.joints[f].parent {
                Some(p) if p != under && Some(p) != chest && is_ancestor(skeleton, under, p) => p,
                _ => f,
            });
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
    }

    /// Limbs whose names label the joint at a bone's far end, as some ASF files name their
    /// bones (PyAsfAmc's `LeftHip` is the pelvis bone that ends at the hip, `LeftKnee` the
    /// thigh): read by name, every role sits one bone up (the thigh on the pelvis bone, the
    /// clavicle on the chest). The bones' lengths tell: a thigh is about as long as the shin
    /// below it, and a foot much shorter; an upper arm at least as long as the forearm, and a
    /// hand shorter. A chain whose first bone is less than half the next and whose last is a
    /// long bone again is moved one joint down.
    fn shift_chains_read_one_bone_up(&mut self, skeleton: &Skeleton) {
        let mut rest = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut rest);
        let length = |a: usize, b: usize| (rest[b].1 - rest[a].1).length();
        // The joint below `joint` towards `toward` when it lies under it, else its first child.
        let below = |joint: usize, toward: Option<usize>| -> Option<usize> {
            let children = &skeleton.joints[joint].children;
            toward
                .filter(|&t| t != joint && is_ancestor(skeleton, joint, t))
                .and_then(|t| {
                    children
                        .iter()
                        .copied()
                        .find(|&c| is_ancestor(skeleton, c, t))
                })
                .or_else(|| children.first().copied())
        };
        for side in 0..2 {
            let limbs = &mut self.limbs[side];
            // Legs: thigh, shin, foot, toe.
            if let [Some(thigh), Some(shin), Some(foot)] = [limbs[4], limbs[5], limbs[6]]
                && let Some(next) = below(foot, limbs[7])
            {
                let (hip_bone, thigh_bone, shin_bone) =
                    (length(thigh, shin), length(shin, foot), length(foot, next));
                if hip_bone < 0.5 * thigh_bone && shin_bone > 0.6 * thigh_bone {
                    let toe = below(next, limbs[7]).filter(|&t| !skeleton.joints[t].end_site);
                    limbs[4..8].copy_from_slice(&[Some(shin), Some(foot), Some(next), toe]);
                }
            }
            // Arms: clavicle, upper arm, forearm, hand.
            if let [Some(upper), Some(fore), Some(hand)] = [limbs[1], limbs[2], limbs[3]]
                && let Some(next) = below(hand, None)
            {
                let (collar_bone, upper_bone, fore_bone) =
                    (length(upper, fore), length(fore, hand), length(hand, next));
                if collar_bone < 0.8 * upper_bone && fore_bone > 0.6 * upper_bone {
                    limbs[0..4].copy_from_slice(&[Some(upper), Some(fore), Some(hand), Some(next)]);
                }
            }
        }
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
        for (side, finger, bone, j) in self.finger_roles() {
            roles.push((Role::Finger(side, finger as u8, bone as u8), j));
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
            Role::Finger(side, finger, bone) => *self.fingers[side_index(side)]
                .get(finger as usize)?
                .get(bone as usize)?,
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
