//! Every help line says what the command does, options that only a
//! sequence gives a meaning to are refused without one, and counts read "1 frame", "2 frames".

use crate::common;
use common::*;
use std::path::PathBuf;
use std::process::Command;

fn help(args: &[&str]) -> String {
    let out = bvhview(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
    String::from_utf8(out.stdout).unwrap()
}

fn tiny() -> String {
    oracle("inputs/tiny_crlf.bvh").display().to_string()
}

fn scratch(name: &str) -> PathBuf {
    static FOLDER: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FOLDER
        .get_or_init(|| crate::common::scratch_folder("messages"))
        .join(name)
}

/// A usage error: exit 2, `bvhview: MESSAGE` and nothing more on stderr.
fn refused_with(args: &[&str], message: &str) {
    let out = bvhview(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {out:?}");
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!("bvhview: {message}\n"),
        "{args:?}"
    );
}

#[test]
fn snapshot_and_convert_help_name_every_format_they_write() {
    let top = help(&["--help"]);
    assert!(
        top.contains(
            "snapshot   Draw offscreen (no display needed): one frame as PNG, or with --frames a \
             sequence as an animated GIF or APNG, an MP4 video, or as one PNG per frame in a \
             folder\n"
        ),
        "{top}"
    );
    assert!(
        top.contains(
            "convert    Write a take (BVH, ASF + AMC, FBX or glTF) as BVH or glTF (.glb, .gltf), \
             trimmed, resampled, scaled, turned, mirrored, in place or grounded on the way if \
             asked\n"
        ),
        "{top}"
    );
    assert!(!top.contains("write it as PNG") && !top.contains("as BVH\n"));

    let snapshot = help(&["snapshot", "--help"]);
    assert!(
        snapshot.contains(
            "A sequence instead: N, A..B (B left out), A..=B, A.. or ..B, written as -o says: an \
             animated .gif, .apng or .png, an .mp4 video (H.264), or OUT/frame_NNNNN.png into a \
             folder\n"
        ),
        "{snapshot}"
    );
    assert!(
        snapshot.contains(
            "Frames per second of an animated output, with --frames (default: the file's rate, \
             at most 50 for GIF)\n"
        ),
        "{snapshot}"
    );
    let convert = help(&["convert", "--help"]);
    assert!(
        convert.contains(
            "Turn the take to stand along this axis from its own (as `info` reads it, or --up \
             says it): y or z fourth"
        ) && convert.contains("The axis the file stands along, over the guess, as `info --up`"),
        "{convert}"
    );
    // `help COMMAND` says the same as `COMMAND --help`.
    assert_eq!(help(&["help", "snapshot"]), snapshot);
}

#[test]
fn up_help_says_what_up_does_and_nothing_else() {
    let up = "The file's up axis (default: guessed from the motion in a framed or studio view, as \
              written in the article's view; `info` prints the guess)";
    for args in [
        &["--help"][..],
        &["snapshot", "--help"],
        &["trace", "--help"],
    ] {
        let text = help(args);
        assert!(text.contains(up), "{args:?}: {text}");
        assert!(!text.contains("O switches the offset mode"), "{args:?}");
    }
}

#[test]
fn an_animated_output_needs_frames_whatever_the_case_of_its_name() {
    let gif = scratch("one.gif");
    refused_with(
        &[
            "snapshot",
            &tiny(),
            "--frame",
            "1",
            "-o",
            gif.to_str().unwrap(),
        ],
        &format!(
            "-o {}: a GIF needs --frames A..B (one frame is written as .png)",
            gif.display()
        ),
    );
    let apng = scratch("one.APNG");
    refused_with(
        &["snapshot", &tiny(), "-o", apng.to_str().unwrap()],
        &format!(
            "-o {}: an APNG needs --frames A..B (one frame is written as .png)",
            apng.display()
        ),
    );
    assert!(!gif.exists() && !apng.exists());
}

#[test]
fn fps_without_an_animation_is_a_usage_error() {
    let png = scratch("fps.png");
    refused_with(
        &[
            "snapshot",
            &tiny(),
            "--fps",
            "10",
            "-o",
            png.to_str().unwrap(),
        ],
        "--fps needs --frames A..B: it is the rate of an animated .gif, .apng or .png, or an .mp4",
    );
    let folder = scratch("fps_folder");
    refused_with(
        &[
            "snapshot",
            &tiny(),
            "--frames",
            "0..2",
            "--fps",
            "10",
            "-o",
            folder.to_str().unwrap(),
        ],
        &format!(
            "--fps is the rate of an animation; -o {} is a folder of PNGs, which has none",
            folder.display()
        ),
    );
    assert!(!png.exists() && !folder.exists());
}

#[test]
fn counts_of_one_are_singular_in_every_message_that_writes_them() {
    let stderr_of = |args: &[&str]| {
        let out = bvhview(args);
        assert!(out.status.success(), "{args:?}: {out:?}");
        String::from_utf8(out.stderr).unwrap()
    };
    let gif = scratch("single.gif");
    assert_eq!(
        stderr_of(&[
            "snapshot",
            &tiny(),
            "--frames",
            "0",
            "--size",
            "32x32",
            "-o",
            gif.to_str().unwrap()
        ]),
        format!(
            "bvhview: wrote {}: 1 frame at 30.000 per second\n",
            gif.display()
        )
    );
    let folder = scratch("single_folder");
    assert_eq!(
        stderr_of(&[
            "snapshot",
            &tiny(),
            "--frames",
            "1",
            "--size",
            "32x32",
            "-o",
            folder.to_str().unwrap()
        ]),
        format!("bvhview: wrote 1 picture into {}\n", folder.display())
    );
    let csv = scratch("single.csv");
    let one_point = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 1 Xposition\n}\n\
                     MOTION\nFrames: 1\nFrame Time: 0.1\n0\n";
    let one_point_file = scratch("one_point.bvh");
    std::fs::write(&one_point_file, one_point).unwrap();
    let one_point_file = one_point_file.to_str().unwrap();
    assert_eq!(
        stderr_of(&["positions", one_point_file, "-o", csv.to_str().unwrap()]),
        format!("bvhview: wrote {}: 1 frame × 1 point\n", csv.display())
    );
    let bvh = scratch("single.bvh");
    assert_eq!(
        stderr_of(&["convert", one_point_file, "-o", bvh.to_str().unwrap()]),
        format!("bvhview: wrote {}: 1 joint, 1 frame\n", bvh.display())
    );
    let png = scratch("single_pixel.png");
    stderr_of(&[
        "snapshot",
        &tiny(),
        "--size",
        "1x1",
        "-q",
        "-o",
        png.to_str().unwrap(),
    ]);
    let png = png.to_str().unwrap();
    assert_eq!(
        String::from_utf8(bvhview(&["diff", png, png]).stdout).unwrap(),
        "0 of 1 pixel differ (0.000%)\n"
    );

    // `info FOLDER`: one joint, one frame, one file.
    let folder = scratch("single_take");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(one_point_file, folder.join("one.bvh")).unwrap();
    let out = bvhview(&["info", folder.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.starts_with(&format!(
            "ok     {}: 1 joint, 1 frame, 0.1 s\n1 file: 1 ok, 0 failed; ",
            folder.join("one.bvh").display()
        )),
        "{text}"
    );

    // Loader messages count values and frames the same way.
    assert!(
        error_text(
            "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 2 Xposition Yposition\n\
             \tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0\n"
        )
        .ends_with("frame 0 has 1 value, expected 2 (one per channel)"),
    );
    assert!(
        error_text(
            "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 1 Xposition\n\tEnd Site\n\t{\n\
             \t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n"
        )
        .contains("expected 1 frame as Frames: says (line 12), found 0: the file ends"),
    );
}

/// Every command that reads takes names every format it reads (FBX and glTF beside
/// BVH and ASF/AMC) in its `--help`, with examples after it, as ripgrep's and cargo's do.
#[test]
fn every_help_names_every_format_a_command_reads_with_examples() {
    for command in [
        "print",
        "info",
        "positions",
        "snapshot",
        "trace",
        "convert",
        "dataset",
        "retarget",
    ] {
        let text = help(&[command, "--help"]);
        for format in [".bvh", ".fbx", ".gltf", ".glb", ".asf"] {
            assert!(
                text.contains(format),
                "{command} --help lacks {format}:\n{text}"
            );
        }
        assert!(
            text.contains("Examples:\n  bvhview "),
            "{command} --help:\n{text}"
        );
    }
    let top = help(&["--help"]);
    for format in ["BVH", "ASF/AMC", "FBX", "glTF"] {
        assert!(top.contains(format), "--help lacks {format}:\n{top}");
    }
}

/// The man page and the completions are made from the clap command; bash loads the
/// completions and offers the commands for `bvhview re<TAB>`.
#[test]
fn the_man_page_and_completions_are_generated_from_the_command() {
    let man = help(&["generate", "man"]);
    assert!(
        man.starts_with(".ie \\n(.g .ds Aq") || man.contains(".TH bvhview"),
        "{man}"
    );
    for command in ["retarget", "dataset", "convert", "snapshot"] {
        assert!(man.contains(command), "the man page lacks {command}");
    }
    let fish = help(&["generate", "complete-fish"]);
    assert!(fish.contains("complete -c bvhview"), "{fish}");
    let zsh = help(&["generate", "complete-zsh"]);
    assert!(zsh.starts_with("#compdef bvhview"), "{zsh}");
    let bash = help(&["generate", "complete-bash"]);
    let script = format!(
        "{bash}\nCOMP_WORDS=(bvhview re); COMP_CWORD=1; COMP_LINE='bvhview re'; COMP_POINT=10\n\
         _bvhview bvhview re bvhview\nprintf '%s\\n' \"${{COMPREPLY[@]}}\"\n"
    );
    let out = Command::new("bash").arg("-c").arg(script).output().unwrap();
    let offered = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(offered.trim(), "retarget", "{offered}");
}
