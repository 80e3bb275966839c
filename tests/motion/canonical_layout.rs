//! The canonical layout (`convert --channels root6,rot3 --order ORDER --strip-prefix`): every
//! take of the corpus, with each option alone and all together, keeps every joint's world
//! position within 1e-4 of the figure's height on every frame.

use crate::common::{asf_of, files_in, repo_data, shared_data};
use bvhview::Take;
use bvhview::edit::{Canonical, canonical};
use bvhview::model::pose::{OffsetMode, world_positions};
use bvhview::model::skeleton::RotationOrder;

/// Every take of a corpus: BVH files, and ASF skeletons with their motions.
fn corpus(data: fn(&str) -> std::path::PathBuf) -> Vec<Take> {
    let mut takes: Vec<Take> = files_in(&data("bvh"), "bvh")
        .iter()
        .map(|path| Take::open(path).unwrap())
        .collect();
    for amc in files_in(&data("asf_amc"), "amc") {
        let options = bvhview::OpenOptions::new().motion(&amc);
        takes.push(Take::open_with(asf_of(&amc), &options).unwrap());
    }
    takes
}

/// The largest distance between a joint before and after, over every frame, over the height.
fn worst(
    take: &Take,
    skeleton: &bvhview::Skeleton,
    motion: &bvhview::Motion,
    mode: OffsetMode,
) -> f32 {
    let height = take.stance(take.offset_mode).height.max(1e-6);
    let mut worst = 0.0f32;
    for f in 0..take.motion.frame_count().max(1) {
        let row = |m: &bvhview::Motion| {
            if m.frame_count() == 0 {
                Vec::new()
            } else {
                m.frame(f).to_vec()
            }
        };
        let before = world_positions(&take.skeleton, &row(&take.motion), take.offset_mode);
        let after = world_positions(skeleton, &row(motion), mode);
        for (a, b) in before.iter().zip(&after) {
            worst = worst.max(a.distance(*b) / height);
        }
    }
    worst
}

#[test]
fn every_repository_take_keeps_every_joint_where_it_was_with_each_option_and_all() {
    keeps_every_joint(&corpus(repo_data), 18);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_take_keeps_every_joint_where_it_was_with_each_option_and_all() {
    keeps_every_joint(&corpus(shared_data), 33);
}

fn keeps_every_joint(takes: &[Take], at_least: usize) {
    let options = [
        Canonical {
            root6_rot3: true,
            ..Default::default()
        },
        Canonical {
            order: Some(RotationOrder::Xyz),
            ..Default::default()
        },
        Canonical {
            order: Some(RotationOrder::Yxz),
            ..Default::default()
        },
        Canonical {
            strip_prefix: true,
            ..Default::default()
        },
        Canonical {
            root6_rot3: true,
            order: Some(RotationOrder::Zxy),
            strip_prefix: true,
        },
    ];
    assert!(takes.len() >= at_least, "{} takes", takes.len());
    for take in takes {
        for wanted in &options {
            let (skeleton, motion, _) =
                match canonical(&take.skeleton, &take.motion, take.offset_mode, wanted) {
                    Ok(done) => done,
                    // A moving position channel below the root is refused by name, never dropped.
                    Err(e)
                        if wanted.root6_rot3
                            && e.to_string().contains("position channels that move") =>
                    {
                        continue;
                    }
                    Err(e) => panic!("{}: {wanted:?}: {e}", take.name),
                };
            let mode = if wanted.root6_rot3 {
                OffsetMode::Replace
            } else {
                take.offset_mode
            };
            let error = worst(take, &skeleton, &motion, mode);
            assert!(
                error <= 1e-4,
                "{}: {wanted:?}: {error:e} of the height",
                take.name
            );
            if wanted.root6_rot3 {
                for joint in skeleton.joints.iter().filter(|j| !j.end_site) {
                    let positions = joint.channels.iter().filter(|c| c.is_position()).count();
                    let rotations = joint.channels.iter().filter(|c| c.is_rotation()).count();
                    let want = if joint.parent.is_none() { 3 } else { 0 };
                    assert_eq!(
                        (positions, rotations),
                        (want, 3),
                        "{}: {}",
                        take.name,
                        joint.name
                    );
                }
            }
            if let Some(order) = wanted.order {
                assert!(
                    skeleton
                        .joints
                        .iter()
                        .all(|j| j.rotation_order.is_none_or(|o| o == order))
                );
            }
        }
    }
}

/// A position channel below the root that moves is refused by name with how far it moves; one
/// that never moves goes into the OFFSET.
#[test]
fn moving_position_channels_below_the_root_are_refused_and_still_ones_kept() {
    let text = |second: &str| {
        format!(
            "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
             Zrotation Xrotation Yrotation\n JOINT Chest\n {{\n  OFFSET 0 10 0\n  CHANNELS 6 \
             Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  End Site\n  {{\n   \
             OFFSET 0 5 0\n  }}\n }}\n}}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0 90 0 0 0 0 0 10 \
             0 0 0 0\n1 90 0 0 0 0 {second} 0 0 0\n"
        )
    };
    let wanted = Canonical {
        root6_rot3: true,
        ..Default::default()
    };
    let moving = bvhview::OpenOptions::new()
        .open_bytes(text("0 12 0").as_bytes(), "m.bvh")
        .unwrap();
    let error = canonical(
        &moving.skeleton,
        &moving.motion,
        OffsetMode::Replace,
        &wanted,
    )
    .unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("joint 'Chest' has position channels that move it 2 from"),
        "{error}"
    );
    let still = bvhview::OpenOptions::new()
        .open_bytes(text("0 10 0").as_bytes(), "s.bvh")
        .unwrap();
    let (skeleton, _, said) =
        canonical(&still.skeleton, &still.motion, OffsetMode::Replace, &wanted).unwrap();
    assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 10.0, 0.0));
    assert_eq!(skeleton.joints[1].channels.len(), 3);
    assert!(
        said[0].contains("'Chest': its position channels never move it"),
        "{said:?}"
    );
}

