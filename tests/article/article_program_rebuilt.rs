//! The article's own program, built from its text, on BVH files bvhview converted from FBX
//! ("the article's patched loader where it can": FBX takes the article reads through a BVH).
//!
//! `bench/article.py --patched --print` rebuilds the article's `BVH.cpp` from
//! `../shared/seeds/000_*.txt` with its loader made robust to whitespace, line endings and number
//! widths (the loader that made `tests/oracle`; each patch is listed in the script) and
//! TEACHING.md Part 7's printing stub and driver, which print the tree as `init` does or the GL
//! calls `draw` makes for one frame. The first test shows the rebuilt program is the oracle's:
//! it prints every file of `tests/oracle/print` byte for byte, three of which the unpatched
//! loader cannot read. The second converts every FBX take of `tests/data/fbx` to BVH with
//! `bvhview convert` and, where the article's program can read the file at all (its layout:
//! six channels on the root, positions first; three rotations on every other joint; at most 16
//! children; a joint besides the root), compares what it prints and draws with `bvhview print`
//! and `bvhview trace`, byte for byte, as Part 7 compares them.

use crate::common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const NEEDS: &str = "needs ../shared/seeds (the article's text), python3 and g++; scripts/test.sh \
                     runs it when ../shared is there";

/// The rebuilt program (`article_print`), built once per test run into a temporary folder.
fn article() -> &'static Path {
    static BUILT: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, program) = BUILT.get_or_init(|| {
        let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/seeds");
        let seed = std::fs::read_dir(&seeds)
            .unwrap_or_else(|e| panic!("{}: {e} ({NEEDS})", seeds.display()))
            .map(|e| e.unwrap().path())
            .find(|p| p.file_name().unwrap().to_string_lossy().starts_with("000_"))
            .unwrap_or_else(|| panic!("no 000_*.txt in {}", seeds.display()));
        let out = tempfile::tempdir().unwrap();
        let built = Command::new("python3")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("bench/article.py"))
            .arg(&seed)
            .arg(out.path())
            .args(["--patched", "--print"])
            .output()
            .unwrap_or_else(|e| panic!("python3: {e} ({NEEDS})"));
        assert!(
            built.status.success(),
            "building the article's program: {}",
            String::from_utf8_lossy(&built.stderr)
        );
        let program = PathBuf::from(String::from_utf8(built.stdout).unwrap().trim());
        (out, program)
    });
    program
}

/// What the rebuilt program prints: the tree, or (`frame`) that frame's draw calls.
fn article_output(file: &Path, frame: Option<usize>) -> String {
    let mut command = Command::new(article());
    command.arg(file);
    if let Some(frame) = frame {
        command.arg(frame.to_string());
    }
    let out = command.output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{}: {text}", file.display());
    text
}

/// `bvhview trace FILE --frame N` without `display`'s camera (its first four lines) and floor
/// (its last six): the calls `draw` makes, as Part 7's `sed '1,4d' | head -n -6` keeps them.
fn bvhview_draw(file: &Path, frame: usize) -> String {
    let frame = frame.to_string();
    let trace = bvhview_stdout(&[
        "trace".as_ref(),
        file.as_os_str(),
        "--frame".as_ref(),
        frame.as_ref(),
    ]);
    let lines: Vec<&str> = trace.lines().collect();
    assert!(lines.len() > 10, "{trace}");
    lines[4..lines.len() - 6]
        .iter()
        .map(|l| format!("{l}\n"))
        .collect()
}

#[test]
#[ignore = "needs ../shared/seeds (the article's text), python3 and g++; scripts/test.sh runs it when ../shared is there"]
fn the_patched_program_prints_what_the_oracle_printed() {
    for expected in files_in(&oracle("print"), "txt") {
        let name = expected.file_stem().unwrap().to_str().unwrap();
        let mut input = oracle("inputs").join(format!("{name}.bvh"));
        if !input.exists() {
            input = data(&format!("bvh/{name}.bvh"));
        }
        assert!(
            article_output(&input, None) == std::fs::read_to_string(&expected).unwrap(),
            "{name}: the rebuilt program prints otherwise than the oracle's"
        );
    }
    // And it draws what bvhview traces, as Part 7 shows for the unpatched program.
    let tiny = oracle("inputs/tiny_crlf.bvh");
    for frame in 0..3 {
        assert_eq!(
            article_output(&tiny, Some(frame)),
            bvhview_draw(&tiny, frame)
        );
    }
}

