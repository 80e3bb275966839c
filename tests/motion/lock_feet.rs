//! Foot locking: during each contact the reading of the body finds, the
//! ankle stays where it landed, by two-bone IK on thigh and shin; only those legs' rotation
//! channels change, so every bone keeps its length.

use bvhview::Take;
use bvhview::edit::{LockFeet, lock_feet};
use bvhview::model::pose::OffsetMode;

use crate::common;

use bvhview::model::body::contact::{Planting, sliding};
use bvhview::model::body::{Body, Limb};
use glam::DVec3;
use std::ops::Range;

fn locked(path: &str) -> (Take, bvhview::Motion, bvhview::edit::FeetLocked) {
    let take = Take::open(path).unwrap();
    let (motion, report) = lock(&take);
    (take, motion, report)
}

/// `take` with its feet locked by the default options, in its own stance.
fn lock(take: &Take) -> (bvhview::Motion, bvhview::edit::FeetLocked) {
    let stance = take.stance(OffsetMode::Replace);
    lock_feet(
        &take.skeleton,
        &take.motion,
        OffsetMode::Replace,
        stance.up,
        f64::from(stance.units.metres),
        &LockFeet::default(),
    )
    .unwrap()
}

#[test]
fn planted_ankles_stay_where_they_landed_and_no_bone_changes_length() {
    // Per take, each foot's contacts and how many are held within a millimetre; the others
    // are where a leg does not reach where its foot landed (late in a step, the hips gone on).
    for (path, feet) in [
        ("tests/data/bvh/bvh11_131_01.bvh", [(12, 8), (8, 7)]),
        ("tests/data/bvh/bvhparser_walk_01.bvh", [(4, 2), (3, 1)]),
        (
            "tests/data/bvh/animateddrawings_rokoko_jesse_dance.bvh",
            [(6, 6), (8, 8)],
        ),
    ] {
        let (take, motion, report) = locked(path);
        assert_eq!(report.feet.len(), 2, "{path}: {:?}", report.notes);
        for (foot, (contacts, held)) in report.feet.iter().zip(feet) {
            assert_eq!(
                (foot.contacts, foot.held),
                (contacts, held),
                "{path}: {foot:?}"
            );
            assert_eq!(foot.held + foot.not_held.len(), foot.contacts);
            for not in &foot.not_held {
                assert!(
                    not.why
                        .starts_with("the leg does not reach where it landed from frame "),
                    "{path}: {not:?}"
                );
            }
        }
        // Only the legs' rotation channels change: positions and every other joint as they were.
        let legs: Vec<usize> = report
            .feet
            .iter()
            .flat_map(|foot| {
                let shin = take.skeleton.joints[foot.ankle].parent.unwrap();
                [foot.ankle, shin, take.skeleton.joints[shin].parent.unwrap()]
            })
            .collect();
        for (j, joint) in take.skeleton.joints.iter().enumerate() {
            for (i, channel) in joint.channels.iter().enumerate() {
                if legs.contains(&j) && channel.is_rotation() {
                    continue;
                }
                let column = joint.first_channel + i;
                for f in 0..motion.frame_count() {
                    assert_eq!(
                        motion.frame(f)[column],
                        take.motion.frame(f)[column],
                        "{path}: {} frame {f}",
                        joint.name
                    );
                }
            }
        }
        // Every bone's length, frame by frame.
        for f in (0..motion.frame_count()).step_by(7) {
            let before = bvhview::model::pose::world_positions(
                &take.skeleton,
                take.motion.frame(f),
                OffsetMode::Replace,
            );
            let after = bvhview::model::pose::world_positions(
                &take.skeleton,
                motion.frame(f),
                OffsetMode::Replace,
            );
            for (j, joint) in take.skeleton.joints.iter().enumerate() {
                let Some(p) = joint.parent else { continue };
                let (a, b) = (
                    (before[j] - before[p]).length(),
                    (after[j] - after[p]).length(),
                );
                assert!(
                    (a - b).abs() <= 1e-4 * a.max(1.0),
                    "{path}: {} {a} {b}",
                    joint.name
                );
            }
        }
    }
}

