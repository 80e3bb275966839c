//! `bvhview convert DIR -o OUT --to FORMAT`: every take of the repository's corpus
//! (BVH, ASF/AMC, FBX, glTF/GLB, and the malformed files) converted at once. Each output is the
//! same bytes as `convert TAKE -o OUT/TAKE.FORMAT` alone writes and loads back with the same
//! positions; every take that fails alone is said as failing, with the same message, and the
//! others are written; the output folder follows `dataset -o`'s rules.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use crate::common;
use common::*;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Every file under `dir`, relative to it.
fn files_under(dir: &Path) -> BTreeSet<PathBuf> {
    let mut files = BTreeSet::new();
    for entry in walkdir::WalkDir::new(dir) {
        let entry = entry.unwrap();
        if entry.file_type().is_file() {
            files.insert(entry.path().strip_prefix(dir).unwrap().to_path_buf());
        }
    }
    files
}

/// The output a take gets: its path under the corpus with the format's extension; the two
/// takes of `gltf/` named `bvh11_131_01` (`.glb` and `.gltf`) keep theirs before it.
fn expected_name(relative: &Path, format: &str) -> PathBuf {
    let clashing = [
        "gltf/bvh11_131_01.glb",
        "gltf/bvh11_131_01.gltf",
        "characters/capsule_mixamo.fbx",
        "characters/capsule_mixamo.glb",
    ];
    match clashing.iter().any(|c| relative == Path::new(c)) {
        true => PathBuf::from(format!("{}.{format}", relative.display())),
        false => relative.with_extension(format),
    }
}

/// World positions of every point of every frame, as bits.
fn position_bits(path: &Path) -> Vec<u32> {
    let loaded = crate::common::load_take(path, None, None).unwrap_or_else(|e| panic!("{e}"));
    let mut bits = Vec::new();
    for f in 0..loaded.motion.frame_count() {
        let points = bvhview::model::pose::world_positions(
            &loaded.skeleton,
            loaded.motion.frame(f),
            Default::default(),
        );
        bits.extend(points.iter().flat_map(|p| p.to_array()).map(f32::to_bits));
    }
    bits
}

/// Converts the whole corpus to `format` with `extra` options, then every take alone with the
/// same options: the same takes fail with the same messages, and the others are written, each
/// the same bytes as alone, loading back with bit-identical positions.
fn folder_equals_takes_alone(format: &str, extra: &[&str]) {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let data = data.as_path();
    let temp = tempfile::tempdir().unwrap();
    let out = temp.path().join("out");
    let mut args: Vec<std::ffi::OsString> = vec!["convert".into(), data.into(), "-o".into()];
    args.extend([out.clone().into(), "--to".into(), format.into()]);
    args.extend(extra.iter().map(Into::into));
    let folder = bvhview(&args);
    let said = stderr(&folder);
    // The malformed files fail: exit 2, the others still written.
    assert_eq!(folder.status.code(), Some(2), "{said}");

    let takes = bvhview::info::batch::collect(data).unwrap().items;
    assert!(takes.len() > 60, "{} takes", takes.len());
    let mut written = BTreeSet::new();
    let mut failures = 0;
    for item in &takes {
        let take = item.motion.as_deref().unwrap_or(&item.path);
        let relative = take.strip_prefix(data).unwrap();
        let name = expected_name(relative, format);
        let single = temp.path().join("single").join(&name);
        std::fs::create_dir_all(single.parent().unwrap()).unwrap();
        let mut alone: Vec<std::ffi::OsString> = vec!["convert".into(), item.path.clone().into()];
        if let Some(amc) = &item.motion {
            alone.extend(["--motion".into(), amc.into()]);
        }
        alone.extend(["-o".into(), single.clone().into()]);
        alone.extend(extra.iter().map(Into::into));
        let alone = bvhview(&alone);
        if !alone.status.success() {
            // Said the same way: `bvhview: MESSAGE` alone, `failed MESSAGE` in the folder.
            assert_eq!(alone.status.code(), Some(2), "{}", stderr(&alone));
            let message = stderr(&alone)
                .lines()
                .find_map(|l| {
                    l.strip_prefix("bvhview: ")
                        .filter(|m| !m.contains("warning"))
                })
                .unwrap()
                .to_string();
            // A message that does not name the file (an edit's) is said after it.
            let named = format!("failed {}: {message}", take.display());
            assert!(
                said.lines()
                    .any(|l| l == format!("failed {message}") || l == named),
                "{message} not said in:\n{said}"
            );
            assert!(!out.join(&name).exists(), "{}", name.display());
            failures += 1;
            continue;
        }
        let converted = out.join(&name);
        let bytes = std::fs::read(&converted)
            .unwrap_or_else(|e| panic!("{}: {e}\n{said}", converted.display()));
        assert!(
            bytes == std::fs::read(&single).unwrap(),
            "{}: the folder's output differs from the take's alone",
            name.display()
        );
        assert_eq!(
            position_bits(&converted),
            position_bits(&single),
            "{}",
            name.display()
        );
        written.insert(name);
    }
    // Nothing else in the folder, and every failure counted once.
    assert_eq!(files_under(&out), written);
    assert_eq!(
        said.lines().filter(|l| l.starts_with("failed ")).count(),
        failures
    );
    assert!(failures >= 8, "the malformed files fail: {failures}");
    assert!(
        said.lines().any(|l| l
            == format!(
                "bvhview: wrote {}: {} takes as .{format}; {failures} failed, 0 skipped",
                out.display(),
                written.len()
            )),
        "{said}"
    );
}

