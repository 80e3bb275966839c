//! The fingers of each hand: five of up to three bones, read from their names under the hand
//! the reading found (Mixamo's `LeftHandIndex1`, Daz's `lIndex1`, MakeHuman's `Index1_L` and
//! `finger2-1.L`, 3ds Max Biped's `Bip01 L Finger1`, Unreal's `index_01_l`, Rigify's
//! `DEF-f_index.01.L`, CMU's `LThumb`). Palm bones (Perception Neuron's `LeftInHandIndex`,
//! metacarpals) and helpers are left out: a finger's bones are its first three joints below them.

pub use super::names::FINGERS;
use super::names::{Limb, tokens};
use super::roles::{Body, depth, is_ancestor};
use super::sides::Side;
use crate::model::skeleton::Skeleton;

/// The finger a name's words say, counted from 0 for the thumb, and whether it says it by a
/// number after `finger` (`finger2`, `Finger0`) rather than a word: such numbers count from 1
/// (MakeHuman) or from 0 (3ds Max Biped), which only the hand's other fingers tell.
fn finger_word(name: &str) -> Option<(usize, Option<u32>)> {
    if name
        .rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .starts_with("__")
    {
        return None;
    }
    let words = tokens(name);
    // Palm bones and helpers: `LeftInHandIndex`, `metacarpal`, `twist`, tips.
    let helper = |w: &str| {
        matches!(
            w,
            "in" | "metacarpal"
                | "meta"
                | "carpal"
                | "palm"
                | "base"
                | "end"
                | "nub"
                | "tip"
                | "site"
                | "twist"
                | "share"
        )
    };
    if words.iter().any(|w| helper(w)) {
        return None;
    }
    // CMU's ASF glues the side letter on: `lthumb`, `rfingers` (the fingers as one bone).
    if let [word] = &words[..]
        && let Some(rest) = word.strip_prefix(['l', 'r'])
    {
        match rest {
            "thumb" => return Some((0, None)),
            "fingers" => return Some((1, None)),
            _ => {}
        }
    }
    for (i, word) in words.iter().enumerate() {
        let named = match word.as_str() {
            "thumb" => Some(0),
            "index" | "pointer" => Some(1),
            "middle" | "mid" => Some(2),
            "ring" => Some(3),
            "pinky" | "pinkie" | "little" | "small" => Some(4),
            _ => None,
        };
        if let Some(finger) = named {
            return Some((finger, None));
        }
        if word == "finger" || word == "fingers" {
            // Biped's `Finger01` is the thumb's second bone: the finger is the first digit.
            let digit = words
                .get(i + 1)?
                .bytes()
                .next()
                .filter(u8::is_ascii_digit)?;
            return Some((0, Some(u32::from(digit - b'0'))));
        }
    }
    None
}

/// The number a name ends its words with (`f_index.01.L` 1, `LeftHandIndex4` 4), if any.
fn last_number(name: &str) -> Option<u32> {
    tokens(name)
        .iter()
        .rev()
        .find(|w| w.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|w| w.parse().ok())
}

/// A finger's three phalanges among the joints named for it, from the hand out: the chain's
/// last three, since a metacarpal named for its finger (`LeftHandIndex0`, `index_00_l`) comes
/// first and is no phalanx; but where the names count from 1 to 4 or more, the fourth and on
/// are the fingertip's markers (Mixamo's `LeftHandIndex4`), and the first three are kept.
fn phalanges<'a>(skeleton: &Skeleton, chain: &'a [usize]) -> &'a [usize] {
    if chain.len() <= 3 {
        return chain;
    }
    let numbers: Vec<Option<u32>> = chain
        .iter()
        .map(|&j| last_number(&skeleton.joints[j].name))
        .collect();
    let counted_from_one = numbers[0] == Some(1)
        && numbers
            .windows(2)
            .all(|w| matches!(w, [Some(a), Some(b)] if b > a));
    if counted_from_one {
        &chain[..3]
    } else {
        &chain[chain.len() - 3..]
    }
}

impl Body {
    /// Reads the fingers under each hand found: `self.fingers[side][finger][bone]`.
    pub(super) fn read_fingers(&mut self, skeleton: &Skeleton) {
        for side in 0..2 {
            let Some(hand) = self.limbs[side][Limb::Hand as usize] else {
                continue;
            };
            let below: Vec<(usize, (usize, Option<u32>))> = (0..skeleton.joints.len())
                .filter(|&j| j != hand && !skeleton.joints[j].end_site)
                .filter(|&j| is_ancestor(skeleton, hand, j))
                .filter_map(|j| Some((j, finger_word(&skeleton.joints[j].name)?)))
                .collect();
            // Numbers after `finger`: from 0 when any is 0 (Biped), else from 1 (MakeHuman).
            let from = match below.iter().filter_map(|(_, (_, n))| *n).min() {
                Some(0) => 0,
                _ => 1,
            };
            let mut chains: [Vec<usize>; 5] = Default::default();
            for (joint, (finger, number)) in below {
                let finger = match number {
                    Some(n) => match (n as usize).checked_sub(from) {
                        Some(f) if f < 5 => f,
                        _ => continue,
                    },
                    None => finger,
                };
                chains[finger].push(joint);
            }
            for (finger, mut chain) in chains.into_iter().enumerate() {
                // A finger's bones in order from the hand: a joint of this finger above another
                // goes first.
                chain.sort_by_key(|&j| (depth(skeleton, j), j));
                chain.dedup();
                // Two chains named as one finger (a thumb and its mirror under one hand): keep
                // the one that starts nearest the hand.
                let Some(&first) = chain.first() else {
                    continue;
                };
                chain.retain(|&j| is_ancestor(skeleton, first, j));
                let bones = phalanges(skeleton, &chain);
                let slots = &mut self.fingers[side][finger];
                *slots = [None; 3];
                for (slot, &j) in slots.iter_mut().zip(bones) {
                    *slot = Some(j);
                }
            }
        }
    }

    /// Each side's fingers that were found, as `(side, finger, bone, joint)`.
    pub(super) fn finger_roles(&self) -> Vec<(Side, usize, usize, usize)> {
        let mut out = Vec::new();
        for (s, side) in [Side::Left, Side::Right].into_iter().enumerate() {
            for (finger, bones) in self.fingers[s].iter().enumerate() {
                for (bone, joint) in bones.iter().enumerate() {
                    if let Some(joint) = joint {
                        out.push((side, finger, bone, *joint));
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finger_words_of_each_family() {
        for (name, want) in [
            ("mixamorig:LeftHandIndex1", Some((1, None))),
            ("LeftHandThumb2", Some((0, None))),
            ("lMid1", Some((2, None))),
            ("Pinky3_R", Some((4, None))),
            ("finger2-1.L", Some((0, Some(2)))),
            ("Bip01 L Finger01", Some((0, Some(0)))),
            ("Bip01 R Finger4", Some((0, Some(4)))),
            ("index_01_l", Some((1, None))),
            ("DEF-f_ring.01.L", Some((3, None))),
            ("LThumb", Some((0, None))),
            ("lthumb", Some((0, None))),
            ("rfingers", Some((1, None))),
            ("LeftInHandIndex", None),
            ("LeftFingerBase", None),
            ("__Index1_L", None),
            ("LeftHandIndex4_End", None),
            ("LeftHand", None),
            ("palm_index.L", None),
            ("DEF-palm.01.L", None),
            ("lCarpal1", None),
            ("index_metacarpal_l", None),
            ("f_index.01.L", Some((1, None))),
        ] {
            assert_eq!(finger_word(name), want, "{name}");
        }
    }
}