#[test]
fn convert_says_the_sliding_before_and_after() {
    let dir = tempfile::tempdir().unwrap();
    let out = crate::common::bvhview_command()
        .args([
            "convert",
            "tests/data/bvh/bvh11_131_01.bvh",
            "--lock-feet",
            "-o",
        ])
        .arg(dir.path().join("locked.bvh"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let (_, _, report) = locked("tests/data/bvh/bvh11_131_01.bvh");
    let stderr = String::from_utf8(out.stderr).unwrap();
    let said = stderr
        .lines()
        .find(|l| l.starts_with("feet locked: "))
        .unwrap();
    let take = Take::open("tests/data/bvh/bvh11_131_01.bvh").unwrap();
    assert_eq!(
        said,
        format!("feet locked: {}", report.summary(&take.skeleton))
    );
    assert!(
        said.starts_with(
            "feet locked: LeftAnkle: 12 contacts, 8 held, sliding 58.2 cm → 18.9 cm, \
             farthest from where it landed 7.4 cm, not held: frames 229..242 (2.7 cm: the leg \
             does not reach where it landed from frame 234)"
        ),
        "{said}"
    );
}

#[test]
fn a_leg_that_cannot_be_locked_is_said_and_left_as_it_was() {
    // CMU's ASF knees turn about one axis: no three rotation channels to write.
    let take = Take::open_with(
        "tests/data/asf_amc/heiden_12.asf",
        &bvhview::OpenOptions::new().motion("tests/data/asf_amc/heiden_12_02_01.amc"),
    )
    .unwrap();
    let (motion, report) = lock_feet(
        &take.skeleton,
        &take.motion,
        OffsetMode::Replace,
        take.stance(OffsetMode::Replace).up,
        0.0254,
        &LockFeet::default(),
    )
    .unwrap();
    assert!(report.feet.is_empty());
    assert_eq!(
        report.notes,
        [
            "left leg not locked: a joint without three rotation channels of its own (an ASF bone's axis or hinge)",
            "right leg not locked: a joint without three rotation channels of its own (an ASF bone's axis or hinge)"
        ]
    );
    assert_eq!(motion, take.motion);
}

/// A leg with joints between thigh, shin and ankle (MakeHuman's `upperleg02`, `lowerleg02`)
/// is locked as two rigid stretches: the joints between keep their channels, no bone changes
/// length. It was refused before ("joints between upperleg01.L and foot.L").
#[test]
fn a_leg_with_joints_between_is_locked_as_two_stretches() {
    let walk = Take::open("tests/data/bvh/bvh11_131_01.bvh").unwrap();
    let take = bvhview::retarget::onto(&walk, "tests/data/bvh/makehuman_tpose.bvh").unwrap();
    let (motion, report) = lock(&take);
    assert!(report.notes.is_empty(), "{:?}", report.notes);
    assert_eq!(report.feet.len(), 2);
    for foot in &report.feet {
        assert!(foot.contacts >= 3, "{foot:?}");
        assert_eq!(foot.held + foot.not_held.len(), foot.contacts);
        assert!(foot.sliding_after <= 0.5 * foot.sliding_before, "{foot:?}");
    }
    let joint = |name: &str| {
        take.skeleton
            .joints
            .iter()
            .position(|j| j.name == name)
            .unwrap()
    };
    for between in [
        "upperleg02.L",
        "lowerleg02.L",
        "upperleg02.R",
        "lowerleg02.R",
    ] {
        let j = &take.skeleton.joints[joint(between)];
        for f in 0..motion.frame_count() {
            assert_eq!(
                j.values(motion.frame(f)),
                j.values(take.motion.frame(f)),
                "{between} frame {f}"
            );
        }
    }
    // The feet keep their world orientation on every frame, held or not: the ankle's turn
    // undoes what the thigh and shin turns (and the joints between) did to its parent.
    let ankles: Vec<usize> = report.feet.iter().map(|foot| foot.ankle).collect();
    let (mut before, mut after) = (Vec::new(), Vec::new());
    for f in 0..motion.frame_count() {
        let world = bvhview::model::pose::world_transforms_f64;
        world(
            &take.skeleton,
            take.motion.frame(f),
            OffsetMode::Replace,
            &mut before,
        );
        world(
            &take.skeleton,
            motion.frame(f),
            OffsetMode::Replace,
            &mut after,
        );
        for &ankle in &ankles {
            let turned = before[ankle].0.angle_between(after[ankle].0);
            assert!(turned < 1e-4, "frame {f}: the foot turned {turned} rad");
        }
    }
    for f in (0..motion.frame_count()).step_by(5) {
        let [before, after] = [&take.motion, &motion].map(|m| {
            bvhview::model::pose::world_positions(&take.skeleton, m.frame(f), OffsetMode::Replace)
        });
        for (j, joint) in take.skeleton.joints.iter().enumerate() {
            let Some(p) = joint.parent else { continue };
            let (a, b) = (
                (before[j] - before[p]).length(),
                (after[j] - after[p]).length(),
            );
            assert!((a - b).abs() <= 1e-4 * a.max(1.0), "{} {a} {b}", joint.name);
        }
    }
}

/// A take of one frame printed an empty "feet locked:" line; it has no
/// sliding to lock, and says so.
#[test]
fn one_frame_says_there_is_nothing_to_lock() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
    let (hierarchy, motion) = text.split_once("MOTION").unwrap();
    let first_row = motion
        .lines()
        .skip_while(|l| !l.starts_with("Frame Time"))
        .nth(1)
        .unwrap();
    let one = dir.path().join("one.bvh");
    std::fs::write(
        &one,
        format!("{hierarchy}MOTION\nFrames: 1\nFrame Time: 0.0333333\n{first_row}\n"),
    )
    .unwrap();
    let output = dir.path().join("out.bvh");
    let out = crate::common::bvhview_command()
        .arg("convert")
        .arg(&one)
        .arg("--lock-feet")
        .arg("-o")
        .arg(&output)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!(
            "feet not locked: nothing to lock in 1 frame (a foot slides between frames)\n\
             bvhview: wrote {}: 31 joints, 1 frame\n",
            output.display()
        )
    );
}

