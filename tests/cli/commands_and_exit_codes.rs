//! The command line: positions, info, exit codes and messages.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use crate::common;
use common::*;
use std::process::{Command, Output};

fn tiny() -> String {
    oracle("inputs/tiny_crlf.bvh").display().to_string()
}

/// Parses `frame,joint,x,y,z` rows into (frame, joint, [x, y, z]).
fn rows(csv: &str) -> Vec<(usize, String, [f32; 3])> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("frame,joint,x,y,z"));
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let n = |i: usize| f[i].parse::<f32>().unwrap();
            (f[0].parse().unwrap(), f[1].to_string(), [n(2), n(3), n(4)])
        })
        .collect()
}

fn find(rows: &[(usize, String, [f32; 3])], frame: usize, joint: &str) -> [f32; 3] {
    rows.iter()
        .find(|r| r.0 == frame && r.1 == joint)
        .unwrap()
        .2
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
}

#[test]
fn positions_csv_gives_hand_computed_points() {
    let out = bvhview(&["positions", &tiny(), "--frames", "0..2"]);
    assert!(out.status.success());
    let rows = rows(&String::from_utf8(out.stdout).unwrap());
    assert_eq!(rows.len(), 2 * 12, "12 joints and End Sites, 2 frames");
    // Frame 0: no rotation; the root's position channels replace its OFFSET: (0, 30, 0).
    assert_eq!(find(&rows, 0, "Hips"), [0.0, 30.0, 0.0]);
    assert_eq!(find(&rows, 0, "Neck_End"), [0.0, 77.0, 0.0]);
    assert_eq!(find(&rows, 0, "LeftArm_End"), [37.0, 60.0, 0.0]);
    // Frame 1: root at (5, 30, -3) turned 30° about Y; LeftLeg (8, 0, 0) lands at
    // (5 + 8 cos 30°, 30, -3 - 8 sin 30°); its End Site (0, -40, 0) turned -30° about X is
    // (0, -34.641, 20), then 30° about Y: (10, -34.641, 17.3205).
    assert!(close(find(&rows, 1, "LeftLeg"), [11.928203, 30.0, -7.0]));
    assert!(close(
        find(&rows, 1, "LeftLeg_End"),
        [21.928203, -4.641016, 10.320508]
    ));
}

#[test]
fn positions_left_handed_negates_z_and_json_has_the_same_numbers() {
    let right =
        rows(&String::from_utf8(bvhview(&["positions", &tiny(), "--frames", "1"]).stdout).unwrap());
    let left_out = bvhview(&["positions", &tiny(), "--frames", "1", "--left-handed"]);
    let left = rows(&String::from_utf8(left_out.stdout).unwrap());
    for (r, l) in right.iter().zip(&left) {
        assert_eq!(r.1, l.1);
        assert_eq!([r.2[0], r.2[1], -r.2[2]], l.2);
    }
    let json = bvhview(&[
        "positions",
        &tiny(),
        "--frames",
        "1..=1",
        "--format",
        "json",
    ]);
    let text = String::from_utf8(json.stdout).unwrap();
    assert!(text.starts_with(
        "{\"frame_time\":0.033333,\"joints\":[\"Hips\",\"Chest\",\"Neck\",\"Neck_End\","
    ));
    assert!(
        text.contains("{\"frame\":1,\"positions\":[[5,30,-3],[5,45,-3],"),
        "{text}"
    );
    assert!(text.trim_end().ends_with("]}]}"));
}

#[test]
fn positions_offset_mode_add_adds_position_channels() {
    let file = data("bvh/makehuman_tpose.bvh").display().to_string();
    let replace = rows(&String::from_utf8(bvhview(&["positions", &file]).stdout).unwrap());
    let add_out = bvhview(&["positions", &file, "--offset-mode", "add"]);
    let add = rows(&String::from_utf8(add_out.stdout).unwrap());
    // The root's position channels hold (0, 0.6394, 0.027754); its OFFSET is (0, 0.6394, 0.6314).
    assert!(close(find(&replace, 0, "root"), [0.0, 0.6394, 0.027754]));
    assert!(close(find(&add, 0, "root"), [0.0, 1.2788, 0.659154]));
    let stderr = String::from_utf8(bvhview(&["positions", &file]).stderr).unwrap();
    assert!(
        stderr.contains("looks written for `--offset-mode add`"),
        "{stderr}"
    );
}

