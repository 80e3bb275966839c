//! Joint positions to rotations (`bvhview solve`, `solve::solve`). Real takes'
//! positions solved onto their own skeleton, and their 22 joints (retargeted onto `smpl22`)
//! solved back onto `smpl22`, come back within 1e-4 of the figure's height on every frame; the
//! command line reads `.npy` (SMPL's order, metres, float32 or float64) and the CSV `positions`
//! writes, and refuses what it cannot read with exit 2.

use crate::common;

use crate::common::bvhview_command;
use bvhview::model::pose::{OffsetMode, world_transforms_f64};
use bvhview::solve::{Positions, solve};
use bvhview::{Motion, Skeleton, Take};
use glam::{DVec3, Vec3};
use std::path::Path;

/// Every point's world position in every frame (64-bit FK), the take's offset mode.
fn points_of(skeleton: &Skeleton, motion: &Motion, mode: OffsetMode) -> Vec<DVec3> {
    let mut out = Vec::new();
    let mut world = Vec::new();
    for f in 0..motion.frame_count() {
        world_transforms_f64(skeleton, motion.frame(f), mode, &mut world);
        out.extend(world.iter().map(|&(_, p)| p));
    }
    out
}

/// The figure's size: the longest distance between two points of its first frame.
fn size_of(points: &[DVec3]) -> f64 {
    let (lo, hi) = points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    (hi - lo).length()
}

/// Solves `take`'s own positions (named as exports name them) back onto its skeleton and
/// returns the largest distance of any point, over its size.
fn own_positions_back(take: &Take) -> f64 {
    let mode =
        bvhview::model::pose::guessed_mode(&take.skeleton, &take.motion, OffsetMode::Replace);
    let points = points_of(&take.skeleton, &take.motion, mode);
    let count = take.skeleton.joints.len();
    let size = size_of(&points[..count]);
    // The points as `positions` writes them (an ASF bone's name for where it ends).
    let exported = bvhview::positions::export_points(&take.skeleton);
    let names: Vec<String> = exported.iter().map(|(n, _)| n.clone()).collect();
    let data: Vec<DVec3> = points
        .chunks(count)
        .flat_map(|pose| exported.iter().map(|&(_, j)| pose[j]))
        .collect();
    let positions = Positions::new(names, data, take.motion.frame_time).unwrap();
    let (motion, solved) = solve(
        &take.skeleton,
        bvhview::model::pose::Up::guess(&take.skeleton),
        &positions,
        None,
    )
    .unwrap();
    // The scale is the legs' over the data's: 1, but for MakeHuman's tiny deltas on the
    // position channels of its leg joints, which move the data's legs by 2e-8 of their length.
    assert!(
        (solved.scale - 1.0).abs() < 1e-6,
        "{}: {}",
        take.name,
        solved.scale
    );
    let back = points_of(&take.skeleton, &motion, OffsetMode::Replace);
    points
        .iter()
        .zip(&back)
        .map(|(a, b)| (*a - *b).length() / size)
        .fold(0.0, f64::max)
}

