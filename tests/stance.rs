//! Issue 27, point 1: the up axis and the units are guessed from the motion, and the guess
//! matches what each file's source says (or, where it says nothing, what was checked by hand once
//! from the figure: a person between 1.4 and 2 m tall in exactly one of the candidate units).

mod common;

use bvhview::pose::{OffsetMode, Up};
use common::{repo_data, shared_data};
use std::path::{Path, PathBuf};

/// Every take of the corpus (`bvh/…` or an ASF/AMC pair), its up axis and its units, with where
/// the answer comes from.
const EXPECTED: &[(&str, Option<&str>, Up, &str, &str)] = &[
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
    let loaded = bvhview::input::load(file, motion, None).unwrap();
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
    let walk = bvhview::input::default_motion().unwrap();
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
    let loaded = bvhview::input::load(&dir.join("rest_y_motion_z.bvh"), None, None).unwrap();
    assert_eq!(
        Up::guess(&loaded.skeleton),
        Up::Y,
        "the rest pose alone says y"
    );
    let stance = loaded.stance(OffsetMode::Replace);
    assert!((stance.height - 183.0).abs() < 1e-3, "{}", stance.height);
}

/// `convert --up/--scale` writes files that read back as written (issue 27 row 3), and `info`
/// prints the guess with how sure it is.
#[test]
fn converted_takes_read_back_as_written() {
    let exe = env!("CARGO_BIN_EXE_bvhview");
    let dir = std::env::temp_dir().join(format!("bvhview-stance-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    for (edits, up, units) in [
        (&["--up", "z"][..], "z", "centimetres"),
        (&["--scale", "0.01"][..], "y", "metres"),
        (&["--scale", "10"][..], "y", "millimetres"),
        (&["--scale", "0.3937"][..], "y", "inches"),
        (&["--up", "z", "--scale", "0.1"][..], "z", "decimetres"),
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
