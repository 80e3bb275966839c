//! Every human family onto every family: each take of the corpus that reads as a two-legged body
//! with two arms is put on every other family's skeleton (and SMPL's), and every result's own
//! check ([`bvhview::retarget::Check`]) must hold: no side crossed, no width collapsed. Not a
//! chosen list: a take added to tests/data or ../shared/data joins on its own. The table it
//! prints is GUIDE's ("Retargeting onto every family").

use crate::common;
use bvhview::Take;
use bvhview::model::body::{Body, Doubt, Limb};
use bvhview::model::pose::OffsetMode;
use bvhview::retarget::{Insist, Target};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Frames of each source put on every target: enough to move, few enough for 900 pairs.
const FRAMES: usize = 90;

/// Every take under `root`: BVH files, ASF/AMC pairs, and FBX and glTF takes.
fn takes_under(root: &Path) -> Vec<(PathBuf, Option<PathBuf>)> {
    let mut found = Vec::new();
    for entry in walkdir::WalkDir::new(root).sort_by_file_name() {
        let path = entry.unwrap().into_path();
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let malformed = path.components().any(|c| c.as_os_str() == "bvh_malformed");
        match extension {
            "bvh" | "fbx" | "glb" | "gltf" if !malformed => found.push((path, None)),
            "amc" => found.push((common::asf_of(&path), Some(path))),
            _ => {}
        }
    }
    found
}

/// Two legs and two arms, standing: a person.
fn human(take: &Take) -> bool {
    let body = Body::of(&take.skeleton);
    let limbs = [Limb::Thigh, Limb::Shin, Limb::UpperArm, Limb::ForeArm];
    let whole = (0..2).all(|side| {
        limbs
            .iter()
            .all(|&l| body.limbs[side][l as usize].is_some())
    });
    whole
        && body.hips.is_some()
        && !body
            .doubts(&take.skeleton, &take.motion, OffsetMode::Replace)
            .iter()
            .any(|d| matches!(d, Doubt::NotBiped(_) | Doubt::NoTwoLegs))
}

/// One take per skeleton family (its fingerprint), the first found; the short name it goes by.
fn families(roots: &[PathBuf]) -> Vec<(String, Take)> {
    let mut by_family: BTreeMap<String, (String, Take)> = BTreeMap::new();
    for root in roots {
        for (path, motion) in takes_under(root) {
            let Ok(take) = crate::common::load_take(&path, motion.as_deref(), None) else {
                continue;
            };
            if !human(&take) {
                continue;
            }
            let name = motion
                .as_deref()
                .unwrap_or(&path)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let frames = take.motion.frame_count().min(FRAMES);
            let take = if frames > 0 {
                take.trim(0..frames)
            } else {
                take
            };
            by_family
                .entry(take.skeleton.fingerprint())
                .or_insert((name, take));
        }
    }
    by_family.into_values().collect()
}

/// Each source onto each target: the checks that failed, and the table.
fn everyone_onto_everyone(roots: &[PathBuf]) -> (Vec<String>, String, usize) {
    let families = families(roots);
    let mut targets: Vec<(String, Target)> = families
        .iter()
        .map(|(name, take)| {
            (
                name.clone(),
                Target::new(name.clone(), take.skeleton.clone(), &take.motion),
            )
        })
        .collect();
    targets.push(("smpl22".into(), Target::load("smpl22", u64::MAX).unwrap()));
    let mut failures = Vec::new();
    let mut table = String::from(
        "| source | onto every family: held / refused by its map / failed |\n|---|---|\n",
    );
    let mut pairs = 0;
    for (source_name, source) in &families {
        let (mut held, mut refused, mut failed) = (0, 0, Vec::new());
        for (target_name, target) in &targets {
            // Forced, so that a refused output is counted here with its reason.
            let insist = Insist {
                force: true,
                ..Insist::default()
            };
            let put = target.apply(
                source_name,
                &source.skeleton,
                &source.motion,
                &[],
                insist,
                1,
            );
            let Ok(put) = put else {
                refused += 1;
                continue;
            };
            pairs += 1;
            match put.forced {
                None => held += 1,
                Some(why) => {
                    failed.push(target_name.clone());
                    failures.push(format!("{source_name} onto {target_name}: {why}"));
                }
            }
        }
        table.push_str(&format!(
            "| {source_name} | {held} / {refused} / {}{} |\n",
            failed.len(),
            if failed.is_empty() {
                String::new()
            } else {
                format!(" ({})", failed.join(", "))
            }
        ));
    }
    (failures, table, pairs)
}

