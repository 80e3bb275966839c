//! What the reading of a body is sure of: the one-line summary `info` prints, and the doubts
//! `info`, `dataset` and `retarget` say (no two legs, no feet, a side without its other, a body
//! that does not stand on two legs).

use super::names::{LIMBS, Limb, Role};
use super::roles::Body;
use super::sides::Side;
use crate::model::body::names::FINGERS;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use crate::model::skeleton::export_name;
use glam::DVec3;
use std::fmt;

/// A doubt about a reading, said as a warning (or, onto a human target, as the reason a take is
/// refused).
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::{Body, Doubt};
/// use bvhview::model::pose::OffsetMode;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // A quadruped rigged with 3ds Max Biped's human names.
/// let take = Take::open("tests/body/biped_elephant.bvh")?;
/// let doubts = Body::of(&take.skeleton).doubts(&take.skeleton, &take.motion, OffsetMode::Replace);
/// assert!(matches!(doubts.as_slice(), [Doubt::NotBiped(_)]));
/// let said = doubts[0].to_string();
/// assert_eq!(said, "not a two-legged body: its head lies 80° from the legs' up; four-legged?");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub enum Doubt {
    /// Fewer than two legs (thigh and shin on each side) were read.
    NoTwoLegs,
    /// Two legs, but not both reach an ankle: no foot points.
    NoFeet,
    /// A limb was read on one side only (`left upper arm` without a right one).
    OneSided(Role),
    /// Two legs and a spine, but not standing on the legs: the head lies along the ground
    /// (degrees from the legs' up), or the hands reach the floor as the feet do.
    NotBiped(String),
    /// Something of a body was read (a hand, an arm, fingers) but no leg: a hand or part of a
    /// body, whose up axis is not guessed from a figure it does not have.
    NoLegs,
    /// More legs than two (a crab's eight): not a two-legged body, and no up axis guessed from
    /// it.
    ManyLegs(usize),
    /// The names' left and right contradict where the limbs lie, and the geometry was followed
    /// ([`Body::sides_by_geometry`]).
    SidesByGeometry(String),
}

impl fmt::Display for Doubt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Doubt::NoTwoLegs => f.write_str("no two legs read (thigh and shin on each side)"),
            Doubt::NoFeet => f.write_str("no feet read (no ankle below each leg)"),
            Doubt::OneSided(role) => {
                let other = match role {
                    Role::Limb(Side::Left, limb) => Role::Limb(Side::Right, *limb),
                    Role::Limb(Side::Right, limb) => Role::Limb(Side::Left, *limb),
                    role => *role,
                };
                write!(f, "sides undecided: a {role} but no {other}")
            }
            Doubt::NotBiped(why) => write!(f, "not a two-legged body: {why}"),
            Doubt::NoLegs => f.write_str(
                "no legs: a hand or part of a body; its up axis is not guessed from a body",
            ),
            Doubt::ManyLegs(n) => write!(
                f,
                "{} legs: not a two-legged body; its up axis is not guessed from a body",
                super::legs::count_word(*n)
            ),
            Doubt::SidesByGeometry(why) => write!(f, "sides from geometry: {why}"),
        }
    }
}

impl Body {
    /// Whether anything of a body was read: a limb, a neck or a head (every skeleton has a
    /// joint that could be hips).
    pub fn is_a_body(&self) -> bool {
        self.neck.is_some()
            || self.head.is_some()
            || self.limbs.iter().flatten().any(Option::is_some)
    }

    /// What the reading doubts about `skeleton`'s body, most serious first; empty when it read
    /// a biped with both legs and feet. Whether it stands on two legs is judged in the rest pose
    /// and in five frames of `motion` spread over the take (a rest pose may lie along the bones'
    /// axes, as Rokoko's does): a body that stands in any of them stands.
    pub fn doubts(&self, skeleton: &Skeleton, motion: &Motion, mode: OffsetMode) -> Vec<Doubt> {
        let mut doubts = Vec::new();
        match self.legs_not_two(skeleton) {
            Some(0) => doubts.push(Doubt::NoLegs),
            Some(n) => doubts.push(Doubt::ManyLegs(n)),
            None => {}
        }
        doubts.extend(self.sides_by_geometry.clone().map(Doubt::SidesByGeometry));
        if !doubts.is_empty() && !matches!(doubts[0], Doubt::SidesByGeometry(_)) {
            // A hand or a crab: what a person's reading would miss of it says nothing more.
            return doubts;
        }
        let has = |side: usize, limb: Limb| self.limbs[side][limb as usize].is_some();
        let legs = (0..2).all(|s| has(s, Limb::Thigh) && has(s, Limb::Shin));
        if !legs {
            doubts.push(Doubt::NoTwoLegs);
        } else if !(0..2).all(|s| has(s, Limb::Foot)) {
            doubts.push(Doubt::NoFeet);
        }
        if legs && let Some(why) = self.not_standing(skeleton, motion, mode) {
            doubts.push(Doubt::NotBiped(why));
        }
        for (slot, &limb) in LIMBS.iter().enumerate() {
            let (left, right) = (self.limbs[0][slot], self.limbs[1][slot]);
            match (left, right) {
                (Some(_), None) => doubts.push(Doubt::OneSided(Role::Limb(Side::Left, limb))),
                (None, Some(_)) => doubts.push(Doubt::OneSided(Role::Limb(Side::Right, limb))),
                _ => {}
            }
        }
        doubts
    }

