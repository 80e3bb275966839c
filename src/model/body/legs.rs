//! How many legs a skeleton has: a person two, a hand or an arm alone none, a crab or a spider
//! eight. A body with no legs or more than two is no standing person: its up axis is not
//! guessed from a figure it does not have, and it is not carried over as a person's.

use super::names::{NOT_PARTS, Word, tokens, word_of};
use super::roles::Body;
use crate::model::skeleton::Skeleton;

/// Words that name a leg's part, with or without a side (`Leg1_L`, `leg3.R.001`, `lfemur`).
const LEG_WORDS: [&str; 18] = [
    "leg", "legs", "thigh", "upleg", "upperleg", "femur", "shin", "lowerleg", "loleg", "lowleg",
    "calf", "tibia", "knee", "foot", "ankle", "toe", "toes", "forefoot",
];

/// Whether a joint's name says it is part of a leg.
fn names_a_leg(name: &str) -> bool {
    if name
        .rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .starts_with("__")
    {
        return false;
    }
    let words = tokens(name);
    if words.iter().any(|w| NOT_PARTS.contains(&w.as_str())) {
        return false;
    }
    let glued = matches!(
        word_of(name),
        Some((
            _,
            Word::Thigh
                | Word::Leg
                | Word::Shin
                | Word::Foot
                | Word::Ankle
                | Word::Toe
                | Word::Buttock
        ))
    );
    glued || words.iter().any(|w| LEG_WORDS.contains(&w.as_str()))
}

/// A count in words, as a person says it: `no`, `one` … `twelve`, then digits.
pub(crate) fn count_word(n: usize) -> String {
    const WORDS: [&str; 13] = [
        "no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
        "eleven", "twelve",
    ];
    WORDS.get(n).map_or(n.to_string(), |w| w.to_string())
}

impl Body {
    /// The legs a skeleton has: the chains its names say are legs (a joint named for a leg's
    /// part with no such joint above it: `LeftUpLeg` and `RightUpLeg`, or eight `Leg1_L` …
    /// `Leg4_R`), or two when the tree gave this reading its legs.
    pub fn leg_count(&self, skeleton: &Skeleton) -> usize {
        let joints = &skeleton.joints;
        let leg: Vec<bool> = joints
            .iter()
            .map(|j| !j.end_site && names_a_leg(&j.name))
            .collect();
        let named = (0..joints.len())
            .filter(|&j| leg[j])
            .filter(|&j| {
                let mut up = joints[j].parent;
                while let Some(p) = up {
                    if leg[p] {
                        return false;
                    }
                    up = joints[p].parent;
                }
                true
            })
            .count();
        if named == 0 && self.from_tree {
            2
        } else {
            named
        }
    }

    /// `Some(legs)` when this reading is of a body that does not stand on two legs by its
    /// count of them: none (a hand or an arm alone: something of a body was read, no leg) or
    /// more than two (a crab). `None` for two legs, one (a weak reading, said otherwise) and a
    /// skeleton read as no body at all. A figure without two legs has no up of its own to
    /// guess: its file's Y is kept ([`crate::model::stance::Stance::guess`]).
    pub fn legs_not_two(&self, skeleton: &Skeleton) -> Option<usize> {
        if !self.is_a_body() && !self.fingers.iter().flatten().flatten().any(Option::is_some) {
            return None;
        }
        match self.leg_count(skeleton) {
            0 if !self
                .limbs
                .iter()
                .any(|side| side[4..].iter().any(Option::is_some)) =>
            {
                Some(0)
            }
            n if n > 2 => Some(n),
            _ => None,
        }
    }
}