#[test]
fn every_take_of_the_corpus_converts_to_bvh_as_it_converts_alone() {
    folder_equals_takes_alone("bvh", &[]);
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn every_take_of_the_corpus_converts_to_glb_with_edits_as_it_converts_alone() {
    folder_equals_takes_alone("glb", &["--fps", "24", "--out-up", "y"]);
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn every_take_of_the_corpus_converts_to_gltf_on_one_thread_as_alone() {
    folder_equals_takes_alone("gltf", &["--threads", "1", "--scale", "2", "--ground"]);
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// A folder of a multi-take FBX and a BVH: without `--take` the FBX gives its first take and
/// says it has several, as `convert FBX` alone does; `--take` picks the same take of every FBX
/// and glTF file, and BVH files, which hold one, convert as they are.
#[test]
fn a_multi_take_fbx_converts_its_first_take_or_the_one_take_picks() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    let fbx = dir.join("stack.fbx");
    std::fs::copy(
        data("fbx/ufbx/synthetic_anim_stack_no_props_7100_ascii.fbx"),
        &fbx,
    )
    .unwrap();
    std::fs::copy(data("bvh/bvhparser_simple.bvh"), dir.join("simple.bvh")).unwrap();
    for pick in [None, Some("1"), Some("2")] {
        let out = temp.path().join(format!("out{}", pick.unwrap_or("")));
        let mut args: Vec<std::ffi::OsString> = vec!["convert".into(), dir.clone().into()];
        args.extend(["-o".into(), out.clone().into(), "--to".into(), "bvh".into()]);
        if let Some(pick) = pick {
            args.extend(["--take".into(), pick.into()]);
        }
        let folder = bvhview(&args);
        let said = stderr(&folder);
        assert!(folder.status.success(), "{said}");
        assert_eq!(
            said.contains("warning: 3 takes; reading take 0 'X'"),
            pick.is_none(),
            "{said}"
        );
        let alone = temp.path().join("alone.bvh");
        let mut args: Vec<std::ffi::OsString> = vec!["convert".into(), fbx.clone().into()];
        args.extend(["-o".into(), alone.clone().into()]);
        if let Some(pick) = pick {
            args.extend(["--take".into(), pick.into()]);
        }
        assert!(bvhview(&args).status.success());
        assert!(std::fs::read(out.join("stack.bvh")).unwrap() == std::fs::read(&alone).unwrap());
        assert_eq!(
            position_bits(&out.join("simple.bvh")),
            position_bits(&dir.join("simple.bvh"))
        );
    }
    // The takes differ, so the picks did: take 1 is not take 0.
    assert!(
        std::fs::read(temp.path().join("out/stack.bvh")).unwrap()
            != std::fs::read(temp.path().join("out1/stack.bvh")).unwrap()
    );
    // A take no file has fails that file, with the loader's message.
    let out = temp.path().join("out9");
    let folder = bvhview(&[
        "convert".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--to".as_ref(),
        "bvh".as_ref(),
        "--take".as_ref(),
        "9".as_ref(),
    ]);
    let said = stderr(&folder);
    assert_eq!(folder.status.code(), Some(2), "{said}");
    assert!(
        said.contains(&format!("failed {}", fbx.display())),
        "{said}"
    );
    assert!(out.join("simple.bvh").is_file());
    assert!(!out.join("stack.bvh").exists());
}

/// A folder with an ASF and its AMC, an AMC alone in a subfolder and a take deeper down: the
/// pair converts by its AMC's name, the unpaired AMC is skipped, not failed.
#[test]
fn asf_amc_pairs_convert_by_the_amc_and_an_unpaired_amc_is_skipped() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(dir.join("sub/deeper")).unwrap();
    std::fs::copy(data("asf_amc/heiden_12.asf"), dir.join("heiden_12.asf")).unwrap();
    std::fs::copy(
        data("asf_amc/heiden_12_02_01.amc"),
        dir.join("heiden_12_02_01.amc"),
    )
    .unwrap();
    // Alone in its folder: no skeleton pairs with it.
    std::fs::copy(
        data("asf_amc/heiden_12_02_01.amc"),
        dir.join("sub/07_01.amc"),
    )
    .unwrap();
    std::fs::copy(
        data("bvh/bvhparser_simple.bvh"),
        dir.join("sub/deeper/s.bvh"),
    )
    .unwrap();
    let out = temp.path().join("out");
    let folder = bvhview(&[
        "convert".as_ref(),
        dir.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--to".as_ref(),
        "bvh".as_ref(),
    ]);
    let said = stderr(&folder);
    assert!(folder.status.success(), "{said}");
    assert!(
        said.contains(&format!(
            "skipped {}: motion without a skeleton (07.asf is not beside it)",
            dir.join("sub/07_01.amc").display()
        )),
        "{said}"
    );
    let files: Vec<PathBuf> = files_under(&out).into_iter().collect();
    assert_eq!(
        files,
        [
            PathBuf::from("heiden_12_02_01.bvh"),
            PathBuf::from("sub/deeper/s.bvh")
        ]
    );
    assert!(
        said.contains("2 takes as .bvh; 0 failed, 1 skipped"),
        "{said}"
    );
}

/// The output folder's rules are `dataset -o`'s: it must not exist or be empty; nothing is left
/// when no take converts; a missing or unwritable place says why; the options a folder cannot
/// take are refused before anything is read.
#[test]
fn the_output_folder_is_new_or_empty_and_left_whole_or_not_at_all() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("bvh/bvhparser_simple.bvh"), dir.join("a.bvh")).unwrap();
    let run = |out: &Path, extra: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec!["convert".into(), dir.clone().into()];
        args.extend(["-o".into(), out.into()]);
        args.extend(extra.iter().map(Into::into));
        bvhview(&args)
    };
    // An existing folder with anything in it is refused, and left as it was.
    let full = temp.path().join("full");
    std::fs::create_dir_all(&full).unwrap();
    std::fs::write(full.join("keep.txt"), "mine").unwrap();
    let refused = run(&full, &["--to", "bvh"]);
    assert_eq!(refused.status.code(), Some(2));
    assert_eq!(
        stderr(&refused),
        format!(
            "bvhview: {}: already exists; converted takes go into a new (or empty) folder\n",
            full.display()
        )
    );
    assert_eq!(
        files_under(&full),
        BTreeSet::from([PathBuf::from("keep.txt")])
    );
    // An empty folder is filled.
    let empty = temp.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert!(run(&empty, &["--to", "bvh", "-q"]).status.success());
    assert!(empty.join("a.bvh").is_file());
    // No format, a skin for BVH, a motion for a folder: refused, nothing made.
    let out = temp.path().join("out");
    for (extra, says) in [
        (
            &["-q"][..],
            "is a folder: say the format its takes are written in with --to",
        ),
        (&["--to", "bvh", "--skin"][..], "--skin needs a glTF output"),
        (
            &["--to", "bvh", "--motion", "x.amc"][..],
            "a folder pairs each AMC with its ASF itself",
        ),
    ] {
        let refused = run(&out, extra);
        assert_eq!(refused.status.code(), Some(2), "{extra:?}");
        assert!(stderr(&refused).contains(says), "{}", stderr(&refused));
        assert!(!out.exists());
    }
    // No take converts: exit 2, nothing written, no temporary folder left beside it.
    std::fs::write(dir.join("a.bvh"), "HIERARCHY\nROOT Hips\n{\n").unwrap();
    let failed = run(&out, &["--to", "glb"]);
    let said = stderr(&failed);
    assert_eq!(failed.status.code(), Some(2), "{said}");
    assert!(
        said.contains("no take could be converted (1 failed, 0 skipped), so nothing was written")
    );
    assert!(!out.exists());
    let left: Vec<_> = std::fs::read_dir(temp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // A place nothing can be made in says the real cause, exit 1.
    std::fs::copy(data("bvh/bvhparser_simple.bvh"), dir.join("a.bvh")).unwrap();
    let proc = run(Path::new("/proc/x"), &["--to", "bvh"]);
    assert_eq!(proc.status.code(), Some(1));
    assert!(
        stderr(&proc).contains("nothing can be created in /proc"),
        "{}",
        stderr(&proc)
    );
}