/// Whether the article's loader can read a BVH of this skeleton: the root first in the file with
/// `Xposition Yposition Zposition` then three rotations (it reads the root's first three values
/// as its position and finds its rotations by their `r`), three rotation channels on every other
/// joint (a row is `jointCount * 3 + 3` values), no more than 16 children (`CHILDSIZE`) and at
/// least one `JOINT` (`loadFile` refuses a root alone).
fn the_article_can_read(skeleton: &bvhview::Skeleton) -> bool {
    use bvhview::model::skeleton::Channel;
    let position_first = [Channel::Xposition, Channel::Yposition, Channel::Zposition];
    let root = &skeleton.joints[0];
    let roots = skeleton
        .joints
        .iter()
        .filter(|j| j.parent.is_none())
        .count();
    let joints = skeleton.joints.iter().filter(|j| !j.end_site).count();
    roots == 1
        && joints > 1
        && root.channels.len() == 6
        && root.channels[..3] == position_first
        && rotations_only(&root.channels[3..])
        && skeleton.joints[1..]
            .iter()
            .filter(|j| !j.end_site)
            .all(|j| j.channels.len() == 3 && rotations_only(&j.channels))
        && skeleton.joints.iter().all(|j| j.children.len() <= 16)
}

/// Whether every channel is a rotation.
fn rotations_only(channels: &[bvhview::model::skeleton::Channel]) -> bool {
    channels.iter().all(|c| !c.is_position())
}

#[test]
#[ignore = "needs ../shared/seeds (the article's text), python3 and g++; scripts/test.sh runs it when ../shared is there"]
fn the_article_reads_bvh_converted_from_fbx_as_bvhview_does() {
    let temp = tempfile::tempdir().unwrap();
    let mut fbx_files: Vec<PathBuf> = walkdir::WalkDir::new(data("fbx"))
        .sort_by_file_name()
        .into_iter()
        .map(|e| e.unwrap().into_path())
        .filter(|p| p.extension().is_some_and(|e| e == "fbx"))
        .collect();
    fbx_files.sort();
    let mut compared = Vec::new();
    for fbx in &fbx_files {
        let name = fbx.file_stem().unwrap().to_string_lossy().into_owned();
        let bvh = temp.path().join(format!("{name}.bvh"));
        let converted = crate::common::bvhview_command()
            .arg("convert")
            .arg(fbx)
            .arg("-o")
            .arg(&bvh)
            .output()
            .unwrap();
        if !converted.status.success() {
            // A file with no skeleton (tests/formats/fbx_gltf_reading.rs pins which): nothing to read.
            continue;
        }
        let loaded = crate::common::load_take(&bvh, None, None).unwrap();
        if !the_article_can_read(&loaded.skeleton) {
            continue;
        }
        assert!(
            article_output(&bvh, None) == bvhview_stdout(&["print".as_ref(), bvh.as_os_str()]),
            "{name}: the article's tree differs from `bvhview print`"
        );
        let frames = loaded.motion.frame_count();
        // Every frame of the three takes Blender made from repository BVH files; the first,
        // middle and last of ufbx's samples (up to 250 frames each).
        let picked: Vec<usize> = match fbx.parent() == Some(data("fbx").as_path()) {
            true => (0..frames).collect(),
            false => vec![0, frames / 2, frames - 1],
        };
        for frame in picked {
            assert!(
                article_output(&bvh, Some(frame)) == bvhview_draw(&bvh, frame),
                "{name}, frame {frame}: the article draws otherwise than `bvhview trace`"
            );
        }
        compared.push(name);
    }
    // Where it can: the takes whose skeleton has the article's layout. The others have position
    // channels below the root (ufbx's rotation-order and pivot samples) or a root alone.
    assert_eq!(
        compared,
        [
            "animateddrawings_rokoko_jesse_dance",
            "bvh11_131_01",
            "bvhpython_test_freebvh",
            "blender_279_bone_radius_6100_ascii",
            "blender_279_bone_radius_7400_binary",
            "maya_bone_radius_6100_ascii",
            "maya_bone_radius_7500_ascii",
            "maya_character_7500_binary",
            // Its helpers are folded into the character's bones.
            "maya_human_ik_7400_binary",
        ]
    );
}