fn repository_takes() -> Vec<Take> {
    let mut takes: Vec<Take> = std::fs::read_dir(common::repo_data("bvh"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .map(|p| Take::open(&p).unwrap())
        .collect();
    takes.sort_by(|a, b| a.name.cmp(&b.name));
    takes
}

#[test]
fn a_take_s_own_positions_solve_back_onto_its_skeleton() {
    let mut checked = 0;
    for take in repository_takes() {
        let take = take.trim(0..take.frame_count().min(300));
        let worst = own_positions_back(&take);
        assert!(worst < 1e-4, "{}: {worst:e} of its size", take.name);
        checked += 1;
    }
    assert!(checked >= 15, "{checked}");
}

/// CMU's ASF: knees and elbows that turn about one axis (the bone above each is twisted so the
/// hinge's plane holds the data's bend), feet, hands and clavicles about two (of their two
/// solutions, the one their joints below can reach from), wrists about their own bone (the turn
/// that lets the hand and fingers reach), the thorax twisted so both clavicles reach: within
/// 1e-4 of the figure's size, as BVH takes are.
#[test]
fn an_asf_take_s_own_positions_solve_back_near_it() {
    let asf = bvhview::take::OpenOptions::new()
        .motion(common::repo_data("asf_amc/heiden_12_02_01.amc"))
        .open(common::repo_data("asf_amc/heiden_12.asf"))
        .unwrap();
    let asf = asf.trim(0..300);
    let worst = own_positions_back(&asf);
    println!("CMU ASF 12_02_01 solved back: {worst:.1e} of its size at worst");
    assert!(worst < 1e-4, "{worst:e} of its size");
}

/// A take onto `smpl22` (22 joints), those positions solved back onto `smpl22`: the worst
/// point's distance over the figure's size.
fn smpl_positions_back(take: &Take) -> f64 {
    let smpl = bvhview::retarget::onto(take, "smpl22").unwrap();
    let points = points_of(&smpl.skeleton, &smpl.motion, OffsetMode::Replace);
    let count = smpl.skeleton.joints.len();
    // Only the 22 joints, in SMPL's order, as HumanML3D's arrays hold them.
    let names = smpl.point_names();
    let order: Vec<usize> = bvhview::solve::SMPL22_ORDER
        .iter()
        .map(|n| names.iter().position(|m| m == n).unwrap())
        .collect();
    let joints: Vec<DVec3> = points
        .chunks(count)
        .flat_map(|frame| order.iter().map(|&j| frame[j]))
        .collect();
    let positions = Positions::new(
        bvhview::solve::joint_names("smpl22"),
        joints,
        smpl.motion.frame_time,
    )
    .unwrap();
    let (motion, _) = solve(
        &smpl.skeleton,
        bvhview::model::pose::Up::Y,
        &positions,
        None,
    )
    .unwrap();
    let back = points_of(&smpl.skeleton, &motion, OffsetMode::Replace);
    let size = size_of(&points[..count]);
    points
        .chunks(count)
        .zip(back.chunks(count))
        .flat_map(|(a, b)| order.iter().map(move |&j| (a[j] - b[j]).length() / size))
        .fold(0.0, f64::max)
}

#[test]
fn every_family_s_22_joints_solve_back_onto_smpl22() {
    let mut checked = 0;
    for take in repository_takes() {
        if bvhview::retarget::onto(&take, "smpl22").is_err() {
            continue;
        }
        let take = take.trim(0..take.frame_count().min(300));
        let worst = smpl_positions_back(&take);
        assert!(worst < 1e-4, "{}: {worst:e} of its size", take.name);
        checked += 1;
    }
    assert!(checked >= 10, "{checked}");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn the_whole_corpus_solves_back() {
    let dir = common::shared_data("bvh");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .collect();
    names.sort();
    // And every CMU ASF/AMC pair (a skeleton, each of its motions).
    let acclaim = common::shared_data("asf_amc");
    let pairs = bvhview::dataset::takes(&acclaim).unwrap();
    let takes = names
        .iter()
        .map(|path| (path.clone(), Take::open(path).unwrap()))
        .chain(pairs.iter().map(|item| {
            let motion = item.motion.clone().unwrap();
            let take = bvhview::take::OpenOptions::new()
                .motion(&motion)
                .open(&item.path)
                .unwrap();
            (motion, take)
        }));
    let mut acclaim_checked = 0;
    for (path, take) in takes {
        acclaim_checked += usize::from(path.extension().is_some_and(|e| e == "amc"));
        let take = take.trim(0..take.frame_count().min(300));
        let own = own_positions_back(&take);
        assert!(own < 1e-4, "{}: {own:e}", path.display());
        if bvhview::retarget::onto(&take, "smpl22").is_ok() {
            let smpl = smpl_positions_back(&take);
            assert!(smpl < 1e-4, "{}: onto smpl22 {smpl:e}", path.display());
        }
    }
    assert!(acclaim_checked >= 5, "{acclaim_checked} ASF/AMC takes");
}

/// A little-endian `.npy` of `shape` holding `values` as `descr` (`<f4` or `<f8`).
fn npy(path: &Path, descr: &str, shape: &[usize], values: &[f64]) {
    let shape_text = match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape_text}, }}");
    let total = (10 + dict.len() + 1).div_ceil(64) * 64;
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&((total - 10) as u16).to_le_bytes());
    bytes.extend_from_slice(dict.as_bytes());
    bytes.resize(total - 1, b' ');
    bytes.push(b'\n');
    for &v in values {
        match descr {
            "<f4" => bytes.extend_from_slice(&(v as f32).to_le_bytes()),
            _ => bytes.extend_from_slice(&v.to_le_bytes()),
        }
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn the_command_line_solves_an_npy_in_smpl_order_and_metres() {
    let dir = tempfile::tempdir().unwrap();
    // A CMU walk onto smpl22 (centimetres), its 22 joints in SMPL's order in metres, as
    // HumanML3D keeps them.
    let walk = Take::open(common::repo_data("bvh/bvhparser_walk_01.bvh"))
        .unwrap()
        .trim(0..60);
    let smpl = bvhview::retarget::onto(&walk, "smpl22").unwrap();
    let points = points_of(&smpl.skeleton, &smpl.motion, OffsetMode::Replace);
    let names = smpl.point_names();
    let count = names.len();
    let order: Vec<usize> = bvhview::solve::SMPL22_ORDER
        .iter()
        .map(|n| names.iter().position(|m| m == n).unwrap())
        .collect();
    let values: Vec<f64> = points
        .chunks(count)
        .flat_map(|frame| order.iter().map(move |&j| frame[j] / 100.0))
        .flat_map(|p| [p.x, p.y, p.z])
        .collect();
    let input = dir.path().join("walk.npy");
    npy(&input, "<f4", &[60, 22, 3], &values);
    let out = dir.path().join("walk.bvh");
    let run = bvhview_command()
        .args([
            "solve",
            input.to_str().unwrap(),
            "--onto",
            "smpl22",
            "--fps",
            "120",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("22 unnamed joints read in SMPL's order"),
        "{stderr}"
    );
    assert!(stderr.contains("path ×100.0"), "{stderr}");
    let solved = Take::open(&out).unwrap();
    assert_eq!(solved.frame_count(), 60);
    assert!((solved.motion.frame_time - 1.0 / 120.0).abs() < 1e-9);
    let back = points_of(&solved.skeleton, &solved.motion, OffsetMode::Replace);
    let size = size_of(&points[..count]);
    for (a, b) in points.chunks(count).zip(back.chunks(count)) {
        for &j in &order {
            // The BVH holds 32-bit floats: within 1e-4 of the size still.
            assert!((a[j] - b[j]).length() < 1e-4 * size, "{} {}", a[j], b[j]);
        }
    }
    // Bad input: exit 2, nothing written.
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--joints".into(), "pelvis,left_hip".into()],
            "22 joints a frame, and --joints names 2",
        ),
        (vec!["--fps".into(), "0".into()], "--fps 0"),
    ];
    for (extra, said) in cases {
        let bad_out = dir.path().join("bad.bvh");
        let mut command = bvhview_command();
        command.args(["solve", input.to_str().unwrap(), "--onto", "smpl22"]);
        if !extra.contains(&"--fps".to_string()) {
            command.args(["--fps", "20"]);
        }
        let run = command
            .args(&extra)
            .arg("-o")
            .arg(&bad_out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(said), "{extra:?}: {stderr}");
        assert!(!bad_out.exists());
    }
    // Not a number, a wrong shape, names the skeleton has not.
    let nan = dir.path().join("nan.npy");
    let mut with_nan = values.clone();
    with_nan[7] = f64::NAN;
    npy(&nan, "<f8", &[60, 22, 3], &with_nan);
    let flat = dir.path().join("flat.npy");
    npy(&flat, "<f8", &[values.len()], &values);
    let csv = dir.path().join("other.csv");
    std::fs::write(&csv, "frame,joint,x,y,z\n0,Alpha,0,0,0\n0,Beta,1,0,0\n").unwrap();
    for (file, said) in [
        (&nan, "frame 0, joint \"right_hip\": not a finite position"),
        (&flat, "expected frames × joints × 3"),
        (&csv, "0 of their 2 joints are joints of the skeleton"),
    ] {
        let run = bvhview_command()
            .args([
                "solve",
                file.to_str().unwrap(),
                "--onto",
                "smpl22",
                "--fps",
                "20",
                "-o",
            ])
            .arg(dir.path().join("x.bvh"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(said), "{said}: {stderr}");
    }
}

/// HumanML3D's own processed pair (tests/humanml3d, MIT): its 263-value
/// vectors recovered as its `recover_from_ric` does give its processed positions back within
/// 1e-4 m on every joint and frame; `solve --from humanml3d` puts them on `smpl22`.
#[test]
fn humanml3d_vectors_recover_its_own_positions() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/humanml3d");
    let vectors_bytes = std::fs::read(root.join("new_joint_vecs_012314.npy")).unwrap();
    let vectors = bvhview::humanml3d::read_vectors(&vectors_bytes, "vecs").unwrap();
    let recovered = bvhview::humanml3d::recover_from_ric(&vectors).unwrap();
    let joints_bytes = std::fs::read(root.join("new_joints_012314.npy")).unwrap();
    let (count, positions) = bvhview::solve::read_npy(&joints_bytes, "joints").unwrap();
    assert_eq!((count, positions.len()), (22, 170 * 22));
    let worst = recovered
        .iter()
        .zip(&positions)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    println!("HumanML3D 012314: recovered within {worst:e} m of its processed positions");
    assert!(worst < 1e-4, "{worst}");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h.bvh");
    let run = bvhview_command()
        .args([
            "solve",
            root.join("new_joint_vecs_012314.npy").to_str().unwrap(),
        ])
        .args([
            "--from",
            "humanml3d",
            "--onto",
            "smpl22",
            "--fps",
            "20",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let take = Take::open(&out).unwrap();
    assert_eq!(take.frame_count(), 170);
    // smpl22's bones are not HumanML3D's: each point off the data is said, farthest first.
    let said = String::from_utf8_lossy(&run.stderr);
    let off = said
        .lines()
        .find(|l| l.contains("off the data"))
        .unwrap_or_else(|| panic!("{said}"));
    assert!(off.contains(": head by 3.92"), "{off}");
    // Every joint but the pelvis, which the path puts where the data does: ten, and the rest
    // counted.
    assert_eq!(off.matches(" by ").count(), 10, "{off}");
    assert!(off.ends_with(" and 11 more"), "{off}");
    // A wrong width is refused.
    let run = bvhview_command()
        .args([
            "solve",
            root.join("new_joints_012314.npy").to_str().unwrap(),
        ])
        .args([
            "--from",
            "humanml3d",
            "--onto",
            "smpl22",
            "--fps",
            "20",
            "-o",
        ])
        .arg(dir.path().join("x.bvh"))
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("expected frames × 263"));
}

/// `positions` of an ASF take, then `solve` of that CSV back onto the ASF: the CSV names each
/// point by the bone that ends there, and `solve` reads it so (it once read those names as the
/// bones' starts: path ×1.41 and the feet 57 % of the figure off).
#[test]
fn an_asf_takes_positions_csv_solves_back_onto_its_asf() {
    let folder = tempfile::tempdir().unwrap();
    let csv = folder.path().join("asf.csv");
    let asf = common::repo_data("asf_amc/heiden_12.asf");
    let amc = common::repo_data("asf_amc/heiden_12_02_01.amc");
    let written = bvhview_command()
        .args(["positions"])
        .arg(&asf)
        .arg("--motion")
        .arg(&amc)
        .arg("-o")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(written.status.success(), "{written:?}");
    let out = folder.path().join("back.bvh");
    let solved = bvhview_command()
        .arg("solve")
        .arg(&csv)
        .arg("--onto")
        .arg(&asf)
        .args(["--fps", "120", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&solved.stderr);
    assert!(solved.status.success(), "{said}");
    assert!(said.contains("path ×1.0000"), "{said}");
    // Its own bones: nothing off the data.
    assert!(!said.contains("off the data"), "{said}");
    // Every joint and End Site, where the solved take puts it: within 1e-4 of the figure.
    let back = Take::open(&out).unwrap();
    let take = bvhview::take::OpenOptions::new()
        .motion(&amc)
        .open(&asf)
        .unwrap();
    let here = points_of(&take.skeleton, &take.motion, OffsetMode::Replace);
    let there = points_of(&back.skeleton, &back.motion, OffsetMode::Replace);
    let (count, back_count) = (take.skeleton.joints.len(), back.skeleton.joints.len());
    let size = size_of(&here[..count]);
    let name = |s: &Skeleton, j| bvhview::model::skeleton::export_name(s, j);
    let order: Vec<usize> = (0..count)
        .map(|j| {
            let wanted = name(&take.skeleton, j);
            (0..back_count)
                .find(|&k| name(&back.skeleton, k) == wanted)
                .unwrap()
        })
        .collect();
    let worst = here
        .chunks(count)
        .zip(there.chunks(back_count))
        .flat_map(|(a, b)| {
            order
                .iter()
                .enumerate()
                .map(move |(j, &k)| (a[j] - b[k]).length())
        })
        .fold(0.0f64, f64::max)
        / size;
    println!("ASF positions CSV solved back: {worst:.1e} of its size at worst");
    assert!(worst < 1e-4, "{worst}");
}

/// Hostile positions files. Each is refused in one line naming the
/// file and what is wrong in it (the frame and joint of a value), having read no more than the
/// file's first bytes where the start is already wrong, and nothing is written.
#[test]
fn hostile_positions_are_refused_in_one_line_before_they_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    // A version-2 header claiming 0xFFFFFFF0 bytes (npyz asked for 4 GB and aborted).
    let mut claim = b"\x93NUMPY\x02\x00".to_vec();
    claim.extend_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    claim.extend_from_slice(&[b'{'; 15]);
    let claim = file("claim.npy", &claim);
    // A version-1 header claiming more than the file holds.
    let mut short = b"\x93NUMPY\x01\x00".to_vec();
    short.extend_from_slice(&1000u16.to_le_bytes());
    short.extend_from_slice(&[b' '; 90]);
    let short = file("short.npy", &short);
    // Sparse files of 1.86 GB (a few KB of disk) that are not what their names say: read whole
    // before their first bytes were checked.
    let sparse = |name: &str| {
        let path = dir.path().join(name);
        std::fs::File::create(&path)
            .unwrap()
            .set_len(1_860_000_000)
            .unwrap();
        path
    };
    let sparse_npy = sparse("sparse.npy");
    let sparse_csv = sparse("sparse.csv");
    // A header that is not a Python dict (npyz's parser said so in 6 lines), and float16.
    let bad_dict = dir.path().join("dict.npy");
    npy(&bad_dict, "<f8", &[2, 22, 3], &[0.0; 132]);
    let mut bytes = std::fs::read(&bad_dict).unwrap();
    let close = bytes.iter().position(|&b| b == b'}').unwrap();
    bytes[close] = b' ';
    bytes[close - 2] = b' ';
    let bad_dict = file("dict.npy", &bytes);
    // A header whose dict opens 20 braces deep, its shape 21 (the solve fuzzer's hangs): npyz's
    // parser takes three times longer for each brace (12 took 28 s in a debug build); refused
    // before it is parsed.
    let deep = dir.path().join("deep.npy");
    npy(&deep, "<f4", &[1, 22, 3], &[0.0; 66]);
    let mut bytes = std::fs::read(&deep).unwrap();
    bytes.splice(10..10, [b'{'; 19]);
    let end = bytes.iter().position(|&b| b == b'\n').unwrap();
    bytes.drain(end - 19..end);
    let deep = file("deep.npy", &bytes);
    // Shapes whose count (the solve fuzzer's crash) or, past a 0, whose strides overflow 64
    // bits: npyz multiplied them unchecked, a panic where overflow is checked.
    let huge = dir.path().join("huge.npy");
    npy(&huge, "<f4", &[3, 6_666_666_666_666_666_663], &[]);
    let strides = dir.path().join("strides.npy");
    npy(&strides, "<f4", &[0, 1 << 40, 1 << 40, 3], &[]);
    let half = dir.path().join("half.npy");
    npy(&half, "<f2", &[2, 22, 3], &[]);
    let mut bytes = std::fs::read(&half).unwrap();
    bytes.extend_from_slice(&[0; 2 * 22 * 3 * 2]);
    let half = file("half.npy", &bytes);
    // Finite float64 positions past float32's range (solved to "spine1 by inf" and written).
    let far = dir.path().join("far.npy");
    let mut values = vec![0.0; 2 * 22 * 3];
    values[(22 + 3) * 3 + 1] = -1e300;
    npy(&far, "<f8", &[2, 22, 3], &values);
    // The largest frame number then 0 read as consecutive (the sum wrapped).
    let wrap = file(
        "wrap.csv",
        b"frame,joint,x,y,z\n18446744073709551615,pelvis,0,0,0\n0,pelvis,1,1,1\n",
    );
    // A joint name of 10 MB, echoed whole before.
    let long = "A".repeat(10_000_000);
    let named = file(
        "named.csv",
        format!("frame,joint,x,y,z\n0,pelvis,0,0,0\n1,{long},0,0,0\n").as_bytes(),
    );
    let p = |path: &Path| path.display().to_string();
    let cases = [
        (
            &named,
            format!(
                "{}:3: frame 1, joint \"{}\"… (10000000 bytes): expected frame 1, joint \
                 \"pelvis\" (every frame lists the same joints in the same order, frame after \
                 frame)",
                p(&named),
                &long[..64]
            ),
        ),
        (
            &claim,
            format!(
                "{}: its .npy header claims 4294967280 bytes, more than the 65535 bvhview reads \
                 (the file is damaged)",
                p(&claim)
            ),
        ),
        (
            &short,
            format!(
                "{}: its .npy header claims 1000 bytes, and 90 follow in the file",
                p(&short)
            ),
        ),
        (
            &sparse_npy,
            format!(
                "{}: not an .npy array (it does not begin with numpy's \\x93NUMPY)",
                p(&sparse_npy)
            ),
        ),
        (
            &sparse_csv,
            format!(
                "{}:1: expected the header frame,joint,x,y,z (the CSV `bvhview positions` writes)",
                p(&sparse_csv)
            ),
        ),
        (
            &bad_dict,
            format!(
                "{}: not an .npy array: its header: could not parse Python expression: syntax \
                 error at 1:60 (expected minus_sign, fraction, pos_exponent, neg_exponent, or digit)",
                p(&bad_dict)
            ),
        ),
        (
            &deep,
            format!(
                "{}: its .npy header nests brackets 21 deep; an array's header nests at most 4 \
                 (the file is damaged)",
                p(&deep)
            ),
        ),
        (
            &huge,
            format!(
                "{}: shape [3, 6666666666666666663]: more values than a 64-bit count holds (the \
                 file is damaged)",
                p(&huge)
            ),
        ),
        (
            &strides,
            format!(
                "{}: shape [0, 1099511627776, 1099511627776, 3]: more values than a 64-bit count \
                 holds (the file is damaged)",
                p(&strides)
            ),
        ),
        (
            &half,
            format!(
                "{}: dtype \"<f2\": not supported; bvhview reads float32 and float64 (<f4, >f4, \
                 <f8, >f8)",
                p(&half)
            ),
        ),
        (
            &far,
            format!(
                "{}: positions: frame 1, joint \"spine1\": position (0, -1e300, 0) is beyond a \
                 32-bit float's range (±3.4e38), which bvhview's takes hold",
                p(&far)
            ),
        ),
        (
            &wrap,
            format!(
                "{}:3: frame 0, joint \"pelvis\": expected nothing after frame \
                 18446744073709551615, the largest frame number (every frame lists the same \
                 joints in the same order, frame after frame)",
                p(&wrap)
            ),
        ),
    ];
    let output = dir.path().join("out.bvh");
    for (input, said) in cases {
        let run = bvhview_command()
            .args(["solve", &p(input), "--onto", "smpl22", "--fps", "20", "-o"])
            .arg(&output)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr, format!("bvhview: {said}\n"));
        assert!(!output.exists());
    }
    // HumanML3D's vectors are read by the same guarded reader.
    let run = bvhview_command()
        .args([
            "solve",
            &p(&claim),
            "--from",
            "humanml3d",
            "--onto",
            "smpl22",
        ])
        .args(["--fps", "20", "-o"])
        .arg(&output)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("claims 4294967280 bytes"), "{stderr}");
}

