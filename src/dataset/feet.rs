//! Feet, floor and contacts: which joints are the feet, the floor under them over a sliding
//! window, and when each foot is planted.

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::pose;
use crate::model::pose::OffsetMode;
use glam::Vec3;
use std::path::Path;

/// The feet of a skeleton standing in its rest pose, for a body whose legs the reading does not
/// find (`rest`: world positions, Y up): at most two
/// end points per leg. A leg ends in the leaves within the lowest tenth of the figure's height;
/// the leaves under the same last joint above that band (the knee) are one leg, whose feet are
/// its ankle (the knee's child on the way down) and the leaf farthest from it across the floor
/// (the toe). A creature has as many legs as it has; a figure without height has none.
pub fn guess_feet(skeleton: &crate::Skeleton, rest: &[Vec3]) -> Vec<u32> {
    let (low, high) = rest
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    if high.partial_cmp(&low) != Some(std::cmp::Ordering::Greater) {
        return Vec::new();
    }
    let band = low + 0.1 * (high - low);
    let is_low = |p: usize| rest[p].y <= band;
    let mut has_child = vec![false; skeleton.joints.len()];
    for joint in &skeleton.joints {
        if let Some(parent) = joint.parent {
            has_child[parent] = true;
        }
    }
    // (knee, ankle, leaves) in the order the legs' first leaves come.
    let mut legs: Vec<(usize, usize, Vec<usize>)> = Vec::new();
    for leaf in (0..skeleton.joints.len()).filter(|&p| !has_child[p] && is_low(p)) {
        let mut below = leaf;
        let mut knee = skeleton.joints[leaf].parent;
        while let Some(k) = knee.filter(|&k| is_low(k)) {
            below = k;
            knee = skeleton.joints[k].parent;
        }
        // A figure lying on the floor has no knee above the band: no leg.
        let Some(knee) = knee else { continue };
        match legs.iter_mut().find(|(k, _, _)| *k == knee) {
            Some((_, _, leaves)) => leaves.push(leaf),
            None => legs.push((knee, below, vec![leaf])),
        }
    }
    let across = |a: Vec3, b: Vec3| (a.x - b.x).hypot(a.z - b.z);
    let mut feet = Vec::new();
    for (_, ankle, leaves) in legs {
        feet.push(ankle as u32);
        let toe = leaves.iter().copied().fold(ankle, |best, leaf| {
            match across(rest[leaf], rest[ankle]) > across(rest[best], rest[ankle]) {
                true => leaf,
                false => best,
            }
        });
        if toe != ankle {
            feet.push(toe as u32);
        }
    }
    feet.sort_unstable();
    feet
}

/// The foot points of `skeleton`: the ankle and toe of each leg the reading of the body finds,
/// else (a body without two feet: a creature, a torso) the rest-pose guess; `true` when guessed.
pub(super) fn feet_of(skeleton: &crate::Skeleton, mode: OffsetMode) -> (Vec<u32>, bool) {
    let read = crate::model::body::Body::of(skeleton).foot_points(skeleton);
    if read.is_empty() {
        let rest = pose::world_positions(skeleton, &[], mode);
        (guess_feet(skeleton, &rest), true)
    } else {
        (read.into_iter().map(|p| p as u32).collect(), false)
    }
}

/// The points `names` names (as the dataset names them), in file order.
pub(super) fn named_feet(
    path: &Path,
    joints: &[String],
    names: &[String],
) -> Result<Vec<u32>, Error> {
    let mut feet = Vec::new();
    for name in names {
        let index = joints.iter().position(|j| j == name).ok_or_else(|| {
            Error::usage(
                Message::from(format!("{}: ", path.display()))
                    .argument("feet", None)
                    .text(format!(
                        " names {}, which this skeleton does not have",
                        crate::io::error::quoted(name)
                    )),
            )
        })?;
        feet.push(index as u32);
    }
    feet.sort_unstable();
    feet.dedup();
    Ok(feet)
}