    /// Why a body with two legs stands on them in none of the poses looked at, if it does not.
    fn not_standing(
        &self,
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
    ) -> Option<String> {
        let frames = motion.frame_count();
        let mut samples: Vec<Option<usize>> = vec![None];
        if frames > 0 {
            samples.extend((0..5).map(|k| Some(k * (frames - 1) / 4)));
            samples.dedup();
        }
        let mut first_reason = None;
        let mut world = Vec::new();
        for sample in samples {
            let values = sample.map_or(&[][..], |f| motion.frame(f));
            world_transforms_f64(skeleton, values, mode, &mut world);
            match self.why_not_standing(|j| world[j].1) {
                None => return None,
                Some(why) => {
                    first_reason.get_or_insert(why);
                }
            }
        }
        first_reason
    }

    /// Why a body with two legs does not stand on them in one pose (`at`: world positions), if
    /// it does not: "up" is from the ankles to the hips, so a file's own up axis does not
    /// matter.
    fn why_not_standing(&self, at: impl Fn(usize) -> DVec3) -> Option<String> {
        let hips = self.hips?;
        let feet: Vec<DVec3> = (0..2)
            .filter_map(|s| {
                self.limbs[s][Limb::Foot as usize].or(self.limbs[s][Limb::Shin as usize])
            })
            .map(&at)
            .collect();
        let ground = feet.iter().copied().sum::<DVec3>() / feet.len().max(1) as f64;
        let leg = at(hips) - ground;
        let up = leg.try_normalize()?;
        let top = self.head.or(self.neck).or(self.spine.last().copied())?;
        let spine = (at(top) - at(hips)).try_normalize()?;
        let lean = spine.dot(up).clamp(-1.0, 1.0).acos().to_degrees();
        if lean > 50.0 {
            return Some(format!(
                "its head lies {lean:.0}° from the legs' up; four-legged?"
            ));
        }
        let hands: Vec<f64> = (0..2)
            .filter_map(|s| self.limbs[s][Limb::Hand as usize])
            .map(|h| (at(h) - ground).dot(up))
            .collect();
        if hands.len() == 2 && hands.iter().all(|&h| h < 0.25 * leg.length()) {
            return Some("its hands reach the floor as its feet do; four-legged?".to_string());
        }
        None
    }

    /// The reading in one line, joints by the names exports use: `from names` or `from the
    /// tree`, then hips, spine, neck, head, each arm and leg from the body out, each hand's
    /// fingers (where any was read), and the feet.
    pub fn summary(&self, skeleton: &Skeleton) -> String {
        let name = |j: usize| export_name(skeleton, j);
        let or_none = |j: Option<usize>| j.map_or("none".to_string(), name);
        let mut parts = vec![
            if self.from_tree {
                "from the tree"
            } else {
                "from names"
            }
            .to_string(),
            format!("hips {}", or_none(self.hips)),
        ];
        let spine: Vec<String> = self.spine.iter().map(|&j| name(j)).collect();
        parts.push(format!(
            "spine {}",
            if spine.is_empty() {
                "none".to_string()
            } else {
                spine.join(" ")
            }
        ));
        parts.push(format!("neck {}", or_none(self.neck)));
        parts.push(format!("head {}", or_none(self.head)));
        for (side, word) in [(0, "left"), (1, "right")] {
            for (part, slots) in [("arm", 0..4), ("leg", 4..8)] {
                let chain: Vec<String> =
                    slots.map(|slot| or_none(self.limbs[side][slot])).collect();
                parts.push(format!("{word} {part} {}", chain.join(" > ")));
            }
        }
        for (side, word) in [(0, "left"), (1, "right")] {
            let fingers: Vec<String> = self.fingers[side]
                .iter()
                .zip(FINGERS)
                .filter(|(bones, _)| bones.iter().any(Option::is_some))
                .map(|(bones, finger)| {
                    let bones: Vec<String> = bones.iter().flatten().map(|&j| name(j)).collect();
                    format!("{finger} {}", bones.join(" "))
                })
                .collect();
            if !fingers.is_empty() {
                parts.push(format!("{word} fingers {}", fingers.join(", ")));
            }
        }
        let feet: Vec<String> = self.foot_points(skeleton).into_iter().map(name).collect();
        parts.push(format!(
            "feet {}",
            if feet.is_empty() {
                "none".to_string()
            } else {
                feet.join(" ")
            }
        ));
        parts.join("; ")
    }
}