// `solve` continuous in time.

/// `take`'s own positions (named as exports name them), each point moved by `noise` (frame,
/// point → offset), solved back onto its skeleton: the solved motion, and the clean points.
fn solve_own(take: &Take, noise: impl Fn(usize, usize) -> DVec3) -> (Motion, Vec<DVec3>) {
    let mode =
        bvhview::model::pose::guessed_mode(&take.skeleton, &take.motion, OffsetMode::Replace);
    let points = points_of(&take.skeleton, &take.motion, mode);
    let count = take.skeleton.joints.len();
    let exported = bvhview::positions::export_points(&take.skeleton);
    let names: Vec<String> = exported.iter().map(|(n, _)| n.clone()).collect();
    let data: Vec<DVec3> = points
        .chunks(count)
        .enumerate()
        .flat_map(|(f, pose)| {
            let noise = &noise;
            exported
                .iter()
                .enumerate()
                .map(move |(k, &(_, j))| pose[j] + noise(f, k))
        })
        .collect();
    let positions = Positions::new(names, data, take.motion.frame_time).unwrap();
    let up = bvhview::model::pose::Up::guess(&take.skeleton);
    let (motion, _) = solve(&take.skeleton, up, &positions, None).unwrap();
    (motion, points)
}

/// Per joint that turns, the largest turn (degrees) of its rotation from a frame to the next.
fn largest_turns(skeleton: &Skeleton, motion: &Motion) -> Vec<f64> {
    let rotation = |j: usize, f: usize| {
        let joint = &skeleton.joints[j];
        bvhview::model::pose::channel_rotations_f64(joint, joint.values(motion.frame(f)))
    };
    (0..skeleton.joints.len())
        .map(|j| {
            (1..motion.frame_count())
                .map(|f| {
                    let d = rotation(j, f - 1).inverse() * rotation(j, f);
                    2.0 * d.xyz().length().atan2(d.w.abs()).to_degrees()
                })
                .fold(0.0, f64::max)
        })
        .collect()
}

