//! Retargeting: A → A exact, A → A′ (renamed, A-pose rest, ×1.3) by bone directions
//! and the root's path, a sample skeleton per naming family, the real corpus's skeletons onto
//! each other and onto the built-in one, and bad input from the command line.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use crate::common;

use crate::common::bvhview_command;
use bvhview::model::body::{Body, Role};
use bvhview::model::pose::{OffsetMode, Up};
use bvhview::retarget::{self, Map, Ups};
use bvhview::{Motion, Skeleton};
use glam::{Quat, Vec3};
use std::path::Path;

fn take(path: &Path) -> (Skeleton, Motion) {
    let loaded = crate::common::load_take(path, None, None).unwrap();
    (loaded.skeleton, loaded.motion)
}

/// A naming family's sample skeleton, `tests/body/FAMILY.bvh` (written for these tests from
/// the names each family uses; not third-party data, so not in tests/data).
fn sample(family: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/body")
        .join(format!("{family}.bvh"))
}

fn up_of(skeleton: &Skeleton, motion: &Motion) -> Up {
    bvhview::model::stance::Stance::guess(skeleton, motion, OffsetMode::Replace, None).up
}

#[test]
fn a_take_onto_its_own_skeleton_is_exact() {
    for name in [
        "bvh/assimp_01_01.bvh",
        "bvh/bvhpython_test_freebvh.bvh",
        "bvh/makehuman_walk1.bvh",
        "bvh/opencollar_run.bvh",
        "bvh/animateddrawings_rokoko_jesse_dance.bvh",
    ] {
        let (skeleton, motion) = take(&common::repo_data(name));
        let map = Map::guess(&skeleton, &skeleton);
        for (t, s) in map.source_of.iter().enumerate() {
            if !skeleton.joints[t].end_site {
                assert_eq!(*s, Some(t), "{name}: {}", skeleton.joints[t].name);
            }
        }
        let up = up_of(&skeleton, &motion);
        let ups = Ups {
            source: up,
            target: up,
        };
        let (out_skeleton, out) =
            retarget::retarget(&skeleton, &motion, &skeleton, &map, ups, 2).unwrap();
        assert_eq!(out_skeleton, skeleton);
        assert_eq!(out.frame_count(), motion.frame_count());
        let worst = motion
            .data
            .iter()
            .zip(&out.data)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst <= 1e-6, "{name}: a value differs by {worst}");
    }
}

/// An ASF take onto its own skeleton: its hinges (`dof rx` knees and elbows) and two-channel
/// joints give back their own values too, as the three-channel ones do.
#[test]
fn an_asf_take_with_hinges_onto_its_own_skeleton_is_exact() {
    let loaded = crate::common::load_take(
        &common::repo_data("asf_amc/heiden_12.asf"),
        Some(&common::repo_data("asf_amc/heiden_12_02_01.amc")),
        None,
    )
    .unwrap();
    let (skeleton, motion) = (loaded.skeleton, loaded.motion);
    let hinges = skeleton
        .joints
        .iter()
        .filter(|j| j.channels.iter().filter(|c| c.is_rotation()).count() == 1)
        .count();
    assert!(hinges >= 6, "{hinges} hinges");
    let map = Map::guess(&skeleton, &skeleton);
    let up = up_of(&skeleton, &motion);
    let ups = Ups {
        source: up,
        target: up,
    };
    let (_, out) = retarget::retarget(&skeleton, &motion, &skeleton, &map, ups, 2).unwrap();
    let worst = motion
        .data
        .iter()
        .zip(&out.data)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    // Within one 32-bit step of the values (2⁻¹⁶ between 128° and 256°): the hinge angle is
    // solved from the bone, not read back from the Euler angles.
    assert!(worst <= 2e-5, "a value differs by {worst}");
}

/// A renamed to Xsens's names (the rest prefixed `Char:`), its arms hanging 45° down at rest
/// (an A-pose), every bone 1.3 times as long.
fn a_prime(skeleton: &Skeleton) -> Skeleton {
    let mut renamed = skeleton.clone();
    let names = [
        ("Hips", "Pelvis"),
        ("LowerBack", "L5"),
        ("Spine", "L3"),
        ("Spine1", "T8"),
        ("Neck", "Neck"),
        ("Head", "Head"),
        ("LeftShoulder", "LeftShoulder"),
        ("LeftArm", "LeftUpperArm"),
        ("LeftForeArm", "LeftForeArm"),
        ("LeftHand", "LeftHand"),
        ("RightShoulder", "RightShoulder"),
        ("RightArm", "RightUpperArm"),
        ("RightForeArm", "RightForeArm"),
        ("RightHand", "RightHand"),
        ("LeftUpLeg", "LeftUpperLeg"),
        ("LeftLeg", "LeftLowerLeg"),
        ("LeftFoot", "LeftFoot"),
        ("LeftToeBase", "LeftToe"),
        ("RightUpLeg", "RightUpperLeg"),
        ("RightLeg", "RightLowerLeg"),
        ("RightFoot", "RightFoot"),
        ("RightToeBase", "RightToe"),
    ];
    let arms: Vec<(usize, f32)> = skeleton
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| match j.name.as_str() {
            "LeftArm" => Some((i, -45f32)),
            "RightArm" => Some((i, 45f32)),
            _ => None,
        })
        .collect();
    let under = |ancestor: usize, mut j: usize| loop {
        match skeleton.joints[j].parent {
            Some(p) if p == ancestor => return true,
            Some(p) => j = p,
            None => return false,
        }
    };
    for (i, joint) in renamed.joints.iter_mut().enumerate() {
        if !joint.end_site {
            joint.name = names
                .iter()
                .find(|(from, _)| *from == joint.name)
                .map_or(format!("Char:{}", joint.name), |(_, to)| to.to_string());
        }
        for &(arm, degrees) in &arms {
            if under(arm, i) {
                joint.offset = Quat::from_rotation_z(degrees.to_radians()) * joint.offset;
            }
        }
        joint.offset *= 1.3;
    }
    renamed
}

