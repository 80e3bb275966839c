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

/// Where `joint` is at frame 0 of a `positions` CSV of `file` read with `extra` options.
fn joint_at_first_frame(file: &str, joint: &str, extra: &[&str]) -> [f64; 3] {
    let mut args = vec!["positions", file, "--frames", "0"];
    args.extend(extra);
    let text = bvhview_stdout(&args);
    let line = text
        .lines()
        .find(|line| line.split(',').nth(1) == Some(joint))
        .unwrap_or_else(|| panic!("no {joint} in {text}"));
    let v: Vec<f64> = line
        .split(',')
        .skip(2)
        .map(|v| v.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
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
        // Written along `axis`: from the feet to the head is that way, by most of the height.
        let (head, foot) = (
            joint_at_first_frame(turned, "Head", &[]),
            joint_at_first_frame(turned, "LeftFoot", &[]),
        );
        let rise: Vec<f64> = (0..3).map(|k| head[k] - foot[k]).collect();
        let (along, sign) = match axis {
            "x" => (0, 1.0),
            "-x" => (0, -1.0),
            "-y" => (1, -1.0),
            _ => (2, -1.0),
        };
        assert!(
            sign * rise[along] > 18.0 && (0..3).all(|k| k == along || rise[k].abs() < 8.0),
            "--out-up {axis}: from the foot to the head is {rise:?}"
        );
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
    // An .npy of positions is SMPL's joints, metres and y up: no axis to state.
    let npy = bvhview(&["metrics", "positions.npy", "--up", "z"]);
    assert_eq!(npy.status.code(), Some(2), "{npy:?}");
    assert!(
        String::from_utf8_lossy(&npy.stderr).contains("--up and --units say what a take is"),
        "{npy:?}"
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
    // The file's axis given and the axis wanted: a turn from what the user says, not from the
    // guess. The Y-up walk said to stand along z and turned to y: (x, y, z) → (x, z, −y).
    let both = bvhview(&[
        "convert",
        &walk,
        "--up",
        "z",
        "--out-up",
        "y",
        "-o",
        &out("from_z.bvh"),
    ]);
    assert_eq!(both.status.code(), Some(0), "{both:?}");
    assert!(
        !String::from_utf8_lossy(&both.stderr).contains("turns a take"),
        "{both:?}"
    );
    let (before, after) = (
        joint_at_first_frame(&walk, "Head", &[]),
        joint_at_first_frame(&out("from_z.bvh"), "Head", &[]),
    );
    for (k, wanted) in [before[0], before[2], -before[1]].into_iter().enumerate() {
        assert!(
            (after[k] - wanted).abs() < 1e-3,
            "{before:?} turned to {after:?}"
        );
    }
    // Put on a target, the take stands as the target does; --out-up turns it from there.
    let onto = bvhview(&[
        "convert",
        &walk,
        "--onto",
        "smpl22",
        "--out-up",
        "x",
        "-o",
        &out("onto_x.bvh"),
    ]);
    assert_eq!(onto.status.code(), Some(0), "{onto:?}");
    let (head, foot) = (
        joint_at_first_frame(&out("onto_x.bvh"), "head", &[]),
        joint_at_first_frame(&out("onto_x.bvh"), "left_ankle", &[]),
    );
    assert!(
        head[0] - foot[0] > 100.0,
        "onto smpl22, --out-up x: {head:?} {foot:?}"
    );
    // The FBX writer turns the take to y from the axis the user gave, not from the guess.
    #[cfg(feature = "fbx")]
    {
        // The Y-up walk said to stand along z: the FBX writer turns it from z, so it lies
        // along −z in the FBX (centimetres).
        let fbx = bvhview(&["convert", &walk, "--up", "z", "-o", &out("said_z.fbx")]);
        assert_eq!(fbx.status.code(), Some(0), "{fbx:?}");
        let (head, foot) = (
            joint_at_first_frame(&out("said_z.fbx"), "Head", &[]),
            joint_at_first_frame(&out("said_z.fbx"), "LeftFoot", &[]),
        );
        assert!(
            foot[2] - head[2] > 100.0 && (head[1] - foot[1]).abs() < 20.0,
            "--up z into FBX: {head:?} {foot:?}"
        );
    }
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

/// What the user says of the skeleton a take is put on (`--onto-units`, `--onto-up`) replaces
/// the guess as `--units` and `--up` do for a take: a 174 cm figure scaled to 61 cm, still in
/// centimetres, is read as inches by its size; said to be centimetres, what `retarget`,
/// `solve` and `convert --onto` write in metres is 0.61 m tall, not 1.55 m. A target turned to
/// stand along −z and said so gives the take on the upright target back.
#[test]
fn what_the_user_says_of_a_target_replaces_the_guess() {
    let folder = scratch_folder("onto_stated");
    std::fs::create_dir_all(&folder).unwrap();
    let out = |name: &str| folder.join(name).display().to_string();
    let freebvh = data("bvh/bvhpython_test_freebvh.bvh").display().to_string();
    let walk = data("bvh/bvhparser_walk_01.bvh").display().to_string();
    let small = out("small.bvh");
    let made = bvhview(&["convert", &freebvh, "--scale", "0.35", "-o", &small]);
    assert_eq!(made.status.code(), Some(0), "{made:?}");
    let info = bvhview_stdout(&["info", &small]);
    assert!(
        info_line(&info, "units:")
            .contains("inches (sure: the figure spans 67.9; it stands 61.0 tall, 1.55 m)"),
        "{info}"
    );
    let tall = |file: &str| {
        let info = bvhview_stdout(&["info", file, "--units", "m"]);
        let line = info_line(&info, "units:");
        let metres: f64 = line
            .split("it stands ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .unwrap()
            .parse()
            .unwrap();
        metres
    };
    let commands: [Vec<&str>; 3] = [
        vec!["retarget", &walk, "--onto", &small],
        vec!["convert", &walk, "--onto", &small],
        vec!["solve", "SMPL_POSITIONS", "--onto", &small, "--fps", "20"],
    ];
    let positions = out("walk_smpl.npy");
    let on_smpl = bvhview(&["positions", &walk, "--layout", "smpl24", "-o", &positions]);
    assert_eq!(on_smpl.status.code(), Some(0), "{on_smpl:?}");
    for command in commands {
        let name = command[0];
        let args: Vec<&str> = command
            .iter()
            .map(|a| {
                if *a == "SMPL_POSITIONS" {
                    positions.as_str()
                } else {
                    a
                }
            })
            .collect();
        let mut args = args;
        if name == "solve" {
            args.extend(["--layout", "smpl24"]);
        }
        let guessed = out(&format!("{name}_guessed.bvh"));
        let given = out(&format!("{name}_given.bvh"));
        for (file, extra) in [(&guessed, &[][..]), (&given, &["--onto-units", "cm"][..])] {
            let mut all = args.clone();
            all.extend(extra);
            all.extend(["--out-units", "m", "-o", file]);
            let run = bvhview(&all);
            assert_eq!(run.status.code(), Some(0), "{name}: {run:?}");
        }
        let (guessed, given) = (tall(&guessed), tall(&given));
        assert!((guessed - 1.51).abs() < 0.02, "{name}: {guessed} m guessed");
        assert!((given - 0.596).abs() < 0.01, "{name}: {given} m given");
    }
    // A dataset of takes put on it says the units given for it, per clip.
    let takes = folder.join("takes");
    std::fs::create_dir(&takes).unwrap();
    std::fs::copy(&walk, takes.join("walk.bvh")).unwrap();
    for (extra, units, given) in [
        (&[][..], "inches", None),
        (&["--onto-units", "cm"][..], "centimetres", Some(true)),
    ] {
        let dataset = folder.join(format!("dataset_{units}"));
        let mut args = vec![
            "dataset",
            takes.to_str().unwrap(),
            "--onto",
            &small,
            "-o",
            dataset.to_str().unwrap(),
        ];
        args.extend(extra);
        let run = bvhview(&args);
        assert_eq!(run.status.code(), Some(0), "{run:?}");
        let manifest: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dataset.join("manifest.json")).unwrap())
                .unwrap();
        let clip = &manifest["clips"][0];
        assert_eq!(clip["units"], units, "{clip}");
        assert_eq!(clip["units_given"].as_bool(), given, "{clip}");
    }
    // A target turned to stand along −z, said so: the take on it is the take on the upright one.
    let lying = out("small_negz.bvh");
    let turned = bvhview(&["convert", &small, "--out-up=-z", "-o", &lying]);
    assert_eq!(turned.status.code(), Some(0), "{turned:?}");
    for (target, extra, file) in [
        (&small, &[][..], out("upright.bvh")),
        (&lying, &["--onto-up=-z"][..], out("stated.bvh")),
    ] {
        let mut args = vec!["retarget", walk.as_str(), "--onto", target, "-o", &file];
        args.extend(extra);
        let run = bvhview(&args);
        assert_eq!(run.status.code(), Some(0), "{run:?}");
    }
    let upright = positions_csv(&["positions", &out("upright.bvh"), "--frames", "0..40"]);
    let stated = positions_csv(&["positions", &out("stated.bvh"), "--frames", "0..40"]);
    assert_eq!(upright.len(), stated.len());
    for (a, b) in upright.iter().zip(&stated) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= 1e-4 * 61.0, "{a:?} and {b:?}");
        }
    }
    std::fs::remove_dir_all(&folder).unwrap();
}

