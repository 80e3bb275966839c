//! Hostile inputs and options: counts, rates, sizes and names from a file or an option
//! that once panicked, aborted, rendered without end or wrote a file nothing could read. Each
//! now gets one line on stderr, exit 2, and no output file.
// Helpers of the tests a build without every feature leaves out.
#![cfg_attr(
    not(all(feature = "window", feature = "fbx", feature = "gltf")),
    allow(dead_code, unused_imports)
)]

use crate::common;
use common::*;
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::scratch_folder("hostile");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn walk() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/walk.bvh")
        .display()
        .to_string()
}

/// Exit 2, one line on stderr containing `want`, and `output` not written.
fn refused(out: &Output, want: &str, output: &Path) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains(want), "{stderr}");
    assert!(!output.exists(), "{} was written", output.display());
}

/// `bytes` written to a scratch file `name`, then `convert NAME -o NAME.bvh`: refused with one
/// line that starts with the path and then `want`, and nothing written.
fn convert_refuses(name: &str, bytes: &[u8], want: &str) {
    let path = scratch(name);
    std::fs::write(&path, bytes).unwrap();
    let output = scratch(&format!("{name}.bvh"));
    let out = bvhview(&[
        "convert",
        path.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    refused(&out, &format!("{}: {want}", path.display()), &output);
}

/// A one-joint take with two frames and the given frame time and root name.
fn tiny_take(name: &str, frame_time: &str) -> String {
    format!(
        "HIERARCHY\nROOT {name}\n{{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Zrotation Xrotation Yrotation\n\
         \tEnd Site\n\t{{\n\t\tOFFSET 0 1 0\n\t}}\n}}\nMOTION\nFrames: 2\nFrame Time: {frame_time}\n\
         1 2 3\n4 5 6\n"
    )
}

/// Row 4: rates and frame times that asked for billions of frames (a panic, "capacity
/// overflow", or ~666k frames drawn) are refused.
#[test]
fn rates_and_frame_times_that_ask_for_endless_frames_are_refused() {
    let gif = scratch("endless.gif");
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--frames",
        "0..",
        "--fps",
        "1e300",
        "-o",
        gif.to_str().unwrap(),
    ]);
    refused(
        &out,
        "--fps 1e300: expected frames per second from 0.01 to 50",
        &gif,
    );
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--frames",
        "0..",
        "--frame-time",
        "1e308",
        "-o",
        gif.to_str().unwrap(),
    ]);
    refused(&out, "--frame-time 1e308: expected seconds per frame", &gif);
    let apng = scratch("two.apng");
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--frames",
        "0..2",
        "--fps",
        "1e7",
        "-o",
        apng.to_str().unwrap(),
    ]);
    refused(
        &out,
        "--fps 1e7: expected frames per second from 0.01 to 1000",
        &apng,
    );
    // 2 frames of an hour each at 1000 per second: 7.2 million pictures.
    let slow = scratch("slow.bvh");
    std::fs::write(&slow, tiny_take("Hips", "3600")).unwrap();
    let out = bvhview(&[
        "snapshot",
        slow.to_str().unwrap(),
        "--frames",
        "0..",
        "--fps",
        "1000",
        "-o",
        apng.to_str().unwrap(),
    ]);
    refused(&out, "make 7.2e6 frames; at most 100000 can be made", &apng);
    // A frame time no loader should take, from the file itself.
    let huge = scratch("huge_frame_time.bvh");
    std::fs::write(&huge, tiny_take("Hips", "1e308")).unwrap();
    let out = bvhview(&[
        "snapshot",
        huge.to_str().unwrap(),
        "--frames",
        "0..",
        "-o",
        gif.to_str().unwrap(),
    ]);
    refused(
        &out,
        "huge_frame_time.bvh:13:13: expected the frame time (seconds: 0, or 1e-6 to 3600), found '1e308'",
        &gif,
    );
    // Resampling to a rate that would make 7.2 million frames of 3 values is fine; one that
    // makes more values than the limit is not.
    let bvh = scratch("resampled.bvh");
    let out = bvhview(&[
        "convert",
        slow.to_str().unwrap(),
        "--fps",
        "1e300",
        "-o",
        bvh.to_str().unwrap(),
    ]);
    refused(&out, "--fps 1e300", &bvh);
}

/// Row 5: edits and ASF numbers that overflow 32-bit floats wrote `inf` and `null`, exit 0.
#[test]
fn values_that_overflow_are_refused_before_anything_is_written() {
    for name in ["scaled.bvh", "scaled.glb", "scaled.gltf"] {
        let output = scratch(name);
        let out = bvhview(&[
            "convert",
            &walk(),
            "--scale",
            "1e38",
            "-o",
            output.to_str().unwrap(),
        ]);
        refused(
            &out,
            "--scale 1e38 gives values too large for a 32-bit float; nothing was written",
            &output,
        );
    }
    let asf = scratch("huge.asf");
    let bvh = scratch("huge.bvh");
    for (bone, want) in [
        (
            "direction 0 1 0\n    length 1e308",
            "huge.asf:17:12: expected a number (length), found '1e308'",
        ),
        // A direction within rounding of unit length is taken as written (a longer one is
        // normalised), so only the largest length can still overflow.
        (
            "direction 0 1.0009 0\n    length 3.4e38",
            "huge.asf:13:1: bone 'a': direction × length is too large for a 32-bit float",
        ),
        (
            "direction 0 1 0\n    length 1\n    axis 0 0 1e308 XYZ",
            "huge.asf:18:14: expected a number (axis), found '1e308'",
        ),
    ] {
        std::fs::write(&asf, chain_asf(1, bone)).unwrap();
        let out = bvhview(&[
            "convert",
            asf.to_str().unwrap(),
            "-o",
            bvh.to_str().unwrap(),
        ]);
        refused(&out, want, &bvh);
    }
}

/// An ASF skeleton of `bones` bones in one chain, each given `bone` (its direction, length and
/// perhaps axis lines).
fn chain_asf(bones: usize, bone: &str) -> String {
    let mut text = String::from(
        ":version 1.10\n:name chain\n:units\n  mass 1.0\n  length 1\n  angle deg\n:root\n\
         \x20 order TX TY TZ RX RY RZ\n  axis XYZ\n  position 0 0 0\n  orientation 0 0 0\n:bonedata\n",
    );
    for i in 0..bones {
        text.push_str(&format!(
            "  begin\n    id {}\n    name {}\n    {bone}\n    dof rx\n  end\n",
            i + 1,
            bone_name(i)
        ));
    }
    text.push_str(":hierarchy\n  begin\n    root a\n");
    for i in 1..bones {
        text.push_str(&format!("    {} {}\n", bone_name(i - 1), bone_name(i)));
    }
    text.push_str("  end\n");
    text
}

fn bone_name(i: usize) -> String {
    if i == 0 { "a".into() } else { format!("b{i}") }
}