#[test]
fn bad_frame_ranges_and_bad_files_exit_2_with_one_line() {
    let out = bvhview(&["positions", &tiny(), "--frames", "2..9"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(
        stderr,
        "bvhview: --frames 2..9: expected N, A..B (B left out), A..=B, A.. or ..B within frames 0 to 2\n"
    );

    let broken = data("bvh_malformed/dali_test-invalid-hierarchy1.bvh")
        .display()
        .to_string();
    for command in ["print", "info", "positions"] {
        let out = bvhview(&[command, &broken]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert_eq!(
            stderr,
            format!("bvhview: {broken}:3:3: expected '{{' after 'root', found 'OFFSET'\n")
        );
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn info_reports_counts_timing_orders_and_a_trailer_warning() {
    let file = data("bvh/opencollar_oc_stand_boy01.bvh")
        .display()
        .to_string();
    let out = bvhview(&["info", &file]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for line in [
        "joints:           19\n",
        "end sites:        5\n",
        "channels:         60\n",
        "frames:           100\n",
        "frame time:       0.033333 s (30.00 frames per second)\n",
        "duration:         3.333 s\n",
        "rotation orders:  XYZ ×2, XZY ×9, YZX ×4, ZYX ×4\n",
        "position channels: hip\n",
        "  - 24 extra rows after the 100 announced by Frames: (line 118) ignored, from line 220 on\n",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
    // Said once: in the summary, not again on stderr.
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn info_reports_counts_timing_orders_and_warnings() {
    let file = shared_data("bvh/assimp_Boxing_Toes.bvh")
        .display()
        .to_string();
    let out = bvhview(&["info", &file]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for line in [
        "joints:           21\n",
        "end sites:        5\n",
        "channels:         66\n",
        "frames:           3069\n",
        "frame time:       0.01 s (100.00 frames per second)\n",
        "duration:         30.690 s\n",
        "rotation orders:  ZXY ×21\n",
        "  - 1 extra row after the 3069 announced by Frames: (line 128) ignored, from line 3199 on\n",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
}

#[test]
fn info_without_a_file_describes_the_bundled_walk() {
    let out = bvhview(&["info"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("file:             the bundled walk\n"),
        "{text}"
    );
    assert!(text.contains("frames:           40\n"));
    assert!(text.contains("rotation orders:  YXZ ×23\n"));
}

#[cfg(feature = "window")]
#[test]
fn the_window_without_a_display_says_so_in_one_line() {
    for args in [&[][..], &[tiny().as_str()][..]] {
        let out = crate::common::bvhview_command()
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert_eq!(
            stderr,
            "bvhview: no display to open a window on: neither DISPLAY nor WAYLAND_DISPLAY is set. \
             `bvhview snapshot FILE -o out.png` draws without one\n"
        );
    }
    // The skinning demo points to its own offscreen form, and a display nobody serves
    // is named without the source path winit's error carries.
    let out = crate::common::bvhview_command()
        .arg("skin-demo")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.ends_with("`bvhview skin-demo -o out.png` draws without one\n"),
        "{stderr}"
    );
    let out = crate::common::bvhview_command()
        .arg(tiny())
        .env("DISPLAY", ":55")
        .output()
        .unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("bvhview: cannot open the X display \":55\""),
        "{stderr}"
    );
    assert!(
        !stderr.contains(".rs:") && !stderr.contains("registry"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
#[test]
fn info_on_the_repository_folder_lists_every_file_and_sums_up() {
    let dir = repo_data("").display().to_string();
    let out = bvhview(&["info", &dir]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "a malformed file makes the run fail"
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // The BVH and ASF/AMC takes, the FBX and glTF ones (the characters among them) and the
    // three AMASS files.
    assert_eq!(lines.len(), 71, "{text}");
    // Two FBX files of cameras only have no skeleton: 59 of 70 load.
    assert_eq!(lines.iter().filter(|l| l.starts_with("ok ")).count(), 59);
    assert!(
        lines[0].starts_with("ok     ")
            && lines[0].contains("heiden_12.asf + ")
            && lines[0].ends_with(": 31 joints, 343 frames, 2.9 s"),
        "{}",
        lines[0]
    );
    assert!(
        text.contains("error  ")
            && text.contains(
                "dali_test-invalid-hierarchy1.bvh:3:3: expected '{' after 'root', found 'OFFSET'\n"
            )
    );
    assert!(
        text.contains("smpl/amass_smplx_walk.npz: 55 joints, 60 frames, 2.0 s (1 warning)\n"),
        "{text}"
    );
    assert!(
        lines[70].starts_with("70 files: 59 ok, 11 failed; 10.9 MB in "),
        "{}",
        lines[70]
    );
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn info_on_a_folder_lists_every_file_and_sums_up() {
    let dir = shared_data("").display().to_string();
    let out = bvhview(&["info", &dir]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "a malformed file makes the run fail"
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Every BVH and every ASF/AMC pair of the corpus reads; 8 of the malformed files do not.
    let files = files_in(&shared_data("bvh"), "bvh").len()
        + files_in(&shared_data("asf_amc"), "amc").len()
        + files_in(&shared_data("bvh_malformed"), "bvh").len();
    let read = files - 8;
    assert_eq!(lines.len(), files + 1, "{text}");
    assert_eq!(lines.iter().filter(|l| l.starts_with("ok ")).count(), read);
    assert!(
        lines[0].starts_with("ok     ")
            && lines[0].contains("heiden_12.asf + ")
            && lines[0].ends_with(": 31 joints, 343 frames, 2.9 s"),
        "{}",
        lines[0]
    );
    assert!(
        text.contains("error  ")
            && text.contains(
                "dali_test-invalid-hierarchy1.bvh:3:3: expected '{' after 'root', found 'OFFSET'\n"
            )
    );
    assert!(
        lines[files].starts_with(&format!("{files} files: {read} ok, 8 failed; ")),
        "{}",
        lines[files]
    );
}

#[test]
fn snapshot_frames_writes_a_sequence_equal_to_single_snapshots() {
    let dir = crate::common::scratch_folder("seq");
    let out = bvhview(&[
        "snapshot",
        &tiny(),
        "--frames",
        "0..3",
        "--size",
        "96x64",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["frame_00000.png", "frame_00001.png", "frame_00002.png"]
    );
    let single = dir.join("single.png");
    assert!(
        bvhview(&[
            "snapshot",
            &tiny(),
            "--frame",
            "2",
            "--size",
            "96x64",
            "-o",
            single.to_str().unwrap()
        ])
        .status
        .success()
    );
    let a = bvhview::render::Image::read_png(&dir.join("frame_00002.png")).unwrap();
    let b = bvhview::render::Image::read_png(&single).unwrap();
    assert_eq!(a.differing_pixels(&b), 0);
    // A second run into the folder, now holding pictures, is refused as `convert`
    // refuses it (it left frame_00003… of a longer earlier run beside the new ones).
    let again = bvhview(&[
        "snapshot",
        &tiny(),
        "--frames",
        "0..2",
        "-o",
        dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert_eq!(again.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("already exists; the pictures go into a new (or empty) folder"),
        "{stderr}"
    );
    // A file or a device where the folder would go is no folder (`-o /dev/full` said "file
    // exists").
    let full = bvhview(&["snapshot", &tiny(), "--frames", "0..2", "-o", "/dev/full"]);
    assert_eq!(full.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&full.stderr)
            .starts_with("bvhview: -o /dev/full: is not a folder;"),
        "{}",
        String::from_utf8_lossy(&full.stderr)
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Frame times past an hour or under a microsecond (other than 0) are refused where they stand
/// (`Frame Time: 1e308` made an animation panic, `1e-320` played at "inf" frames per
/// second); 0, which some exporters write, loads.
#[test]
fn absurd_frame_times_are_refused_where_they_stand() {
    let base = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    for (time, loads) in [("1e300", false), ("1e-320", false), ("0", true)] {
        let path = crate::common::scratch_folder("time-x").join(format!("time-{time}.bvh"));
        std::fs::write(
            &path,
            base.replace("Frame Time: 0.033333", &format!("Frame Time: {time}")),
        )
        .unwrap();
        let out = bvhview(&["info", path.to_str().unwrap()]);
        let stderr = String::from_utf8(out.stderr).unwrap();
        if loads {
            assert!(out.status.success(), "{stderr}");
        } else {
            assert_eq!(out.status.code(), Some(2));
            let want =
                format!("expected the frame time (seconds: 0, or 1e-6 to 3600), found '{time}'\n");
            assert!(stderr.ends_with(&want), "{stderr}");
        }
        std::fs::remove_file(path).unwrap();
    }
}

/// `info FOLDER` loads every file with the options `info FILE` takes, and counts the same
/// warnings.
#[test]
fn info_on_a_folder_honours_max_size_frame_time_and_offset_mode() {
    let dir = repo_data("").display().to_string();
    let text = |args: &[&str]| String::from_utf8(bvhview(args).stdout).unwrap();
    let line = |text: &str, name: &str| {
        text.lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("{name} in\n{text}"))
            .to_string()
    };
    let plain = text(&["info", &dir]);
    assert!(line(&plain, "heiden_12.asf").ends_with(": 31 joints, 343 frames, 2.9 s"));
    assert!(line(&plain, "makehuman_tpose").ends_with("(1 warning)"));

    let slow = text(&["info", &dir, "--frame-time", "0.5"]);
    assert!(line(&slow, "heiden_12.asf").ends_with(": 31 joints, 343 frames, 171.5 s"));
    assert!(line(&slow, "opencollar_run").ends_with(": 20 joints, 31 frames, 15.5 s"));

    let add = text(&["info", &dir, "--offset-mode", "add"]);
    assert!(line(&add, "makehuman_tpose").ends_with(": 173 joints, 1 frame, 0.0 s"));

    let small = text(&["info", &dir, "--max-size", "100K"]);
    assert_eq!(
        line(&small, "assimp_01_01"),
        format!(
            "error  {}: 2070355 bytes, more than --max-size 102400",
            repo_data("bvh/assimp_01_01.bvh").display()
        )
    );
    // Single-file mode lists the same warnings the folder line counts.
    let tpose = repo_data("bvh/makehuman_tpose.bvh").display().to_string();
    let single = text(&["info", &tpose]);
    assert_eq!(single.matches("\n  - ").count(), 1, "{single}");

    let bad = bvhview(&["info", &dir, "--frame-time", "0"]);
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(bad.stderr).unwrap(),
        "bvhview: --frame-time 0: expected seconds per frame, from 1e-6 to 3600\n"
    );
}

/// Positions that overflow to infinity are refused, naming the frame and the joint, and nothing
/// is written: CSV and JSON readers refuse `inf`.
#[test]
fn positions_that_are_not_finite_are_refused() {
    let base = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let path = crate::common::scratch_folder("overflow").join("overflow.bvh");
    std::fs::write(
        &path,
        base.replace("OFFSET 0.000000 15.000000 0.000000", "OFFSET 0 3e38 0")
            .replace("OFFSET 0.000000 20.000000 0.000000", "OFFSET 0 3e38 0"),
    )
    .unwrap();
    for format in ["csv", "json"] {
        let out = bvhview(&["positions", path.to_str().unwrap(), "--format", format]);
        assert_eq!(out.status.code(), Some(2), "{format}");
        assert!(out.stdout.is_empty(), "{format}");
        assert_eq!(
            String::from_utf8(out.stderr).unwrap(),
            "bvhview: frame 0, Chest_End: the position (0, inf, 0) is not a finite number \
             (the offsets, the values or a scale overflow)\n"
        );
    }
    // To a file: refused before the end, so nothing appears under its name or beside it.
    let dir = crate::common::scratch_folder("refused");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("out.csv");
    let out = bvhview(&[
        "positions",
        path.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "a file was left"
    );
    std::fs::remove_dir_all(dir).unwrap();
    std::fs::remove_file(path).unwrap();
    let scaled = bvhview(&["positions", &tiny(), "--scale", "1e38"]);
    assert_eq!(scaled.status.code(), Some(2));
}

/// `diff` reads grey, grey + alpha, RGB and RGBA pictures alike; it exits 1 only when pictures
/// differ, and names a file it cannot read.
#[test]
fn diff_reads_grey_and_colour_pictures_and_names_bad_files() {
    let dir = crate::common::scratch_folder("diff");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, color: png::ColorType, pixel: &[u8]| {
        let path = dir.join(name);
        let file = std::fs::File::create(&path).unwrap();
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 4, 4);
        encoder.set_color(color);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&pixel.repeat(16)).unwrap();
        writer.finish().unwrap();
        path.display().to_string()
    };
    let grey = write("grey.png", png::ColorType::Grayscale, &[128]);
    let grey_alpha = write("ga.png", png::ColorType::GrayscaleAlpha, &[128, 255]);
    let rgb = write("rgb.png", png::ColorType::Rgb, &[128, 128, 128]);
    let red = write("red.png", png::ColorType::Rgba, &[255, 0, 0, 255]);
    for other in [&grey_alpha, &rgb] {
        let out = bvhview(&["diff", &grey, other]);
        assert_eq!(out.status.code(), Some(0), "{other}");
        assert_eq!(
            String::from_utf8(out.stdout).unwrap(),
            "0 of 16 pixels differ (0.000%)\n"
        );
    }
    let out = bvhview(&["diff", &grey, &red]);
    assert_eq!(out.status.code(), Some(1));
    let text = dir.join("notes.png");
    std::fs::write(&text, "not a picture").unwrap();
    let out = bvhview(&["diff", text.to_str().unwrap(), &rgb]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.starts_with(&format!("bvhview: {}: ", text.display())),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// A file that looks written for the other offset mode is said once by `snapshot`; a Z-up file is
/// stood up and that is said too, unless `--up` says how to draw it.
#[test]
fn snapshot_says_once_what_it_guessed_about_conventions() {
    let file = data("bvh/makehuman_tpose.bvh").display().to_string();
    let dir = crate::common::scratch_folder("conventions");
    std::fs::create_dir_all(&dir).unwrap();
    let picture = |name: &str| dir.join(name).display().to_string();
    let (guessed, upright, lying) = (picture("g.png"), picture("z.png"), picture("y.png"));
    let out = bvhview(&["snapshot", &file, "--fit", "-q", "-o", &guessed]);
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(
        stderr
            .matches("looks written for `--offset-mode add`")
            .count(),
        1,
        "{stderr}"
    );
    assert_eq!(
        stderr
            .matches("drawn Z-up (--up y draws it as written)")
            .count(),
        1,
        "{stderr}"
    );
    let out = bvhview(&[
        "snapshot",
        &file,
        "--fit",
        "-q",
        "--offset-mode",
        "add",
        "--up",
        "z",
        "-o",
        &upright,
    ]);
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
    let out = bvhview(&[
        "snapshot",
        &file,
        "--fit",
        "-q",
        "--offset-mode",
        "add",
        "--up",
        "y",
        "-o",
        &lying,
    ]);
    assert_eq!(String::from_utf8(out.stderr).unwrap(), "");
    let read = |path: &str| bvhview::render::Image::read_png(std::path::Path::new(path)).unwrap();
    assert!(read(&upright).differing_pixels(&read(&lying)) > 1000);
    let info = String::from_utf8(bvhview(&["info", &file]).stdout).unwrap();
    assert!(info.contains("up axis:          z ("), "{info}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `snapshot --frames` into .apng (lossless: each frame is the snapshot of that frame) and .gif
/// (a palette: the same frames, counted and timed), at the file's rate or `--fps`.
#[test]
fn animated_snapshots_hold_the_frames_at_their_rate() {
    let dir = crate::common::scratch_folder("anim");
    std::fs::create_dir_all(&dir).unwrap();
    let apng = dir.join("walk.apng");
    let out = bvhview(&[
        "snapshot",
        &tiny(),
        "--frames",
        "0..3",
        "--size",
        "96x64",
        "-o",
        apng.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!(
            "bvhview: wrote {}: 3 frames at 30.000 per second\n",
            apng.display()
        )
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&apng).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control().unwrap();
    assert_eq!((control.num_frames, control.num_plays), (3, 0));
    let bvh = bvhview::bvh::load_file(&oracle("inputs/tiny_crlf.bvh"), Default::default()).unwrap();
    for frame in 0..3 {
        let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
        reader.next_frame(&mut buffer).unwrap();
        let fc = reader.info().frame_control().unwrap();
        assert_eq!((fc.delay_num, fc.delay_den), (33, 1000));
        let want = bvhview::render::snapshot(
            &bvh.skeleton,
            &bvh.motion,
            &bvhview::render::SnapshotOptions {
                frame,
                width: 96,
                height: 64,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(buffer == want.rgb, "frame {frame}");
    }

    let gif = dir.join("walk.gif");
    let out = bvhview(&[
        "snapshot",
        &tiny(),
        "--frames",
        "0..3",
        "--fps",
        "10",
        "--size",
        "96x64",
        "-q",
        "-o",
        gif.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(&gif).unwrap())
        .unwrap();
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width, frame.height), (96, 64));
        delays.push(frame.delay);
    }
    // Three frames at 30 fps shown at 10: one picture of a tenth of a second.
    assert_eq!(delays, vec![10]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `snapshot --hud` writes the HUD bottom left above the timeline (pinned picture); without it the picture is the
/// article's, unchanged.
#[test]
fn snapshot_hud_is_pinned_and_opt_in() {
    let dir = crate::common::scratch_folder("hudpin");
    std::fs::create_dir_all(&dir).unwrap();
    let (with, without) = (dir.join("with.png"), dir.join("without.png"));
    let input = tiny();
    for (path, extra) in [(&with, Some("--hud")), (&without, None)] {
        let mut args = vec!["snapshot", input.as_str(), "--frame", "1", "-q"];
        args.extend(extra);
        args.extend(["-o", path.to_str().unwrap()]);
        assert!(bvhview(&args).status.success());
    }
    let read = |p: &std::path::Path| bvhview::render::Image::read_png(p).unwrap();
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots/tiny_crlf__f1__hud.png");
    if std::env::var_os("BVHVIEW_BLESS").is_some() {
        std::fs::copy(&with, &golden).unwrap();
    }
    let differing = read(&with).differing_pixels(&read(&golden));
    println!("drift tiny_crlf__f1__hud: {differing} of 360000 pixels differ (at most 360)");
    assert!(differing <= 360, "{differing}");
    let article = read(&oracle("refs/tiny_crlf__f1__a10__600x600.png"));
    assert_eq!(read(&without).differing_pixels(&article), 0);
    assert!(read(&with).differing_pixels(&article) > 1000);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `snapshot --names` writes each joint's name beside it (pinned picture), over the picture the
/// same options draw without it.
#[test]
fn snapshot_names_are_pinned_and_opt_in() {
    let dir = crate::common::scratch_folder("namespin");
    std::fs::create_dir_all(&dir).unwrap();
    let (with, without) = (dir.join("with.png"), dir.join("without.png"));
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    for (path, extra) in [(&with, Some("--names")), (&without, None)] {
        let mut args = vec![
            "snapshot",
            walk.to_str().unwrap(),
            "--frame",
            "10",
            "--fit",
            "--angle",
            "0.6",
            "--style",
            "both",
            "-q",
        ];
        args.extend(extra);
        args.extend(["-o", path.to_str().unwrap()]);
        assert!(bvhview(&args).status.success());
    }
    let read = |p: &std::path::Path| bvhview::render::Image::read_png(p).unwrap();
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots/walk__f10__names__both__fit__a0.6.png");
    if std::env::var_os("BVHVIEW_BLESS").is_some() {
        std::fs::copy(&with, &golden).unwrap();
    }
    let differing = read(&with).differing_pixels(&read(&golden));
    println!(
        "drift walk__f10__names__both__fit__a0.6: {differing} of 360000 pixels differ (at most 360)"
    );
    assert!(differing <= 360, "{differing}");
    // The names add only text: the figure's own golden picture is what is drawn without them.
    let plain = read(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/snapshots/walk__f10__both__fit__a0.6.png"
    )));
    assert_eq!(read(&without).differing_pixels(&plain), 0);
    assert!(read(&with).differing_pixels(&plain) > 1000);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `info` says which up axis and units the motion suggests, and how sure the guess is.
#[test]
fn info_guesses_the_units_from_the_height() {
    for (file, line) in [
        (
            "bvh/makehuman_walk1.bvh",
            "units:            decimetres (sure: the figure spans 16.4; it stands 15.7 tall, 1.57 m)",
        ),
        (
            "bvh/makehuman_walk1.bvh",
            "up axis:          z (sure: the figure spreads 7.57 along y and 15.7 along z over 14 frames)",
        ),
        (
            "bvh/bvhpython_test_freebvh.bvh",
            "units:            centimetres (sure: the figure spans 194; it stands 174 tall, 1.74 m)",
        ),
        (
            "bvh/opencollar_run.bvh",
            "units:            inches (sure: the figure spans 71.6; it stands 66.6 tall, 1.69 m)",
        ),
    ] {
        let out = bvhview(&["info", data(file).to_str().unwrap()]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.lines().any(|l| l == line), "{file}:\n{text}");
    }
}

/// Two files side by side on one timeline (pinned picture): each at its own frame for the time,
/// labelled with the HUD; a frame past both takes' ends is refused.
#[test]
fn snapshot_of_two_takes_side_by_side_is_pinned() {
    let dir = crate::common::scratch_folder("twopin");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("two.png");
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let free = data("bvh/bvhpython_test_freebvh.bvh");
    let run = |frame: &str| {
        bvhview(&[
            "snapshot",
            walk.to_str().unwrap(),
            free.to_str().unwrap(),
            "--frame",
            frame,
            "--look",
            "studio",
            "--style",
            "both",
            "--hud",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ])
    };
    assert!(run("20").status.success());
    let read = |p: &std::path::Path| bvhview::render::Image::read_png(p).unwrap();
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots/two_takes__walk_freebvh__f20__studio__both__hud.png");
    if std::env::var_os("BVHVIEW_BLESS").is_some() {
        std::fs::copy(&out, &golden).unwrap();
    }
    let differing = read(&out).differing_pixels(&read(&golden));
    println!(
        "drift two_takes__walk_freebvh__f20__studio__both__hud: {differing} of 360000 pixels differ (at most 360)"
    );
    assert!(differing <= 360, "{differing}");
    // Both at 30 frames per second: the walk's 40 frames and the other's 69 make 69 frames.
    let past = run("69");
    assert_eq!(past.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&past.stderr),
        "bvhview: --frame 69: the takes together have frames 0 to 68 (at 0.033333 s each)\n"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--overlay` draws several takes one over the other: a take over itself stands exactly where
/// it stands alone (the same picture, pixel for pixel, the copy hidden under it), where side by
/// side the two stand apart; with one file it is refused.
#[test]
fn snapshot_overlay_draws_takes_where_they_stand() {
    let dir = crate::common::scratch_folder("overlay");
    std::fs::create_dir_all(&dir).unwrap();
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let walk = walk.to_str().unwrap();
    let picture = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "snapshot", walk, "--frame", "10", "--look", "studio", "--angle", "0.6", "--size",
            "200x200", "-q", "-o",
        ];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let result = bvhview(&args);
        assert!(result.status.success(), "{result:?}");
        bvhview::render::Image::read_png(&out).unwrap()
    };
    let alone = picture("alone.png", &[]);
    let overlaid = picture("overlaid.png", &[walk, "--overlay"]);
    let apart = picture("apart.png", &[walk]);
    assert_eq!(overlaid.differing_pixels(&alone), 0);
    let moved = apart.differing_pixels(&alone);
    assert!(moved > 1000, "{moved}");
    let one = bvhview(&[
        "snapshot",
        walk,
        "--overlay",
        "-o",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(one.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&one.stderr),
        "bvhview: --overlay draws several files one over the other: give two files or more\n"
    );
    assert!(!dir.join("x.png").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// `bvhview --help` and the window's help overlay (H) name every key the window reads.
#[test]
fn help_and_the_help_overlay_list_every_window_key() {
    let out = bvhview(&["--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout).to_string();
    let overlay = bvhview::render::hud::help_lines().join("\n");
    for key in [
        "W ",
        "S ",
        "A / D",
        "Space",
        "Home / End",
        "+ / -",
        "L ",
        "F ",
        "C ",
        "V ",
        "T",
        "O ",
        "I ",
        "H",
        "N ",
        "B ",
        "K ",
        "J/Shift+J",
        "R ",
        "P ",
        "drop",
        "Esc",
    ] {
        let compact = |text: &str| text.replace(" / Shift+J", "/Shift+J");
        assert!(
            compact(&help).contains(key),
            "--help lacks {key:?}:\n{help}"
        );
        assert!(
            overlay.contains(key),
            "the overlay lacks {key:?}:\n{overlay}"
        );
    }
}

/// Ctrl-C while an animated picture is being written: the hidden temporary is removed, nothing
/// appears under the output's name, and the process ends by the signal itself, which a shell
/// reports as 128 + its number (it was 130 for every signal).
#[test]
fn an_interrupted_write_leaves_nothing() {
    // Ctrl-C, and what a service manager or a closed terminal sends.
    for (signal, number, what) in [
        ("INT", 2, "interrupted"),
        ("TERM", 15, "terminated"),
        ("HUP", 1, "hung up"),
    ] {
        interrupt_a_write(signal, number, what);
    }
}

fn interrupt_a_write(signal: &str, number: i32, what: &str) {
    use std::os::unix::process::ExitStatusExt;
    let dir = crate::common::scratch_folder(&format!("interrupt-{signal}"));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("walk.gif");
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    // The planted pause holds the write once its temporary file exists, until the signal comes
    // (no test waits on the clock: a sleep would make the verdict depend on the machine's speed).
    let mut child = with_default_signals(&mut std::process::Command::new(env!(
        "CARGO_BIN_EXE_bvhview"
    )))
    .env("BVHVIEW_PLANT_PAUSE", "output")
    .args([
        "snapshot",
        walk.to_str().unwrap(),
        "--frames",
        "0..2",
        "--size",
        "64x64",
    ])
    .args(["--fps", "30", "-q", "-o"])
    .arg(&out)
    .stderr(std::process::Stdio::piped())
    .spawn()
    .unwrap();
    let started = std::time::Instant::now();
    let partial = loop {
        let found = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.path())
            .find(|p| p.to_string_lossy().ends_with(".partial"));
        if let Some(found) = found {
            break found;
        }
        assert!(
            started.elapsed() < std::time::Duration::from_secs(60),
            "no temporary appeared"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the signal"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let killed = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.signal(), Some(number), "SIG{signal}");
    assert_eq!(
        String::from_utf8_lossy(&output.stderr),
        format!("bvhview: {what}; no output was left half-written\n")
    );
    assert!(!partial.exists(), "{} was left", partial.display());
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(dir).unwrap();
}

/// A take without frames beside one with frames, in the studio look and as an animation: the
/// rest pose stands still while the other plays.
#[test]
fn a_rest_pose_beside_a_take_draws_in_every_look() {
    let dir = crate::common::scratch_folder("restbeside");
    std::fs::create_dir_all(&dir).unwrap();
    let rest = dir.join("rest.bvh");
    std::fs::write(
        &rest,
        "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n \
         End Site\n {\n  OFFSET 0 10 0\n }\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n",
    )
    .unwrap();
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    for (look, out) in [
        ("article", "a.png"),
        ("studio", "s.png"),
        ("studio", "s.gif"),
    ] {
        let out = dir.join(out);
        let mut args = vec![
            "snapshot",
            rest.to_str().unwrap(),
            walk.to_str().unwrap(),
            "--look",
            look,
            "--hud",
            "-q",
        ];
        if out.extension().is_some_and(|e| e == "gif") {
            args.extend(["--frames", "0..3", "--size", "64x64"]);
        }
        args.extend(["-o", out.to_str().unwrap()]);
        let result = bvhview(&args);
        assert!(
            result.status.success(),
            "{look} {}: {}",
            out.display(),
            String::from_utf8_lossy(&result.stderr)
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The framed views hold any rig's size: the walk scaled to millimetres (1.6 m = 1600 units,
/// its camera 4000 units away, past the article's far plane at 1000) and to metres (its camera
/// under 5 units away) draws as the walk does, and `info` says what it guesses.
#[test]
fn a_rig_in_millimetres_or_metres_draws_like_one_in_centimetres() {
    let dir = crate::common::scratch_folder("scales");
    std::fs::create_dir_all(&dir).unwrap();
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let snapshot = |input: &std::path::Path, output: &std::path::Path| {
        let out = bvhview(&[
            "snapshot",
            input.to_str().unwrap(),
            "--frame",
            "10",
            "--look",
            "studio",
            "--style",
            "both",
            "-q",
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        bvhview::render::Image::read_png(output).unwrap()
    };
    let original = snapshot(&walk, &dir.join("walk.png"));
    for (scale, units, allowed) in [("10", "millimetres", 720), ("0.01", "metres", 3600)] {
        let scaled = dir.join(format!("walk_{scale}.bvh"));
        let out = bvhview(&[
            "convert",
            walk.to_str().unwrap(),
            "--scale",
            scale,
            "-q",
            "-o",
            scaled.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        let info = String::from_utf8_lossy(&bvhview(&["info", scaled.to_str().unwrap()]).stdout)
            .into_owned();
        assert!(
            info.contains(&format!("units:            {units} (")),
            "{info}"
        );
        let picture = snapshot(&scaled, &dir.join(format!("walk_{scale}.png")));
        // Only the spheres' edges round differently (measured: 444 and 1808 of 360 000).
        let differing = picture.differing_pixels(&original);
        assert!(differing <= allowed, "x{scale}: {differing} pixels differ");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// `-o` onto a FIFO writes into it (a reader gets the CSV) and leaves it a
/// FIFO; onto a device, the device stays. Both used to be replaced by a regular file.
#[test]
fn an_output_that_is_a_fifo_or_a_device_is_written_to() {
    use std::os::unix::fs::FileTypeExt;
    let dir = crate::common::scratch_folder("fifo");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("out.csv");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let written = bvhview(&["positions", &tiny(), "-q", "-o", fifo.to_str().unwrap()]);
    assert!(written.status.success(), "{written:?}");
    let received = reader.join().unwrap();
    let expected = bvhview(&["positions", &tiny()]);
    assert_eq!(received, expected.stdout);
    assert!(
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "nothing beside it"
    );
    let null = bvhview(&["positions", &tiny(), "-q", "-o", "/dev/null"]);
    assert!(null.status.success(), "{null:?}");
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--version` names the row reader this machine runs (machines differ, and one
/// without AVX-512 never runs rows/wide.rs).
#[test]
fn version_names_the_row_reader() {
    let out = bvhview(&["--version"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let reader = bvhview::bvh::rows::row_reader();
    assert_eq!(
        text,
        format!(
            "bvhview {}\nrow reader: {reader}\n",
            env!("CARGO_PKG_VERSION")
        )
    );
}

/// The article's picture for every file, by default. Each repository file's default
/// snapshot is the one made with the guess off (`--up y`, every file as written, as the
/// article's program draws it); a file that stands along z says so once, with what stands it up
/// (stderr, and the HUD when shown).
#[test]
fn the_default_view_is_the_article_picture_for_every_file() {
    let dir = crate::common::scratch_folder("default-view");
    std::fs::create_dir_all(&dir).unwrap();
    let mut inputs: Vec<Vec<String>> = std::fs::read_dir(repo_data("bvh"))
        .unwrap()
        .map(|e| vec![e.unwrap().path().display().to_string()])
        .filter(|p| p[0].ends_with(".bvh"))
        .collect();
    inputs.sort();
    inputs.push(vec![
        repo_data("asf_amc/heiden_12.asf").display().to_string(),
        "--motion".into(),
        repo_data("asf_amc/heiden_12_02_01.amc")
            .display()
            .to_string(),
    ]);
    let mut lying = 0;
    for (i, input) in inputs.iter().enumerate() {
        let shot = |extra: &[&str], name: &str| {
            let path = dir.join(format!("{i}-{name}.png"));
            let mut args: Vec<&str> = vec!["snapshot"];
            args.extend(input.iter().map(String::as_str));
            let size = if extra.contains(&"--hud") {
                "400x400"
            } else {
                "96x96"
            };
            args.extend(["--frame", "0", "--size", size, "-q", "-o"]);
            args.push(path.to_str().unwrap());
            args.extend(extra);
            let out = bvhview(&args);
            assert!(out.status.success(), "{input:?}: {out:?}");
            let picture = bvhview::render::Image::read_png(&path).unwrap();
            (picture, String::from_utf8(out.stderr).unwrap())
        };
        let (default, said) = shot(&[], "default");
        let (as_written, _) = shot(&["--up", "y"], "y");
        assert_eq!(default.differing_pixels(&as_written), 0, "{input:?}");
        let stands_along_z = {
            let loaded = crate::common::load_take(
                std::path::Path::new(&input[0]),
                input.get(2).map(std::path::Path::new),
                None,
            )
            .unwrap();
            bvhview::model::pose::Up::guess(&loaded.skeleton) == bvhview::model::pose::Up::Z
        };
        let hint = "drawn as written, as the article draws every file (--up z or --look studio stands it up; V in the window)";
        assert_eq!(
            said.matches(hint).count(),
            usize::from(stands_along_z),
            "{input:?}: {said}"
        );
        if stands_along_z {
            lying += 1;
            // The same figure as written; asked for with --up y, the HUD has no hint to give.
            let (with_hint, _) = shot(&["--hud"], "hud");
            let (without, _) = shot(&["--hud", "--up", "y"], "hud-y");
            assert!(with_hint.differing_pixels(&without) > 0, "{input:?}");
        }
    }
    assert!(lying >= 1, "no repository file stands along z");
    std::fs::remove_dir_all(dir).unwrap();
}

/// `command` with SIGINT, SIGTERM and SIGHUP at their default actions in its process, whatever
/// this test run inherited: a run a script started in the background ignores SIGINT, one under
/// `nohup` ignores SIGHUP, and bvhview rightly keeps a signal ignored that it started with.
fn with_default_signals(command: &mut Command) -> &mut Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: between fork and exec the hook calls only signal(2), which is async-signal-safe.
    unsafe {
        command.pre_exec(|| {
            for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                libc::signal(signal, libc::SIG_DFL);
            }
            Ok(())
        })
    }
}

/// A shell sees 128 + the signal, and `nohup` keeps SIGHUP ignored (signal
/// handling replaced an inherited SIG_IGN, so `nohup bvhview …` died on hang-up).
#[test]
fn a_shell_sees_128_plus_the_signal_and_nohup_is_kept() {
    let bin = env!("CARGO_BIN_EXE_bvhview");
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let dir = crate::common::scratch_folder("nohup");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("walk.gif");
    // The planted pause holds bvhview once its temporary file exists, until a signal ends it: the
    // signals arrive mid-write however fast the machine (no sleep decides the verdict). With
    // SIGHUP ignored, the SIGTERM after it is what ends the process.
    let script = format!(
        "{{trap}} BVHVIEW_PLANT_PAUSE=output '{bin}' snapshot '{walk}' --frames 0..2 --size 64x64 --fps 30 -q -o '{out}' & \
         pid=$!; while [ -z \"$(ls -A '{dir}')\" ] && kill -0 $pid; do sleep 0.01; done; kill -HUP $pid; {{then}} wait $pid; echo $?",
        walk = walk.display(),
        out = out.display(),
        dir = dir.display()
    );
    let run = |trap: &str, then: &str| {
        let script = script.replace("{trap}", trap).replace("{then}", then);
        let output = with_default_signals(&mut Command::new("sh"))
            .arg("-c")
            .arg(script)
            .output()
            .unwrap();
        String::from_utf8(output.stdout).unwrap().trim().to_string()
    };
    assert_eq!(run("", ""), "129");
    assert!(!out.exists());
    // As `nohup` starts it: SIGHUP ignored, so only the SIGTERM sent next ends it (143, not 129).
    assert_eq!(run("trap '' HUP;", "kill -TERM $pid;"), "143");
    assert!(!out.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

/// `-o x.json` without `--format` writes JSON, not CSV under a .json name; `--format` still
/// decides when given.
#[test]
fn positions_to_a_json_name_write_json() {
    let dir = crate::common::scratch_folder("json-name");
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("p.json");
    let out = bvhview(&["positions", &tiny(), "-q", "-o", json.to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    assert!(
        std::fs::read_to_string(&json)
            .unwrap()
            .starts_with("{\"frame_time\":")
    );
    let out = bvhview(&[
        "positions",
        &tiny(),
        "--format",
        "csv",
        "-q",
        "-o",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(
        std::fs::read_to_string(&json)
            .unwrap()
            .starts_with("frame,joint,x,y,z")
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `bvhview info DIR | head -1` ended in a panic ("failed printing to stdout: Broken
/// pipe", exit 101). A reader that has gone ends the output quietly; the exit code is the one
/// the files earned. The pipe is closed before bvhview writes, so it is gone at the first line.
#[test]
fn info_of_a_folder_into_a_closed_pipe_ends_quietly() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bvh");
    let mut child = crate::common::bvhview_command()
        .arg("info")
        .arg(&data)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("Broken pipe"), "{stderr}");
    assert_eq!(output.status.code(), Some(0), "{stderr}");
}

/// Runs bvhview with `input` on its standard input.
fn with_stdin(args: &[&str], input: &[u8]) -> Output {
    use std::io::Write as _;
    let mut child = crate::common::bvhview_command()
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let input = input.to_vec();
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let output = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    output
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// `-` reads a take from standard input and writes to standard output, as a user
/// piping between Unix tools expects; the format comes from --from or --to, or the first bytes.
#[test]
fn a_dash_reads_standard_input_and_writes_standard_output() {
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let bytes = std::fs::read(&walk).unwrap();
    let walk = walk.to_str().unwrap();
    // info -: the summary of the same take, named <stdin>.
    let piped = with_stdin(&["info", "-"], &bytes);
    let named = bvhview(&["info", walk]);
    assert!(
        piped.status.success(),
        "{}",
        String::from_utf8_lossy(&piped.stderr)
    );
    let tail = |o: &Output| {
        let text = String::from_utf8_lossy(&o.stdout).to_string();
        text.lines().skip(1).collect::<Vec<_>>().join("\n")
    };
    assert_eq!(tail(&piped), tail(&named));
    // positions - -o -: the same numbers as from the file.
    let piped = with_stdin(&["positions", "-", "-o", "-"], &bytes);
    let named = bvhview(&["positions", walk]);
    assert!(
        piped.status.success(),
        "{}",
        String::from_utf8_lossy(&piped.stderr)
    );
    assert_eq!(piped.stdout, named.stdout);
    // convert - -o - --to glb, then that GLB through standard input again (told by its bytes).
    let glb = with_stdin(&["convert", "-", "-o", "-", "--to", "glb", "-q"], &bytes);
    assert!(
        glb.status.success(),
        "{}",
        String::from_utf8_lossy(&glb.stderr)
    );
    assert!(glb.stdout.starts_with(b"glTF"));
    let back = with_stdin(
        &["convert", "-", "-o", "-", "--to", "bvh", "-q"],
        &glb.stdout,
    );
    assert!(
        back.status.success(),
        "{}",
        String::from_utf8_lossy(&back.stderr)
    );
    assert!(back.stdout.starts_with(b"HIERARCHY"));
    // No --to for standard output, and bytes nothing can tell: one clear line each, exit 2.
    let untold = with_stdin(&["convert", "-", "-o", "-"], &bytes);
    assert_eq!(untold.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&untold.stderr).contains("--to bvh, glb, gltf or fbx"));
    let unknown = with_stdin(&["info", "-"], b"just some words\n");
    assert_eq!(unknown.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("--from bvh, fbx, gltf or glb"));
    let empty = with_stdin(&["info", "-"], b"");
    assert_eq!(empty.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&empty.stderr).contains("<stdin>: empty: no take to read"));
}

/// `snapshot --overlay` (and side by side) refused ASF/AMC takes. An .amc right after
/// its .asf is its motion: the pair stands beside a BVH, and the picture of the pair alone is
/// the one `--motion` gives.
#[test]
fn an_asf_amc_pair_stands_beside_other_takes() {
    let dir = tempfile::tempdir().unwrap();
    let asf = repo_data("asf_amc/heiden_12.asf").display().to_string();
    let amc = repo_data("asf_amc/heiden_12_02_01.amc")
        .display()
        .to_string();
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/walk.bvh")
        .display()
        .to_string();
    let out = |name: &str| dir.path().join(name).display().to_string();
    for args in [
        vec!["snapshot", &asf, &amc, &walk, "--overlay", "--frame", "5"],
        vec!["snapshot", &asf, &amc, &walk, "--frame", "5"],
    ] {
        let run = bvhview(&[&args[..], &["-q", "-o", &out("both.png")]].concat());
        assert!(
            run.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let paired = bvhview(&[
        "snapshot",
        &asf,
        &amc,
        "--frame",
        "5",
        "-q",
        "-o",
        &out("pair.png"),
    ]);
    let flagged = bvhview(&[
        "snapshot",
        &asf,
        "--motion",
        &amc,
        "--frame",
        "5",
        "-q",
        "-o",
        &out("flag.png"),
    ]);
    assert!(paired.status.success() && flagged.status.success());
    let a = bvhview::render::Image::read_png(std::path::Path::new(&out("pair.png"))).unwrap();
    let b = bvhview::render::Image::read_png(std::path::Path::new(&out("flag.png"))).unwrap();
    assert_eq!(a.differing_pixels(&b), 0);
    let both = bvhview(&[
        "snapshot",
        &asf,
        &amc,
        "--motion",
        &amc,
        "--frame",
        "5",
        "-o",
        &out("x.png"),
    ]);
    assert_eq!(both.status.code(), Some(2));
}

/// A built-in skeleton is a take every command reads by its name: its rest pose, one frame;
/// `info --list-skeletons` names each one; a file of that name in the current folder wins and
/// is said.
#[test]
fn built_in_skeletons_are_takes_every_command_reads() {
    let info = bvhview_stdout(&["info", "smpl22"]);
    assert!(info.contains("joints:           22\n"), "{info}");
    assert!(info.contains("frames:           1\n"), "{info}");
    assert!(
        info.contains("units:            centimetres (sure"),
        "{info}"
    );
    let printed = bvhview_stdout(&["print", "smpl22"]);
    assert!(printed.starts_with("pelvis : "), "{printed}");
    let folder = common::scratch_folder("built_in");
    let csv = folder.join("smpl22.csv");
    bvhview_stdout(&["positions", "smpl22", "-o", csv.to_str().unwrap()]);
    let rows = rows(&std::fs::read_to_string(&csv).unwrap());
    assert_eq!(rows.len(), 27);
    assert_eq!(find(&rows, 0, "pelvis"), [0.0, 97.0, 0.0]);
    let listed = bvhview_stdout(&["info", "--list-skeletons"]);
    assert!(listed.starts_with("smpl22: 22 joints, centimetres, 1.74 m tall at rest, y up; "));
    // A file named like the built-in, in the current folder: read, and said.
    std::fs::copy(data("bvh/bvhparser_simple.bvh"), folder.join("smpl22")).unwrap();
    let out = bvhview_command()
        .args(["info", "smpl22"])
        .current_dir(&folder)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(!text.contains("joints:           22\n"), "{text}");
    assert!(
        text.contains("the file 'smpl22' in this folder was read, not the built-in skeleton"),
        "{text}"
    );
    // A built-in has no motion file and no takes to choose.
    let out = bvhview(&["info", "smpl22", "--take", "1"]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `convert --out-units`: the take scaled from its own units into the ones asked for, in BVH,
/// and in FBX stated in `UnitScaleFactor` (read back as the same metres).
#[cfg(feature = "fbx")]
#[test]
fn convert_writes_the_units_asked_for() {
    let folder = common::scratch_folder("out_units");
    let walk = data("bvh/bvh11_131_01.bvh");
    let csv = |input: &std::path::Path, name: &str| {
        let out = folder.join(name);
        bvhview_stdout(&[
            "positions".as_ref(),
            input.as_os_str(),
            "--frames".as_ref(),
            "7".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        rows(&std::fs::read_to_string(out).unwrap())
    };
    let source = csv(&walk, "source.csv");
    // CMU units are 1/0.45 inch: 0.0254 / 0.45 metres.
    let factor = 0.0254f32 / 0.45;
    for (name, units, per_metre) in [
        ("m.bvh", "m", 1.0f32),
        ("mm.bvh", "mm", 1000.0),
        ("m.fbx", "m", 1.0),
    ] {
        let out = folder.join(name);
        bvhview_stdout(&[
            "convert".as_ref(),
            walk.as_os_str(),
            "--out-units".as_ref(),
            units.as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        let written = csv(&out, &format!("{name}.csv"));
        assert_eq!(written.len(), source.len());
        for (a, b) in source.iter().zip(&written) {
            for k in 0..3 {
                let want = a.2[k] * factor * per_metre;
                assert!(
                    (want - b.2[k]).abs() <= 1e-4 * per_metre,
                    "{name}: {a:?} vs {b:?}"
                );
            }
        }
    }
    let out = bvhview(&[
        "convert",
        walk.to_str().unwrap(),
        "--out-units",
        "parsecs",
        "-o",
        "x.bvh",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected mm, cm, m, in, ft"));
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `positions --out-units`: every coordinate in the units asked for, from the take's own.
#[test]
fn positions_write_the_units_asked_for() {
    let walk = data("bvh/bvh11_131_01.bvh").display().to_string();
    let own = rows(&bvhview_stdout(&["positions", &walk, "--frames", "3"]));
    let metres = rows(&bvhview_stdout(&[
        "positions",
        &walk,
        "--frames",
        "3",
        "--out-units",
        "m",
    ]));
    let factor = 0.0254f32 / 0.45; // CMU units
    for (a, b) in own.iter().zip(&metres) {
        assert!(
            (0..3).all(|k| (a.2[k] * factor - b.2[k]).abs() < 1e-5),
            "{a:?} vs {b:?}"
        );
    }
}

/// `--units` says what a take's lengths are in, over the guess: `info` shows them given, the
/// size warning that second-guesses units is not said, and a dataset's heights follow them and
/// its manifest records that they were given.
#[test]
fn units_given_replace_the_guess() {
    let simple = data("bvh/bvhparser_simple.bvh").display().to_string();
    let guessed = bvhview_stdout(&["info", &simple]);
    assert!(
        guessed.contains("units:            inches (likely"),
        "{guessed}"
    );
    let given = bvhview_stdout(&["info", &simple, "--units", "cm"]);
    assert!(
        given.contains("units:            centimetres (stated: given, not guessed; it stands 29.2 tall, 0.292 m)"),
        "{given}"
    );
    assert!(given.contains("warnings:         none"), "{given}");
    let folder = common::scratch_folder("units_given");
    let takes = takes_folder(&folder, &["bvhparser_simple.bvh"]);
    let manifest = compiled(&takes, &folder.join("set"), &["--units", "cm"]);
    let clip = &manifest["clips"][0];
    assert_eq!(clip["units"], "centimetres");
    assert_eq!(clip["units_given"], true);
    std::fs::remove_dir_all(&folder).unwrap();
}

/// With `--lock-feet`, `retarget`'s check line measures what is written, the locked legs (their
/// bones leave the source's directions while the feet are held), not the take before the lock.
#[test]
fn the_retarget_check_measures_the_locked_take() {
    let folder = common::scratch_folder("lock_check");
    let walk = data("bvh/bvh11_131_01.bvh").display().to_string();
    let check_line = |extra: &[&str]| {
        let out = folder.join("out.bvh");
        let mut args = vec![
            "retarget",
            &walk,
            "--onto",
            "smpl22",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let output = bvhview(&args);
        assert_eq!(output.status.code(), Some(0), "{output:?}");
        String::from_utf8_lossy(&output.stderr)
            .lines()
            .find(|l| l.starts_with("check: "))
            .unwrap()
            .to_string()
    };
    let free = check_line(&[]);
    let locked = check_line(&["--lock-feet"]);
    assert!(free.contains("bones 0.0° median, 0.0° p99"), "{free}");
    assert!(locked.ends_with("(after --lock-feet)"), "{locked}");
    assert!(!locked.contains("0.0° p99"), "{locked}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `convert --rest tpose` makes a T-pose rest (as `info` reads it) of a CMU walk whose rest has
/// the arms down, and `snapshot --rest` draws a rest pose (not with --frames).
#[test]
fn a_t_pose_rest_is_read_and_drawn() {
    let folder = common::scratch_folder("tpose");
    let walk = data("bvh/bvh11_131_01.bvh").display().to_string();
    let before = bvhview_stdout(&["info", &walk]);
    assert!(
        before.contains("rest pose:        neither a T-pose nor an A-pose: arms 90.0° below"),
        "{before}"
    );
    let tpose = folder.join("tpose.bvh");
    bvhview_stdout(&[
        "convert",
        &walk,
        "--rest",
        "tpose",
        "-o",
        tpose.to_str().unwrap(),
    ]);
    let after = bvhview_stdout(&["info", tpose.to_str().unwrap()]);
    assert!(after.contains("rest pose:        a T-pose: arms 0.0° above and 0.0° above level, legs 0.0° and 0.0° from straight down"), "{after}");
    let png = folder.join("rest.png");
    bvhview_stdout(&[
        "snapshot",
        tpose.to_str().unwrap(),
        "--rest",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(std::fs::metadata(&png).unwrap().len() > 0);
    let out = bvhview(&[
        "snapshot", &walk, "--rest", "--frames", "0..3", "-o", "x.gif",
    ]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `retarget --out-units m`: the result (in the target's centimetres) written in metres.
#[test]
fn retarget_writes_the_units_asked_for() {
    let folder = common::scratch_folder("retarget_units");
    let walk = data("bvh/bvh11_131_01.bvh").display().to_string();
    let (cm, m) = (folder.join("cm.bvh"), folder.join("m.bvh"));
    bvhview_stdout(&[
        "retarget",
        &walk,
        "--onto",
        "smpl22",
        "-o",
        cm.to_str().unwrap(),
    ]);
    bvhview_stdout(&[
        "retarget",
        &walk,
        "--onto",
        "smpl22",
        "--out-units",
        "m",
        "-o",
        m.to_str().unwrap(),
    ]);
    let at = |path: &std::path::Path| {
        rows(&bvhview_stdout(&[
            "positions",
            path.to_str().unwrap(),
            "--frames",
            "9",
        ]))
    };
    for (a, b) in at(&cm).iter().zip(&at(&m)) {
        assert!(
            (0..3).all(|k| (a.2[k] * 0.01 - b.2[k]).abs() < 1e-5),
            "{a:?} vs {b:?}"
        );
    }
    assert!(bvhview_stdout(&["info", m.to_str().unwrap()]).contains("units:            metres"));
    std::fs::remove_dir_all(&folder).unwrap();
}

/// Units given, then `--scale`: the scaled lengths are no longer in the units given, so they are
/// guessed again (a 1.74 m figure in centimetres scaled by 0.01 is written 1.74 m tall).
#[test]
fn units_given_then_scaled_are_guessed_again() {
    let folder = common::scratch_folder("units_scaled");
    let free = data("bvh/bvhpython_test_freebvh.bvh").display().to_string();
    let out = folder.join("u.bvh");
    bvhview_stdout(&[
        "convert",
        &free,
        "--units",
        "cm",
        "--scale",
        "0.01",
        "--out-units",
        "m",
        "-o",
        out.to_str().unwrap(),
    ]);
    let info = bvhview_stdout(&["info", out.to_str().unwrap()]);
    assert!(info.contains("it stands 1.74 tall, 1.74 m"), "{info}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `info --up` and `dataset --up` say what axis a take stands along, over the guess: `info` says
/// it was given, and a dataset turns the take by it and records it per clip.
#[test]
fn an_up_axis_given_replaces_the_guess() {
    let walk = data("bvh/makehuman_walk1.bvh").display().to_string();
    let guessed = bvhview_stdout(&["info", &walk]);
    assert!(guessed.contains("up axis:          z (sure"), "{guessed}");
    let given = bvhview_stdout(&["info", &walk, "--up", "y"]);
    assert!(
        given.contains("up axis:          y (stated: given, not guessed)"),
        "{given}"
    );
    let folder = common::scratch_folder("up_given");
    let takes = takes_folder(&folder, &["makehuman_walk1.bvh"]);
    let guessed = compiled(&takes, &folder.join("guessed"), &[]);
    let given = compiled(&takes, &folder.join("given"), &["--up", "y"]);
    assert_eq!(guessed["clips"][0]["up"], "z");
    assert!(guessed["clips"][0].get("up_given").is_none());
    assert_eq!(given["clips"][0]["up"], "y");
    assert_eq!(given["clips"][0]["up_given"], true);
    std::fs::remove_dir_all(&folder).unwrap();
}

/// `retarget --up`: the axis given turns the take up as the guess would: the right one gives
/// the guess's bytes, the wrong one (a Z-up MakeHuman walk said to be Y up) a figure lying down.
#[test]
fn retarget_takes_the_up_axis_given() {
    let folder = common::scratch_folder("retarget_up");
    let walk = data("bvh/makehuman_walk1.bvh").display().to_string();
    let written = |up: &[&str], name: &str| {
        let out = folder.join(name);
        let mut args = vec![
            "retarget",
            &walk,
            "--onto",
            "smpl22",
            "-o",
            out.to_str().unwrap(),
            "--force",
        ];
        args.extend_from_slice(up);
        let output = bvhview(&args);
        assert_eq!(output.status.code(), Some(0), "{output:?}");
        std::fs::read(out).unwrap()
    };
    let guessed = written(&[], "guessed.bvh");
    let right = written(&["--up", "z"], "right.bvh");
    let wrong = written(&["--up", "y"], "wrong.bvh");
    assert_eq!(guessed, right);
    assert_ne!(guessed, wrong);
    let lying = bvhview_stdout(&["info", folder.join("wrong.bvh").to_str().unwrap()]);
    assert!(lying.contains("up axis:          z"), "{lying}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// A map file's `[stated.FINGERPRINT]` sections say what each rig of a mixed folder is: a
/// dataset takes each one's units and up axis as given; a wrong value is refused with its line.
#[test]
fn a_map_file_states_each_rigs_units_and_up_axis() {
    let folder = common::scratch_folder("stated_rigs");
    let takes = takes_folder(&folder, &["bvhparser_simple.bvh", "makehuman_walk1.bvh"]);
    let fingerprint = |name: &str| {
        let info = bvhview_stdout(&["info", takes.join(name).to_str().unwrap()]);
        info.lines()
            .find_map(|l| l.strip_prefix("fingerprint:"))
            .unwrap()
            .trim()
            .to_string()
    };
    let map = folder.join("rigs.toml");
    std::fs::write(
        &map,
        format!(
            "[stated.{}]\nunits = \"cm\"\n\n[stated.{}]\nup = \"y\"\n",
            fingerprint("bvhparser_simple.bvh"),
            fingerprint("makehuman_walk1.bvh")
        ),
    )
    .unwrap();
    let manifest = compiled(
        &takes,
        &folder.join("set"),
        &["--map", map.to_str().unwrap()],
    );
    let clip = |path: &str| {
        manifest["clips"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["path"] == path)
            .unwrap()
            .clone()
    };
    assert_eq!(clip("bvhparser_simple.bvh")["units"], "centimetres");
    assert_eq!(clip("bvhparser_simple.bvh")["units_given"], true);
    assert_eq!(clip("makehuman_walk1.bvh")["up"], "y");
    assert_eq!(clip("makehuman_walk1.bvh")["up_given"], true);
    std::fs::write(&map, "[stated.abc]\nup = \"w\"\n").unwrap();
    let out = bvhview(&[
        "dataset",
        takes.to_str().unwrap(),
        "-o",
        folder.join("no").to_str().unwrap(),
        "--map",
        map.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("rigs.toml:1:1: up \"w\": expected y, z, x, -y, -z or -x"),
        "{out:?}"
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

/// A folder `takes` under `folder` with copies of these repository BVH files.
fn takes_folder(folder: &std::path::Path, names: &[&str]) -> std::path::PathBuf {
    let takes = folder.join("takes");
    std::fs::create_dir(&takes).unwrap();
    for name in names {
        std::fs::copy(data(&format!("bvh/{name}")), takes.join(name)).unwrap();
    }
    takes
}

/// `bvhview dataset TAKES -o OUT EXTRA…`, and the manifest it wrote.
fn compiled(takes: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "dataset",
        takes.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    bvhview_stdout(&args);
    serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap()
}
