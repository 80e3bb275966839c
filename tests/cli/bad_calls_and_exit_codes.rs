//! Every kind of bad call gets one line on stderr and its documented exit code: 2 for bad input,
//! 1 for everything else.

use crate::common;
use common::*;
use std::process::{Command, Output};

/// Runs as an unprivileged user when the tests run as root (root may read and write anything).
fn bvhview_unprivileged(args: &[&str]) -> Output {
    let root = Command::new("id")
        .arg("-u")
        .output()
        .map(|o| o.stdout == b"0\n")
        .unwrap_or(false);
    let mut command = if root {
        // A copy in a world-readable folder: the checkout may sit where that user cannot enter.
        // Copied once, before any test runs it (a binary still being written cannot be run).
        static BINARY: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
        let binary = BINARY.get_or_init(|| {
            let binary = scratch("bvhview");
            std::fs::copy(env!("CARGO_BIN_EXE_bvhview"), &binary).unwrap();
            Command::new("chmod")
                .args(["755", binary.to_str().unwrap()])
                .status()
                .unwrap();
            binary
        });
        let mut c = Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(binary);
        c
    } else {
        crate::common::bvhview_command()
    };
    command.args(args);
    // Another test thread forking while the copy was open for writing keeps that descriptor
    // in its child for a moment; running the copy then fails with ETXTBSY. Try again.
    for _ in 0..50 {
        let out = command.output().unwrap();
        if !String::from_utf8_lossy(&out.stderr).contains("Text file busy") {
            return out;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    command.output().unwrap()
}

fn one_line(out: &Output, code: i32, want: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("bvhview: "), "{stderr}");
    assert!(stderr.contains(want), "{stderr} lacks {want}");
    assert!(
        !stderr.contains("panicked") && !stderr.contains(".rs:"),
        "{stderr}"
    );
}

fn tiny() -> String {
    oracle("inputs/tiny_crlf.bvh").display().to_string()
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = crate::common::scratch_folder("errors");
    std::fs::create_dir_all(&dir).unwrap();
    // Readable and enterable by the unprivileged user.
    let _ = Command::new("chmod")
        .args(["755", dir.to_str().unwrap()])
        .status();
    dir.join(name)
}

#[test]
fn a_missing_file_is_bad_input() {
    one_line(
        &bvhview(&["info", "/no/such/take.bvh"]),
        2,
        "/no/such/take.bvh: no such file",
    );
    let amc = format!("{}", repo_data("asf_amc/nope.amc").display());
    let asf = data("asf_amc/heiden_12.asf").display().to_string();
    one_line(
        &bvhview(&["info", &asf, "--motion", &amc]),
        2,
        "nope.amc: no such file",
    );
}

#[test]
fn a_folder_where_a_file_is_needed_is_bad_input() {
    let folder = data("bvh").display().to_string();
    for command in ["print", "positions", "trace"] {
        one_line(
            &bvhview(&[command, folder.as_str()]),
            2,
            "is a folder, not a file",
        );
    }
    // `convert` takes a folder (tests/cli/convert_folder.rs), with the format its takes go in.
    one_line(
        &bvhview(&["convert", folder.as_str(), "-o", "/tmp/x.bvh"]),
        2,
        "is a folder: say the format its takes are written in with --to bvh, glb, gltf or fbx",
    );
}

#[test]
fn an_unknown_extension_is_bad_input() {
    one_line(
        &bvhview(&["info", &data("SOURCES.md").display().to_string()]),
        2,
        "unknown extension 'md'",
    );
}

#[test]
fn a_file_without_read_permission_is_an_other_failure() {
    let path = scratch("secret.bvh");
    std::fs::copy(tiny(), &path).unwrap();
    Command::new("chmod")
        .args(["000", path.to_str().unwrap()])
        .status()
        .unwrap();
    one_line(
        &bvhview_unprivileged(&["info", path.to_str().unwrap()]),
        1,
        "permission denied (cannot read it)",
    );
    std::fs::remove_file(path).unwrap();
}

#[test]
fn an_unwritable_output_is_an_other_failure() {
    let folder = scratch("locked");
    std::fs::create_dir_all(&folder).unwrap();
    Command::new("chmod")
        .args(["555", folder.to_str().unwrap()])
        .status()
        .unwrap();
    // An input the unprivileged user can read, wherever the checkout is.
    let input = scratch("input.bvh");
    std::fs::copy(tiny(), &input).unwrap();
    Command::new("chmod")
        .args(["644", input.to_str().unwrap()])
        .status()
        .unwrap();
    let input = input.display().to_string();
    let output = folder.join("out.bvh");
    let out = bvhview_unprivileged(&["convert", &input, "-o", output.to_str().unwrap()]);
    one_line(&out, 1, "cannot write");
    assert!(String::from_utf8_lossy(&out.stderr).contains("permission denied"));
    let png = folder.join("out.png");
    one_line(
        &bvhview_unprivileged(&[
            "snapshot",
            &input,
            "--size",
            "8x8",
            "-o",
            png.to_str().unwrap(),
        ]),
        1,
        "permission denied",
    );
}

#[test]
fn an_output_folder_that_does_not_exist_is_an_other_failure() {
    for args in [
        vec!["convert", "TINY", "-o", "/no/such/folder/out.bvh"],
        vec!["positions", "TINY", "-o", "/no/such/folder/out.csv"],
        vec![
            "snapshot",
            "TINY",
            "--size",
            "8x8",
            "-o",
            "/no/such/folder/out.png",
        ],
    ] {
        let tiny = tiny();
        let args: Vec<&str> = args
            .iter()
            .map(|a| if *a == "TINY" { tiny.as_str() } else { a })
            .collect();
        one_line(
            &bvhview(&args),
            1,
            "the folder /no/such/folder does not exist",
        );
    }
}

#[test]
fn a_file_larger_than_max_size_is_refused_before_reading() {
    one_line(
        &bvhview(&["info", &tiny(), "--max-size", "1K"]),
        2,
        "1826 bytes, more than --max-size 1024",
    );
    assert!(
        bvhview(&["info", &tiny(), "--max-size", "2K"])
            .status
            .success()
    );
}

/// A path with no size up front (here a link to /proc/self/smaps, a regular file that says it
/// holds 0 bytes and holds many thousands) is read only up to `--max-size`, for every format. A
/// device (/dev/zero, endless) is refused by its type before any read.
#[test]
fn max_size_bounds_what_is_read_from_any_path() {
    let dir = scratch("endless");
    std::fs::create_dir_all(&dir).unwrap();
    // A BVH stops at its first word, before the limit, quoting none of it.
    for (name, want) in [
        (
            "smaps.bvh",
            "smaps.bvh:1:1: expected HIERARCHY, found other text",
        ),
        ("smaps.asf", "smaps.asf: more than --max-size 1024 bytes"),
    ] {
        let link = dir.join(name);
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/proc/self/smaps", &link).unwrap();
        let out = bvhview(&["info", link.to_str().unwrap(), "--max-size", "1K"]);
        one_line(&out, 2, want);
    }
    let amc = dir.join("smaps.amc");
    let _ = std::fs::remove_file(&amc);
    std::os::unix::fs::symlink("/proc/self/smaps", &amc).unwrap();
    let asf = data("asf_amc/heiden_12.asf").display().to_string();
    let out = bvhview(&[
        "info",
        &asf,
        "--motion",
        amc.to_str().unwrap(),
        "--max-size",
        "8K",
    ]);
    one_line(&out, 2, "smaps.amc: more than --max-size 8192 bytes");
    let zero = dir.join("zero.bvh");
    let _ = std::fs::remove_file(&zero);
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let out = bvhview(&["info", zero.to_str().unwrap()]);
    one_line(&out, 2, "zero.bvh: a character device, not a regular file");
    std::fs::remove_dir_all(dir).unwrap();
}

/// What a newcomer's first mistakes get: one line each, in one style, exit code 2.
#[test]
fn first_mistakes_get_one_clear_line() {
    let file = tiny();
    for (args, want) in [
        (
            vec!["positions", file.as_str(), "--frames", "1..1"],
            "--frames 1..1: no frames: A..B leaves B out (for frame A alone, give A or A..=A)",
        ),
        (
            vec!["info", file.as_str(), "--frame-time", "-1"],
            "--frame-time -1: expected seconds per frame, from 1e-6 to 3600",
        ),
        (
            vec!["snapshto", file.as_str()],
            "'snapshto' is neither a file nor a command; did you mean `bvhview snapshot`?",
        ),
        (
            vec!["snapshot", file.as_str(), "-o", "out.jpg"],
            "-o out.jpg: this command writes .png",
        ),
        (
            vec!["positions", file.as_str(), "-o", "out.txt"],
            "-o out.txt: this command writes .csv or .json",
        ),
        (
            vec![
                "snapshot",
                file.as_str(),
                "--frames",
                "0..2",
                "-o",
                "out.txt",
            ],
            "-o out.txt: --frames writes an animated .gif, .apng or .png, an .mp4 video, or one PNG per frame",
        ),
        (
            vec!["info", "--bogus"],
            "unexpected argument '--bogus' found",
        ),
    ] {
        let out = bvhview(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.starts_with("bvhview: "), "{args:?}: {stderr}");
        assert!(stderr.contains(want), "{args:?}: {stderr}");
        assert!(!stderr.contains("error:"), "{args:?}: {stderr}");
    }
}

/// Every write ends with one line saying what was written; -q silences it.
#[test]
fn writes_say_what_they_wrote_unless_quiet() {
    let out_path = scratch("said.png");
    let path = out_path.to_str().unwrap();
    let out = bvhview(&["snapshot", &tiny(), "--size", "64x48", "-o", path]);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!("bvhview: wrote {path} (64x48)\n")
    );
    let quiet = bvhview(&["snapshot", &tiny(), "--size", "64x48", "-q", "-o", path]);
    assert!(quiet.status.success() && quiet.stderr.is_empty());
    std::fs::remove_file(out_path).unwrap();
}

