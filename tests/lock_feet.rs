//! Foot locking (issue 46, point 5): during each contact the reading of the body finds, the
//! ankle stays where it landed, by two-bone IK on thigh and shin; only those legs' rotation
//! channels change, so every bone keeps its length.

use bvhview::Take;
use bvhview::edit::{LockFeet, lock_feet};
use bvhview::model::pose::OffsetMode;
use std::process::Command;

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
    for path in [
        "tests/data/bvh/bvh11_131_01.bvh",
        "tests/data/bvh/bvhparser_walk_01.bvh",
        "tests/data/bvh/animateddrawings_rokoko_jesse_dance.bvh",
    ] {
        let (take, motion, report) = locked(path);
        assert_eq!(report.feet.len(), 2, "{path}: {:?}", report.notes);
        for foot in &report.feet {
            assert!(foot.contacts >= 3, "{path}: {foot:?}");
            // Held to within a centimetre of where it landed, over every contact.
            assert!(foot.drift_after <= 0.01, "{path}: {foot:?}");
            assert!(
                foot.sliding_after <= 0.1 * foot.sliding_before,
                "{path}: {foot:?}"
            );
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
    let out = Command::new(env!("CARGO_BIN_EXE_bvhview"))
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
        said.starts_with("feet locked: LeftAnkle: 10 contacts, sliding 40.3 cm → 0.0 cm"),
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
        assert!(foot.drift_after <= 0.01, "{foot:?}");
        assert!(foot.sliding_after <= 0.1 * foot.sliding_before, "{foot:?}");
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

/// Issue 58, point 9: a take of one frame printed an empty "feet locked:" line; it has no
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
    let out = Command::new(env!("CARGO_BIN_EXE_bvhview"))
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
