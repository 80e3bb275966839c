//! `convert` writes BVH that loads back to the same skeleton and the same values.

use crate::common;
use common::*;

#[test]
fn every_repository_file_round_trips_exactly() {
    check_round_trips(&repo_data("bvh"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_file_round_trips_exactly() {
    check_round_trips(&shared_data("bvh"));
}

fn check_round_trips(folder: &std::path::Path) {
    for path in files_in(folder, "bvh") {
        let original = bvhview::bvh::load_file(&path, Default::default()).unwrap();
        let text = bvhview::bvh::writer::to_string(&original.skeleton, &original.motion).unwrap();
        let again = bvhview::bvh::load_bytes(text.as_bytes(), "written.bvh")
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(again.skeleton, original.skeleton, "{}", path.display());
        assert_eq!(again.motion.frame_count(), original.motion.frame_count());
        assert_eq!(again.motion.frame_time, original.motion.frame_time);
        // Bit for bit, so -0 stays -0.
        let bits = |m: &bvhview::Motion| m.data.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert!(
            bits(&again.motion) == bits(&original.motion),
            "{}",
            path.display()
        );
        assert!(again.warnings.is_empty());
    }
}

#[test]
fn convert_command_writes_a_loadable_file() {
    let out = crate::common::scratch_folder("convert").join("convert.bvh");
    let input = data("bvh/opencollar_run.bvh");
    let status = crate::common::bvhview_command()
        .args(["convert"])
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let written = bvhview::bvh::load_file(&out, Default::default()).unwrap();
    let original = bvhview::bvh::load_file(&input, Default::default()).unwrap();
    assert_eq!(written.skeleton, original.skeleton);
    assert_eq!(written.motion, original.motion);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(!text.contains('\r'), "the writer uses LF");
    std::fs::remove_file(out).unwrap();
}

#[test]
fn convert_writes_names_with_blanks_safe_and_says_so() {
    let text = std::fs::read_to_string(edge("article_base_crlf.bvh"))
        .unwrap()
        .replace("JOINT Chest", "JOINT Upper Chest");
    let dir = crate::common::scratch_folder("temp");
    let input = dir.join(format!("bvhview-blank-{}.bvh", std::process::id()));
    let out = dir.join(format!("bvhview-blank-out-{}.bvh", std::process::id()));
    std::fs::write(&input, text).unwrap();
    let result = crate::common::bvhview_command()
        .arg("convert")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success());
    assert_eq!(
        String::from_utf8(result.stderr).unwrap(),
        format!(
            "bvhview: {}: joint \"Upper Chest\" written as \"Upper_Chest\" (a BVH name holds no \
             whitespace or braces)\nbvhview: wrote {}: 2 joints, 2 frames\n",
            out.display(),
            out.display()
        )
    );
    let written = bvhview::bvh::load_file(&out, Default::default()).unwrap();
    assert_eq!(written.skeleton.joints[1].name, "Upper_Chest");
    std::fs::remove_file(input).unwrap();
    std::fs::remove_file(out).unwrap();
}

/// `convert --frames --fps --scale`: trimmed, resampled (every second frame of a doubled rate is
/// an original frame, to float precision), scaled; world positions scale with it.
#[test]
fn convert_edits_trim_resample_and_scale() {
    let dir = crate::common::scratch_folder("temp");
    let out = dir.join(format!("bvhview-edits-{}.bvh", std::process::id()));
    let input = data("bvh/bvh11_131_01.bvh");
    let status = crate::common::bvhview_command()
        .arg("convert")
        .arg(&input)
        .args([
            "--frames", "10..20", "--fps", "240", "--scale", "2", "-q", "-o",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let original = bvhview::bvh::load_file(&input, Default::default()).unwrap();
    let edited = bvhview::bvh::load_file(&out, Default::default()).unwrap();
    std::fs::remove_file(&out).unwrap();
    // Ten frames at 120 span 9/120 s: 19 frames at 240.
    assert_eq!(edited.motion.frame_count(), 19);
    assert_eq!(edited.motion.frame_time, 1.0 / 240.0);
    let mode = bvhview::model::pose::OffsetMode::Replace;
    for k in 0..10 {
        let want = bvhview::model::pose::world_positions(
            &original.skeleton,
            original.motion.frame(10 + k),
            mode,
        );
        let got = bvhview::model::pose::world_positions(
            &edited.skeleton,
            edited.motion.frame(2 * k),
            mode,
        );
        for (w, g) in want.iter().zip(&got) {
            assert!((*w * 2.0).distance(*g) < 1e-3, "frame {k}: {w} vs {g}");
        }
    }
}

/// `convert --out-up y --mirror --in-place --ground` on MakeHuman's Z-up walk: the result is guessed
/// Y-up, stands where the viewer stood the original, is its mirror image, does not travel, and
/// its lowest point over the take is at 0.
#[test]
fn convert_edits_up_mirror_in_place_and_ground() {
    let out = crate::common::scratch_folder("edits2").join("edits2.bvh");
    let input = data("bvh/makehuman_walk1.bvh");
    let run = |extra: &[&str]| {
        let status = crate::common::bvhview_command()
            .arg("convert")
            .arg(&input)
            .args(extra)
            .args(["-q", "-o"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        let loaded = bvhview::bvh::load_file(&out, Default::default()).unwrap();
        std::fs::remove_file(&out).unwrap();
        loaded
    };
    let original = bvhview::bvh::load_file(&input, Default::default()).unwrap();
    let mode = bvhview::model::pose::OffsetMode::Replace;
    let upright = run(&["--out-up", "y"]);
    assert_eq!(
        bvhview::model::pose::Up::guess(&upright.skeleton),
        bvhview::model::pose::Up::Y
    );
    let stand = bvhview::model::pose::Up::Z.to_y_up();
    for frame in [0, 7, 13] {
        let before = bvhview::model::pose::world_positions(
            &original.skeleton,
            original.motion.frame(frame),
            mode,
        );
        let after = bvhview::model::pose::world_positions(
            &upright.skeleton,
            upright.motion.frame(frame),
            mode,
        );
        for (b, a) in before.iter().zip(&after) {
            assert!((stand * *b).abs_diff_eq(*a, 1e-4), "frame {frame}: {b} {a}");
        }
    }
    let edited = run(&["--out-up", "y", "--mirror", "--in-place", "--ground"]);
    let mut lowest = f32::MAX;
    let mut roots = Vec::new();
    for frame in 0..edited.motion.frame_count() {
        let points = bvhview::model::pose::world_positions(
            &edited.skeleton,
            edited.motion.frame(frame),
            mode,
        );
        lowest = points.iter().fold(lowest, |l, p| l.min(p.y));
        roots.push((points[0].x, points[0].z));
    }
    assert!(lowest.abs() < 1e-4, "lowest {lowest}");
    assert!(roots.iter().all(|&r| r == roots[0]), "{roots:?}");
    let names: Vec<&str> = edited
        .skeleton
        .joints
        .iter()
        .map(|j| j.name.as_str())
        .collect();
    let original_names: Vec<&str> = original
        .skeleton
        .joints
        .iter()
        .map(|j| j.name.as_str())
        .collect();
    // `--mirror` swaps the sides' motion and keeps every name; `--mirror-rename` exchanges the
    // names instead.
    assert_eq!(names, original_names);
    let renamed = run(&["--out-up", "y", "--mirror-rename"]);
    let left = original_names
        .iter()
        .position(|n| {
            n.contains(".L") || n.contains("_L") || n.contains("Left") || n.ends_with("_l")
        })
        .expect("a left joint");
    assert_ne!(
        renamed.skeleton.joints[left].name, original_names[left],
        "sides exchanged: {}",
        original_names[left]
    );
}
