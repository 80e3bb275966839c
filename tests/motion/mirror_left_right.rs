//! `mirror` swaps the motion of left and right and keeps every name and the
//! skeleton's layout, on real takes of every naming family the repository holds: the mirrored
//! world positions are the counterparts' reflected, twice gives the take back bit for bit, and a
//! mirrored clip lands in its original's dataset group.

use crate::common;

use bvhview::edit::{MirrorOptions, lateral_axis, mirror, mirror_partners};
use bvhview::model::body::name_side;
use bvhview::model::pose::{OffsetMode, guessed_mode, world_positions};
use common::repo_data;
use std::path::Path;
use std::process::Command;

/// Repository takes: (file, motion, sided joints that must find their counterpart).
const TAKES: &[(&str, Option<&str>, usize)] = &[
    // CMU by cgspeed: LHipJoint, LThumb and Left…/Right….
    ("bvh/bvhparser_walk_01.bvh", None, 24),
    ("bvh/bvh11_131_01.bvh", None, 24),
    // CMU's ASF: lhipjoint, lfemur, ….
    (
        "asf_amc/heiden_12.asf",
        Some("asf_amc/heiden_12_02_01.amc"),
        24,
    ),
    // Mixamo (mixamorig:).
    ("bvh/bvhpython_test_freebvh.bvh", None, 48),
    // Rokoko (Mixamo's names, fingers).
    ("bvh/animateddrawings_rokoko_jesse_dance.bvh", None, 54),
    // Second Life (lThigh, rCollar), Bento (mHandThumb1Left, mFaceEar1Left).
    ("bvh/opencollar_run.bvh", None, 14),
    ("bvh/opencollar_cutie.bvh", None, 76),
    // MakeHuman (Clavicle_L, __Eye_R).
    ("bvh/makehuman_walk1.bvh", None, 62),
    // Biovision's example (LeftCollar).
    ("bvh/bvhio_example.bvh", None, 14),
];

fn load(file: &str, motion: Option<&str>) -> bvhview::take::Take {
    let motion = motion.map(repo_data);
    crate::common::load_take(&repo_data(file), motion.as_deref(), None).unwrap()
}

/// The mirror of one take: every joint whose name marks a side finds its counterpart (`sided`
/// of them when given), names, parents and channels are kept, every world position is its
/// counterpart's reflected (within 1e-5 of the figure's size) and twice gives the take back.
fn check(file: &str, take: &bvhview::take::Take, sided: Option<usize>) {
    let (skeleton, motion) = (&take.skeleton, &take.motion);
    let partners = mirror_partners(skeleton, &Default::default()).unwrap();
    // A sided name whose partner the skeleton lacks has nothing to pair with (PyAsfAmc's
    // `LeftCollar` is its chest, with no `RightCollar`).
    let has = |name: &str| skeleton.joints.iter().any(|j| j.name == name);
    let named = skeleton
        .joints
        .iter()
        .filter(|j| !j.end_site && name_side(&j.name).is_some_and(|(_, other)| has(&other)))
        .count();
    let paired = (0..partners.len())
        .filter(|&j| partners[j] != j && !skeleton.joints[j].end_site)
        .count();
    assert_eq!(named, paired, "{file}");
    if let Some(sided) = sided {
        assert_eq!(paired, sided, "{file}");
    }
    for (j, &k) in partners.iter().enumerate() {
        if k != j && !skeleton.joints[j].end_site {
            let (side, other) = name_side(&skeleton.joints[j].name).unwrap();
            assert_eq!(other, skeleton.joints[k].name, "{file}: {side:?}");
        }
    }

    let options = MirrorOptions::default();
    let (mirrored, mirrored_motion) = mirror(skeleton, motion, &options).unwrap();
    // Names, parents, channels (so rotation orders) and End Sites kept.
    assert_eq!(mirrored.joints.len(), skeleton.joints.len());
    for (a, b) in mirrored.joints.iter().zip(&skeleton.joints) {
        assert_eq!(
            (&a.name, a.parent, &a.channels, a.end_site, a.rotation_order),
            (&b.name, b.parent, &b.channels, b.end_site, b.rotation_order),
            "{file}"
        );
    }
    let axis = lateral_axis(skeleton, motion, &partners);
    let mode = guessed_mode(skeleton, motion, OffsetMode::Replace);
    let frames = motion.frame_count();
    let size = take.stance(mode).size;
    let mut worst = 0f32;
    for frame in (0..frames).step_by((frames / 50).max(1)) {
        let before = world_positions(skeleton, motion.frame(frame), mode);
        let after = world_positions(&mirrored, mirrored_motion.frame(frame), mode);
        for (j, a) in after.iter().enumerate() {
            let mut reflected = before[partners[j]];
            reflected[axis] = -reflected[axis];
            worst = worst.max(reflected.distance(*a));
        }
    }
    assert!(worst <= 1e-5 * size, "{file}: {worst} off, size {size}");

    let (again, back) = mirror(&mirrored, &mirrored_motion, &options).unwrap();
    assert_eq!(&again, skeleton, "{file}");
    assert_eq!(&back, motion, "{file}");
}

