//! The up axis and the units are guessed from the motion, and the guess
//! matches what each file's source says (or, where it says nothing, what was checked by hand once
//! from the figure: a person between 1.4 and 2 m tall in exactly one of the candidate units).

use crate::common;

use bvhview::model::pose::{OffsetMode, Up};
use common::{repo_data, shared_data};
use std::path::{Path, PathBuf};

/// Every take of the corpus (`bvh/…` or an ASF/AMC pair), its up axis and its units, with where
/// the answer comes from.
const EXPECTED: &[(&str, Option<&str>, Up, &str, &str)] = &[
    (
        "bvh/pybvh_bvh_test1.bvh",
        None,
        Up::Z,
        "inches",
        "pybvh's test take: Z up, spine bones of 4.45 (11 cm), 1.64 m tall",
    ),
    (
        "bvh/alinen_samba_dancing.bvh",
        None,
        Up::Y,
        "centimetres",
        "Mixamo export (Y up, cm)",
    ),
    (
        "bvh/alinen_t-pose.bvh",
        None,
        Up::Y,
        "centimetres",
        "Mixamo export (Y up, cm)",
    ),
    (
        "bvh/animateddrawings_rokoko_jesse_dance.bvh",
        None,
        Up::Y,
        "centimetres",
        "Rokoko Studio export (Y up, cm); its rest pose lies across y",
    ),
    (
        "bvh/assimp_01_01.bvh",
        None,
        Up::Y,
        "CMU units (1/0.45 inch)",
        "CMU subject 01 by cgspeed: the ASF's lengths",
    ),
    (
        "bvh/assimp_Boxing_Toes.bvh",
        None,
        Up::Y,
        "centimetres",
        "by hand: 1.63 m in cm",
    ),
    (
        "bvh/bandai_dataset-1_dance-short_normal_001.bvh",
        None,
        Up::Y,
        "centimetres",
        "Bandai-Namco dataset (Y up, cm)",
    ),
    (
        "bvh/bandai_dataset-2_wave-left-hand_active_011.bvh",
        None,
        Up::Y,
        "centimetres",
        "Bandai-Namco dataset (Y up, cm)",
    ),
    (
        "bvh/bvh11_131_01.bvh",
        None,
        Up::Y,
        "CMU units (1/0.45 inch)",
        "CMU subject 131 by cgspeed",
    ),
    (
        "bvh/bvhanim_test_simple.bvh",
        None,
        Up::Z,
        "decimetres",
        "a 3-joint test chain along z, 30 long: no unit said; its nearest",
    ),
    (
        "bvh/bvhio_example.bvh",
        None,
        Up::Y,
        "inches",
        "the Biovision example figure, 72 inches",
    ),
    (
        "bvh/bvhparser_example.bvh",
        None,
        Up::Y,
        "inches",
        "the Biovision example figure, 72 inches",
    ),
    (
        "bvh/bvhparser_simple.bvh",
        None,
        Up::Y,
        "inches",
        "that figure cut down; its rest pose stands 47 along y",
    ),
    (
        "bvh/bvhparser_walk_01.bvh",
        None,
        Up::Y,
        "CMU units (1/0.45 inch)",
        "CMU 01 walk by cgspeed",
    ),
    (
        "bvh/bvhpython_test_freebvh.bvh",
        None,
        Up::Y,
        "centimetres",
        "Mixamo export (mixamorig, Y up, cm)",
    ),
    (
        "bvh/bvhpython_test_mocapbank.bvh",
        None,
        Up::Y,
        "centimetres",
        "MocapBank export (Y up, cm)",
    ),
    (
        "bvh/deepmotionediting_blender_example.bvh",
        None,
        Up::Y,
        "CMU units (1/0.45 inch)",
        "a CMU take by cgspeed",
    ),
    (
        "bvh/deepmotionediting_xia_neutral_01_000.bvh",
        None,
        Up::Y,
        "CMU units (1/0.45 inch)",
        "Xia's takes on CMU's skeleton",
    ),
    (
        "bvh/makehuman_dance1.bvh",
        None,
        Up::Z,
        "decimetres",
        "MakeHuman's units are decimetres; Z up",
    ),
    (
        "bvh/makehuman_face-poseunits.bvh",
        None,
        Up::Z,
        "decimetres",
        "MakeHuman, decimetres, Z up",
    ),
    (
        "bvh/makehuman_tpose.bvh",
        None,
        Up::Z,
        "decimetres",
        "MakeHuman, decimetres, Z up (written for the add mode)",
    ),
    (
        "bvh/makehuman_walk1.bvh",
        None,
        Up::Z,
        "decimetres",
        "MakeHuman, decimetres, Z up",
    ),
    (
        "bvh/opencollar_cutie.bvh",
        None,
        Up::Y,
        "inches",
        "Second Life animation: Y up, inches",
    ),
    (
        "bvh/opencollar_oc_stand_boy01.bvh",
        None,
        Up::Y,
        "inches",
        "Second Life animation: Y up, inches",
    ),
    (
        "bvh/opencollar_run.bvh",
        None,
        Up::Y,
        "inches",
        "Second Life animation: Y up, inches",
    ),
    (
        "bvh/pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh",
        None,
        Up::Y,
        "inches",
        "by hand: 58 units tall, a person only in inches",
    ),
    (
        "bvh/usdbvhanim_test_bvh.bvh",
        None,
        Up::Z,
        "metres",
        "USD's 2-joint test rig, one unit along z",
    ),
    (
        "asf_amc/heiden_12.asf",
        Some("asf_amc/heiden_12_02_01.amc"),
        Up::Y,
        "CMU units (1/0.45 inch)",
        "its ASF: length 0.45",
    ),
    (
        "asf_amc/pyasfamc_test.asf",
        Some("asf_amc/pyasfamc_test.amc"),
        Up::Y,
        "millimetres",
        "PyAsfAmc's test pair: not CMU's, `:units length 1.0`, bones in millimetres",
    ),
    (
        "asf_amc/simchoni_charleston.asf",
        Some("asf_amc/simchoni_charleston_1.amc"),
        Up::Y,
        "CMU units (1/0.45 inch)",
        "its ASF: length 0.45",
    ),
    (
        "asf_amc/simchoni_charleston.asf",
        Some("asf_amc/simchoni_charleston_2.amc"),
        Up::Y,
        "CMU units (1/0.45 inch)",
        "its ASF: length 0.45",
    ),
    (
        "asf_amc/simchoni_lambada.asf",
        Some("asf_amc/simchoni_lambada_1.amc"),
        Up::Y,
        "CMU units (1/0.45 inch)",
        "its ASF: length 0.45",
    ),
    (
        "asf_amc/simchoni_pirouette.asf",
        Some("asf_amc/simchoni_pirouette_1.amc"),
        Up::Y,
        "CMU units (1/0.45 inch)",
        "its ASF: length 0.45",
    ),
];