/// `--character -` said "-: no such file": a character is read from a file, and says so.
#[test]
fn a_character_from_standard_input_is_refused_with_what_to_give() {
    let out = scratch("stdin_character.png");
    one_line(
        &bvhview(&[
            "snapshot",
            &tiny(),
            "--character",
            "-",
            "-o",
            out.to_str().unwrap(),
        ]),
        2,
        "--character -: a character is read from a file, not standard input",
    );
    assert!(!out.exists());
}

/// FBX out takes a character: `--character` to .fbx writes its mesh, a character file converted
/// to FBX keeps its own; the viewer's generated skin stays glTF's, and a BVH has no mesh.
#[cfg(feature = "fbx")]
#[test]
fn convert_to_fbx_writes_a_characters_mesh_and_refuses_the_generated_skin() {
    let folder = common::scratch_folder("fbx_character");
    let kenney = data("characters/maya_kenney_character_7700_binary.fbx");
    let copy = folder.join("copy.fbx");
    let out = bvhview(&[
        "convert".as_ref(),
        kenney.as_os_str(),
        "-o".as_ref(),
        copy.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let back = bvhview::character::Character::open(&copy).unwrap();
    assert_eq!(back.mesh.vertex_count(), 804);
    assert_eq!(back.take.frame_count(), 21);
    let walk = data("bvh/bvh11_131_01.bvh");
    let capsule = data("characters/capsule_mixamo.fbx");
    let dressed = folder.join("walk.fbx");
    let out = bvhview(&[
        "convert".as_ref(),
        walk.as_os_str(),
        "--frames".as_ref(),
        "0..10".as_ref(),
        "--character".as_ref(),
        capsule.as_os_str(),
        "-o".as_ref(),
        dressed.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let back = bvhview::character::Character::open(&dressed).unwrap();
    assert_eq!(
        (back.mesh.vertex_count(), back.take.frame_count()),
        (2904, 10)
    );
    let refused = folder.join("skin.fbx");
    one_line(
        &bvhview(&[
            "convert".as_ref(),
            walk.as_os_str(),
            "--skin".as_ref(),
            "-o".as_ref(),
            refused.as_os_str(),
        ]),
        2,
        "--skin needs a glTF output (.glb or .gltf): FBX out writes a character's own mesh",
    );
    let bvh = folder.join("walk.bvh");
    one_line(
        &bvhview(&[
            "convert".as_ref(),
            walk.as_os_str(),
            "--character".as_ref(),
            capsule.as_os_str(),
            "-o".as_ref(),
            bvh.as_os_str(),
        ]),
        2,
        "--character needs a glTF or FBX output (.glb, .gltf or .fbx); a BVH file has no mesh",
    );
    assert!(!refused.exists() && !bvh.exists());
    std::fs::remove_dir_all(&folder).unwrap();
}

/// A character file converted to FBX keeps its mesh and takes the edits that keep its rig
/// (frames, names, units); an edit that changes the rig writes the take without the mesh and
/// says so; a take piped in converts to FBX as before.
#[cfg(feature = "fbx")]
#[test]
fn a_character_file_to_fbx_takes_its_edits() {
    let folder = common::scratch_folder("own_character");
    let capsule = data("characters/capsule_mixamo.fbx").display().to_string();
    let cut = folder.join("cut.fbx");
    bvhview_stdout(&[
        "convert",
        &capsule,
        "--frames",
        "0..5",
        "--strip-prefix",
        "--out-units",
        "mm",
        "-o",
        cut.to_str().unwrap(),
    ]);
    let back = bvhview::character::Character::open(&cut).unwrap();
    assert_eq!(
        (back.take.frame_count(), back.mesh.vertex_count()),
        (5, 2904)
    );
    assert_eq!(back.take.skeleton.joints[0].name, "Hips");
    let scaled = folder.join("scaled.fbx");
    let out = bvhview(&[
        "convert",
        &capsule,
        "--scale",
        "2",
        "-o",
        scaled.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("its mesh is not written: the edits changed")
    );
    assert!(bvhview::character::Character::open(&scaled).is_err());
    let piped = folder.join("piped.fbx");
    let out = bvhview_command()
        .args([
            "convert",
            "-",
            "--from",
            "fbx",
            "-o",
            piped.to_str().unwrap(),
        ])
        .stdin(std::fs::File::open(data("fbx/bvh11_131_01.fbx")).unwrap())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// A folder named like a built-in skeleton does not hide it where a take is read (only a
/// regular file wins; `info DIR` still lists a folder it is given).
#[test]
fn a_folder_named_like_a_built_in_does_not_hide_it() {
    let folder = common::scratch_folder("built_in_folder");
    std::fs::create_dir(folder.join("smpl22")).unwrap();
    let out = bvhview_command()
        .args(["print", "smpl22"])
        .current_dir(&folder)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("pelvis : "));
    let walk = data("bvh/bvh11_131_01.bvh").display().to_string();
    let out = bvhview_command()
        .args(["retarget", &walk, "--onto", "smpl22", "-o", "r.bvh"])
        .current_dir(&folder)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    std::fs::remove_dir_all(&folder).unwrap();
}