#[test]
fn a_take_onto_a_renamed_a_posed_larger_copy_keeps_bone_directions_and_path() {
    let (skeleton, motion) = take(&common::repo_data("bvh/assimp_01_01.bvh"));
    let motion = bvhview::edit::trim(&motion, 0..600);
    let target = a_prime(&skeleton);
    let map = Map::guess(&skeleton, &target);
    map.check("A", "A'").unwrap();
    assert_eq!(
        map.target_body
            .joint(Role::Hips)
            .map(|j| &target.joints[j].name[..]),
        Some("Pelvis")
    );
    let up = up_of(&skeleton, &motion);
    let ups = Ups {
        source: up,
        target: up,
    };
    let (out_skeleton, out) =
        retarget::retarget(&skeleton, &motion, &target, &map, ups, 2).unwrap();
    let errors: Vec<f64> =
        retarget::direction_errors(&skeleton, &motion, &out_skeleton, &out, &map, ups).concat();
    assert!(errors.len() >= 600 * 20, "{} bones compared", errors.len());
    let worst = errors.iter().copied().fold(0.0, f64::max);
    assert!(worst <= 0.5, "a bone direction is {worst}° off");
    // Every mapped bone, not only the main ones: each joint's direction to its mapped child.
    for frame in (0..600).step_by(37) {
        let a = bvhview::model::pose::world_positions(
            &skeleton,
            motion.frame(frame),
            OffsetMode::Replace,
        );
        let b = bvhview::model::pose::world_positions(
            &out_skeleton,
            out.frame(frame),
            OffsetMode::Replace,
        );
        for (t, joint) in target.joints.iter().enumerate() {
            let (Some(p), Some(s), Some(sp)) = (
                joint.parent,
                map.source_of[t],
                joint.parent.and_then(|p| map.source_of[p]),
            ) else {
                continue;
            };
            let (da, db) = (a[s] - a[sp], b[t] - b[p]);
            if da.length() > 1e-3 {
                let angle = da.angle_between(db).to_degrees();
                assert!(
                    angle <= 0.5,
                    "frame {frame}: {} is {angle}° off",
                    joint.name
                );
            }
        }
        // The root's path: A's times 1.3.
        let want = a[0] * 1.3;
        assert!(
            (b[0] - want).length() <= 1e-3 * want.length().max(1.0),
            "frame {frame}: root at {} for {want}",
            b[0]
        );
    }
}

