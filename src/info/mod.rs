//! `bvhview info`: what a file holds, in a few lines.

#[doc(hidden)] // the walk and the batch, for the command line and the Python package
pub mod batch;

use crate::io::message::{Message, Spelling};
use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use crate::model::stance::Stance;
use crate::take::Take;
use std::collections::BTreeMap;
use std::fmt::Write;

/// `value` with `decimals` decimals, or in scientific notation when it is so large or so small
/// that it would print hundreds of digits or only zeros (a file may say `Frame Time: 1e300`).
pub fn readable(value: f64, decimals: usize) -> String {
    let tiny = value != 0.0 && value.abs() < 1e-6;
    if value.is_finite() && (value.abs() >= 1e9 || tiny) {
        format!("{value:.3e}")
    } else {
        format!("{value:.decimals$}")
    }
}

/// Every warning `info` gives for a file: the loader's, the offset-mode guess, then the size of
/// a human-like figure.
pub fn warnings(loaded: &Take, mode: OffsetMode) -> Vec<Message> {
    warnings_with(loaded, mode, &loaded.stance(mode))
}

/// [`warnings`] with the take's stance already guessed.
pub fn warnings_with(loaded: &Take, mode: OffsetMode, stance: &Stance) -> Vec<Message> {
    let mut warnings = loaded.warnings.clone();
    warnings.extend(offset_mode_warning(&loaded.skeleton, &loaded.motion, mode));
    warnings.extend(size_warning(&loaded.skeleton, stance));
    warnings.extend(
        body_warnings(&loaded.skeleton, &loaded.motion, mode)
            .into_iter()
            .map(Message::from),
    );
    warnings
}

/// The reading of the body's doubts, one warning each, for a skeleton read as a body at all
/// (a limb, a neck or a head found): a chain of three joints is not a body with no legs.
pub fn body_warnings(skeleton: &Skeleton, motion: &Motion, mode: OffsetMode) -> Vec<String> {
    let body = crate::model::body::Body::of(skeleton);
    if !body.is_a_body() {
        return Vec::new();
    }
    body.doubts(skeleton, motion, mode)
        .into_iter()
        .map(|doubt| format!("body: {doubt}"))
        .collect()
}

/// A person, in metres, spans at least this…
pub const HUMAN_LEAST: f32 = 0.5;
/// … and at most this.
pub const HUMAN_MOST: f32 = 2.5;

/// Whether a skeleton looks like a person's, by the reading of the body
/// ([`crate::model::body::Body`]): a head, and a left and a right upper arm and thigh. `Some`
/// names the joints it goes by (`Head, LeftArm/RightArm, LeftUpLeg/RightUpLeg`).
pub fn human_like(skeleton: &Skeleton) -> Option<String> {
    use crate::model::body::{Body, Limb, Role, Side};
    let body = Body::of(skeleton);
    let name = |joint: usize| skeleton.joints[joint].name.as_str();
    let pair = |limb: Limb| -> Option<String> {
        let left = body.joint(Role::Limb(Side::Left, limb))?;
        let right = body.joint(Role::Limb(Side::Right, limb))?;
        Some(format!("{}/{}", name(left), name(right)))
    };
    Some(format!(
        "{}, {}, {}",
        name(body.head?),
        pair(Limb::UpperArm)?,
        pair(Limb::Thigh)?
    ))
}

/// Warns when a human-like skeleton ([`human_like`]), in the units guessed (or stated by the
/// file) for it, spans less than 0.5 m or more than 2.5 m: the units, or the offset mode, are
/// likely wrong. Units the caller gave are not second-guessed.
/// The figure's size (its largest spread, standing or lying) is what is compared: a person
/// lying down stands low but still spans a person's length.
pub fn size_warning(skeleton: &Skeleton, stance: &Stance) -> Option<Message> {
    // Units the caller gave are theirs to know (a child, a doll, a giant).
    if stance.units_basis == crate::model::stance::UnitsBasis::Given {
        return None;
    }
    let metres = stance.size * stance.units.metres;
    if !metres.is_finite() || stance.size <= 1e-6 || (HUMAN_LEAST..=HUMAN_MOST).contains(&metres) {
        return None;
    }
    let joints = human_like(skeleton)?;
    let bound = if metres < HUMAN_LEAST {
        format!("under the {HUMAN_LEAST} m a person spans at least")
    } else {
        format!("over the {HUMAN_MOST} m a person spans at most")
    };
    let said = format!(
        "a human-like skeleton ({joints}) spans {} m in {}, {bound} (it stands {} m tall): the \
         units or the offset mode may be wrong (`",
        readable(f64::from(metres), 3),
        stance.units.name,
        readable(f64::from(stance.height * stance.units.metres), 3),
    );
    Some(
        Message::from(said)
            .argument("scale", None)
            .text("` rescales; `")
            .argument("offset_mode", None)
            .text("` says how position channels count)"),
    )
}