/// `--names smpl22`: every repository take whose body the reading maps takes SMPL's names for
/// the joints it maps (the pelvis, knees and wrists among them), keeps the rest, and no two
/// joints share a name.
#[test]
fn names_of_a_family_come_from_the_body_reading() {
    let smpl = Take::open("smpl22").unwrap();
    let mut named_takes = 0;
    for take in corpus(repo_data) {
        let Ok((named, _)) = bvhview::retarget::names_of_family(&take.skeleton, &smpl.skeleton)
        else {
            continue;
        };
        let has = |name: &str| named.joints.iter().any(|j| j.name == name);
        if has("pelvis") && has("left_knee") && has("right_wrist") {
            named_takes += 1;
        }
        assert_eq!(named.joints.len(), take.skeleton.joints.len());
    }
    assert!(named_takes >= 16, "{named_takes} takes named");
}

/// `--rest tpose` on every take whose body has arms and legs: every joint where it was on every
/// frame (within 1e-4 of the height), and the rest pose `info` reads is a T-pose within 1°.
fn rest_tpose_keeps_every_joint(takes: &[Take], at_least: usize) {
    let mut posed = 0;
    for take in takes {
        let up = take.stance(take.offset_mode).up;
        let Ok((skeleton, motion, _)) =
            bvhview::edit::rest_tpose(&take.skeleton, &take.motion, take.offset_mode, up)
        else {
            continue;
        };
        let error = worst(take, &skeleton, &motion, OffsetMode::Replace);
        assert!(error <= 1e-4, "{}: {error:e} of the height", take.name);
        let body = bvhview::model::body::Body::of(&skeleton);
        let line = bvhview::info::rest_pose_text(&skeleton, &body, up).unwrap();
        let angles: Vec<f64> = line
            .split(|c: char| !(c.is_ascii_digit() || c == '.'))
            .filter_map(|w| w.parse().ok())
            .collect();
        assert!(line.starts_with("a T-pose"), "{}: {line}", take.name);
        assert!(angles.iter().all(|a| *a <= 1.0), "{}: {line}", take.name);
        posed += 1;
    }
    assert!(posed >= at_least, "{posed} takes T-posed");
}

#[test]
fn every_repository_take_with_arms_and_legs_rests_in_a_t_pose() {
    rest_tpose_keeps_every_joint(&corpus(repo_data), 16);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_take_with_arms_and_legs_rests_in_a_t_pose() {
    rest_tpose_keeps_every_joint(&corpus(shared_data), 31);
}