/// Row 10: an ASF chain as deep as the ASF loader takes made a BVH file the BVH loader refused.
/// The writer says so first; a chain one shorter converts and loads back.
#[test]
fn a_writer_that_cannot_nest_deeper_says_so_before_writing() {
    let asf = scratch("deep.asf");
    let bvh = scratch("deep.bvh");
    std::fs::write(&asf, chain_asf(999, "direction 0 1 0\n    length 1")).unwrap();
    let out = bvhview(&[
        "convert",
        asf.to_str().unwrap(),
        "-o",
        bvh.to_str().unwrap(),
    ]);
    refused(
        &out,
        "nests 1001 levels deep; a BVH loader reads at most 1000",
        &bvh,
    );
    // The root, 997 bones and each leaf's End Site: 999 levels.
    std::fs::write(&asf, chain_asf(998, "direction 0 1 0\n    length 1")).unwrap();
    let out = bvhview(&[
        "convert",
        asf.to_str().unwrap(),
        "-q",
        "-o",
        bvh.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let info = bvhview(&["info", bvh.to_str().unwrap()]);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    std::fs::remove_file(bvh).unwrap();
}

/// Row 8: a link to /dev/zero grew the header buffer to --max-size (8.4 GB) before failing.
/// A device is refused by its type before any read; the peak memory of every
/// child this test has waited for stays far below that of the old run.
#[test]
fn a_link_to_dev_zero_is_refused_without_reading_gigabytes() {
    for (name, want) in [
        (
            "zero.bvh",
            "zero.bvh: a character device, not a regular file",
        ),
        (
            "zero.asf",
            "zero.asf: a character device, not a regular file",
        ),
        (
            "zero.amc",
            "zero.amc: a character device, not a regular file",
        ),
    ] {
        let link = scratch(name);
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let asf = repo_data("asf_amc/heiden_12.asf").display().to_string();
        let out = if name.ends_with(".amc") {
            bvhview(&["info", &asf, "--motion", link.to_str().unwrap()])
        } else {
            bvhview(&["info", link.to_str().unwrap()])
        };
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(want), "{stderr}");
    }
    // SAFETY: getrusage writes one rusage struct.
    let usage = unsafe {
        let mut usage = std::mem::zeroed::<libc::rusage>();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage
    };
    let peak_mb = usage.ru_maxrss / 1024;
    assert!(peak_mb < 1024, "a child peaked at {peak_mb} MB");
}

/// Row 12: a 2 MB joint name made a 910 MB CSV; names are at most 1024 bytes, in BVH and ASF.
#[test]
fn a_name_of_megabytes_is_refused_where_it_stands() {
    let long = "A".repeat(2 << 20);
    let bvh = scratch("long_name.bvh");
    std::fs::write(&bvh, tiny_take(&long, "0.1")).unwrap();
    let csv = scratch("long_name.csv");
    let out = bvhview(&[
        "positions",
        bvh.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    refused(
        &out,
        "long_name.bvh:2:6: a name of 2097152 bytes; names are at most 1024 bytes",
        &csv,
    );
    let asf = scratch("long_name.asf");
    std::fs::write(
        &asf,
        chain_asf(1, "direction 0 1 0\n    length 1").replace("name a", &format!("name {long}")),
    )
    .unwrap();
    let out = bvhview(&[
        "positions",
        asf.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    refused(&out, "long_name.asf:15:10: a name of 2097152 bytes", &csv);
}

/// The repository's BVH and ASF/AMC files, as `convert` arguments.
fn inputs() -> Vec<Vec<String>> {
    let mut inputs = Vec::new();
    for entry in std::fs::read_dir(repo_data("bvh")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "bvh") {
            inputs.push(vec![path.display().to_string()]);
        }
    }
    inputs.sort();
    let asf = repo_data("asf_amc/heiden_12.asf");
    let amc = repo_data("asf_amc/heiden_12_02_01.amc");
    inputs.push(vec![
        asf.display().to_string(),
        "--motion".into(),
        amc.display().to_string(),
    ]);
    inputs
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, .. ProptestConfig::default() })]

    /// Point 2: whatever `convert` writes, `info` loads. Any file of the repository, any mix of
    /// edits (scales up to 1e38 included), BVH or glTF: either a clear refusal with no file, or
    /// a file that loads (BVH) or is whole (glTF, checked by the validator elsewhere).
    #[test]
    fn whatever_convert_writes_loads_back(
        pick in any::<prop::sample::Index>(),
        frames in prop::option::of((0usize..40, 1usize..40)),
        fps in prop::option::of(prop_oneof![Just(0.5), Just(24.0), Just(100.0), Just(999.0)]),
        scale in prop::option::of(prop_oneof![Just(0.01f32), Just(-2.0), Just(1e30), Just(1e38)]),
        up in prop::option::of(prop_oneof![Just("y"), Just("z")]),
        mirror in any::<bool>(),
        in_place in any::<bool>(),
        ground in any::<bool>(),
    ) {
        let inputs = inputs();
        let input = pick.get(&inputs);
        let output = scratch(&format!("prop-{}.bvh", std::process::id()));
        let mut args: Vec<String> = vec!["convert".into()];
        args.extend(input.iter().cloned());
        if let Some((start, length)) = frames {
            args.extend(["--frames".into(), format!("{start}..{}", start + length)]);
        }
        if let Some(fps) = fps {
            args.extend(["--fps".into(), fps.to_string()]);
        }
        if let Some(scale) = scale {
            args.extend(["--scale".into(), format!("{scale:e}")]);
        }
        if let Some(up) = up {
            args.extend(["--out-up".into(), up.into()]);
        }
        for (flag, on) in [("--mirror", mirror), ("--in-place", in_place), ("--ground", ground)] {
            if on {
                args.push(flag.into());
            }
        }
        args.extend(["-q".into(), "-o".into(), output.display().to_string()]);
        let _ = std::fs::remove_file(&output);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = bvhview(&args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        match out.status.code() {
            Some(0) => {
                let info = bvhview(&["info", output.to_str().unwrap()]);
                prop_assert!(info.status.success(), "{args:?} wrote a file info refuses: {}",
                    String::from_utf8_lossy(&info.stderr));
            }
            Some(2) => {
                prop_assert!(!output.exists(), "{args:?} failed but wrote: {stderr}");
                // One line for the refusal (the file's own warnings may come before it).
                let lines = stderr.lines().filter(|l| !l.contains(": warning: ")).count();
                prop_assert_eq!(lines, 1, "{:?}: {}", args, stderr);
            }
            other => prop_assert!(false, "{args:?}: exit {other:?}: {stderr}"),
        }
    }
}

/// A FIFO named like a take in a folder is skipped, not waited on;
/// a name of bytes that are not UTF-8 is counted as kept (U+FFFD, three bytes each), so what
/// loads also converts; resampling values near the 32-bit limit gives no NaN; a picture past
/// 8192x8192 is refused.
#[test]
fn review_findings_stay_fixed() {
    // `info FOLDER` with a FIFO named `f.bvh` beside a take.
    let folder = scratch("with-fifo");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(walk(), folder.join("walk.bvh")).unwrap();
    let fifo = folder.join("f.bvh");
    let _ = std::fs::remove_file(&fifo);
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let out = bvhview(&["info", folder.to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("1 file: 1 ok"));
    // A root named by 400 bytes of 0xFF: 1200 bytes as kept, so refused where it stands.
    let named = |count: usize| {
        let mut bytes = tiny_take("X", "0.1").into_bytes();
        let at = bytes.windows(6).position(|w| w == b"ROOT X").unwrap() + 5;
        bytes.splice(at..at + 1, std::iter::repeat_n(0xFF, count));
        bytes
    };
    let ff = scratch("ff.bvh");
    std::fs::write(&ff, named(400)).unwrap();
    let out = bvhview(&["info", ff.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("a name of 1200 bytes"));
    // 300 bytes of 0xFF (900 as kept): loads, converts, loads back.
    std::fs::write(&ff, named(300)).unwrap();
    let back = scratch("ff-back.bvh");
    let out = bvhview(&[
        "convert",
        ff.to_str().unwrap(),
        "-q",
        "-o",
        back.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(bvhview(&["info", back.to_str().unwrap()]).status.success());
    // Positions of -3e38 and 3e38 resampled: between them, never NaN.
    let extreme = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 1 Xposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 1\n-3e38\n3e38\n";
    let path = scratch("extreme.bvh");
    std::fs::write(&path, extreme).unwrap();
    let resampled = scratch("extreme-4.bvh");
    let out = bvhview(&[
        "convert",
        path.to_str().unwrap(),
        "--fps",
        "4",
        "-q",
        "-o",
        resampled.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    let loaded = bvhview::bvh::load_file(&resampled, Default::default()).unwrap();
    assert_eq!(loaded.motion.frame_count(), 5);
    assert!(loaded.motion.data.iter().all(|v| v.is_finite()));
    assert_eq!(loaded.motion.data[2], 0.0);
    // A picture of 16384x16384 (5 GB of buffers) is refused before any is made.
    let png = scratch("huge.png");
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--size",
        "16384x16384",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--size 16384x16384: at most 67108864 pixels (8192x8192)"),
        "{stderr}"
    );
    assert!(!png.exists());
}

/// `--frames` into a folder whose parent is missing is refused, as a file in a
/// missing folder is (it made every missing folder); the folder itself may be new.
#[test]
fn a_frame_folder_in_a_missing_folder_is_refused() {
    let missing = scratch("no/such/dir/");
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--frames",
        "0..2",
        "--size",
        "64x64",
        "-o",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("does not exist"),
        "{out:?}"
    );
    assert!(!scratch("no").exists());
    let new = scratch("frames-new");
    let _ = std::fs::remove_dir_all(&new);
    let out = bvhview(&[
        "snapshot",
        &walk(),
        "--frames",
        "0..2",
        "--size",
        "64x64",
        "-q",
        "-o",
        new.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    assert_eq!(std::fs::read_dir(&new).unwrap().count(), 2);
}

/// An FBX or glTF reader handed damage. A small deterministic generator (xorshift).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// `bytes` with one kind of damage: cut short, bytes flipped, a 32-bit count made huge, a run of
/// bytes repeated, or a run removed.
fn damaged(bytes: &[u8], noise: &mut Noise) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let at = noise.below(out.len());
    match noise.below(5) {
        0 => out.truncate(at),
        1 => {
            for _ in 0..1 + noise.below(8) {
                let i = noise.below(out.len());
                out[i] ^= 1 << noise.below(8);
            }
        }
        2 => {
            let huge = [0xFFu8, 0xFF, 0xFF, 0x7F];
            let end = (at + 4).min(out.len());
            out[at..end].copy_from_slice(&huge[..end - at]);
        }
        3 => {
            let end = (at + 1 + noise.below(64)).min(out.len());
            let run = out[at..end].to_vec();
            out.splice(at..at, run);
        }
        _ => {
            let end = (at + 1 + noise.below(64)).min(out.len());
            out.drain(at..end);
        }
    }
    out
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// The mutation loop over both readers: 400 damaged copies (`BVHVIEW_MUTATIONS` sets how many,
/// `BVHVIEW_MUTATION_SEED` the seed) of each of four files (ASCII and binary FBX, GLB, glTF JSON
/// with a data: URI). Each either loads (and poses) or is refused with
/// `name: what`; none panics.
#[test]
fn damaged_fbx_and_gltf_are_refused_not_crashed() {
    let glb = std::fs::read(repo_data("gltf/bvh11_131_01.glb")).unwrap();
    let sources: Vec<(&str, Vec<u8>)> = vec![
        (
            "ascii.fbx",
            std::fs::read(repo_data("fbx/ufbx/maya_bone_radius_7500_ascii.fbx")).unwrap(),
        ),
        (
            "binary.fbx",
            std::fs::read(repo_data(
                "fbx/ufbx/blender_279_bone_radius_7400_binary.fbx",
            ))
            .unwrap(),
        ),
        ("take.glb", glb),
        ("take.gltf", small_gltf().into_bytes()),
    ];
    let setting = |name: &str, default: u64| {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let mut noise = Noise(setting("BVHVIEW_MUTATION_SEED", 0x9E37_79B9_7F4A_7C15).max(1));
    let (mut loaded, mut refused) = (0, 0);
    for (name, bytes) in &sources {
        for _ in 0..setting("BVHVIEW_MUTATIONS", 400) {
            let input = damaged(bytes, &mut noise);
            let result = if name.ends_with(".fbx") {
                bvhview::fbx::load_bytes(
                    &input,
                    name,
                    &bvhview::take::OpenOptions::new().threads(1),
                )
            } else {
                bvhview::gltf::load_bytes(&input, name, &Default::default())
            };
            match result {
                Ok(read) => {
                    loaded += 1;
                    assert!(read.motion.data.iter().all(|v| v.is_finite()));
                    let last = read.motion.frame_count() - 1;
                    let _ = bvhview::model::pose::world_positions(
                        &read.skeleton,
                        read.motion.frame(last),
                        Default::default(),
                    );
                }
                Err(error) => {
                    refused += 1;
                    let text = error.to_string();
                    assert!(text.starts_with(&format!("{name}: ")), "{text}");
                    assert!(error.is_the_callers(), "{text}");
                    assert_eq!(text.lines().count(), 1, "{text}");
                }
            }
        }
    }
    assert!(
        loaded > 0 && refused > 100,
        "{loaded} loaded, {refused} refused"
    );
}

/// A one-node glTF, animated, its buffer in a data: URI: two keys of a translation.
fn small_gltf() -> String {
    gltf_with(
        r#""uri": "data:application/octet-stream;base64,AAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAA=""#,
        "",
    )
}

/// A glTF JSON whose one buffer has `source` (a `"uri": …` or nothing) and whose first node
/// adds `node` (such as `"children": [0],`).
fn gltf_with(source: &str, node: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}},
  "nodes": [{{{node} "name": "root"}}],
  "buffers": [{{{source}, "byteLength": 32}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 8}},
                  {{"buffer": 0, "byteOffset": 8, "byteLength": 24}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR",
                  "min": [0], "max": [1]}},
                {{"bufferView": 1, "componentType": 5126, "count": 2, "type": "VEC3"}}],
  "animations": [{{"name": "slide", "samplers": [{{"input": 0, "output": 1}}],
                   "channels": [{{"sampler": 0, "target": {{"node": 0, "path": "translation"}}}}]}}]
}}"#
    )
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// Point 5: a glTF's buffers come from its folder or a data: URI, nothing else; counts past the
/// buffer, cycles and broken keys are refused by name; the CLI says `file: what`, exits 2.
#[test]
fn hostile_gltf_buffers_and_counts_are_refused() {
    let folder = scratch("gltf-hostile");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("inside.bin"), [0u8; 32]).unwrap();
    let good = folder.join("good.gltf");
    std::fs::write(&good, small_gltf()).unwrap();
    let out = bvhview(&["info", good.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "outside.gltf",
            gltf_with(r#""uri": "../outside.bin""#, ""),
            "out of the glTF's folder",
        ),
        (
            "absolute.gltf",
            gltf_with(r#""uri": "/etc/passwd""#, ""),
            "only files beside the glTF",
        ),
        (
            "network.gltf",
            gltf_with(r#""uri": "http://example.com/x.bin""#, ""),
            "only files beside",
        ),
        (
            "encoded.gltf",
            gltf_with(r#""uri": "%2E%2E/outside.bin""#, ""),
            "out of the glTF's folder",
        ),
        (
            "bad64.gltf",
            gltf_with(r#""uri": "data:application/octet-stream;base64,@@@@""#, ""),
            "not base64",
        ),
        (
            "short.gltf",
            gltf_with(r#""uri": "data:application/octet-stream;base64,AAAA""#, ""),
            "fewer than its byteLength",
        ),
        (
            "missing.gltf",
            gltf_with(r#""uri": "nothere.bin""#, ""),
            "nothere.bin",
        ),
        (
            "cycle.gltf",
            gltf_with(r#""uri": "inside.bin""#, r#""children": [0],"#),
            "more than one parent",
        ),
        ("json.gltf", "{\"asset\": ".to_string(), "not a valid glTF"),
    ];
    for (name, text, want) in cases {
        let path = folder.join(name);
        std::fs::write(&path, text).unwrap();
        let output = folder.join(format!("{name}.bvh"));
        let out = bvhview(&[
            "convert",
            path.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ]);
        refused(&out, want, &output);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.starts_with(&format!("bvhview: {}: ", path.display())),
            "{stderr}"
        );
    }
    // An accessor counting a billion keys in a 32-byte buffer, keys that go back in time.
    let huge = small_gltf().replacen(
        "\"count\": 2, \"type\": \"SCALAR\"",
        "\"count\": 1000000000, \"type\": \"SCALAR\"",
        1,
    );
    let error =
        bvhview::gltf::load_bytes(huge.as_bytes(), "huge.gltf", &Default::default()).unwrap_err();
    assert!(error.to_string().contains("huge.gltf: "), "{error}");
    let backwards = gltf_with(
        r#""uri": "data:application/octet-stream;base64,AACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAA=""#,
        "",
    );
    let error = bvhview::gltf::load_bytes(backwards.as_bytes(), "back.gltf", &Default::default())
        .unwrap_err();
    assert!(
        error.to_string().contains("not finite and increasing"),
        "{error}"
    );
    // A buffer file that is a link out of the folder.
    let outside = scratch("outside.bin");
    std::fs::write(&outside, [0u8; 32]).unwrap();
    let link = folder.join("link.bin");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&outside, &link).unwrap();
    let linked = folder.join("linked.gltf");
    std::fs::write(&linked, gltf_with(r#""uri": "link.bin""#, "")).unwrap();
    let error = crate::common::load_take(&linked, None, None).unwrap_err();
    assert!(
        error.to_string().contains("leads out of the glTF's folder"),
        "{error}"
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// `scripts/fuzz.sh gltf` (10 minutes): its three timeouts, kept here byte for byte as
/// the bytes they changed in `tests/data/gltf/bvh11_131_01.glb`. Each flips the sign (and some
/// bits) of the first key time, 1/120 s, to about -495 s: the keys still rise, so the take ran
/// from -495 s to 0.5 s, 59,469 frames of 32 joints (1.2 s in a release build, over AFL's 1 s;
/// 12 s in a debug one). glTF's key times start at 0: each is now refused, by name, before a
/// frame is made.
#[test]
fn a_gltf_key_before_0_is_refused_not_stretched_into_minutes() {
    let seed = std::fs::read(repo_data("gltf/bvh11_131_01.glb")).unwrap();
    let flips: [&[(usize, u8)]; 3] = [
        &[(27506, 0xf7), (27507, 0xc3)],
        &[(27505, 0x77), (27506, 0xf7), (27507, 0xc3), (27508, 0x76)],
        &[(27506, 0xf7), (27507, 0xc3), (27508, 0x76), (27509, 0x77)],
    ];
    for (k, flip) in flips.iter().enumerate() {
        let mut bytes = seed.clone();
        for &(at, byte) in flip.iter() {
            bytes[at] = byte;
        }
        let path = scratch(&format!("fuzz-timeout-{k}.glb"));
        std::fs::write(&path, &bytes).unwrap();
        let out = bvhview(&["info", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.starts_with(&format!(
                "bvhview: {}: animation 0: a key at -49",
                path.display()
            )),
            "{stderr}"
        );
        assert!(
            stderr.contains("s, before 0 (glTF's key times start at 0 or later)"),
            "{stderr}"
        );
    }
}

/// Point 5 for FBX: a cut file, a file of noise and an FBX header over nothing each get one line
/// and exit 2.
#[test]
fn truncated_and_noise_fbx_are_refused_by_the_cli() {
    let bytes = std::fs::read(repo_data("fbx/bvh11_131_01.fbx")).unwrap();
    let mut noise = Noise(7);
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("half.fbx", bytes[..bytes.len() / 2].to_vec()),
        ("header.fbx", bytes[..27].to_vec()),
        ("noise.fbx", (0..4096).map(|_| noise.next() as u8).collect()),
        ("empty.fbx", Vec::new()),
    ];
    for (name, input) in cases {
        convert_refuses(name, &input, "");
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// ufbx says only "Failed to load" of most damaged binary files; the message says
/// which record is broken, where, and inside which records. A text file that is not FBX is
/// called that, not "truncated", and nothing of it is quoted.
#[test]
fn a_damaged_fbx_is_refused_with_the_record_and_byte_that_break() {
    let mut bytes = std::fs::read(repo_data("fbx/bvh11_131_01.fbx")).unwrap();
    // FBX 7400: the first record, FBXHeaderExtension, at byte 27 (a 13-byte header and its
    // 18-byte name), holds FBXHeaderVersion at byte 58, whose 16-byte name ends at 87, where its
    // one property starts with the type byte b'I'.
    assert_eq!(bytes[87], b'I');
    bytes[87] = 0xf0;
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "damaged.fbx",
            bytes,
            "damaged FBX: the record \"FBXHeaderVersion\" at byte 58 (inside \
             \"FBXHeaderExtension\"): property type byte 0xf0 at byte 87 is none of FBX's",
        ),
        (
            "text.fbx",
            b"hello\n".to_vec(),
            "not an FBX file: text, but not FBX's `Key: value` lines",
        ),
        (
            "binary.fbx",
            vec![0x00, 0x9f, 0x92, 0x96, 0xff, 0x01],
            "not an FBX file: binary data without FBX's header",
        ),
    ];
    for (name, input, want) in cases {
        convert_refuses(name, &input, want);
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// Found by fuzzing (`scripts/fuzz.sh gltf`, 2026-11-28): a 12-byte GLB whose header's length
/// field is 0 made the gltf crate subtract 12 from it, a panic in a debug build (exit 101) and a
/// wrapped length in a release one. The input is the fuzzer's, byte for byte.
#[test]
fn a_glb_header_shorter_than_itself_is_refused_not_a_panic() {
    let found = [
        0x67, 0x6c, 0x54, 0x46, 0xc0, 0x96, 0x01, 0x41, 0x00, 0x00, 0x00, 0x00,
    ];
    for (name, bytes, want) in [
        (
            "fuzz-crash-0.glb",
            &found[..],
            "a GLB header whose length field (0) is shorter than the header itself",
        ),
        (
            "cut.glb",
            &found[..7],
            "a GLB of 7 bytes, shorter than its 12-byte header",
        ),
    ] {
        convert_refuses(name, bytes, want);
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// A Draco-compressed glTF's refusal was one line of 12,214 characters (an error per
/// accessor); it names the required extension first, then two more and how many are left.
#[test]
fn a_draco_gltf_is_refused_in_one_short_line_naming_the_extension() {
    let accessors: Vec<String> = (0..300)
        .map(|_| r#"{"componentType": 5126, "count": 3, "type": "VEC3"}"#.to_string())
        .collect();
    let text = format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"], "nodes": [{{"name": "a"}}],
        "accessors": [{}]}}"#,
        accessors.join(", ")
    );
    let path = scratch("draco.gltf");
    std::fs::write(&path, text).unwrap();
    let output = scratch("draco.bvh");
    let out = bvhview(&[
        "convert",
        path.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    let want = format!(
        "{}: not a valid glTF (extensionsRequired[0] = \"KHR_draco_mesh_compression\": \
         Unsupported extension; accessors[0].bufferView: Missing data; accessors[1].bufferView: \
         Missing data; and 298 more)",
        path.display()
    );
    refused(&out, &want, &output);
    // The path is a scratch folder's; the rest of the line stays short whatever the file holds.
    assert!(out.stderr.len() - path.display().to_string().len() < 300);
}

// Every file a stranger sends: the glTF and FBX readers.

/// One animated property of a glTF made by [`gltf_take`]: its node, path, key times and values.
struct Keys {
    node: usize,
    path: &'static str,
    times: Vec<f32>,
    values: Vec<f32>,
}

/// A glTF JSON of `nodes` (a JSON array) with one animation of `tracks` (all of them on the
/// first track's sampler when `shared`), its buffer at `uri`; and the buffer's bytes.
fn gltf_take(nodes: &str, tracks: &[Keys], shared: bool, uri: &str) -> (String, Vec<u8>) {
    let (mut bin, mut views, mut accessors, mut samplers, mut channels) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, track) in tracks.iter().enumerate() {
        if !shared || k == 0 {
            let kind = if track.values.len() == 4 * track.times.len() {
                "VEC4"
            } else {
                "VEC3"
            };
            for (values, kind) in [(&track.times, "SCALAR"), (&track.values, kind)] {
                let offset = bin.len();
                bin.extend(values.iter().flat_map(|v| v.to_le_bytes()));
                views.push(format!(
                    r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {}}}"#,
                    4 * values.len()
                ));
                let count = if kind == "SCALAR" {
                    values.len()
                } else {
                    track.times.len()
                };
                accessors.push(format!(
                    r#"{{"bufferView": {}, "componentType": 5126, "count": {count}, "type": "{kind}"}}"#,
                    views.len() - 1
                ));
            }
            samplers.push(format!(
                r#"{{"input": {}, "output": {}}}"#,
                accessors.len() - 2,
                accessors.len() - 1
            ));
        }
        channels.push(format!(
            r#"{{"sampler": {}, "target": {{"node": {}, "path": "{}"}}}}"#,
            samplers.len() - 1,
            track.node,
            track.path
        ));
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "nodes": {nodes},
  "buffers": [{{"uri": "{uri}", "byteLength": {}}}],
  "bufferViews": [{}], "accessors": [{}],
  "animations": [{{"name": "take", "samplers": [{}], "channels": [{}]}}]}}"#,
        bin.len(),
        views.join(","),
        accessors.join(","),
        samplers.join(","),
        channels.join(",")
    );
    (json, bin)
}

/// A translation of node `node` keyed at `times` (x = the time).
fn slide(node: usize, times: Vec<f32>) -> Keys {
    let values = times.iter().flat_map(|&t| [t, 0.0, 0.0]).collect();
    Keys {
        node,
        path: "translation",
        times,
        values,
    }
}

/// `name.gltf` and `name.bin` in `dir` from [`gltf_take`]; the .gltf's path.
fn write_gltf(dir: &Path, name: &str, nodes: &str, tracks: &[Keys], shared: bool) -> PathBuf {
    let (json, bin) = gltf_take(nodes, tracks, shared, &format!("{name}.bin"));
    std::fs::write(dir.join(format!("{name}.bin")), bin).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// `input::load`'s error for `path`, checked to be a refusal (exit 2, one line, `path: …`).
fn load_refused(path: &Path) -> String {
    let error = match crate::common::load_take(path, None, None) {
        Ok(loaded) => panic!(
            "{}: loaded ({} frames), not refused",
            path.display(),
            loaded.motion.frame_count()
        ),
        Err(error) => error,
    };
    let text = error.to_string();
    assert!(error.is_the_callers(), "{text}");
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(text.starts_with(&format!("{}: ", path.display())), "{text}");
    text
}

/// `bvhview ARGS` with the address space held to 4 GB where `prlimit` is there (a reader
/// that allocated a sparse file's size would abort), else plainly.
fn bvhview_within_4gb(args: &[&str]) -> Output {
    let bin = env!("CARGO_BIN_EXE_bvhview");
    let limited = Command::new("prlimit")
        .arg("--as=4000000000")
        .arg(bin)
        .args(args)
        .output();
    match limited {
        Ok(out) => out,
        Err(_) => bvhview(args),
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// A glTF whose buffer is a FIFO waited for a writer for ever; a FIFO named
/// `.fbx` too. Buffers and files are opened without waiting and refused by their type before a
/// read. The FIFO's writer is a thread that waits to be let through once the command is done:
/// a reader that opened the FIFO would get it at once and read nothing (a different message),
/// so this test fails, not hangs, against such a reader.
#[test]
fn a_buffer_or_file_that_is_not_a_regular_file_is_refused_before_a_read() {
    let dir = tempfile::tempdir().unwrap();
    let fifo_answer = |fifo: PathBuf, args: Vec<String>| -> Output {
        assert!(
            Command::new("mkfifo")
                .arg(&fifo)
                .status()
                .unwrap()
                .success()
        );
        let writer = {
            let fifo = fifo.clone();
            std::thread::spawn(move || drop(std::fs::OpenOptions::new().write(true).open(fifo)))
        };
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = bvhview(&args);
        // Let the writer through (an open for reading, without waiting, completes its open).
        use std::os::unix::fs::OpenOptionsExt;
        let _reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(&fifo)
            .unwrap();
        writer.join().unwrap();
        out
    };
    let (json, _) = gltf_take(
        r#"[{"name": "root"}]"#,
        &[slide(0, vec![0.0, 1.0])],
        false,
        "f.bin",
    );
    let gltf = dir.path().join("g.gltf");
    std::fs::write(&gltf, &json).unwrap();
    let out = fifo_answer(
        dir.path().join("f.bin"),
        vec!["info".into(), gltf.display().to_string()],
    );
    refused(
        &out,
        &format!(
            "{}: buffer 'f.bin': a FIFO, not a regular file",
            gltf.display()
        ),
        &dir.path().join("none"),
    );
    // A socket beside the glTF.
    let socket_json = json.replace("f.bin", "s.bin");
    let socket_gltf = dir.path().join("s.gltf");
    std::fs::write(&socket_gltf, socket_json).unwrap();
    let _socket = std::os::unix::net::UnixListener::bind(dir.path().join("s.bin")).unwrap();
    let text = load_refused(&socket_gltf);
    assert!(
        text.contains("buffer 's.bin': a socket, not a regular file"),
        "{text}"
    );
    // The FBX or GLB itself.
    for name in ["take.fbx", "take.glb"] {
        let path = dir.path().join(name);
        let out = fifo_answer(
            path.clone(),
            vec!["info".into(), path.display().to_string()],
        );
        refused(
            &out,
            &format!("{}: a FIFO, not a regular file", path.display()),
            &dir.path().join("none"),
        );
    }
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// A buffer of 6 GB on disk (sparse) of which 32 bytes are used was read
/// whole (an abort under a 4 GB address space); a sparse 6 GB `.fbx` asked for 6 GB at once
/// ("memory allocation of 6000000001 bytes failed", SIGABRT). Now a buffer is read to its
/// byteLength only (a shorter file is refused), and a file read whole is refused by its size
/// on disk past 2 GiB, before a byte is read.
#[test]
fn sparse_files_are_read_only_as_far_as_used_or_refused_by_size() {
    let dir = tempfile::tempdir().unwrap();
    let take = [slide(0, vec![0.0, 1.0])];
    let gltf = write_gltf(dir.path(), "sparse", r#"[{"name": "root"}]"#, &take, false);
    let bin = dir.path().join("sparse.bin");
    std::fs::File::options()
        .write(true)
        .open(&bin)
        .unwrap()
        .set_len(6 << 30)
        .unwrap();
    let out = bvhview_within_4gb(&["info", gltf.to_str().unwrap()]);
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("frames:           2\n"));
    // A buffer file shorter than its byteLength.
    let short = write_gltf(dir.path(), "short", r#"[{"name": "root"}]"#, &take, false);
    std::fs::write(dir.path().join("short.bin"), [0u8; 8]).unwrap();
    let text = load_refused(&short);
    assert!(
        text.contains("buffer 'short.bin': 8 bytes, fewer than its byteLength 32"),
        "{text}"
    );
    // A byteLength of 3 GB over a sparse file that long: refused by the budget, not read.
    let (json, _) = gltf_take(r#"[{"name": "root"}]"#, &take, false, "sparse.bin");
    let big = dir.path().join("big.gltf");
    std::fs::write(
        &big,
        json.replace("\"byteLength\": 32}],", "\"byteLength\": 3000000000}],"),
    )
    .unwrap();
    let text = load_refused(&big);
    assert!(
        text.contains("buffer 'sparse.bin': 3000000000 bytes, more than the 2 GiB"),
        "{text}"
    );
    // A sparse 6 GB FBX.
    let fbx = dir.path().join("sparse.fbx");
    std::fs::copy(repo_data("fbx/bvh11_131_01.fbx"), &fbx).unwrap();
    std::fs::File::options()
        .write(true)
        .open(&fbx)
        .unwrap()
        .set_len(6 << 30)
        .unwrap();
    let out = bvhview_within_4gb(&["info", fbx.to_str().unwrap()]);
    refused(
        &out,
        &format!(
            "{}: 6442450944 bytes, more than the 2 GiB bvhview reads of a binary file (FBX, glTF, .npy: read whole into memory); not read",
            fbx.display()
        ),
        &dir.path().join("none"),
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// 3,600 channels on one sampler of 56,000 keys decoded the sampler 3,600
/// times (3.8 GB, then an abort); keys 1 ms apart with one key at 1,000 s made a million
/// frames of a 15.5 KB file (13 s). Each accessor is now decoded once, and both asks are
/// refused by the file's size before the work; a fair share of one sampler still loads.
#[test]
fn gltf_animation_work_is_bounded_by_the_input_size() {
    let dir = tempfile::tempdir().unwrap();
    let many = |count: usize| {
        let children: Vec<String> = (1..count).map(|i| i.to_string()).collect();
        let mut nodes = vec![format!(
            r#"{{"name": "root", "children": [{}]}}"#,
            children.join(",")
        )];
        nodes.extend((1..count).map(|i| format!(r#"{{"name": "j{i}"}}"#)));
        format!("[{}]", nodes.join(","))
    };
    let turn = |node: usize, keys: usize| Keys {
        node,
        path: "rotation",
        times: (0..keys).map(|k| k as f32 / 30.0).collect(),
        values: (0..keys).flat_map(|_| [0.0, 0.0, 0.0, 1.0]).collect(),
    };
    let tracks: Vec<Keys> = (0..3600)
        .map(|n| turn(n, if n == 0 { 56_000 } else { 0 }))
        .collect();
    let path = write_gltf(dir.path(), "shared", &many(3600), &tracks, true);
    let text = load_refused(&path);
    assert!(
        text.contains("animation 0: its 3600 channels ask for 1.008e9 key values"),
        "{text}"
    );
    // 200 channels on one sampler of 300 keys: within the budget, one take of 300 frames.
    let tracks: Vec<Keys> = (0..200)
        .map(|n| turn(n, if n == 0 { 300 } else { 0 }))
        .collect();
    let path = write_gltf(dir.path(), "fair", &many(200), &tracks, true);
    let loaded = crate::common::load_take(&path, None, None).unwrap();
    assert_eq!(loaded.motion.frame_count(), 300);
    // 999 keys 1 ms apart, then one at 900 s.
    let mut times: Vec<f32> = (0..999).map(|k| k as f32 * 1e-3).collect();
    times.push(900.0);
    let path = write_gltf(
        dir.path(),
        "long",
        r#"[{"name": "root"}]"#,
        &[slide(0, times)],
        false,
    );
    let text = load_refused(&path);
    assert!(
        text.contains("the take lasts 900 s at 1000 fps: 900001 frames of 1 joint and 1 track, more than a file of"),
        "{text}"
    ); // One joint under a chain of 999 nodes, for 400 s at 30 fps: each frame poses all 1000.
    let mut nodes: Vec<String> = (0..999)
        .map(|i| format!(r#"{{"name": "n{i}", "children": [{}]}}"#, i + 1))
        .collect();
    nodes.push(r#"{"name": "leaf"}"#.to_string());
    let turn = Keys {
        node: 999,
        path: "rotation",
        times: vec![0.0, 400.0],
        values: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
    };
    let tracks = [slide(999, vec![0.0, 1.0 / 30.0]), turn];
    let path = write_gltf(
        dir.path(),
        "deep",
        &format!("[{}]", nodes.join(",")),
        &tracks,
        false,
    );
    let text = load_refused(&path);
    assert!(
        text.contains(
            "the take lasts 400 s at 30 fps: 12001 frames of 1 joint (1000 nodes with those \
             above them) and 2 tracks, more than a file of"
        ),
        "{text}"
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// 31 keys at 30 fps and one 1.5 ms later read as 668 frames at 666.7 fps;
/// keys 0.5 ms apart refused the file for "a frame rate of 1999.9 fps" it never states. The
/// rate is the key step that fits the most keys (a warning says when some do not fit); a rate
/// past 1000 fps is sampled at 1000 with a warning; tracks keyed only at their ends do not
/// outvote the one keyed at every frame.
#[test]
fn gltf_frame_rate_is_the_key_step_that_fits_the_most_keys() {
    let dir = tempfile::tempdir().unwrap();
    let mut times: Vec<f32> = (0..31).map(|k| k as f32 / 30.0).collect();
    times.push(1.0015);
    let odd = write_gltf(
        dir.path(),
        "odd",
        r#"[{"name": "root"}]"#,
        &[slide(0, times)],
        false,
    );
    let loaded = crate::common::load_take(&odd, None, None).unwrap();
    assert_eq!(loaded.motion.frame_count(), 31);
    assert_eq!(loaded.motion.frame_time, 1.0 / 30.0);
    let said = warnings_of(&loaded);
    assert!(
        said.contains("1 of 32 key times do not fall on a frame at 30 fps"),
        "{said}"
    );
    // `convert` says it on stderr.
    let out_bvh = dir.path().join("odd.bvh");
    let out = bvhview(&[
        "convert",
        odd.to_str().unwrap(),
        "-o",
        out_bvh.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("do not fall on a frame at 30 fps"));
    // Keys 0.5 ms apart.
    let fast = (0..100).map(|k| k as f32 * 5e-4).collect();
    let fast = write_gltf(
        dir.path(),
        "fast",
        r#"[{"name": "root"}]"#,
        &[slide(0, fast)],
        false,
    );
    let loaded = crate::common::load_take(&fast, None, None).unwrap();
    assert_eq!(loaded.motion.frame_time, 1e-3);
    assert_eq!(loaded.motion.frame_count(), 50);
    let said = warnings_of(&loaded);
    assert!(
        said.contains("its keys are 0.5 ms apart (2000 fps); sampled at 1000 fps"),
        "{said}"
    );
    // Twenty nodes keyed at 0 and 2 s only, one at every frame of 30 fps.
    let children: Vec<String> = (1..21).map(|i| i.to_string()).collect();
    let mut nodes = vec![format!(
        r#"{{"name": "root", "children": [{}]}}"#,
        children.join(",")
    )];
    nodes.extend((1..21).map(|i| format!(r#"{{"name": "j{i}"}}"#)));
    let mut tracks: Vec<Keys> = (1..21).map(|n| slide(n, vec![0.0, 2.0])).collect();
    tracks.push(slide(0, (0..61).map(|k| k as f32 / 30.0).collect()));
    let ends = write_gltf(
        dir.path(),
        "ends",
        &format!("[{}]", nodes.join(",")),
        &tracks,
        false,
    );
    let loaded = crate::common::load_take(&ends, None, None).unwrap();
    assert_eq!(loaded.motion.frame_count(), 61);
    assert_eq!(loaded.motion.frame_time, 1.0 / 30.0);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

/// An FBX of the ufbx test set, `edit`ed, written to `dir/name`.
fn edited_fbx(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text =
        std::fs::read_to_string(repo_data("fbx/ufbx/maya_anim_interpolation_7700_ascii.fbx"))
            .unwrap();
    let edited = edit(text.clone());
    assert_ne!(edited, text, "{name}: the edit changed nothing");
    let path = dir.join(name);
    std::fs::write(&path, edited).unwrap();
    path
}

/// Its one curve (10 keys, the third `value`) moved from the node's translation X to its
/// rotation X.
fn curve_on_rotation(text: String, value: &str) -> String {
    text.replace(
        r#"C: "OP",2092758031616,2092763624192, "d|X""#,
        r#"C: "OP",2092758031616,2092763622944, "d|X""#,
    )
    .replace(
        "a: 0,-2,-4,-6,-8,-10,-12,-14,-16,-14",
        &format!("a: 0,-2,{value},-6,-8,-10,-12,-14,-16,-14"),
    )
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// NaN rotation keys (FBX, glTF) read as no rotation while NaN
/// translations were refused. Both are refused now, by node and key or time.
#[test]
fn non_finite_rotation_keys_are_refused_by_node_and_time() {
    let dir = tempfile::tempdir().unwrap();
    let keys = Keys {
        node: 0,
        path: "rotation",
        times: vec![0.0, 1.0 / 30.0],
        values: vec![0.0, 0.0, 0.0, 1.0, f32::NAN, 0.0, 0.0, 1.0],
    };
    let gltf = write_gltf(dir.path(), "nan", r#"[{"name": "root"}]"#, &[keys], false);
    let text = load_refused(&gltf);
    assert!(
        text.contains(
            "animation 0: node 0 'root': rotation key 1 (at 0.0333 s) is not a finite number"
        ),
        "{text}"
    );
    for (name, value, want) in [
        ("nan.fbx", "nan", "a rotation that is not finite"),
        ("inf.fbx", "1e999", "a rotation that is not finite"),
    ] {
        let fbx = edited_fbx(dir.path(), name, |t| curve_on_rotation(t, value));
        let text = load_refused(&fbx);
        assert!(
            text.contains(&format!("joint 'pCube1', frame 11 (at 0.3667 s): {want}")),
            "{text}"
        );
    }
    let fbx = edited_fbx(dir.path(), "nan_translation.fbx", |t| {
        t.replace("a: 0,-2,-4,-6,", "a: 0,-2,nan,-6,")
    });
    let text = load_refused(&fbx);
    assert!(
        text.contains("joint 'pCube1', frame 11 (at 0.3667 s): a position that is not finite"),
        "{text}"
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// Rest offsets past a 32-bit float (FBX `UnitScaleFactor` 1e300; a glTF
/// node scaled 1e30 with a child at 1e30) loaded, `info` exit 0, positions NaN. Refused at
/// load, by joint.
#[test]
fn non_finite_rest_offsets_are_refused_by_joint() {
    let dir = tempfile::tempdir().unwrap();
    let nodes = r#"[{"name": "root", "scale": [1e30, 1e30, 1e30], "children": [1]},
                    {"name": "kid", "translation": [1e30, 0, 0]}]"#;
    let gltf = write_gltf(
        dir.path(),
        "huge",
        nodes,
        &[slide(0, vec![0.0, 1.0])],
        false,
    );
    let out = bvhview(&["info", gltf.to_str().unwrap()]);
    refused(
        &out,
        "huge.gltf: joint 'kid': its rest pose has a position that is not finite or past a 32-bit float",
        &dir.path().join("none"),
    );
    // A name of 1,000 bytes is quoted by its first 64 characters.
    let long = "K".repeat(1000);
    let nodes = nodes.replace("\"kid\"", &format!("\"{long}\""));
    let gltf = write_gltf(
        dir.path(),
        "named",
        &nodes,
        &[slide(0, vec![0.0, 1.0])],
        false,
    );
    let text = load_refused(&gltf);
    assert!(
        text.contains(&format!("joint '{}…': its rest pose", &long[..64])),
        "{text}"
    );
    let fbx = edited_fbx(dir.path(), "unit.fbx", |t| {
        t.replace(
            r#""UnitScaleFactor", "double", "Number", "",1"#,
            r#""UnitScaleFactor", "double", "Number", "",1e300"#,
        )
    });
    let text = load_refused(&fbx);
    assert!(
        text.contains("joint 'pCube1': its rest pose has a position that is not finite"),
        "{text}"
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// An FBX take whose LocalStart is after its LocalStop, or that states no
/// range, loaded as one frame without a word. The first is refused; the second is read over
/// its keys (0 s to 1.8333 s here: 56 frames at 30 fps), and a warning says so.
#[test]
fn fbx_take_ranges_backwards_are_refused_and_missing_ones_read_over_the_keys() {
    let dir = tempfile::tempdir().unwrap();
    let stop = "92372316000";
    let backwards = edited_fbx(dir.path(), "backwards.fbx", |t| {
        t.replace(
            &format!(r#"P: "LocalStop", "KTime", "Time", "",{stop}"#),
            &format!(
                "P: \"LocalStart\", \"KTime\", \"Time\", \"\",{stop}\n\t\t\tP: \"LocalStop\", \"KTime\", \"Time\", \"\",0"
            ),
        )
    });
    let text = load_refused(&backwards);
    assert!(
        text.contains(
            "take 'Take 001': its time range runs backwards (LocalStart 2 s is after LocalStop 0 s)"
        ),
        "{text}"
    );
    let takes = bvhview::take::takes(&backwards, bvhview::take::DEFAULT_MAX_SIZE).unwrap_err();
    assert!(takes.to_string().contains("runs backwards"), "{takes}");
    let none = edited_fbx(dir.path(), "no_range.fbx", |t| {
        t.lines()
            .filter(|l| !l.contains(stop))
            .collect::<Vec<_>>()
            .join("\n")
    });
    let loaded = crate::common::load_take(&none, None, None).unwrap();
    assert_eq!(loaded.motion.frame_count(), 56);
    let said = warnings_of(&loaded);
    assert!(
        said.contains("take 'Take 001' states no time range (no LocalStart or LocalStop): read over its keys, 0 s to 1.8333 s"),
        "{said}"
    );
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// The same bound for FBX: a 16 KB file whose range says nine hours (960,001 frames at 30
/// fps) had every frame evaluated (2.6 s in a debug build); its frames × joints are now held
/// to the file's size as a glTF's are, and refused before a frame is evaluated.
#[test]
fn an_fbx_range_longer_than_its_size_allows_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let nine_hours = (46_186_158_000u64 * 32_000).to_string();
    let long = edited_fbx(dir.path(), "long.fbx", |t| {
        t.replace("92372316000", &nine_hours)
    });
    let text = load_refused(&long);
    assert!(
        text.contains(
            "take 'Take 001' lasts 32000 s at 30 fps: 960001 frames of 1 joint (1 node \
             evaluated, 3 animated values in 1 layer), more than a file of"
        ),
        "{text}"
    );
}

/// Maya's layered take (three layers over one node) with its layers, their curve nodes and
/// curves copied until it has `copies` times as many, and its range stretched to `seconds`.
fn layered_fbx(dir: &Path, copies: u64, seconds: u64) -> PathBuf {
    let text =
        std::fs::read_to_string(repo_data("fbx/ufbx/maya_anim_layers_7500_ascii.fbx")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let (mut objects, mut ids) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < lines.len() {
        let kinds = [
            "\tAnimationLayer: ",
            "\tAnimationCurveNode: ",
            "\tAnimationCurve: ",
        ];
        if kinds.iter().any(|k| lines[i].starts_with(k)) {
            let id = lines[i]
                .split(": ")
                .nth(1)
                .unwrap()
                .split(',')
                .next()
                .unwrap();
            ids.push(id.to_string());
            let end = i + lines[i..].iter().position(|l| *l == "\t}").unwrap();
            objects.push(lines[i..=end].join("\n"));
            i = end + 1;
        } else {
            i += 1;
        }
    }
    let links: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.starts_with("\tC: ") && ids.iter().any(|id| l.contains(id.as_str())))
        .collect();
    let (mut more_objects, mut more_links) = (String::new(), String::new());
    for copy in 1..copies {
        let renamed = |text: &str| {
            ids.iter().fold(text.to_string(), |t, id| {
                t.replace(
                    id.as_str(),
                    &(id.parse::<u64>().unwrap() + copy * 1_000_003).to_string(),
                )
            })
        };
        for object in &objects {
            more_objects.push_str(&renamed(object));
            more_objects.push('\n');
        }
        for link in &links {
            more_links.push_str(&renamed(link));
            more_links.push('\n');
        }
    }
    let stop = (46_186_158_000u64 * seconds).to_string();
    let edited = text
        .replacen(
            "Connections:  {\n",
            &format!("Connections:  {{\n{more_links}"),
            1,
        )
        .replacen(
            &format!("{}\n", objects[0]),
            &format!("{more_objects}{}\n", objects[0]),
            1,
        )
        .replace("230930790000", &stop);
    let path = dir.join(format!("layers_{copies}.fbx"));
    std::fs::write(&path, edited).unwrap();
    path
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// Every layer's curves are blended at every frame, so they count in the budget. 40
/// copies of Maya's three layers (a 568 KB file) over 40,000 s at 24 fps asked for 960,000 frames
/// of 520 animated values (16 s in a release build); refused by name. The file as Maya saved it
/// reads.
#[test]
fn an_fbx_frame_budget_counts_every_layers_values() {
    let dir = tempfile::tempdir().unwrap();
    let text = load_refused(&layered_fbx(dir.path(), 40, 40_000));
    assert!(
        text.contains("960000 frames of 1 joint (") && text.contains(" in 120 layers)"),
        "{text}"
    );
    let loaded = crate::common::load_take(&layered_fbx(dir.path(), 1, 5), None, None).unwrap();
    assert_eq!(loaded.motion.frame_count(), 120);
}

#[cfg(all(feature = "fbx", feature = "gltf"))]
/// The same bound for FBX: the nodes a frame evaluates count, not the joints alone. One
/// animated node under a chain of 900 empty nodes for 400 s at 30 fps: 12,001 frames, each
/// posing 901 nodes (11 M transforms from a 70 KB file), is refused by name.
#[test]
fn an_fbx_frame_budget_counts_every_node_evaluated() {
    let dir = tempfile::tempdir().unwrap();
    let seconds_400 = (46_186_158_000u64 * 400).to_string();
    let chain = edited_fbx(dir.path(), "chain.fbx", |t| {
        let nulls: String = (0..900u64)
            .map(|i| {
                format!(
                    "\tModel: {}, \"Model::n{i}\", \"Null\" {{\n\t\tVersion: 232\n\t}}\n",
                    9_000_000 + i
                )
            })
            .collect();
        let links: String = (0..900u64)
            .map(|i| {
                let parent = if i == 0 { 0 } else { 9_000_000 + i - 1 };
                format!("\tC: \"OO\",{},{parent}\n", 9_000_000 + i)
            })
            .collect();
        t.replace("92372316000", &seconds_400)
            .replace(
                "\tModel: 2092721204448,",
                &format!("{nulls}\tModel: 2092721204448,"),
            )
            .replace(
                "\tC: \"OO\",2092721204448,0\n",
                &format!("{links}\tC: \"OO\",2092721204448,9000899\n"),
            )
    });
    let text = load_refused(&chain);
    assert!(
        text.contains(
            "take 'Take 001' lasts 400 s at 30 fps: 12001 frames of 1 joint (901 nodes evaluated, 3 \
             animated values in 1 layer)"
        ),
        "{text}"
    );
}

/// A take's warnings, one a line.
fn warnings_of(take: &bvhview::Take) -> String {
    take.warnings
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}