/// A link another user planted in a sticky shared folder (as in /tmp) on the way to OUT is not
/// followed, as for `dataset -o` and every file output. Only root can make another user's link.
#[test]
fn converted_takes_are_not_written_through_a_link_planted_in_a_shared_folder() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        eprintln!("not root: another user's link needs root to make");
        return;
    }
    use std::os::unix::fs::PermissionsExt;
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("bvh/bvhparser_simple.bvh"), dir.join("a.bvh")).unwrap();
    let shared = temp.path().join("shared");
    let victim = temp.path().join("victim");
    std::fs::create_dir_all(&shared).unwrap();
    std::fs::create_dir_all(&victim).unwrap();
    std::fs::set_permissions(&shared, std::fs::Permissions::from_mode(0o1777)).unwrap();
    let planted = shared.join("pl");
    std::os::unix::fs::symlink(&victim, &planted).unwrap();
    std::os::unix::fs::lchown(&planted, Some(1234), Some(1234)).unwrap();
    let out = planted.join("converted");
    let run = || {
        bvhview(&[
            "convert".as_ref(),
            dir.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--to".as_ref(),
            "bvh".as_ref(),
        ])
    };
    let refused = run();
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("a symbolic link another user (uid 1234) made"),
        "{}",
        stderr(&refused)
    );
    assert_eq!(std::fs::read_dir(&victim).unwrap().count(), 0);
    // The link is root's own: followed, as file outputs follow it.
    std::os::unix::fs::lchown(&planted, Some(0), Some(0)).unwrap();
    assert!(run().status.success());
    assert!(victim.join("converted/a.bvh").is_file());
}