#[test]
fn every_naming_family_maps_every_role_onto_the_built_in_skeleton() {
    let (smpl, _) = retarget::built_in("smpl22").unwrap();
    let smpl_body = Body::of(&smpl);
    assert_eq!(smpl.joints.iter().filter(|j| !j.end_site).count(), 22);
    let names = |body: &Body, skeleton: &Skeleton| -> Vec<(String, String)> {
        body.roles()
            .into_iter()
            .map(|(r, j)| (r.to_string(), skeleton.joints[j].name.clone()))
            .collect()
    };
    // Per family: (file, hips, left thigh, left upper arm, left toe or foot, head).
    let families = [
        ("cmu", "Hips", "LeftUpLeg", "LeftArm", "LeftToeBase", "Head"),
        (
            "mixamo",
            "mixamorig:Hips",
            "mixamorig:LeftUpLeg",
            "mixamorig:LeftArm",
            "mixamorig:LeftToeBase",
            "mixamorig:Head",
        ),
        ("lafan1", "Hips", "LeftUpLeg", "LeftArm", "LeftToe", "Head"),
        (
            "xsens",
            "Pelvis",
            "LeftUpperLeg",
            "LeftUpperArm",
            "LeftToe",
            "Head",
        ),
        (
            "bandai",
            "Hips",
            "UpperLeg_L",
            "UpperArm_L",
            "Toes_L",
            "Head",
        ),
        ("makehuman", "Root", "UpLeg_L", "UpArm_L", "Toe_L", "Head"),
        (
            "daz_poser_secondlife",
            "hip",
            "lThigh",
            "lShldr",
            "lToe",
            "head",
        ),
        ("rokoko", "Hips", "LeftUpLeg", "LeftArm", "LeftToe", "Head"),
        (
            "cgspeed_lowercase",
            "hip",
            "lbuttock",
            "lshoulder",
            "ltoe",
            "head",
        ),
        (
            "biped_human",
            "Bip01 Pelvis",
            "Bip01 L Thigh",
            "Bip01 L UpperArm",
            "Bip01 L Toe0",
            "Bip01 Head",
        ),
        (
            "perception_neuron",
            "Hips",
            "LeftUpLeg",
            "LeftArm",
            "LeftFoot",
            "Head",
        ),
        (
            "optitrack",
            "Skeleton1_Hip",
            "Skeleton1_LThigh",
            "Skeleton1_LUArm",
            "Skeleton1_LToe",
            "Skeleton1_Head",
        ),
        (
            "smpl",
            "pelvis",
            "left_hip",
            "left_shoulder",
            "left_foot",
            "head",
        ),
        (
            "rigify",
            "DEF-spine",
            "DEF-thigh.L",
            "DEF-upper_arm.L",
            "DEF-toe.L",
            "DEF-spine.006",
        ),
    ];
    for (family, hips, thigh, arm, toe, head) in families {
        let (skeleton, motion) = take(&sample(family));
        let body = Body::of(&skeleton);
        let roles = names(&body, &skeleton);
        let named = |role: &str| {
            roles
                .iter()
                .find(|(r, _)| r == role)
                .map(|(_, n)| n.as_str())
        };
        assert_eq!(named("hips"), Some(hips), "{family}: {roles:?}");
        assert_eq!(named("left thigh"), Some(thigh), "{family}: {roles:?}");
        assert_eq!(named("left upper arm"), Some(arm), "{family}: {roles:?}");
        let toe_role = if family == "perception_neuron" {
            "left foot"
        } else {
            "left toe"
        };
        assert_eq!(named(toe_role), Some(toe), "{family}: {roles:?}");
        assert_eq!(named("head"), Some(head), "{family}: {roles:?}");
        // Every role of both sides' limbs, mirrored: the right side as the left.
        for limb in [
            "clavicle",
            "upper arm",
            "forearm",
            "hand",
            "thigh",
            "shin",
            "foot",
        ] {
            assert!(
                named(&format!("left {limb}")).is_some(),
                "{family}: no left {limb}"
            );
            assert!(
                named(&format!("right {limb}")).is_some(),
                "{family}: no right {limb}"
            );
        }
        assert!(
            !body.spine.is_empty() && body.neck.is_some(),
            "{family}: {roles:?}"
        );
        // Onto the built-in skeleton: the chain maps, the take comes out.
        let map = Map::guess(&skeleton, &smpl);
        map.check(family, "smpl22").unwrap();
        for (role, joint) in smpl_body.roles() {
            if role != Role::Spine(1) && map.source_body.joint(role).is_some() {
                assert!(map.source_of[joint].is_some(), "{family}: {role} unmapped");
            }
        }
        let ups = Ups::default();
        let (_, out) = retarget::retarget(&skeleton, &motion, &smpl, &map, ups, 1).unwrap();
        assert_eq!(out.frame_count(), motion.frame_count());
        let errors: Vec<f64> =
            retarget::direction_errors(&skeleton, &motion, &smpl, &out, &map, ups).concat();
        let worst = errors.iter().copied().fold(0.0, f64::max);
        assert!(worst < 0.01, "{family}: a bone {worst}° off");
        // And a CMU walk onto the family's skeleton: the thighs stay apart (cgspeed's
        // lowercase CMU had both on one point), the path scaled by the legs.
        let (walk, walk_motion) = take(&common::repo_data("bvh/bvhparser_walk_01.bvh"));
        let walk_motion = bvhview::edit::trim(&walk_motion, 0..120);
        let map = Map::guess(&walk, &skeleton);
        map.check("walk", family).unwrap();
        let ups = Ups {
            source: up_of(&walk, &walk_motion),
            target: Up::guess(&skeleton),
        };
        let (out_skeleton, out) =
            retarget::retarget(&walk, &walk_motion, &skeleton, &map, ups, 1).unwrap();
        let stand = retarget::standing(&walk, &walk_motion, &out_skeleton, &out, &map, ups, 0.056);
        // Not 1 everywhere: where hip bones lead from the hips to the thighs (cgspeed's
        // `lhipjoint`), they take the source's hip bones' directions, and the width follows
        // (0.83 of the rest's from a CMU walk).
        assert!(stand.pelvis > 0.8, "{family}: {stand:?}");
        let expected = stand.ratio * stand.source_path;
        assert!(
            (stand.target_path - expected).abs() <= 0.02 * expected,
            "{family}: {stand:?}"
        );
    }
}