fn check(file: &Path, motion: Option<&Path>, up: Up, units: &str, source: &str) {
    let loaded = crate::common::load_take(file, motion, None).unwrap();
    let stance = loaded.stance(OffsetMode::Replace);
    assert_eq!(
        (stance.up, stance.units.name),
        (up, units),
        "{} ({source}): guessed {} / {}",
        file.display(),
        stance.up_text(),
        stance.units_text()
    );
}

/// Every entry whose files are under `root`; fails if an entry is missing there while `all`.
fn check_all(root: &dyn Fn(&str) -> PathBuf, all: bool) -> usize {
    let mut checked = 0;
    for &(file, motion, up, units, source) in EXPECTED {
        let path = root(file);
        let motion = motion.map(root);
        if !path.exists() || motion.as_ref().is_some_and(|m| !m.exists()) {
            assert!(
                !all,
                "{} is in the table but not in the corpus",
                path.display()
            );
            continue;
        }
        check(&path, motion.as_deref(), up, units, source);
        checked += 1;
    }
    checked
}

#[test]
fn the_repository_takes_read_right() {
    let checked = check_all(&|f| repo_data(f), false);
    assert!(checked >= 18, "only {checked} repository takes checked");
    // The bundled walk: made by examples/make_walk.rs in centimetres, Y up.
    let walk = bvhview::Take::bundled().unwrap();
    let stance = walk.stance(OffsetMode::Replace);
    assert_eq!((stance.up, stance.units.name), (Up::Y, "centimetres"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn the_whole_corpus_reads_right_and_every_take_has_a_row() {
    assert_eq!(check_all(&|f| shared_data(f), true), EXPECTED.len());
    // A take added to the corpus needs its row here.
    let listed: Vec<&str> = EXPECTED.iter().map(|e| e.1.unwrap_or(e.0)).collect();
    for folder in ["bvh", "asf_amc"] {
        let ext = if folder == "bvh" { "bvh" } else { "amc" };
        for path in common::files_in(&shared_data(folder), ext) {
            let name = format!("{folder}/{}", path.file_name().unwrap().to_str().unwrap());
            assert!(
                listed.contains(&name.as_str()),
                "{name} has no row in EXPECTED"
            );
        }
    }
}

/// Rest poses that mislead (tests/stance/README.md): the old guess from the rest pose read the
/// first as "inches, 36 tall" and the second as Y up.
#[test]
fn rest_poses_that_mislead_read_right_from_the_motion() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/stance");
    check(
        &dir.join("rest_along_x.bvh"),
        None,
        Up::Y,
        "centimetres",
        "hand-written",
    );
    check(
        &dir.join("rest_y_motion_z.bvh"),
        None,
        Up::Z,
        "centimetres",
        "hand-written",
    );
    let loaded = crate::common::load_take(&dir.join("rest_y_motion_z.bvh"), None, None).unwrap();
    assert_eq!(
        Up::guess(&loaded.skeleton),
        Up::Y,
        "the rest pose alone says y"
    );
    let stance = loaded.stance(OffsetMode::Replace);
    assert!((stance.height - 183.0).abs() < 1e-3, "{}", stance.height);
}

/// `convert --out-up/--scale` writes files that read back as written, and `info`
/// prints the guess with how sure it is.
#[test]
fn converted_takes_read_back_as_written() {
    let exe = env!("CARGO_BIN_EXE_bvhview");
    let dir = crate::common::scratch_folder("stance");
    std::fs::create_dir_all(&dir).unwrap();
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    for (edits, up, units) in [
        (&["--out-up", "z"][..], "z", "centimetres"),
        (&["--scale", "0.01"][..], "y", "metres"),
        (&["--scale", "10"][..], "y", "millimetres"),
        (&["--scale", "0.3937"][..], "y", "inches"),
        (&["--out-up", "z", "--scale", "0.1"][..], "z", "decimetres"),
    ] {
        let out = dir.join("converted.bvh");
        let status = std::process::Command::new(exe)
            .arg("convert")
            .arg(&walk)
            .args(edits)
            .args(["-q", "-o"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        let info = std::process::Command::new(exe)
            .arg("info")
            .arg(&out)
            .output()
            .unwrap();
        let text = String::from_utf8(info.stdout).unwrap();
        let line = |key: &str| {
            text.lines()
                .find(|l| l.starts_with(key))
                .unwrap_or_else(|| panic!("no {key} in {text}"))
                .to_string()
        };
        let up_line = line("up axis:");
        assert!(
            up_line.contains(&format!(" {up} (sure: ")),
            "{edits:?}: {up_line}"
        );
        let units_line = line("units:");
        assert!(
            units_line.contains(&format!(" {units} (sure: ")),
            "{edits:?}: {units_line}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `take` written as a BVH file in `dir`, and what `bvhview info` says of it.
fn info_of(dir: &Path, name: &str, take: &bvhview::take::Take) -> String {
    let path = dir.join(name);
    let mut bytes = Vec::new();
    bvhview::bvh::writer::write_bvh(&mut bytes, &take.skeleton, &take.motion).unwrap();
    std::fs::write(&path, bytes).unwrap();
    let info = crate::common::bvhview_command()
        .arg("info")
        .arg(&path)
        .output()
        .unwrap();
    assert!(info.status.success());
    String::from_utf8(info.stdout).unwrap()
}

/// MakeHuman's take with its non-root position channels set by `value(joint, axis)`.
fn makehuman_with(value: &dyn Fn(usize, usize) -> f32) -> bvhview::take::Take {
    let mut take =
        crate::common::load_take(&repo_data("bvh/makehuman_tpose.bvh"), None, None).unwrap();
    let width = take.motion.channels;
    for (j, joint) in take.skeleton.joints.iter().enumerate() {
        if joint.parent.is_none() {
            continue;
        }
        for (i, channel) in joint.channels.iter().enumerate() {
            if channel.is_position() {
                for row in take.motion.data.chunks_mut(width) {
                    row[joint.first_channel + i] = value(j, channel.axis());
                }
            }
        }
    }
    take
}

/// MakeHuman takes whose non-root position channels are tiny but not zero (up to 7e-4
/// against OFFSETs of about 0.33) are written for `--offset-mode add`; read in replace mode
/// their bones collapse ("stands 2.08 tall, 0.208 m").
#[test]
fn tiny_non_root_position_channels_are_read_in_add_mode() {
    // Deltas of 1e-4 to 7e-4, either sign, never 0.
    let tiny = |j: usize, axis: usize| {
        let k = (j * 3 + axis) % 13;
        let magnitude = 1e-4 + 5e-5 * k as f32;
        if (j + axis).is_multiple_of(2) {
            magnitude
        } else {
            -magnitude
        }
    };
    let take = makehuman_with(&tiny);
    let (skeleton, motion) = (&take.skeleton, &take.motion);
    let (matching, candidates) =
        bvhview::model::pose::written_for_other_mode(skeleton, motion, OffsetMode::Replace)
            .expect("looks written for add");
    assert_eq!((matching, candidates), (143, 143));
    assert_eq!(
        bvhview::model::pose::guessed_mode(skeleton, motion, OffsetMode::Replace),
        OffsetMode::Add
    );
    let stance = take.stance(OffsetMode::Replace);
    assert_eq!(stance.mode, OffsetMode::Add);
    assert_eq!(stance.units.name, "decimetres");
    let metres = stance.height * stance.units.metres;
    assert!((1.6..1.75).contains(&metres), "{metres}");

    let dir = tempfile::tempdir().unwrap();
    let text = info_of(dir.path(), "tiny.bvh", &take);
    assert!(
        text.contains("units:            decimetres (sure:"),
        "{text}"
    );
    assert!(
        text.contains("looks written for `--offset-mode add`"),
        "{text}"
    );
    assert!(!text.contains("human-like"), "{text}");

    // A file written for replace (channels within 3% of the OFFSETs) stays in replace, and is
    // said to look so under `--offset-mode add`.
    let offsets: Vec<glam::Vec3> = take.skeleton.joints.iter().map(|j| j.offset).collect();
    let near =
        |j: usize, axis: usize| offsets[j][axis] * if j.is_multiple_of(2) { 1.03 } else { 0.97 };
    let replace = makehuman_with(&near);
    let (skeleton, motion) = (&replace.skeleton, &replace.motion);
    assert_eq!(
        bvhview::model::pose::written_for_other_mode(skeleton, motion, OffsetMode::Replace),
        None
    );
    assert!(
        bvhview::model::pose::written_for_other_mode(skeleton, motion, OffsetMode::Add).is_some()
    );
    // Channels a fifth of the OFFSETs long look written for neither.
    let fifth = |j: usize, axis: usize| offsets[j][axis] * 0.2;
    let neither = makehuman_with(&fifth);
    for mode in [OffsetMode::Replace, OffsetMode::Add] {
        let found =
            bvhview::model::pose::written_for_other_mode(&neither.skeleton, &neither.motion, mode);
        assert_eq!(found, None, "{mode:?}");
    }
}

/// `info` warns when a human-like skeleton is under 0.5 m or over 2.5 m in the units
/// guessed for it (a 0.25 m or 3.9 m "human"), and not for a person's size nor for a skeleton
/// that is not a person's.
#[test]
fn info_warns_of_humans_under_half_a_metre_or_over_two_and_a_half() {
    let dir = tempfile::tempdir().unwrap();
    let walk = bvhview::Take::bundled().unwrap();
    let size = walk.stance(OffsetMode::Replace).size;
    let text = info_of(dir.path(), "walk.bvh", &walk);
    assert!(text.contains("warnings:         none"), "{text}");
    for (metres, what) in [
        (0.25, "under the 0.5 m"),
        (3.9, "over the 2.5 m"),
        (0.45, "under the 0.5 m"),
    ] {
        let (skeleton, motion) =
            bvhview::edit::scale(&walk.skeleton, &walk.motion, metres / size).unwrap();
        let scaled = bvhview::take::Take {
            skeleton,
            motion,
            ..walk.clone()
        };
        let stance = scaled.stance(OffsetMode::Replace);
        assert_eq!(stance.units.name, "metres", "{metres}");
        let text = info_of(dir.path(), "scaled.bvh", &scaled);
        let line = text
            .lines()
            .find(|l| l.contains("human-like skeleton"))
            .unwrap_or_else(|| panic!("{metres} m: no warning in {text}"));
        assert!(line.contains(what), "{line}");
        assert!(line.contains(&format!("spans {metres:.3} m")), "{line}");
    }
    // Within a person's size: none.
    for metres in [0.6, 1.2, 2.3] {
        let (skeleton, motion) =
            bvhview::edit::scale(&walk.skeleton, &walk.motion, metres / size).unwrap();
        let scaled = bvhview::take::Take {
            skeleton,
            motion,
            ..walk.clone()
        };
        let warnings = bvhview::info::warnings(&scaled, OffsetMode::Replace);
        assert!(warnings.is_empty(), "{metres}: {warnings:?}");
    }
    // Not a person: a two-joint take 3 m tall says nothing of it.
    let simple =
        crate::common::load_take(&repo_data("bvh/bvhanim_test_simple.bvh"), None, None).unwrap();
    assert_eq!(bvhview::info::human_like(&simple.skeleton), None);
    let stance = simple.stance(OffsetMode::Replace);
    assert_eq!(bvhview::info::size_warning(&simple.skeleton, &stance), None);
}

/// Every person of the repository's takes is human-like, by the names of every family.
#[test]
fn the_repository_people_are_human_like() {
    for file in [
        "bvh/animateddrawings_rokoko_jesse_dance.bvh",
        "bvh/assimp_01_01.bvh",
        "bvh/bvh11_131_01.bvh",
        "bvh/bvhio_example.bvh",
        "bvh/bvhparser_simple.bvh",
        "bvh/bvhparser_walk_01.bvh",
        "bvh/bvhpython_test_freebvh.bvh",
        "bvh/bvhpython_test_mocapbank.bvh",
        "bvh/makehuman_dance1.bvh",
        "bvh/makehuman_tpose.bvh",
        "bvh/makehuman_walk1.bvh",
        "bvh/opencollar_cutie.bvh",
        "bvh/opencollar_run.bvh",
        "bvh/opencollar_oc_stand_boy01.bvh",
    ] {
        let take = crate::common::load_take(&repo_data(file), None, None).unwrap();
        let found = bvhview::info::human_like(&take.skeleton);
        assert!(found.is_some(), "{file}");
        let stance = take.stance(OffsetMode::Replace);
        assert_eq!(
            bvhview::info::size_warning(&take.skeleton, &stance),
            None,
            "{file}"
        );
    }
    let asf = crate::common::load_take(
        &repo_data("asf_amc/heiden_12.asf"),
        Some(&repo_data("asf_amc/heiden_12_02_01.amc")),
        None,
    )
    .unwrap();
    assert!(bvhview::info::human_like(&asf.skeleton).is_some());
    let usd =
        crate::common::load_take(&repo_data("bvh/usdbvhanim_test_bvh.bvh"), None, None).unwrap();
    assert_eq!(bvhview::info::human_like(&usd.skeleton), None);
}