/// `--to` names a folder's format; given for a file it must agree with `-o`'s extension.
#[test]
fn to_for_a_file_must_agree_with_its_extension() {
    let temp = tempfile::tempdir().unwrap();
    let take = data("bvh/bvhparser_simple.bvh");
    let out = temp.path().join("x.bvh");
    let refused = bvhview(&[
        "convert".as_ref(),
        take.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--to".as_ref(),
        "glb".as_ref(),
    ]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("--to glb: -o"),
        "{}",
        stderr(&refused)
    );
    assert!(!out.exists());
    let agreed = bvhview(&[
        "convert".as_ref(),
        take.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--to".as_ref(),
        "bvh".as_ref(),
    ]);
    assert!(agreed.status.success(), "{}", stderr(&agreed));
    assert!(crate::common::load_take(&out, None, None).is_ok());
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// SIGTERM while the takes are being written: the process ends by the signal (a shell says 143)
/// and leaves neither OUT nor its temporary folder, as `dataset` does.
#[test]
fn a_conversion_terminated_midway_leaves_nothing() {
    use std::os::unix::process::ExitStatusExt;
    let temp = tempfile::tempdir().unwrap();
    let out = temp.path().join("out");
    // The planted pause holds the conversion once its temporary folder exists, until the signal
    // comes (no test waits on the clock: a sleep would make the verdict depend on the
    // machine's speed).
    let mut child = crate::common::bvhview_command()
        .env("BVHVIEW_PLANT_PAUSE", "output")
        .arg("convert")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data"))
        .arg("-o")
        .arg(&out)
        .args(["--to", "gltf", "--threads", "1"])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let temporary = || {
        std::fs::read_dir(temp.path()).unwrap().any(|e| {
            e.unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with(".out.")
        })
    };
    let started = std::time::Instant::now();
    while !temporary() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "it ended before it began writing"
        );
        assert!(started.elapsed() < std::time::Duration::from_secs(60));
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    // SAFETY: signals our own child, which has not been waited for yet.
    unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGTERM) };
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(libc::SIGTERM), "{status}");
    let left: Vec<_> = std::fs::read_dir(temp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// A take named `..bvh` was written to `out/..` ("is a directory", exit 1, nothing
/// written for any take): `with_extension` turns `..bvh` into `..`.
#[test]
fn a_take_named_dot_dot_bvh_converts_beside_the_others() {
    let temp = tempfile::tempdir().unwrap();
    let takes = temp.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    std::fs::copy(&walk, takes.join("..bvh")).unwrap();
    std::fs::copy(&walk, takes.join("walk.bvh")).unwrap();
    let out = temp.path().join("out");
    for format in ["bvh", "glb"] {
        let _ = std::fs::remove_dir_all(&out);
        let run = bvhview(&[
            "convert".as_ref(),
            takes.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--to".as_ref(),
            std::ffi::OsStr::new(format),
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        let mut written: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        written.sort();
        assert_eq!(written, [format!("..{format}"), format!("walk.{format}")]);
    }
}