/// LaFAN1's sample skeleton with position channels on its left forearm, moved 3 units a frame
/// along its parent's x while every joint turns: a joint other than the root that translates
/// (as Perception Neuron and Rigify takes do).
fn forearm_that_translates() -> (Skeleton, Motion) {
    let text = std::fs::read_to_string(sample("lafan1")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let at = lines
        .iter()
        .position(|l| l.trim() == "JOINT LeftForeArm")
        .unwrap();
    let channels = lines[at + 1..]
        .iter()
        .position(|l| l.trim().starts_with("CHANNELS"))
        .unwrap()
        + at
        + 1;
    lines[channels] =
        "CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation".to_string();
    let motion_at = lines.iter().position(|l| l.trim() == "MOTION").unwrap();
    let hierarchy = lines[..motion_at].join("\n");
    let count: usize = lines[..motion_at]
        .iter()
        .filter_map(|l| l.trim().strip_prefix("CHANNELS "))
        .map(|l| {
            l.split_whitespace()
                .next()
                .unwrap()
                .parse::<usize>()
                .unwrap()
        })
        .sum();
    let rest = format!(
        "{hierarchy}\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n{}\n",
        vec!["0"; count].join(" ")
    );
    let skeleton = bvhview::bvh::loader::load_bytes(rest.as_bytes(), "forearm")
        .unwrap()
        .skeleton;
    let forearm = skeleton
        .joints
        .iter()
        .find(|j| j.name == "LeftForeArm")
        .unwrap();
    let (first, offset) = (forearm.first_channel, forearm.offset);
    let frames = 20;
    let mut data = Vec::with_capacity(frames * count);
    for f in 0..frames {
        for c in 0..count {
            let value = match c {
                0 => 2.0 * f as f32,
                1 => 95.0,
                2 => f as f32,
                _ if c == first => offset.x + 3.0 * f as f32,
                _ if c == first + 1 => offset.y,
                _ if c == first + 2 => offset.z + 0.5 * f as f32,
                _ => 20.0 * ((f * 7 + c * 3) as f32 * 0.1).sin(),
            };
            data.push(value);
        }
    }
    (skeleton, Motion::new(1.0 / 30.0, count, frames, data))
}

#[test]
fn position_channels_on_any_joint_are_carried_and_scaled() {
    use bvhview::model::pose::world_transforms_f64;
    let (skeleton, motion) = forearm_that_translates();
    let world = |skeleton: &Skeleton, motion: &Motion, f: usize| {
        let mut out = Vec::new();
        world_transforms_f64(skeleton, motion.frame(f), OffsetMode::Replace, &mut out);
        out
    };
    let hand = skeleton
        .joints
        .iter()
        .position(|j| j.name == "LeftHand")
        .unwrap();
    let hand_end = skeleton.joints[hand].children[0];
    // Onto itself: every joint where it was (the hand's tip had been 4.75 units off when the
    // forearm's translation was dropped).
    let map = Map::guess(&skeleton, &skeleton);
    let ups = Ups::default();
    let (out_skeleton, out) =
        retarget::retarget(&skeleton, &motion, &skeleton, &map, ups, 2).unwrap();
    for f in 0..motion.frame_count() {
        let (a, b) = (world(&skeleton, &motion, f), world(&out_skeleton, &out, f));
        for j in 0..a.len() {
            assert!((a[j].1 - b[j].1).length() < 1e-3, "frame {f}, joint {j}");
        }
    }
    let moved = (world(&skeleton, &motion, 19)[hand_end].1
        - world(&skeleton, &motion, 0)[hand_end].1)
        .length();
    assert!(moved > 40.0, "{moved}");
    // Onto the same skeleton twice as big: every joint twice as far from the origin, the
    // forearm's translation too.
    let (big, _) = bvhview::edit::scale(&skeleton, &motion, 2.0).unwrap();
    let map = Map::guess(&skeleton, &big);
    let (big_skeleton, big_out) =
        retarget::retarget(&skeleton, &motion, &big, &map, ups, 2).unwrap();
    for f in 0..motion.frame_count() {
        let (a, b) = (
            world(&skeleton, &motion, f),
            world(&big_skeleton, &big_out, f),
        );
        for j in 0..a.len() {
            assert!(
                (a[j].1 * 2.0 - b[j].1).length() < 2e-3,
                "frame {f}, joint {j}: {} {}",
                a[j].1 * 2.0,
                b[j].1
            );
        }
    }
    // Onto a skeleton whose forearm has no position channels (smpl22's `left_elbow`), the
    // move cannot be carried: said, not dropped in silence. Onto itself nothing is said.
    let smpl = retarget::Target::load("smpl22", u64::MAX).unwrap();
    let said = smpl
        .apply("take", &skeleton, &motion, &[], Default::default(), 1)
        .unwrap()
        .uncarried;
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with("LeftForeArm's position channels move it up to 57.")
            && said[0]
                .ends_with("left_elbow has no position channels, so that move is not carried"),
        "{said:?}"
    );
    let own = retarget::Target::new("own".into(), skeleton.clone(), &motion);
    assert!(
        own.apply("own", &skeleton, &motion, &[], Default::default(), 1)
            .unwrap()
            .uncarried
            .is_empty()
    );
    // The fast pass is the plain one.
    let fast = retarget::retargeted_values(&skeleton, &motion, &big, &map, ups, 2, true);
    let plain = retarget::retargeted_values(&skeleton, &motion, &big, &map, ups, 2, false);
    for (a, b) in fast.iter().zip(&plain) {
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} {b}");
    }
}