/// Joints whose rotations cannot be split again in their own channels turn by their axis: an
/// ASF bone (C·R·C⁻¹ about its axis C: the axis becomes Q·C, the channels stay, its one or two
/// degrees of freedom too) and a BVH hinge of one rotation (given the axis Q; the BVH writer
/// bakes it into three channels). Each, turned to an axis and read back along it, is where it
/// was on every frame; an ASF read with `--up x` is the ASF turned by a quarter turn about z.
#[test]
fn hinges_and_asf_bones_turn_by_their_axis() {
    let folder = scratch_folder("up_hinges");
    std::fs::create_dir_all(&folder).unwrap();
    let out = |name: &str| folder.join(name).display().to_string();
    let hinge = out("hinge.bvh");
    std::fs::write(
        &hinge,
        "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n\tJOINT Knee\n\t{\n\t\tOFFSET 0 -40 0\n\t\tCHANNELS 1 \
         Xrotation\n\t\tJOINT Ankle\n\t\t{\n\t\t\tOFFSET 0 -40 5\n\t\t\tCHANNELS 2 Zrotation \
         Xrotation\n\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET 0 0 12\n\t\t\t}\n\t\t}\n\t}\n}\n\
         MOTION\nFrames: 3\nFrame Time: 0.1\n0 90 0 0 0 0 10 5 5\n1 91 2 10 20 5 40 10 -5\n\
         2 92 4 20 -10 15 80 -20 30\n",
    )
    .unwrap();
    let asf = data("asf_amc/heiden_12.asf").display().to_string();
    let amc = data("asf_amc/heiden_12_02_01.amc").display().to_string();
    let sources: [(&str, Vec<&str>); 2] = [
        ("hinge", vec![hinge.as_str()]),
        ("asf", vec![asf.as_str(), "--motion", amc.as_str()]),
    ];
    for (name, source) in &sources {
        // The take as BVH writes it, unturned: the reference (an ASF's points are named
        // otherwise than its BVH's).
        let plain = out(&format!("{name}_plain.bvh"));
        let mut args = vec!["convert"];
        args.extend(source);
        args.extend(["-o", &plain]);
        assert_eq!(bvhview(&args).status.code(), Some(0));
        let before = positions_csv(&["positions", &plain]);
        for axis in ["x", "-z"] {
            let turned = out(&format!("{name}_{axis}.bvh"));
            let mut args = vec!["convert"];
            args.extend(source);
            let out_up = format!("--out-up={axis}");
            args.extend([out_up.as_str(), "-o", &turned]);
            let run = bvhview(&args);
            assert_eq!(run.status.code(), Some(0), "{name} {axis}: {run:?}");
            let back = positions_csv(&["positions", &turned, &format!("--up={axis}")]);
            assert_eq!(back.len(), before.len(), "{name} {axis}");
            for (a, b) in before.iter().zip(&back) {
                for k in 0..3 {
                    assert!(
                        (a[k] - b[k]).abs() < 1e-3,
                        "{name} --up {axis}: {a:?} {b:?}"
                    );
                }
            }
        }
    }
    // Read along x, the ASF's points are its own turned by Rz(90°): (x, y, z) → (−y, x, z).
    let own = positions_csv(&["positions", &asf, "--motion", &amc]);
    let turned = positions_csv(&["positions", &asf, "--motion", &amc, "--up", "x"]);
    for (a, b) in own.iter().zip(&turned) {
        let wanted = [-a[1], a[0], a[2]];
        for k in 0..3 {
            assert!(
                (wanted[k] - b[k]).abs() < 1e-3,
                "{a:?} read along x as {b:?}"
            );
        }
    }
    std::fs::remove_dir_all(&folder).unwrap();
}