#[test]
fn mirrored_takes_are_their_counterparts_reflected_and_mirror_twice_gives_them_back() {
    for &(file, amc, sided) in TAKES {
        let take = load(file, amc);
        check(file, &take, Some(sided));
        // These takes face along z: the body's left and right lie along x.
        let partners = mirror_partners(&take.skeleton, &Default::default()).unwrap();
        assert_eq!(
            lateral_axis(&take.skeleton, &take.motion, &partners),
            0,
            "{file}"
        );
    }
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_take_of_the_corpus_mirrors() {
    for path in common::files_in(&common::shared_data("bvh"), "bvh") {
        let take = crate::common::load_take(&path, None, None).unwrap();
        check(&path.display().to_string(), &take, None);
    }
    let folder = common::shared_data("asf_amc");
    for amc in common::files_in(&folder, "amc") {
        let name = amc.file_name().unwrap().to_str().unwrap();
        let skeleton = &common::asf_of(&amc);
        let take = crate::common::load_take(skeleton, Some(&amc), None).unwrap();
        // CMU's 24 sided joints; PyAsfAmc's 14 (seven pairs).
        let sided = if name.starts_with("pyasfamc") { 14 } else { 24 };
        check(name, &take, Some(sided));
    }
}

/// `convert --mirror` writes a take whose clip lands in the original's dataset group (same
/// names, parents, channel orders); `--mirror-rename` renames instead (another group on a
/// skeleton whose left and right come in a fixed order).
#[test]
fn a_mirrored_clip_lands_in_its_originals_dataset_group() {
    let exe = env!("CARGO_BIN_EXE_bvhview");
    let temp = tempfile::tempdir().unwrap();
    let takes = temp.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    let original = repo_data("bvh/bvhparser_walk_01.bvh");
    std::fs::copy(&original, takes.join("walk.bvh")).unwrap();
    let convert = |flag: &str, out: &Path| {
        let run = Command::new(exe)
            .arg("convert")
            .arg(&original)
            .args([flag, "-q", "-o"])
            .arg(out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    };
    convert("--mirror", &takes.join("walk_mirrored.bvh"));
    let groups = |dir: &Path, name: &str| {
        let out = temp.path().join(name);
        let run = Command::new(exe)
            .arg("dataset")
            .arg(dir)
            .args(["-q", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let manifest = bvhview::dataset::read::read_manifest(&out).unwrap();
        assert_eq!(manifest.clips.len(), 2);
        manifest.groups.len()
    };
    assert_eq!(groups(&takes, "swapped.ds"), 1);

    // The mirrored file, loaded back, is the mirror image of the original (as written: six
    // decimals).
    let a = crate::common::load_take(&original, None, None).unwrap();
    let b = crate::common::load_take(&takes.join("walk_mirrored.bvh"), None, None).unwrap();
    let partners = mirror_partners(&a.skeleton, &Default::default()).unwrap();
    let mode = OffsetMode::Replace;
    for frame in [0, 100, 343] {
        let before = world_positions(&a.skeleton, a.motion.frame(frame), mode);
        let after = world_positions(&b.skeleton, b.motion.frame(frame), mode);
        for (j, p) in after.iter().enumerate() {
            let q = before[partners[j]];
            assert!(
                glam::Vec3::new(-q.x, q.y, q.z).distance(*p) < 1e-3,
                "{q} {p}"
            );
        }
    }

    let renamed = temp.path().join("renamed");
    std::fs::create_dir(&renamed).unwrap();
    std::fs::copy(&original, renamed.join("walk.bvh")).unwrap();
    convert("--mirror-rename", &renamed.join("walk_renamed.bvh"));
    assert_eq!(groups(&renamed, "renamed.ds"), 2);
}

/// `convert --mirror --mirror-names` reads counterparts as pairs or from a map file, whose
/// `[skeleton.FINGERPRINT]` sections apply to that skeleton only: thighs renamed so that no side
/// shows (`ThighA`, `ThighB`) swap when named, and a section for another skeleton, which names a
/// joint this one has not, is left aside.
#[test]
fn mirror_names_come_as_pairs_or_from_a_map_file_per_skeleton() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo_data("bvh/bvhio_example.bvh"))
        .unwrap()
        .replace("JOINT LeftUpLeg", "JOINT ThighA")
        .replace("JOINT RightUpLeg", "JOINT ThighB");
    let input = dir.path().join("renamed.bvh");
    std::fs::write(&input, &text).unwrap();
    let skeleton = crate::common::load_take(&input, None, None)
        .unwrap()
        .skeleton;
    let map = dir.path().join("sides.toml");
    std::fs::write(
        &map,
        format!(
            "[skeleton.000000000000]\n\"ThighA\" = \"Nowhere\"\n\n[skeleton.{}]\n\"ThighA\" = \"ThighB\"\n",
            skeleton.fingerprint()
        ),
    )
    .unwrap();
    let run = |extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let status = crate::common::bvhview_command()
            .arg("convert")
            .arg(&input)
            .arg("--mirror")
            .args(extra)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&status.stderr)
        );
        std::fs::read(out).unwrap()
    };
    let guessed = run(&[], "guessed.bvh");
    let paired = run(&["--mirror-names", "ThighA=ThighB"], "paired.bvh");
    let from_file = run(&["--mirror-names", map.to_str().unwrap()], "file.bvh");
    assert_eq!(paired, from_file);
    assert_ne!(paired, guessed);
    // The thighs swapped: the mirrored take's ThighA moves as ThighB did, reflected, so
    // mirroring twice with the same names gives the take back.
    let twice = {
        let once = dir.path().join("file.bvh");
        let out = dir.path().join("twice.bvh");
        let status = crate::common::bvhview_command()
            .args([
                "convert",
                once.to_str().unwrap(),
                "--mirror",
                "--mirror-names",
                "ThighA=ThighB",
                "-o",
            ])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        crate::common::load_take(&out, None, None).unwrap().motion
    };
    let original = crate::common::load_take(&input, None, None).unwrap().motion;
    for (a, b) in twice.data.iter().zip(&original.data) {
        assert!((a - b).abs() < 1e-3, "{a} {b}");
    }
}
