//! Left and right from where the limbs lie: the body's up from the feet to the hips, its facing
//! from the feet to the toes, so that a Z-up file's left stays its left and a figure facing any
//! way is read alike. Names decide where this geometry cannot (no toes, a rest pose that stands
//! on nothing); where it can and the names say the other side, or say none, it wins.

use super::{Body, Limb, is_ancestor};
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use glam::DVec3;

/// How far apart (along the body's left) the two sides of a chain must lie, in legs' lengths,
/// for their places to say which is which.
const APART: f64 = 0.05;

/// The body's up and left in the rest pose, when its feet, toes and hips say them: up from the
/// middle of the feet to the hips (standing at least half a leg above them), facing the way
/// both feet point to their toes (each mostly level, the two within 45° of each other), and
/// left = up × facing. Also the legs' length, for a scale.
fn up_and_left(body: &Body, skeleton: &Skeleton, rest: &[DVec3]) -> Option<(DVec3, DVec3, f64)> {
    let hips = body.hips?;
    let mut feet = Vec::new();
    let mut toes = Vec::new();
    for side in 0..2 {
        let foot = body.limbs[side][Limb::Foot as usize]?;
        let toe = body.limbs[side][Limb::Toe as usize]
            .filter(|&t| t != foot && is_ancestor(skeleton, foot, t))
            .or_else(|| skeleton.joints[foot].children.first().copied())?;
        feet.push(rest[foot]);
        toes.push(rest[toe] - rest[foot]);
    }
    let ground = (feet[0] + feet[1]) / 2.0;
    let leg = rest[hips] - ground;
    let thigh = body.limbs[0][Limb::Thigh as usize]?;
    let chain = (rest[thigh] - rest[body.limbs[0][Limb::Shin as usize]?]).length()
        + (rest[body.limbs[0][Limb::Shin as usize]?] - feet[0]).length();
    let up = leg.try_normalize()?;
    if leg.length() < 0.5 * chain {
        return None;
    }
    let mut level = Vec::new();
    for toe in toes {
        let flat = toe - up * toe.dot(up);
        if flat.length() < 0.5 * toe.length() {
            return None;
        }
        level.push(flat.try_normalize()?);
    }
    if level[0].dot(level[1]) < 45f64.to_radians().cos() {
        return None;
    }
    let facing = (level[0] + level[1]).try_normalize()?;
    let left = up.cross(facing).try_normalize()?;
    Some((up, left, leg.length()))
}

/// Whether the joint read as left lies left of the one read as right: `Some(true)` when it
/// does, `Some(false)` when it lies right of it, `None` when a side is missing or they lie too
/// near to tell (clavicles by the spine).
fn lies_left(pair: [Option<usize>; 2], rest: &[DVec3], left: DVec3, scale: f64) -> Option<bool> {
    let apart = (rest[pair[0]?] - rest[pair[1]?]).dot(left);
    if apart > APART * scale {
        Some(true)
    } else if apart < -APART * scale {
        Some(false)
    } else {
        None
    }
}

impl Body {
    /// Checks each side's arm and leg against where it lies (see [`up_and_left`]) and moves a
    /// chain that lies on the other side there, fingers with their arm. Read from names, the
    /// disagreement is kept in [`Body::sides_by_geometry`] (and said as a doubt); read from the
    /// tree, whose sides were the BVH convention's (left at +x), nothing is said.
    pub(super) fn settle_sides(&mut self, skeleton: &Skeleton) {
        let mut world = Vec::new();
        world_transforms_f64(skeleton, &[], OffsetMode::Replace, &mut world);
        let rest: Vec<DVec3> = world.iter().map(|t| t.1).collect();
        let Some((_, left, scale)) = up_and_left(self, skeleton, &rest) else {
            return;
        };
        let mut crossed = Vec::new();
        for (part, slots) in [("arm", 0..4), ("leg", 4..8)] {
            // Each joint by where it lies; one too near the middle to tell (a clavicle) as the
            // rest of its chain.
            let said: Vec<Option<bool>> = slots
                .clone()
                .map(|slot| {
                    let pair = [self.limbs[0][slot], self.limbs[1][slot]];
                    lies_left(pair, &rest, left, scale)
                })
                .collect();
            let (held, against) = said.iter().fold((0, 0), |(h, a), s| match s {
                Some(true) => (h + 1, a),
                Some(false) => (h, a + 1),
                None => (h, a),
            });
            let mut moved = false;
            for (slot, said) in slots.zip(said) {
                if said.unwrap_or(against <= held) {
                    continue;
                }
                let (l, r) = (self.limbs[0][slot], self.limbs[1][slot]);
                self.limbs[0][slot] = r;
                self.limbs[1][slot] = l;
                moved = true;
            }
            if moved {
                crossed.push(part);
            }
        }
        if !self.from_tree && !crossed.is_empty() {
            let (parts, verb, pronoun) = match crossed.as_slice() {
                [one] => (one.to_string(), "lies", "it lies"),
                _ => (crossed.join(" and "), "lie", "they lie"),
            };
            self.sides_by_geometry = Some(format!(
                "the {parts} named left {verb} on the body's right (by its toes' facing and its \
                 hips' up): sides read from where {pronoun}, not from the names"
            ));
        }
    }
}