/// Source and target of the real-skeleton check, each a take of the corpus (an ASF with its
/// AMC). The corpus holds no LaFAN1 or Xsens take (docs/GUIDE.md#retarget says which files
/// were checked).
const CORPUS: [(&str, &str, Option<&str>); 8] = [
    ("CMU", "bvh/assimp_01_01.bvh", None),
    (
        "Bandai",
        "bvh/bandai_dataset-1_dance-short_normal_001.bvh",
        None,
    ),
    ("MakeHuman", "bvh/makehuman_walk1.bvh", None),
    (
        "Rokoko",
        "bvh/animateddrawings_rokoko_jesse_dance.bvh",
        None,
    ),
    ("Mixamo", "bvh/bvhpython_test_freebvh.bvh", None),
    ("Second Life", "bvh/opencollar_run.bvh", None),
    (
        "CMU ASF 12",
        "asf_amc/heiden_12.asf",
        Some("asf_amc/heiden_12_02_01.amc"),
    ),
    (
        "CMU ASF charleston",
        "asf_amc/simchoni_charleston.asf",
        Some("asf_amc/simchoni_charleston_1.amc"),
    ),
];

fn metres(skeleton: &Skeleton, motion: &Motion) -> f64 {
    f64::from(
        bvhview::model::stance::Stance::guess(skeleton, motion, OffsetMode::Replace, None)
            .units
            .metres,
    )
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn real_skeletons_onto_each_other_keep_bone_directions_and_feet() {
    let mut takes: Vec<(&str, Skeleton, Motion)> = CORPUS
        .iter()
        .map(|(name, path, amc)| {
            let amc = amc.map(common::shared_data);
            let loaded =
                crate::common::load_take(&common::shared_data(path), amc.as_deref(), None).unwrap();
            let (s, m) = (loaded.skeleton, loaded.motion);
            // At most 600 frames of each: enough poses, a debug build's time.
            let frames = m.frame_count().min(600);
            (*name, s, bvhview::edit::trim(&m, 0..frames))
        })
        .collect();
    let (smpl, smpl_motion) = retarget::built_in("smpl22").unwrap();
    takes.push(("smpl22", smpl, smpl_motion));
    println!(
        "| source | target | bones × frames | median ° | p99 ° | max ° | followed: median ° | p99 ° | hips path off | floor off | pelvis width kept | planted ankles slide, leg lengths: source → target (contacts) | with --lock-feet |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|");
    for (source_name, source, motion) in &takes[..CORPUS.len()] {
        for (target_name, target, target_motion) in &takes {
            if source_name == target_name {
                continue;
            }
            let map = Map::guess(source, target);
            map.check(source_name, target_name).unwrap();
            let ups = Ups {
                source: up_of(source, motion),
                target: if target_motion.frame_count() > 1 {
                    up_of(target, target_motion)
                } else {
                    Up::guess(target)
                },
            };
            let (out_skeleton, out) =
                retarget::retarget(source, motion, target, &map, ups, 2).unwrap();
            let errors: Vec<f64> =
                retarget::direction_errors(source, motion, &out_skeleton, &out, &map, ups).concat();
            let median = retarget::quantile(&errors, 0.5);
            let p99 = retarget::quantile(&errors, 0.99);
            let worst = retarget::quantile(&errors, 1.0);
            // What the target's joints can follow: the whole direction on three channels, the
            // direction across the axis on a hinge (the targets with fewer are CMU's ASFs).
            let followable: Vec<f64> =
                retarget::followable_errors(source, motion, &out_skeleton, &out, &map, ups)
                    .into_iter()
                    .flatten()
                    .flatten()
                    .collect();
            let followed_median = retarget::quantile(&followable, 0.5);
            let followed_p99 = retarget::quantile(&followable, 0.99);
            if !target_name.starts_with("CMU ASF") {
                assert_eq!(followable, errors, "{source_name} → {target_name}");
            }
            let stand = retarget::standing(
                source,
                motion,
                &out_skeleton,
                &out,
                &map,
                ups,
                metres(source, motion),
            );
            let target_metres = if target_motion.frame_count() > 1 {
                metres(target, target_motion)
            } else {
                metres(target, &out)
            };
            let expected_path = stand.ratio * stand.source_path;
            let path_error = (stand.target_path - expected_path).abs() / expected_path.max(1e-6);
            let source_take = bvhview::Take::new(source.clone(), motion.clone(), *source_name);
            let on_target = bvhview::Take::new(out_skeleton.clone(), out.clone(), "out");
            let (locked, _) = retarget::lock_feet_from_source(&source_take, &on_target).unwrap();
            let stand_locked = retarget::standing(
                source,
                motion,
                &out_skeleton,
                &locked,
                &map,
                ups,
                metres(source, motion),
            );
            let floor_error = (stand.target_floor - stand.ratio * stand.source_floor).abs();
            println!(
                "| {source_name} | {target_name} | {} | {median:.2} | {p99:.2} | {worst:.2} | {followed_median:.2} | {followed_p99:.2} | {:.2} % | {:.1} mm | {:.4} | {:.3} → {:.3} ({}) | {:.3} |",
                errors.len(),
                100.0 * path_error,
                1000.0 * floor_error * target_metres,
                stand.pelvis,
                stand.source_sliding,
                stand.target_sliding,
                stand.contacts,
                stand_locked.target_sliding,
            );
            assert!(
                followed_median <= 5.0 && followed_p99 <= 15.0,
                "{source_name} → {target_name}: {followed_median}° {followed_p99}°"
            );
            // The hips travel the source's path scaled by the legs; the target's feet stand on
            // the source's floor by their own foot points.
            assert!(
                path_error <= 0.02,
                "{source_name} → {target_name}: path {stand:?}"
            );
            assert!(
                floor_error * target_metres <= 0.005,
                "{source_name} → {target_name}: floor {stand:?}"
            );
            // No pelvis collapse: the thighs stay as far apart as at rest (1.0000 on every
            // pair of the corpus).
            assert!(
                stand.pelvis > 0.8,
                "{source_name} → {target_name}: pelvis {stand:?}"
            );
            // Rotations carried onto legs of other proportions move planted feet (a wider
            // pelvis turning, a longer shin): shown, not held. With `--lock-feet` they slide no
            // farther than the source's, for their size. A hinge knee (CMU's ASF) cannot be
            // locked by turning thigh and shin freely: shown only.
            let hinged = target_name.starts_with("CMU ASF");
            assert!(
                hinged || stand_locked.target_sliding <= stand.source_sliding * 1.1 + 0.01,
                "{source_name} → {target_name}: planted feet slide {stand_locked:?}"
            );
        }
    }
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.bvh");
    let cmu = sample("cmu");
    let json = dir.path().join("bad.json");
    std::fs::write(
        &json,
        "{\n  \"Hips\": \"pelvis\",\n  \"LeftUpLeg\" \"left_hip\"\n}\n",
    )
    .unwrap();
    let toml = dir.path().join("bad.toml");
    std::fs::write(&toml, "\"Hips\" = \"pelvis\"\nLeftUpLeg = left_hip\n").unwrap();
    let two = dir.path().join("two.toml");
    std::fs::write(
        &two,
        "\"LeftUpLeg\" = \"left_hip\"\n\"RightUpLeg\" = \"left_hip\"\n",
    )
    .unwrap();
    let tiny = common::repo_data("bvh/bvhanim_test_simple.bvh");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--onto".into(), tiny.display().to_string()],
            "no mappable chain",
        ),
        (
            vec![
                "--onto".into(),
                "smpl22".into(),
                "--map".into(),
                "Nope=pelvis".into(),
            ],
            "\"Nope\"",
        ),
        (
            vec![
                "--onto".into(),
                "smpl22".into(),
                "--map".into(),
                "Hips=nope".into(),
            ],
            "\"nope\"",
        ),
        (
            vec![
                "--onto".into(),
                "smpl22".into(),
                "--map".into(),
                two.display().to_string(),
            ],
            "two source joints",
        ),
        (
            vec![
                "--onto".into(),
                "smpl22".into(),
                "--map".into(),
                json.display().to_string(),
            ],
            "bad.json:3:",
        ),
        (
            vec![
                "--onto".into(),
                "smpl22".into(),
                "--map".into(),
                toml.display().to_string(),
            ],
            "bad.toml:2:",
        ),
        (vec!["--onto".into(), "nosuchskeleton".into()], "built-in"),
    ];
    for (args, said) in cases {
        let result = bvhview_command()
            .arg("retarget")
            .arg(&cmu)
            .args(&args)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(said), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            3,
            "{args:?} left a file"
        );
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn the_command_writes_bvh_and_glb_and_a_shown_map_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let source = common::repo_data("bvh/bvhpython_test_freebvh.bvh");
    let shown = bvhview_command()
        .args(["retarget"])
        .arg(&source)
        .args(["--onto", "smpl22", "--show-map"])
        .output()
        .unwrap();
    assert!(shown.status.success());
    let text = String::from_utf8(shown.stdout).unwrap();
    assert!(
        text.contains("\"mixamorig:LeftUpLeg\" = \"left_hip\"  # left thigh"),
        "{text}"
    );
    let map = dir.path().join("map.toml");
    std::fs::write(&map, &text).unwrap();
    for name in ["out.bvh", "out.glb"] {
        let out = dir.path().join(name);
        let status = bvhview_command()
            .arg("retarget")
            .arg(&source)
            .args(["--onto", "smpl22", "--map"])
            .arg(&map)
            .arg("-o")
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        assert!(out.exists());
    }
    let (skeleton, motion) = take(&dir.path().join("out.bvh"));
    assert_eq!(skeleton.joints.iter().filter(|j| !j.end_site).count(), 22);
    assert_eq!(motion.frame_count(), 69);
    // Unmapping a source joint leaves its target at rest.
    let out = dir.path().join("unmapped.bvh");
    let status = bvhview_command()
        .arg("retarget")
        .arg(&source)
        .args(["--onto", "smpl22", "--map", "mixamorig:LeftForeArm=", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let (skeleton, motion) = take(&out);
    let elbow = skeleton
        .joints
        .iter()
        .find(|j| j.name == "left_elbow")
        .unwrap();
    for frame in 0..motion.frame_count() {
        assert!(
            elbow
                .values(motion.frame(frame))
                .iter()
                .all(|v| v.abs() < 1e-4)
        );
    }
    let _ = Vec3::ZERO;
}

#[test]
fn a_folder_of_mixed_skeletons_compiles_onto_one_skeleton_as_one_group() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set");
    let folder = common::repo_data("bvh");
    let result = bvhview_command()
        .args(["dataset"])
        .arg(&folder)
        .arg("-o")
        .arg(&out)
        .args(["--onto", "smpl22"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "{stderr}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let groups = manifest["groups"].as_array().unwrap();
    assert_eq!(groups.len(), 1, "{stderr}");
    assert_eq!(groups[0]["joints"][0], "pelvis");
    // The two 2-joint files have no chain: skipped with the reason.
    let skipped = manifest["skipped"].as_array().unwrap();
    assert_eq!(skipped.len(), 2, "{skipped:?}");
    assert!(stderr.contains("no mappable chain"), "{stderr}");
    // Every take that compiled: its bones' directions as in the source, within point 4's figures.
    let target = retarget::Target::load("smpl22", u64::MAX).unwrap();
    let map_of = |s: &Skeleton| Map::guess(s, &target.skeleton);
    let mut compiled = 0;
    for path in common::files_in(&folder, "bvh") {
        let (skeleton, motion) = take(&path);
        let Ok(put) = target.apply("take", &skeleton, &motion, &[], Default::default(), 2) else {
            continue;
        };
        let (out_skeleton, out) = (put.skeleton, put.motion);
        compiled += 1;
        let ups = Ups {
            source: up_of(&skeleton, &motion),
            target: target.up,
        };
        let errors = retarget::direction_errors(
            &skeleton,
            &motion,
            &out_skeleton,
            &out,
            &map_of(&skeleton),
            ups,
        )
        .concat();
        let (median, p99) = (
            retarget::quantile(&errors, 0.5),
            retarget::quantile(&errors, 0.99),
        );
        assert!(
            median <= 5.0 && p99 <= 15.0,
            "{}: {median}° {p99}°",
            path.display()
        );
    }
    assert_eq!(compiled, groups[0]["clips"].as_u64().unwrap() as usize);
}

#[test]
fn any_number_of_threads_gives_the_same_values() {
    let (skeleton, motion) = take(&common::repo_data("bvh/assimp_01_01.bvh"));
    let target = retarget::Target::load("smpl22", u64::MAX).unwrap();
    let one = target.apply("CMU", &skeleton, &motion, &[], Default::default(), 1);
    let three = target.apply("CMU", &skeleton, &motion, &[], Default::default(), 3);
    let (one, three) = (one.unwrap().motion, three.unwrap().motion);
    assert!(motion.frame_count() > 2 * 512, "several pieces of frames");
    assert_eq!(one, three);
}

#[test]
fn a_skeleton_whose_names_say_nothing_maps_by_its_tree() {
    let (skeleton, motion) = take(&sample("cmu"));
    let mut anonymous = skeleton.clone();
    for (i, joint) in anonymous.joints.iter_mut().enumerate() {
        joint.name = format!("J{i}");
    }
    let named = Body::of(&skeleton);
    let body = Body::of(&anonymous);
    for (role, joint) in named.roles() {
        if matches!(role, Role::Spine(_)) {
            continue;
        }
        assert_eq!(body.joint(role), Some(joint), "{role}: {:?}", body.roles());
    }
    // And it retargets onto the built-in skeleton as the named one does.
    let target = retarget::Target::load("smpl22", u64::MAX).unwrap();
    let from_names = target
        .apply("named", &skeleton, &motion, &[], Default::default(), 1)
        .unwrap()
        .motion;
    let from_tree = target
        .apply("anonymous", &anonymous, &motion, &[], Default::default(), 1)
        .unwrap()
        .motion;
    let worst = from_names
        .data
        .iter()
        .zip(&from_tree.data)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-3,
        "{worst}\n{}\n{}",
        Map::guess(&skeleton, &target.skeleton).show(&skeleton, &target.skeleton),
        Map::guess(&anonymous, &target.skeleton).show(&anonymous, &target.skeleton)
    );
}

/// A JSON map with a key given twice kept the last silently (TOML refuses it), and
/// `--map A=b --map A=` ignored the later "leave out".
#[test]
fn a_key_given_twice_is_refused_and_a_later_leave_out_wins() {
    let text = "{\n  \"Hips\": \"pelvis\",\n  \"Spine\": \"spine1\",\n  \"Hips\": \"spine2\"\n}\n";
    let error = retarget::parse_map(text, "m.json").unwrap_err().to_string();
    assert!(error.starts_with("m.json:4:"), "{error}");
    assert!(error.contains("\"Hips\" is given twice"), "{error}");

    let (skeleton, _) = take(&common::repo_data("bvh/assimp_01_01.bvh"));
    let name = skeleton.joints[1].name.clone();
    let other = skeleton.joints[2].name.clone();
    let mut map = Map::guess(&skeleton, &skeleton);
    let pairs = [(name.clone(), other.clone()), (name.clone(), String::new())];
    map.apply(&pairs, &skeleton, &skeleton).unwrap();
    assert!(
        !map.source_of.contains(&Some(1)),
        "{name} is still mapped: {:?}",
        map.source_of
    );
}

/// A key given twice inside the `"skeleton"` section (a fingerprint, or a
/// joint under one) kept the last silently; a map of 95,000 keys took 11 s to check (each key
/// against every one before it); a JSON map after a byte-order mark was called "not a TOML
/// map"; a key of 10 MB was echoed whole.
#[test]
fn a_json_map_refuses_every_key_given_twice_and_reads_after_a_byte_order_mark() {
    let cases = [
        (
            "{\"skeleton\": {\"abc\": {\n  \"Hips\": \"pelvis\",\n  \"Hips\": \"spine1\"}}}",
            "m.json:3:8: not a JSON map: \"Hips\" is given twice",
        ),
        (
            "{\"skeleton\": {\n\"abc\": {},\n\"abc\": {\"Hips\": \"pelvis\"}}}",
            "m.json:3:5: not a JSON map: \"abc\" is given twice",
        ),
    ];
    for (text, said) in cases {
        let error = retarget::parse_map_pairs(text, "m.json").unwrap_err();
        assert_eq!(error.to_string(), said);
    }
    // 95,000 keys, the last a repeat of the second: refused where it is.
    let mut many: String = (0..95_000)
        .map(|i| format!("\"k{i:06}\": \"x\",\n"))
        .collect();
    many = format!("{{\n{many}\"k000001\": \"y\"}}");
    let error = retarget::parse_map_pairs(&many, "m.json").unwrap_err();
    assert_eq!(
        error.to_string(),
        "m.json:95002:9: not a JSON map: \"k000001\" is given twice"
    );
    // A byte-order mark first: read as the map it is.
    let pairs =
        retarget::parse_map_pairs("\u{feff}{\"Hips\": \"pelvis\", \"Spine\": null}", "m.json")
            .unwrap();
    assert_eq!(
        pairs.all,
        [
            ("Hips".to_string(), "pelvis".to_string()),
            ("Spine".to_string(), String::new())
        ]
    );
    let pairs = retarget::parse_map_pairs("\u{feff}\"Hips\" = \"pelvis\"\n", "m.toml").unwrap();
    assert_eq!(pairs.all, [("Hips".to_string(), "pelvis".to_string())]);
    // A 10 MB key is echoed cut, with its length.
    let long = "K".repeat(10_000_000);
    let text = format!("{{\"{long}\": 3}}");
    let error = retarget::parse_map_pairs(&text, "m.json").unwrap_err();
    assert_eq!(
        error.to_string(),
        format!(
            "m.json:1:1: \"{}\"… (10000000 bytes): expected a target joint's name, found a number",
            "K".repeat(64)
        )
    );
    let (skeleton, _) = take(&common::repo_data("bvh/assimp_01_01.bvh"));
    let mut map = Map::guess(&skeleton, &skeleton);
    let error = map
        .apply(&[(long, String::new())], &skeleton, &skeleton)
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with(&format!(
            "map: the source has no joint named \"{}\"… (10000000 bytes) (it has",
            "K".repeat(64)
        )),
        "{}",
        &error[..200.min(error.len())]
    );
    assert!(error.len() < 1000, "{} bytes", error.len());
}

/// A map file that is not UTF-8 gets its line and column.
#[test]
fn a_map_file_that_is_not_utf8_is_refused_at_its_line_and_column() {
    let temp = tempfile::tempdir().unwrap();
    let map = temp.path().join("bad.toml");
    std::fs::write(&map, b"\"Hips\" = \"pelvis\"\n\"Sp\xffine\" = \"spine1\"\n").unwrap();
    let out = crate::common::bvhview_command()
        .arg("retarget")
        .arg(common::repo_data("bvh/assimp_01_01.bvh"))
        .args(["--onto", "smpl22", "--show-map", "--map"])
        .arg(&map)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("bad.toml:2:4: not UTF-8 text"), "{stderr}");
}