/// `info`'s line on the rest pose, for a body with two arms and two legs: how far each arm
/// (shoulder to wrist) lies from level and each leg (hip to ankle) from straight down, and what
/// pose that is (a T-pose: every one within 5°).
pub fn rest_pose_text(
    skeleton: &Skeleton,
    body: &crate::model::body::Body,
    up: crate::model::pose::Up,
) -> Option<String> {
    use crate::model::body::Limb;
    let up = match up {
        crate::model::pose::Up::Y => glam::DVec3::Y,
        crate::model::pose::Up::Z => glam::DVec3::Z,
    };
    let rest = crate::model::pose::world_positions(skeleton, &[], OffsetMode::Replace);
    let bone = |side: usize, from: Limb, to: Limb| -> Option<glam::DVec3> {
        let a = body.limbs[side][from as usize]?;
        let b = body.limbs[side][to as usize]?;
        (rest[b] - rest[a]).as_dvec3().try_normalize()
    };
    let mut arms = [0.0; 2];
    let mut legs = [0.0; 2];
    for side in 0..2 {
        // Above level is positive.
        arms[side] = bone(side, Limb::UpperArm, Limb::Hand)?
            .dot(up)
            .asin()
            .to_degrees();
        legs[side] = bone(side, Limb::Thigh, Limb::Foot)?
            .dot(-up)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
    }
    let level = |a: f64| if a >= 0.0 { "above" } else { "below" };
    let pose = if arms.iter().chain(&legs).all(|a| a.abs() <= 5.0) {
        "a T-pose"
    } else if arms.iter().all(|a| (-60.0..=-20.0).contains(a)) {
        "an A-pose"
    } else {
        "neither a T-pose nor an A-pose"
    };
    Some(format!(
        "{pose}: arms {:.1}° {} and {:.1}° {} level, legs {:.1}° and {:.1}° from straight down",
        arms[0].abs(),
        level(arms[0]),
        arms[1].abs(),
        level(arms[1]),
        legs[0],
        legs[1]
    ))
}

/// A human-readable summary: joints, End Sites, channels, frames, timing, orders, warnings (an
/// argument a warning names written as `spelling` writes it).
pub fn summary(name: &str, loaded: &Take, mode: OffsetMode, spelling: &dyn Spelling) -> String {
    let skeleton = &loaded.skeleton;
    let motion = &loaded.motion;
    let end_sites = skeleton.end_site_count();
    let joints = skeleton.joints.len() - end_sites;
    let mut out = String::new();
    let _ = writeln!(out, "file:             {name}");
    let _ = writeln!(out, "joints:           {joints}");
    let _ = writeln!(out, "end sites:        {end_sites}");
    let _ = writeln!(out, "channels:         {}", skeleton.channel_count());
    let _ = writeln!(out, "frames:           {}", motion.frame_count());
    let rate = if motion.frame_time > 0.0 {
        format!(
            " ({} frames per second)",
            readable(1.0 / motion.frame_time, 2)
        )
    } else {
        String::new()
    };
    // Six significant digits for every input: a BVH's `0.0083333` and an AMC's 1/120 alike.
    let time = if (1e-6..1e9).contains(&motion.frame_time) || motion.frame_time == 0.0 {
        crate::render::trace::format_g(motion.frame_time, 6)
    } else {
        format!("{:e}", motion.frame_time)
    };
    let _ = writeln!(out, "frame time:       {time} s{rate}");
    let _ = writeln!(
        out,
        "duration:         {} s",
        readable(motion.duration(), 3)
    );
    let _ = writeln!(out, "rotation orders:  {}", rotation_orders(skeleton));
    let _ = writeln!(out, "position channels: {}", position_joints(skeleton));
    // Which of several joints with position channels carries the travel (in_place and the
    // dataset's root translations follow it); with one, it is that one.
    let translated = skeleton
        .joints
        .iter()
        .filter(|j| j.channels.iter().any(|c| c.is_position()))
        .count();
    if translated > 1 && motion.frame_count() > 0 {
        let travel = crate::model::body::travel_joint_of_take(skeleton, motion, mode);
        let _ = writeln!(
            out,
            "travel:           {} (the joint whose position channels carry the take across the floor)",
            skeleton.joints[travel].name
        );
    }
    let body = crate::model::body::Body::of(skeleton);
    let reading = if body.is_a_body() {
        body.summary(skeleton)
    } else {
        "none read (no limb, neck or head, by name or by the tree)".to_string()
    };
    let _ = writeln!(out, "body:             {reading}");
    let stance = loaded.stance(mode);
    if let Some(rest) = rest_pose_text(skeleton, &body, stance.up) {
        let _ = writeln!(out, "rest pose:        {rest}");
    }
    // What a map file's `[skeleton.<fingerprint>]` pairs are keyed by.
    let _ = writeln!(out, "fingerprint:      {}", skeleton.fingerprint());
    // Guessed from the motion; the article's view still draws the file as written.
    // A guess that is not sure names the option that says it.
    let say = |name: &'static str, unsure: bool| {
        if unsure {
            Message::from("; ")
                .argument(name, None)
                .text(" says it")
                .spelled(spelling)
        } else {
            String::new()
        }
    };
    let unsure = |s: crate::model::stance::Sureness| s == crate::model::stance::Sureness::Unsure;
    let _ = writeln!(
        out,
        "up axis:          {}{}",
        stance.up_text(),
        say("up", unsure(stance.up_sureness))
    );
    if stance.size > 1e-6 {
        let _ = writeln!(
            out,
            "units:            {}{}",
            stance.units_text(),
            say("units", unsure(stance.units_sureness))
        );
    } else {
        let _ = writeln!(
            out,
            "units:            unknown (every point of the figure is in one place)"
        );
    }
    let warnings = warnings_with(loaded, mode, &stance);
    if warnings.is_empty() {
        let _ = writeln!(out, "warnings:         none");
    } else {
        let _ = writeln!(out, "warnings:");
        for warning in &warnings {
            let _ = writeln!(out, "  - {}", warning.spelled(spelling));
        }
    }
    out
}