// Foot locking says what it did not do. Every contact the reading of the
// body finds (docs/GUIDE.md: within 5 cm of where the ankle rests on the ground both feet stand
// on within a second, slower than 0.5 m/s; `model::body::contact`) is held in the written file
// or named with why not, the printed figures are a measurement of the written file, and the
// lock does not snap the ankle into or out of a contact.

/// A contact counts as held when its ankle stays within this of where it landed (metres).
const HELD: f64 = 0.001;

/// One ankle's track in metres, and the take's up.
fn ankle_track(take: &Take, ankle: usize) -> (Vec<DVec3>, DVec3) {
    let stance = take.stance(OffsetMode::Replace);
    let metres = f64::from(stance.units.metres);
    let up = match stance.up {
        bvhview::model::pose::Up::Y => DVec3::Y,
        bvhview::model::pose::Up::Z => DVec3::Z,
    };
    let mut world = Vec::new();
    let track = (0..take.frame_count())
        .map(|f| {
            bvhview::model::pose::world_transforms_f64(
                &take.skeleton,
                take.motion.frame(f),
                OffsetMode::Replace,
                &mut world,
            );
            world[ankle].1 * metres
        })
        .collect();
    (track, up)
}

/// What a foot's part of the printed line says.
#[derive(Debug, PartialEq)]
struct Said {
    ankle: String,
    contacts: usize,
    held: usize,
    figures: String,
    not_held: Vec<String>,
}

/// The feet of a `feet locked: ` line.
fn said(line: &str) -> Vec<Said> {
    let line = line.strip_prefix("feet locked: ").unwrap();
    line.split("; ")
        .filter(|part| part.contains(" held, sliding "))
        .map(|part| {
            let (ankle, rest) = part.split_once(": ").unwrap();
            let (contacts, rest) = rest.split_once(" contact").unwrap();
            let (_, rest) = rest.split_once(", ").unwrap();
            let (held, rest) = rest.split_once(" held, ").unwrap();
            let (figures, not_held) = match rest.split_once(", not held: ") {
                Some((figures, list)) => (
                    figures,
                    list.split("), ")
                        .map(|s| s.trim_end_matches(')').to_string())
                        .collect(),
                ),
                None => (rest, Vec::new()),
            };
            Said {
                ankle: ankle.to_string(),
                contacts: contacts.parse().unwrap(),
                held: held.parse().unwrap(),
                figures: figures.to_string(),
                not_held,
            }
        })
        .collect()
}

