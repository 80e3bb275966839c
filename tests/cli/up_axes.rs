//! `--up` with any signed axis, and `convert`'s two up options: `--up` says what the file is,
//! as every command's does, and `--out-up` turns the take.

use crate::common::*;
use std::path::Path;

/// Every joint of every frame of a `positions` CSV (`frame,joint,x,y,z`).
fn positions_csv(args: &[&str]) -> Vec<[f64; 3]> {
    let text = bvhview_stdout(args);
    text.lines()
        .skip(1)
        .map(|line| {
            let fields: Vec<f64> = line
                .split(',')
                .skip(2)
                .map(|v| v.parse().unwrap())
                .collect();
            [fields[0], fields[1], fields[2]]
        })
        .collect()
}

/// `info`'s value on the line that starts with `label`.
fn info_line(info: &str, label: &str) -> String {
    info.lines()
        .find(|line| line.starts_with(label))
        .unwrap_or_else(|| panic!("no {label} in {info}"))
        .to_string()
}

/// A Y-up walk turned by `convert --out-up AXIS` to stand along each of the four axes a stance
/// does not stand along reads back standing with `--up AXIS`: every joint of every frame where
/// the original has it (within the CSV's rounding, 1e-4 of the height), the same height and
/// units, and said as given and turned. `--up -z` on a take that stands along +z stands it on
/// its head: the stated axis is the user's word, not a guess.
#[test]
fn every_signed_up_axis_reads_a_take_turned_to_it_back_standing() {
    let folder = scratch_folder("up_axes");
    std::fs::create_dir_all(&folder).unwrap();
    let walk = data("bvh/bvhparser_walk_01.bvh").display().to_string();
    let original = positions_csv(&["positions", &walk, "--frames", "0..40"]);
    let info = bvhview_stdout(&["info", &walk]);
    let height = info_line(&info, "units:");
    assert!(height.contains("it stands 25.4 tall, 1.43 m"), "{height}");
    for axis in ["x", "-x", "-y", "-z"] {
        let turned = folder.join(format!("walk_{axis}.bvh"));
        let turned = turned.to_str().unwrap();
        let out = bvhview(&["convert", &walk, &format!("--out-up={axis}"), "-o", turned]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        // As written, the file stands along `axis`: read as if y were up, the figure is not
        // where it was.
        let as_written = positions_csv(&["positions", turned, "--frames", "0..40"]);
        let moved = original
            .iter()
            .zip(&as_written)
            .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        assert!(moved > 10.0, "--out-up {axis} moved the walk by {moved}");
        let read = bvhview(&[
            "positions",
            turned,
            "--frames",
            "0..40",
            &format!("--up={axis}"),
        ]);
        assert_eq!(read.status.code(), Some(0), "{read:?}");
        let said = String::from_utf8_lossy(&read.stderr);
        assert!(
            said.contains(&format!(
                "warning: --up {axis}: turned to stand along +y as it was read"
            )),
            "{said}"
        );
        let back = positions_csv(&["positions", turned, "--frames", "0..40", "--up", axis]);
        assert_eq!(back.len(), original.len());
        for (a, b) in original.iter().zip(&back) {
            for k in 0..3 {
                assert!(
                    (a[k] - b[k]).abs() <= 1e-4 * 25.4,
                    "--up {axis}: {a:?} read back as {b:?}"
                );
            }
        }
        let info = bvhview_stdout(&["info", turned, "--up", axis]);
        assert_eq!(info_line(&info, "units:"), height, "--up {axis}");
        assert!(
            info_line(&info, "up axis:").ends_with("y (stated: given, not guessed)"),
            "{info}"
        );
        assert!(
            info.contains(&format!("--up {axis}: turned to stand along +y")),
            "{info}"
        );
    }
    // The stated axis is believed: a Z-up MakeHuman walk said to stand along -z stands on its
    // head (its feet above its hips).
    let makehuman = data("bvh/makehuman_walk1.bvh").display().to_string();
    let info = bvhview_stdout(&["info", &makehuman, "--up=-z"]);
    assert!(
        info.contains("legs 176.6° and 176.6° from straight down"),
        "{info}"
    );
    // A value that is no axis is refused by clap with the six it takes.
    let refused = bvhview(&["info", &makehuman, "--up", "w"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&refused.stderr).contains("[possible values: y, z, x, -y, -z, -x]"),
        "{refused:?}"
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `convert --up` says what the file is, as `info --up` does: the values are written as they
/// were (the same bytes as no option), and where the axis given is not the one the motion reads
/// the note names `--out-up`, which turns. FBX is written y up and AMASS z up whatever the
/// take: `--out-up` to another axis is refused for them, not silently undone.
#[test]
fn convert_up_says_what_the_file_is_and_out_up_turns_it() {
    let folder = scratch_folder("convert_up");
    std::fs::create_dir_all(&folder).unwrap();
    let walk = data("bvh/bvhparser_walk_01.bvh").display().to_string();
    let out = |name: &str| folder.join(name).display().to_string();
    let plain = bvhview(&["convert", &walk, "-o", &out("plain.bvh")]);
    assert_eq!(plain.status.code(), Some(0), "{plain:?}");
    let stated = bvhview(&["convert", &walk, "--up", "z", "-o", &out("stated.bvh")]);
    assert_eq!(stated.status.code(), Some(0), "{stated:?}");
    assert_eq!(
        std::fs::read(out("plain.bvh")).unwrap(),
        std::fs::read(out("stated.bvh")).unwrap(),
        "--up only says what the file is"
    );
    let note = String::from_utf8_lossy(&stated.stderr);
    assert!(
        note.contains(
            "--up z says the file stands along z (its motion reads y); --out-up z turns a take"
        ),
        "{note}"
    );
    let turned = bvhview(&["convert", &walk, "--out-up", "z", "-o", &out("turned.bvh")]);
    assert_eq!(turned.status.code(), Some(0), "{turned:?}");
    let info = bvhview_stdout(&["info", &out("turned.bvh")]);
    assert!(info_line(&info, "up axis:").contains(" z (sure"), "{info}");
    // The file's axis given and the axis wanted: a turn from what the user says.
    let both = bvhview(&[
        "convert",
        &out("turned.bvh"),
        "--up",
        "z",
        "--out-up",
        "y",
        "-o",
        &out("back.bvh"),
    ]);
    assert_eq!(both.status.code(), Some(0), "{both:?}");
    let info = bvhview_stdout(&["info", &out("back.bvh")]);
    assert!(info_line(&info, "up axis:").contains(" y (sure"), "{info}");
    for (output, axis, why) in [
        ("turned.fbx", "z", "FBX is written y up whatever the take"),
        (
            "turned.npz",
            "y",
            "AMASS .npz is written z up whatever the take",
        ),
    ] {
        let refused = bvhview(&["convert", &walk, "--out-up", axis, "-o", &out(output)]);
        assert_eq!(refused.status.code(), Some(2), "{refused:?}");
        let said = String::from_utf8_lossy(&refused.stderr);
        assert!(said.contains(&format!("--out-up {axis}: {why}")), "{said}");
        assert!(!Path::new(&out(output)).exists());
    }
    std::fs::remove_dir_all(&folder).unwrap();
}