/// e.g. `ZYX ×19, ZXY ×12`; joints without three rotation channels are counted apart.
fn rotation_orders(skeleton: &Skeleton) -> String {
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut other = 0;
    for joint in skeleton.joints.iter().filter(|j| !j.end_site) {
        match joint.rotation_order {
            Some(order) => *counts.entry(order.letters().to_uppercase()).or_default() += 1,
            None => other += 1,
        }
    }
    let mut parts: Vec<String> = counts.iter().map(|(k, n)| format!("{k} ×{n}")).collect();
    if other > 0 {
        // No rotation, or not exactly three on distinct axes (an ASF bone with one or two dof).
        parts.push(format!("other ×{other} (not three rotations)"));
    }
    if parts.is_empty() {
        "none".to_string()
    } else {
        parts.join(", ")
    }
}

/// Which joints carry position channels: the names if few, else a count.
fn position_joints(skeleton: &Skeleton) -> String {
    let names: Vec<&str> = skeleton
        .joints
        .iter()
        .filter(|j| j.channels.iter().any(|c| c.is_position()))
        .map(|j| j.name.as_str())
        .collect();
    match names.len() {
        0 => "none".to_string(),
        1..=4 => names.join(", "),
        n => format!("{n} joints"),
    }
}

/// Warns when the non-root position channels look written for the other `--offset-mode`: under
/// `replace`, nearly all of them are at or near zero at frame 0 while the OFFSETs are not
/// (MakeHuman's files, which mean "added to OFFSET"); under `add`, they repeat the OFFSETs (so
/// adding doubles every bone). See [`crate::model::pose::written_for_other_mode`].
pub fn offset_mode_warning(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
) -> Option<Message> {
    let (matching, candidates) =
        crate::model::pose::written_for_other_mode(skeleton, motion, mode)?;
    Some(match mode {
        OffsetMode::Replace => Message::from(format!(
            "{matching} of {candidates} non-root joints with position channels have them at or \
             near 0 at frame 0 (within 5% of their OFFSETs' length) while their OFFSETs are not: \
             the file looks written for `"
        ))
        .argument("offset_mode", Some("add"))
        .text("` (position added to OFFSET); with the default (replace) those bones collapse"),
        OffsetMode::Add => Message::from(format!(
            "{matching} of {candidates} non-root joints with position channels repeat their OFFSET \
             at frame 0 (within 5% of its length): the file looks written for the default `"
        ))
        .argument("offset_mode", Some("replace"))
        .text("`; adding doubles those bones"),
    })
}