/// A take's own positions with ±`amount` on each coordinate (uniform, from a fixed-seed
/// xorshift generator, so every run draws the same), solved back with and without `--smooth
/// 6`, and the clean positions solved and smoothed: how far the points of each lie from the
/// clean positions, on average and at worst.
fn noisy_solve_errors(take: &Take, amount: f64) -> [(f64, f64); 3] {
    let count = bvhview::positions::export_points(&take.skeleton).len();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut draws = Vec::with_capacity(take.frame_count() * count * 3);
    for _ in 0..take.frame_count() * count * 3 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        draws.push(((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * amount);
    }
    let noise = |f: usize, k: usize| {
        let at = (f * count + k) * 3;
        DVec3::new(draws[at], draws[at + 1], draws[at + 2])
    };
    let (motion, clean) = solve_own(take, noise);
    let smooth = |motion: &Motion| bvhview::edit::smooth(&take.skeleton, motion, 6.0).unwrap();
    let errors = |motion: &Motion| {
        let back = points_of(&take.skeleton, motion, OffsetMode::Replace);
        let apart: Vec<f64> = clean
            .iter()
            .zip(&back)
            .map(|(a, b)| (*a - *b).length())
            .collect();
        let mean = apart.iter().sum::<f64>() / apart.len() as f64;
        (mean, apart.iter().copied().fold(0.0, f64::max))
    };
    let (clean_motion, _) = solve_own(take, |_, _| DVec3::ZERO);
    [
        errors(&motion),
        errors(&smooth(&motion)),
        errors(&smooth(&clean_motion)),
    ]
}

/// ±1 cm of noise on `take`'s positions (centimetres): smoothed at 6 Hz, the solved take lies
/// nearer the clean positions on average than unsmoothed, and at worst no farther than the
/// noise and the filter's own rounding of the clean take's fastest turns together.
fn assert_smoothing_helps(take: &Take) {
    let [(plain_mean, plain_worst), (mean, worst), (_, filter_worst)] =
        noisy_solve_errors(take, 1.0);
    println!(
        "{} ±1 cm: unsmoothed {plain_mean:.3} cm on average, {plain_worst:.3} at worst; at 6 \
         Hz {mean:.3}, {worst:.3} (clean at 6 Hz: {filter_worst:.3} at worst)",
        take.name
    );
    assert!(
        mean <= plain_mean && worst <= plain_worst + filter_worst,
        "{}: smoothed {mean} cm on average, {worst} at worst; unsmoothed {plain_mean}, \
         {plain_worst}; clean smoothed {filter_worst} at worst",
        take.name
    );
}

#[test]
fn smoothing_a_noisy_solve_brings_it_nearer_the_clean_positions() {
    let path = common::repo_data("bvh/animateddrawings_rokoko_jesse_dance.bvh");
    assert_smoothing_helps(&Take::open(path).unwrap());
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn smoothing_a_noisy_bandai_solve_brings_it_nearer_the_clean_positions() {
    let path = common::shared_data("bvh/bandai_dataset-1_dance-short_normal_001.bvh");
    assert_smoothing_helps(&Take::open(path).unwrap());
}

/// A take's own positions solved back: no joint turns between two frames by more than half as
/// much again as the source's largest turn, and 5°. The slack is for the twist of a lone bone,
/// which the positions leave free: carried from frame to frame, it lands on the joint below
/// (a forearm's twist on the hand) where the source's is its own; a flip is 90° to 180°.
fn assert_no_flips(take: &Take) {
    let (motion, _) = solve_own(take, |_, _| DVec3::ZERO);
    let source = largest_turns(&take.skeleton, &take.motion);
    let back = largest_turns(&take.skeleton, &motion);
    let past: Vec<String> = take
        .skeleton
        .joints
        .iter()
        .enumerate()
        .filter(|&(j, _)| back[j] > 1.5 * source[j] + 5.0)
        .map(|(j, joint)| format!("{}: {:.1}° ({:.1}°)", joint.name, back[j], source[j]))
        .collect();
    assert!(past.is_empty(), "{}: solved (source) {past:?}", take.name);
}

#[test]
fn a_solved_take_turns_no_more_between_frames_than_its_source() {
    let path = common::repo_data("bvh/bvhpython_test_mocapbank.bvh");
    assert_no_flips(&Take::open(path).unwrap());
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn a_solved_bandai_take_turns_no_more_between_frames_than_its_source() {
    let path = common::shared_data("bvh/bandai_dataset-1_dance-short_normal_001.bvh");
    assert_no_flips(&Take::open(path).unwrap());
}

/// A Perception Neuron-style take, every joint with position channels, its spine and neck
/// stretching by up to 3 and 2 cm while the body turns (the channels replace the OFFSETs).
fn translating_spine_take() -> Take {
    let mut text = String::from(
        "HIERARCHY\nROOT Hips\n{\n OFFSET 0 90 0\n CHANNELS 6 Xposition Yposition Zposition \
         Yrotation Xrotation Zrotation\n JOINT Spine\n {\n  OFFSET 0 10 0\n  CHANNELS 6 \
         Xposition Yposition Zposition Yrotation Xrotation Zrotation\n  JOINT Neck\n  {\n   \
         OFFSET 0 40 0\n   CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation \
         Zrotation\n   JOINT LeftArm\n   {\n    OFFSET 15 -5 0\n    CHANNELS 6 Xposition \
         Yposition Zposition Yrotation Xrotation Zrotation\n    End Site\n    {\n     OFFSET \
         25 0 0\n    }\n   }\n   End Site\n   {\n    OFFSET 0 20 3\n   }\n  }\n }\n",
    );
    for side in [1.0, -1.0] {
        let name = if side > 0.0 { "Left" } else { "Right" };
        text += &format!(
            " JOINT {name}UpLeg\n {{\n  OFFSET {} 0 0\n  CHANNELS 6 Xposition Yposition \
             Zposition Yrotation Xrotation Zrotation\n  JOINT {name}Leg\n  {{\n   OFFSET 0 -42 \
             0\n   CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\n   \
             JOINT {name}Foot\n   {{\n    OFFSET 0 -40 0\n    CHANNELS 6 Xposition Yposition \
             Zposition Yrotation Xrotation Zrotation\n    End Site\n    {{\n     OFFSET 0 -5 \
             12\n    }}\n   }}\n  }}\n }}\n",
            9.0 * side
        );
    }
    let frames = 60;
    text += &format!("}}\nMOTION\nFrames: {frames}\nFrame Time: 0.033333\n");
    for f in 0..frames {
        let t = f as f64 / 10.0;
        let (s, c) = t.sin_cos();
        let row = [
            // Hips: travels and turns.
            [5.0 * t, 90.0 + s, 0.0, 30.0 * s, 5.0 * c, 3.0 * s],
            // Spine and neck: their OFFSETs, stretched.
            [0.0, 10.0 + 3.0 * s, 1.5 * c, 10.0 * c, 15.0 * s, -5.0 * s],
            [0.5 * s, 40.0 + 2.0 * c, 0.0, -20.0 * s, 10.0 * c, 4.0 * c],
            [15.0, -5.0, 0.0, 10.0 * s, 20.0 * c, -40.0 + 10.0 * s],
            [9.0, 0.0, 0.0, 5.0 * s, -30.0 * s, 2.0 * c],
            [0.0, -42.0, 0.0, 0.0, 20.0 + 20.0 * s, 0.0],
            [0.0, -40.0, 0.0, 0.0, -10.0 * c, 0.0],
            [-9.0, 0.0, 0.0, -5.0 * s, 30.0 * s, -2.0 * c],
            [0.0, -42.0, 0.0, 0.0, 20.0 - 20.0 * s, 0.0],
            [0.0, -40.0, 0.0, 0.0, 10.0 * c, 0.0],
        ];
        let values: Vec<String> = row.iter().flatten().map(|v| format!("{v:.4}")).collect();
        text += &values.join(" ");
        text += "\n";
    }
    bvhview::take::OpenOptions::new()
        .format(bvhview::take::Format::Bvh)
        .threads(1)
        .open_bytes(text.as_bytes(), "neuron.bvh")
        .unwrap()
}

/// Joints below the root with position channels take their
/// translations from the positions (they kept their OFFSETs, 1.8 % of the height off).
#[test]
fn joints_with_position_channels_take_their_translations_from_the_positions() {
    let take = translating_spine_take();
    let worst = own_positions_back(&take);
    println!("spine and neck stretching: {worst:.1e} of the size at worst");
    assert!(worst < 1e-6, "{worst:e} of its size");
    let (motion, _) = solve_own(&take, |_, _| DVec3::ZERO);
    // The stretch is in the channels: each translation is as long as the source's (which way
    // it points in its parent's frame is the parent's turn, which the hips' three bones share).
    for name in ["Spine", "Neck"] {
        let joint = take
            .skeleton
            .joints
            .iter()
            .find(|j| j.name == name)
            .unwrap();
        let length = |values: &[f32]| Vec3::from_slice(&values[..3]).length();
        for f in 0..motion.frame_count() {
            let (a, b) = (
                joint.values(take.motion.frame(f)),
                joint.values(motion.frame(f)),
            );
            assert!(
                (length(a) - length(b)).abs() < 1e-3,
                "{name} {f}: {a:?} {b:?}"
            );
        }
    }
}

/// Per joint, its turn (degrees) from each frame to the next.
fn turns(skeleton: &Skeleton, motion: &Motion) -> Vec<Vec<f64>> {
    let rotation = |j: usize, f: usize| {
        let joint = &skeleton.joints[j];
        bvhview::model::pose::channel_rotations_f64(joint, joint.values(motion.frame(f)))
    };
    (0..skeleton.joints.len())
        .map(|j| {
            (1..motion.frame_count())
                .map(|f| {
                    let d = rotation(j, f - 1).inverse() * rotation(j, f);
                    2.0 * d.xyz().length().atan2(d.w.abs()).to_degrees()
                })
                .collect()
        })
        .collect()
}

/// A CMU walk's own positions solved back. Its wrists are laid by bones
/// past joints that turn on their own (the fingers past `lhand`, the thumb's end past
/// `LThumb`), and CMU's thumb wanders, up to 90° from where it stands beside the fingers and
/// along them: the wrist followed it (179.6° between two frames where the source's turned
/// 54.8°, 151.3° where it turned 3.3°). Now every joint, every pair of frames, turns at most
/// twice the source's turn and 5° (the slack: a twist the positions leave free lands on another
/// joint than the source's; a flip is 90° to 180°), and the points stay where they were.
#[test]
fn a_solved_cmu_walk_turns_no_joint_more_than_its_source_frame_by_frame() {
    let take = Take::open(common::repo_data("bvh/bvh11_131_01.bvh")).unwrap();
    let worst = own_positions_back(&take);
    assert!(worst < 1e-4, "{worst:e} of its size");
    let (motion, _) = solve_own(&take, |_, _| DVec3::ZERO);
    let (source, back) = (
        turns(&take.skeleton, &take.motion),
        turns(&take.skeleton, &motion),
    );
    let mut past = Vec::new();
    for (j, joint) in take.skeleton.joints.iter().enumerate() {
        let frames = source[j].iter().zip(&back[j]).enumerate();
        if let Some((f, (s, b))) = frames
            .filter(|(_, (s, b))| **b > 2.0 * **s + 5.0)
            .max_by(|a, b| (a.1.1 - a.1.0).total_cmp(&(b.1.1 - b.1.0)))
        {
            past.push(format!("{} {f}→{}: {b:.1}° ({s:.1}°)", joint.name, f + 1));
        }
    }
    assert!(past.is_empty(), "solved (source): {past:?}");
    let largest = |turns: &[f64]| turns.iter().copied().fold(0.0, f64::max);
    let wrist = take
        .skeleton
        .joints
        .iter()
        .position(|j| j.name == "RightWrist")
        .unwrap();
    println!(
        "RightWrist's largest turn: {:.1}° ({:.1}° in the source)",
        largest(&back[wrist]),
        largest(&source[wrist])
    );
}

/// What `solve` prints is measured on what it wrote. After `--smooth` the
/// figures are the smoothed take's (no "before --smooth"), and the line says where smoothing
/// made them worse; every line carries the largest turn between frames against the data's.
#[test]
fn solve_prints_figures_measured_on_the_take_it_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("walk.csv");
    let walk = common::repo_data("bvh/bvh11_131_01.bvh");
    let run = bvhview_command()
        .arg("positions")
        .arg(&walk)
        .arg("-o")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(run.status.success());
    let line = |smooth: &[&str]| {
        let run = bvhview_command()
            .arg("solve")
            .arg(&csv)
            .arg("--onto")
            .arg(&walk)
            .args(["--fps", "120"])
            .args(smooth)
            .arg("-o")
            .arg(dir.path().join("back.bvh"))
            .output()
            .unwrap();
        assert!(run.status.success());
        let said = String::from_utf8_lossy(&run.stderr).to_string();
        let line = said
            .lines()
            .find(|l| l.starts_with("solved: "))
            .unwrap()
            .to_string();
        (line, said)
    };
    let (plain, _) = line(&[]);
    assert_eq!(
        plain,
        "solved: 38 joints matched, path ×1.0000; farthest from the data: RFingers_End by \
         0.0000; largest turn between frames: RThumb 172.3° (its bones: 172.3°)"
    );
    let (smoothed, said) = line(&["--smooth", "6"]);
    assert!(!said.contains("before --smooth"), "{said}");
    assert!(
        smoothed.contains("farthest from the data: RThumb_End by 1.2611")
            && smoothed
                .contains("--smooth made worse: farthest from the data 1.2611 (without: 0.0000)"),
        "{smoothed}"
    );
    // The figure is the written file's: read back, its points stand that far from the data.
    let back = Take::open(dir.path().join("back.bvh")).unwrap();
    let source = Take::open(&walk).unwrap();
    let (a, b) = (
        points_of(&source.skeleton, &source.motion, OffsetMode::Replace),
        points_of(&back.skeleton, &back.motion, OffsetMode::Replace),
    );
    let worst = a
        .iter()
        .zip(&b)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    assert!((worst - 1.2611).abs() < 1e-4, "{worst}");
}
