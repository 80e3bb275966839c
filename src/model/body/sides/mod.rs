//! Left and right in joint names: which side a name is on and what its counterpart is called,
//! for every naming family the corpus holds.

/// Which side of the body a joint is on, by its name.
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::{Body, Limb, Role, Side};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let body = Body::of(&take.skeleton);
/// let name = |side| &take.skeleton.joints[body.joint(Role::Limb(side, Limb::Hand)).unwrap()].name;
/// assert_eq!((name(Side::Left).as_str(), name(Side::Right).as_str()), ("LeftHand", "RightHand"));
/// assert_eq!(Role::Limb(Side::Right, Limb::UpperArm).to_string(), "right upper arm");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The body's own left (the performer's, not the viewer's); first in `[left, right]` pairs.
    Left,
    /// The body's own right; second in `[left, right]` pairs.
    Right,
}

impl Side {
    fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// Body parts a single `l` or `r` is written before in lower-case names (CMU's ASF bones
/// `lhumerus`, `rfemur`; cgspeed's `lhip`, `lknee`, `lelbow`), and that may follow a lower-case
/// `left`/`right` (`lefthand`).
const PARTS: [&str; 49] = [
    "hipjoint",
    "hip",
    "femur",
    "thigh",
    "upleg",
    "upperleg",
    "leg",
    "knee",
    "shin",
    "tibia",
    "lowerleg",
    "loleg",
    "ankle",
    "foot",
    "heel",
    "toes",
    "toe",
    "toebase",
    "ball",
    "forefoot",
    "clavicle",
    "collar",
    "shoulder",
    "shldr",
    "scapula",
    "humerus",
    "uparm",
    "upperarm",
    "arm",
    "forearm",
    "elbow",
    "radius",
    "lowerarm",
    "loarm",
    "wrist",
    "hand",
    "palm",
    "fingers",
    "finger",
    "thumb",
    "index",
    "middle",
    "ring",
    "pinky",
    "eye",
    "buttock",
    "pectoral",
    "breast",
    "metatarsals",
];

/// Whether `text` is one of [`PARTS`], maybe followed by digits (`lhand`, `rthumb1`).
fn is_part(text: &str) -> bool {
    let stem = text.trim_end_matches(|c: char| c.is_ascii_digit());
    PARTS.contains(&stem.to_ascii_lowercase().as_str())
}

/// Whether `text` starts with one of [`PARTS`] (`lefthand`, `RIGHTFOOT`).
fn starts_with_part(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    PARTS.iter().any(|part| lower.starts_with(part))
}

/// The characters that separate the words of a name: `mixamorig:LeftArm`, `UpperLeg_L`,
/// `thigh.L.001`, `Bip01 L Thigh`, `DEF-thigh.L`.
fn is_separator(c: char) -> bool {
    matches!(c, '_' | '.' | ':' | '-' | ' ' | '|' | '/')
}

/// The side a name marks, the byte range of the mark and what the other side writes there.
fn side_mark(name: &str) -> Option<(Side, std::ops::Range<usize>, String)> {
    // The words of the name between separators, with their byte offsets.
    let mut tokens: Vec<(usize, &str)> = Vec::new();
    let mut start = None;
    for (i, c) in name.char_indices().chain([(name.len(), '_')]) {
        match (is_separator(c), start) {
            (true, Some(s)) => {
                tokens.push((s, &name[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    // 1. The words Left and Right (`LeftUpLeg`, `mixamorig:LeftArm`, `left_hip`, `mHipLeft`,
    //    `RightUpperLeg`, `LEFT_ARM`), as a word of their own: at the start of a word or after a
    //    lower-case letter or digit when capitalised, and not running on into a lower-case word
    //    (`Leftover`, `upright`, `Bright` have no side) unless that word is a body part
    //    (`lefthand`).
    const WORDS: [(&str, &str, Side); 6] = [
        ("Left", "Right", Side::Left),
        ("left", "right", Side::Left),
        ("LEFT", "RIGHT", Side::Left),
        ("Right", "Left", Side::Right),
        ("right", "left", Side::Right),
        ("RIGHT", "LEFT", Side::Right),
    ];
    for &(at, token) in &tokens {
        for (word, other, side) in WORDS {
            for (i, _) in token.match_indices(word) {
                let before = token[..i].chars().next_back();
                let after = &token[i + word.len()..];
                let capital = word.starts_with(|c: char| c.is_ascii_uppercase());
                let starts = match before {
                    None => true,
                    Some(c) => capital && (c.is_ascii_lowercase() || c.is_ascii_digit()),
                };
                let last_lower = word.ends_with(|c: char| c.is_ascii_lowercase());
                let ends = match after.chars().next() {
                    None => true,
                    Some(c) if last_lower => !c.is_ascii_lowercase() || starts_with_part(after),
                    Some(c) => !c.is_ascii_uppercase() || starts_with_part(after),
                };
                if starts && ends {
                    return Some((side, at + i..at + i + word.len(), other.to_string()));
                }
            }
        }
    }
    // 2. A word that is a lone L or R (`L_Hip`, `UpperLeg_L`, `thigh.L`, `upperleg01.R`,
    //    `Bip01 L Thigh`, `Finger_l_01`).
    for &(at, token) in &tokens {
        let (side, other) = match token {
            "L" => (Side::Left, "R"),
            "l" => (Side::Left, "r"),
            "R" => (Side::Right, "L"),
            "r" => (Side::Right, "l"),
            _ => continue,
        };
        return Some((side, at..at + 1, other.to_string()));
    }
    // 3. A word that starts with its side's letter: lower case before a capital (Daz's, Poser's
    //    and Second Life's `lThigh`, `rCollar`, `lShldr`), upper case before a capitalised word
    //    (CMU's `LHipJoint`, `LThumb`; not `L5`, `LOWER`), or lower case before a body part
    //    (CMU's ASF `lhumerus`, `lhipjoint`; cgspeed's `lhip`, `lknee`, `lelbow`).
    for &(at, token) in &tokens {
        let bytes = token.as_bytes();
        let Some(&first) = bytes.first() else {
            continue;
        };
        let side = match first {
            b'l' | b'L' => Side::Left,
            b'r' | b'R' => Side::Right,
            _ => continue,
        };
        let rest = &token[1..];
        let marked = if first.is_ascii_lowercase() {
            (bytes.len() >= 2 && bytes[1].is_ascii_uppercase()) || is_part(rest)
        } else {
            bytes.len() >= 3 && bytes[1].is_ascii_uppercase() && bytes[2].is_ascii_lowercase()
        };
        if marked {
            let other = match (side, first.is_ascii_lowercase()) {
                (Side::Left, true) => "r",
                (Side::Left, false) => "R",
                (Side::Right, true) => "l",
                (Side::Right, false) => "L",
            };
            return Some((side, at..at + 1, other.to_string()));
        }
    }
    None
}

/// The side a name marks and the name with the other side's mark, as the common rigs write them:
/// CMU (`LHipJoint`, `LeftUpLeg`, `LThumb`; its ASF's `lhipjoint`, `lhumerus`), cgspeed (`lhip`,
/// `lknee`, `lelbow`, `rhipjoint`), Mixamo (`mixamorig:LeftUpLeg`), LaFAN1 (`LeftUpLeg`), Bandai
/// (`UpperLeg_L`), Xsens (`RightUpperLeg`), Daz, Poser and Second Life (`lThigh`, `lShldr`,
/// `rCollar`, `mHipLeft`), Rokoko (`LeftThigh`), SMPL (`left_hip`, `L_Hip`), MakeHuman and
/// Blender (`upperleg01.R`, `thigh.L`). `None` when the name marks no side (`Hips`, `Spine`,
/// `Head`, `Neck`, `lowerback`, `upperback`, Xsens's `L5`).
pub fn name_side(name: &str) -> Option<(Side, String)> {
    let (side, range, other) = side_mark(name)?;
    let mut mirrored = String::with_capacity(name.len() + 1);
    mirrored.push_str(&name[..range.start]);
    mirrored.push_str(&other);
    mirrored.push_str(&name[range.end..]);
    debug_assert!(side_mark(&mirrored).is_some_and(|(s, _, _)| s == side.other()));
    Some((side, mirrored))
}

/// The name a joint takes in the mirror image: Left and Right exchanged (see [`name_side`]);
/// `None` when the name has no side.
pub fn mirrored_name(name: &str) -> Option<String> {
    name_side(name).map(|(_, mirrored)| mirrored)
}

#[cfg(test)]
mod tests;
