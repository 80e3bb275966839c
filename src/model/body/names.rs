//! Words in joint names: each family's names split into words, and the word a joint's name
//! says it is (thigh, shin, upper arm…), with its side.

use crate::model::body::sides::Side;
use std::fmt;

/// The fingers in the order a finger's number means: 0 thumb, 1 index, 2 middle, 3 ring,
/// 4 pinky.
pub const FINGERS: [&str; 5] = ["thumb", "index", "middle", "ring", "pinky"];

/// The part of a limb a joint moves (the joint at the start of that bone).
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::{Body, Limb, Role, Side};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/body/lafan1.bvh")?;
/// let body = Body::of(&take.skeleton);
/// let shin = body.joint(Role::Limb(Side::Left, Limb::Shin)).unwrap();
/// assert_eq!(take.skeleton.joints[shin].name, "LeftLeg"); // LaFAN1's word for the shin
/// assert_eq!(body.limbs[0][Limb::Shin as usize], Some(shin)); // `limbs` is in `Limb` order
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limb {
    /// The collarbone, from the chest out to the shoulder (a shoulder joint where a family
    /// also names an upper arm).
    Clavicle,
    /// The arm from the shoulder to the elbow.
    UpperArm,
    /// The arm from the elbow to the wrist.
    ForeArm,
    /// The hand, from the wrist.
    Hand,
    /// The leg from the hip to the knee.
    Thigh,
    /// The leg from the knee to the ankle.
    Shin,
    /// The foot, from the ankle.
    Foot,
    /// The toes, from the ball of the foot.
    Toe,
}

pub(super) const LIMBS: [Limb; 8] = [
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
    pub(super) fn name(self) -> &'static str {
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
///
/// ```
/// use bvhview::Take;
/// use bvhview::model::body::{Body, Role};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/body/lafan1.bvh")?;
/// let roles = Body::of(&take.skeleton).roles();
/// let (role, joint) = roles[1];
/// assert_eq!(role, Role::Spine(0));
/// assert_eq!(role.to_string(), "spine 1");
/// assert_eq!(take.skeleton.joints[joint].name, "Spine");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The joint where the legs and the spine part: the root of the body.
    Hips,
    /// The n-th joint of the spine chain above the hips, from 0.
    Spine(usize),
    /// The neck's joint, between the top of the spine and the head.
    Neck,
    /// The head's joint, at the top of the neck.
    Head,
    /// One part of an arm or a leg on one side.
    Limb(Side, Limb),
    /// A finger's bone: the finger (0 thumb … 4 pinky, see [`FINGERS`]) and the bone
    /// from the hand out (0, 1, 2).
    Finger(Side, u8, u8),
}

impl Role {
    /// Whether the role lies on the chain hips → spine → neck → head.
    pub(crate) fn central(self) -> bool {
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
            Role::Finger(side, finger, bone) => {
                let side = if *side == Side::Left { "left" } else { "right" };
                let finger = FINGERS.get(*finger as usize).unwrap_or(&"finger");
                write!(f, "{side} {finger} {}", bone + 1)
            }
        }
    }
}

/// What a name says, before the rest of the skeleton is looked at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Word {
    Hips,
    Spine,
    Neck,
    Head,
    /// A face or skull that hangs from the head (Rigify's `ORG-face`): the head is the joint it
    /// hangs from, or the face itself when it hangs from the neck.
    Face,
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
    /// The thigh where the side has no other thigh (cgspeed's lowercase CMU: `lbuttock` above
    /// `lknee`), else a helper above the thigh (Daz: `lButtock` above `lThigh`).
    Buttock,
    Ankle,
    Toe,
}

/// The words of a name in lower case: split at separators, at lower-to-upper case changes, at
/// letters next to digits, and before the last capital of a run of capitals (`LFArm` → `lf`,
/// `arm`); the part before the last `:` or `|` (`mixamorig:`) left out.
pub(super) fn tokens(name: &str) -> Vec<String> {
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
pub(super) const PREFIXES: [&str; 13] = [
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
pub(super) const NOT_PARTS: [&str; 12] = [
    "end", "top", "nub", "site", "tip", "twist", "roll", "ik", "pole", "ctrl", "helper", "share",
];

/// Body-part words glued to a side letter: CMU's ASF (`lhumerus`, `rfemur`) and cgspeed's
/// lowercase conversions of it (`lbuttock`, `lknee`, `lelbow`, `lankle`).
pub(super) const GLUED: [&str; 27] = [
    "femur", "tibia", "foot", "toes", "toe", "clavicle", "humerus", "radius", "wrist", "hand",
    "hipjoint", "shldr", "thigh", "shin", "collar", "forearm", "uparm", "upleg", "loarm", "loleg",
    "shoulder", "hip", "knee", "elbow", "ankle", "buttock", "calf",
];

/// The side and word a joint's name says, if it names a body part.
pub(super) fn word_of(name: &str) -> Option<(Option<Side>, Word)> {
    let bare = name.rsplit([':', '|']).next().unwrap_or(name);
    // MakeHuman's helpers (`__UpLeg_L`, `__LeftShoulder`) sit above the bones they name.
    if bare.starts_with("__") {
        return None;
    }
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
        "face" | "skull" => Some(Word::Face),
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
        "buttock" => Word::Buttock,
        // The ball of the foot by any name (`LeftForeFoot`, `ball.L`).
        "toe" | "toes" | "toebase" | "ball" | "forefoot" | "balloffoot" => Word::Toe,
        _ => return None,
    };
    side.map(|side| (Some(side), word))
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
            // cgspeed's lowercase CMU.
            ("lhipjoint", None),
            ("lbuttock", Some((Some(Left), Word::Buttock))),
            ("lknee", Some((Some(Left), Word::Shin))),
            ("rankle", Some((Some(Right), Word::Ankle))),
            ("lelbow", Some((Some(Left), Word::ForeArm))),
            ("lwrist", Some((Some(Left), Word::Wrist))),
            // 3ds Max Biped.
            ("Bip01 Pelvis", Some((None, Word::Hips))),
            ("Bip01 L Calf", Some((Some(Left), Word::Shin))),
            ("Bip01 R Toe0", Some((Some(Right), Word::Toe))),
            ("Bip01 L Finger0", None),
            ("Bip01 HeadNub", None),
            // MakeHuman's helpers.
            ("__UpLeg_L", None),
            ("__LeftShoulder", None),
            ("Skeleton1_LShin", Some((Some(Left), Word::Shin))),
            ("LeftForeFoot", Some((Some(Left), Word::Toe))),
            ("forefoot.R", Some((Some(Right), Word::Toe))),
            ("ORG-face", Some((None, Word::Face))),
        ] {
            assert_eq!(role_of(name), want, "{name}");
        }
    }
}