#[test]
fn every_repository_family_onto_every_family_keeps_its_sides_and_widths() {
    let (failures, table, pairs) = everyone_onto_everyone(&[common::repo_data("")]);
    println!("{table}");
    assert!(pairs >= 100, "only {pairs} pairs retargeted");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_corpus_family_onto_every_family_keeps_its_sides_and_widths() {
    let (failures, table, pairs) =
        everyone_onto_everyone(&[common::repo_data(""), common::shared_data("")]);
    println!("{table}");
    assert!(pairs >= 200, "only {pairs} pairs retargeted");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A map that swaps the thighs crosses the sides at the hips: `retarget` says so and writes
/// nothing; `--force` writes it and says it did.
#[test]
fn a_crossed_retarget_is_refused_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("crossed.bvh");
    let run = |force: bool| {
        let mut command = crate::common::bvhview_command();
        command.args([
            "retarget",
            "tests/data/bvh/bvhparser_walk_01.bvh",
            "--onto",
            "smpl22",
            "--map",
            "LeftUpLeg=right_hip",
            "--map",
            "RightUpLeg=left_hip",
            "-o",
        ]);
        command.arg(&out);
        if force {
            command.arg("--force");
        }
        command.output().unwrap()
    };
    let refused = run(false);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with(
            "bvhview: tests/data/bvh/bvhparser_walk_01.bvh onto smpl22: not written: its hips' \
             sides are crossed (180° from the source's)"
        ),
        "{stderr}"
    );
    assert!(!out.exists());
    let forced = run(true);
    let stderr = String::from_utf8_lossy(&forced.stderr);
    assert!(forced.status.success(), "{stderr}");
    assert!(stderr.contains("warning: written as --force asks though its hips' sides are crossed"));
    assert!(out.is_file());
}

/// `dataset --onto` checks each clip as `retarget` does: a crossed take is skipped with the
/// reason, `--force` keeps it with a warning, and every clip's figures are in the manifest.
#[test]
fn a_dataset_records_each_clips_check_and_skips_a_crossed_take_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let takes = dir.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    std::fs::copy(
        "tests/data/bvh/bvhparser_walk_01.bvh",
        takes.join("walk.bvh"),
    )
    .unwrap();
    let run = |out: &str, extra: &[&str]| {
        let mut command = crate::common::bvhview_command();
        command
            .arg("dataset")
            .arg(&takes)
            .arg("-o")
            .arg(dir.path().join(out));
        command.args(["--onto", "smpl22"]).args(extra);
        command.output().unwrap()
    };
    let manifest = |out: &str| -> serde_json::Value {
        let text = std::fs::read_to_string(dir.path().join(out).join("manifest.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    let right = run("right", &[]);
    assert!(
        right.status.success(),
        "{}",
        String::from_utf8_lossy(&right.stderr)
    );
    let clip = &manifest("right")["clips"][0];
    let check = &clip["retarget_check"];
    assert!(check["hips"]["turn"].as_f64().unwrap() < 10.0, "{check}");
    assert!(check["bones_median"].as_f64().unwrap() < 5.0, "{check}");
    let swap = [
        "--map",
        "LeftUpLeg=right_hip",
        "--map",
        "RightUpLeg=left_hip",
    ];
    let refused = run("refused", &swap);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success(), "{stderr}");
    assert!(
        stderr.contains("onto smpl22: not written: its hips' sides are crossed"),
        "{stderr}"
    );
    let forced = run("forced", &[&swap[..], &["--force"]].concat());
    assert!(
        forced.status.success(),
        "{}",
        String::from_utf8_lossy(&forced.stderr)
    );
    let clip = &manifest("forced")["clips"][0];
    assert!(clip["retarget_check"]["hips"]["turn"].as_f64().unwrap() > 170.0);
    let warnings = clip["warnings"].to_string();
    assert!(
        warnings.contains("retarget: kept as `force` asks though its hips' sides are crossed"),
        "{warnings}"
    );
}

/// A take put on a character is checked as a retarget is, and the check is said.
#[test]
#[cfg(feature = "gltf")]
fn a_take_on_a_character_says_its_check() {
    let dir = tempfile::tempdir().unwrap();
    let out = crate::common::bvhview_command()
        .args([
            "positions",
            "tests/data/bvh/bvh11_131_01.bvh",
            "--character",
        ])
        .arg("tests/data/characters/capsule_mixamo.glb")
        .arg("-o")
        .arg(dir.path().join("on.csv"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "tests/data/bvh/bvh11_131_01.bvh onto tests/data/characters/capsule_mixamo.glb: \
             check: sides held; hips "
        ),
        "{stderr}"
    );
}
