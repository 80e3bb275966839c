//! The foot points: per leg the ankle and the toe, read down the leg chain (never "the lowest
//! points", which found shoulders, hand tips and fingers on real rigs), and the legs' length.

use super::{Body, Limb, is_ancestor};
use crate::model::skeleton::Skeleton;

impl Body {
    /// The ankle and the toe of each leg the reading found, in joint order: the toe is the
    /// joint named or read as the toe, else the end of the chain below the ankle (its End Site,
    /// where the file has one). Empty unless both legs reach an ankle: a body without two feet
    /// has its contacts refused or guessed elsewhere, and said so.
    pub fn foot_points(&self, skeleton: &Skeleton) -> Vec<usize> {
        let mut points = Vec::new();
        for side in 0..2 {
            let Some(ankle) = self.limbs[side][Limb::Foot as usize] else {
                return Vec::new();
            };
            points.push(ankle);
            let toe = self.limbs[side][Limb::Toe as usize]
                .filter(|&t| t != ankle && is_ancestor(skeleton, ankle, t))
                .or_else(|| chain_end_below(skeleton, ankle));
            points.extend(toe);
        }
        points.sort_unstable();
        points.dedup();
        points
    }

    /// The soles: each leg's ankle and every point below it (toes, their End Sites), in
    /// joint order; what stands on the floor when a take is grounded (`convert --ground`,
    /// `dataset --ground`), so that no toe tip sinks under it. Empty unless both legs reach an
    /// ankle.
    pub fn sole_points(&self, skeleton: &Skeleton) -> Vec<usize> {
        let ankles: Vec<usize> = self
            .limbs
            .iter()
            .filter_map(|limb| limb[Limb::Foot as usize])
            .collect();
        if ankles.len() < 2 {
            return Vec::new();
        }
        (0..skeleton.joints.len())
            .filter(|&j| ankles.iter().any(|&a| is_ancestor(skeleton, a, j)))
            .collect()
    }

    /// The legs' length in the pose `world` (each joint's world rotation and position): thigh
    /// to shin to ankle, the mean of the sides found; a rest pose lying down or with its bones
    /// along x (Bandai's) measures the same as one standing. `None` without a leg down to an
    /// ankle.
    pub fn leg_length(&self, world: &[(glam::DQuat, glam::DVec3)]) -> Option<f64> {
        let legs: Vec<f64> = self
            .limbs
            .iter()
            .filter_map(|limb| {
                let (thigh, shin, ankle) = (
                    limb[Limb::Thigh as usize]?,
                    limb[Limb::Shin as usize]?,
                    limb[Limb::Foot as usize]?,
                );
                Some(
                    (world[shin].1 - world[thigh].1).length()
                        + (world[ankle].1 - world[shin].1).length(),
                )
            })
            .collect();
        (!legs.is_empty()).then(|| legs.iter().sum::<f64>() / legs.len() as f64)
    }
}

/// The last joint of the chain below `joint`, following its first child each time; `None` when
/// it has no child.
fn chain_end_below(skeleton: &Skeleton, joint: usize) -> Option<usize> {
    let mut at = *skeleton.joints[joint].children.first()?;
    while let Some(&next) = skeleton.joints[at].children.first() {
        at = next;
    }
    Some(at)
}