/// The line `args` print that starts `feet locked: `, and the file they wrote.
fn run_locked(args: &[&str], dir: &std::path::Path) -> (String, Take) {
    let output = dir.join("locked.bvh");
    let out = crate::common::bvhview_command()
        .args(args)
        .arg("-o")
        .arg(&output)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stderr = String::from_utf8(out.stderr).unwrap();
    let line = stderr
        .lines()
        .find(|l| l.starts_with("feet locked: "))
        .unwrap_or_else(|| panic!("{stderr}"))
        .to_string();
    (line, Take::open(&output).unwrap())
}

/// Checks (a) and (b) on one written take: the contacts are read on `read` (the input, or a
/// retarget's source), the sliding before on `before` (the take as it was before locking) and
/// after on `written`. Returns, per foot, the contacts and how many were held.
fn check_report(line: &str, read: &Take, before: &Take, written: &Take) -> Vec<(usize, usize)> {
    let stance = read.stance(OffsetMode::Replace);
    let planted = Body::of(&read.skeleton).planted_ankles(
        &read.skeleton,
        &read.motion,
        OffsetMode::Replace,
        (stance.up, f64::from(stance.units.metres)),
        &Planting::default(),
    );
    let said = said(line);
    let body = Body::of(&written.skeleton);
    let mut counts = Vec::new();
    for (side, flags) in planted.iter().enumerate() {
        let Some(ankle) = body.limbs[side][Limb::Foot as usize] else {
            continue;
        };
        let name = &written.skeleton.joints[ankle].name;
        let foot = said
            .iter()
            .find(|s| &s.ankle == name)
            .unwrap_or_else(|| panic!("{name} not in {line}"));
        let contacts = Planting::contacts(flags);
        let (track_before, up) = ankle_track(before, ankle);
        let (track_after, _) = ankle_track(written, ankle);
        let (slid_before, _) = sliding(&track_before, up, &contacts);
        let (slid_after, farthest) = sliding(&track_after, up, &contacts);
        let not_held: Vec<Range<usize>> = contacts
            .iter()
            .filter(|c| sliding(&track_after, up, std::slice::from_ref(c)).1 > HELD)
            .cloned()
            .collect();
        // (a) Every contact held, or named with its frames and why.
        assert_eq!(foot.contacts, contacts.len(), "{name}: {line}");
        assert_eq!(foot.held, contacts.len() - not_held.len(), "{name}: {line}");
        let named: Vec<String> = foot
            .not_held
            .iter()
            .map(|s| s.split_once(" (").unwrap().0.to_string())
            .collect();
        let measured: Vec<String> = not_held
            .iter()
            .map(|c| format!("frames {}..{}", c.start, c.end))
            .collect();
        assert_eq!(named, measured, "{name}: {line}");
        for entry in &foot.not_held {
            let why = entry.split_once(" (").unwrap().1;
            assert!(why.len() > 10, "{name}: no reason in {entry:?}");
        }
        // (b) The printed figures are the written file's.
        assert_eq!(
            foot.figures,
            format!(
                "sliding {:.1} cm → {:.1} cm, farthest from where it landed {:.1} cm",
                slid_before * 100.0,
                slid_after * 100.0,
                farthest * 100.0
            ),
            "{name}: {line}"
        );
        counts.push((contacts.len(), contacts.len() - not_held.len()));
    }
    counts
}

/// (c) Around each contact's start and end (a tenth of a second each way), the written ankle
/// is never faster than 1.5 times the fastest the source's ankle goes there (plus 1 cm/s, the
/// written file's rounding): the lock does not snap into or out of a contact.
fn check_no_snap(read: &Take, before: &Take, written: &Take) -> f64 {
    let stance = read.stance(OffsetMode::Replace);
    let planted = Body::of(&read.skeleton).planted_ankles(
        &read.skeleton,
        &read.motion,
        OffsetMode::Replace,
        (stance.up, f64::from(stance.units.metres)),
        &Planting::default(),
    );
    let body = Body::of(&written.skeleton);
    let dt = written.motion.frame_time;
    let reach = (0.1 / dt).round() as usize;
    let mut worst = 0.0f64;
    for (side, flags) in planted.iter().enumerate() {
        let Some(ankle) = body.limbs[side][Limb::Foot as usize] else {
            continue;
        };
        let (source, _) = ankle_track(before, ankle);
        let (locked, _) = ankle_track(written, ankle);
        let speed = |track: &[DVec3], f: usize| {
            let (a, b) = (f.saturating_sub(1), (f + 1).min(track.len() - 1));
            (track[b] - track[a]).length() / ((b - a) as f64 * dt)
        };
        for contact in Planting::contacts(flags) {
            for at in [contact.start, contact.end - 1] {
                let window = at.saturating_sub(reach)..(at + reach + 1).min(locked.len());
                let most = window
                    .clone()
                    .map(|f| speed(&source, f))
                    .fold(0.0, f64::max);
                for f in window {
                    let ratio = speed(&locked, f) / (most * 1.5 + 0.01);
                    worst = worst.max(ratio);
                    assert!(
                        ratio <= 1.0,
                        "{}: frame {f} (contact {contact:?}): {:.3} m/s where the source goes at most {most:.3} m/s",
                        written.skeleton.joints[ankle].name,
                        speed(&locked, f)
                    );
                }
            }
        }
    }
    worst
}

fn convert_is_honest(path: &std::path::Path) {
    let dir = tempfile::tempdir().unwrap();
    let path = path.to_str().unwrap();
    let (line, written) = run_locked(&["convert", path, "--lock-feet"], dir.path());
    let take = Take::open(path).unwrap();
    let counts = check_report(&line, &take, &take, &written);
    assert_eq!(counts.len(), 2, "{line}");
    check_no_snap(&take, &take, &written);
}

#[test]
fn convert_holds_every_contact_or_says_why_on_a_cmu_walk() {
    convert_is_honest(&common::data("bvh/bvhparser_walk_01.bvh"));
}

#[test]
fn convert_holds_every_contact_or_says_why_on_a_dance() {
    convert_is_honest(&common::data("bvh/animateddrawings_rokoko_jesse_dance.bvh"));
}

#[test]
fn convert_holds_every_contact_or_says_why_on_another_cmu_walk() {
    convert_is_honest(&common::data("bvh/bvh11_131_01.bvh"));
}

#[test]
#[ignore = "needs ../shared/data; Bandai's dance, alinen's samba, PyMO's walk"]
fn convert_holds_every_contact_or_says_why_on_the_whole_corpus_s_dances() {
    for name in [
        "bandai_dataset-1_dance-short_normal_001.bvh",
        "alinen_samba_dancing.bvh",
        "pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh",
    ] {
        convert_is_honest(&common::shared_data(&format!("bvh/{name}")));
    }
}

#[test]
fn retarget_holds_every_source_contact_or_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let source = common::data("bvh/bvh11_131_01.bvh");
    let target = common::data("bvh/makehuman_tpose.bvh");
    let (source, target) = (source.to_str().unwrap(), target.to_str().unwrap());
    let (line, written) = run_locked(
        &["retarget", source, "--onto", target, "--lock-feet"],
        dir.path(),
    );
    let unlocked = dir.path().join("unlocked.bvh");
    let out = crate::common::bvhview_command()
        .args(["retarget", source, "--onto", target, "-o"])
        .arg(&unlocked)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let (source, unlocked) = (Take::open(source).unwrap(), Take::open(&unlocked).unwrap());
    let counts = check_report(&line, &source, &unlocked, &written);
    assert_eq!(counts.len(), 2, "{line}");
    check_no_snap(&source, &unlocked, &written);
}
