//! ASF/AMC: hand-computed FK, the ASF/AMC article's own algorithm on real takes, every real pair, errors,
//! and conversion to BVH.

use crate::common;
use bvhview::acclaim::amc::parse_amc;
use bvhview::acclaim::asf::parse_asf;
use bvhview::model::pose::{OffsetMode, world_matrices};
use common::*;
use glam::{DMat3, DVec3, Vec3};

/// A root whose order lists rotations first (RZ RY RX, not the default TX TY TZ RX RY RZ), a bone
/// `a` along +X with axis C = Rz(90°) and one dof, and a bone `b` along +Y without dof.
const SMALL_ASF: &str = "# test skeleton\n:version 1.10\n:units\n  mass 1.0\n  length 1\n  angle deg\n\
:root\n  order RZ RY RX TX TY TZ\n  axis XYZ\n  position 0 0 0\n  orientation 0 0 0\n:bonedata\n\
  begin\n    id 1\n    name a\n    direction 1 0 0\n    length 2\n    axis 0 0 90 XYZ\n    dof rx\n\
    limits (-180.0 180.0)\n  end\n  begin\n    id 2\n    name b\n    direction 0 1 0\n    length 3\n\
    axis 0 0 0 XYZ\n  end\n:hierarchy\n  begin\n    root a\n    a b\n  end\n";

const SMALL_AMC: &str =
    ":FULLY-SPECIFIED\n:DEGREES\n1\nroot 90 0 0 1 2 3\na 90\n2\nroot 0 0 0 0 0 0\na 0\n";

fn small() -> (bvhview::Skeleton, bvhview::Motion) {
    let asf = parse_asf(SMALL_ASF, "small.asf").unwrap();
    let (skeleton, maps) = asf.to_skeleton();
    let channels = skeleton.channel_count();
    let motion = parse_amc(SMALL_AMC, "small.amc", &maps, channels, true, 1.0 / 120.0).unwrap();
    (skeleton, motion)
}

fn export_positions(skeleton: &bvhview::Skeleton, frame: &[f32]) -> Vec<(String, Vec3)> {
    let mut matrices = Vec::new();
    world_matrices(skeleton, frame, OffsetMode::Replace, &mut matrices);
    bvhview::positions::export_points(skeleton)
        .into_iter()
        .map(|(name, joint)| (name, matrices[joint].w_axis.truncate()))
        .collect()
}

/// Frame 1 by hand. Root: M = Rx(0)·Ry(0)·Rz(90) (RZ is applied first), T = (1, 2, 3).
/// a: C·Rx(90)·C⁻¹ with C = Rz(90) is a 90° turn about C·x = y, so a's end (2, 0, 0) becomes
/// (0, 0, −2), then Rz(90) keeps it, + T: (1, 2, 1). b: (0, 3, 0) through Ry(90) stays, Rz(90)
/// makes it (−3, 0, 0): (−2, 2, 1). Frame 2 is the rest pose at the origin.
#[test]
fn fk_matches_hand_computed_points() {
    let (skeleton, motion) = small();
    assert_eq!(motion.frame_count(), 2);
    let got = export_positions(&skeleton, motion.frame(0));
    let want = [
        ("root", Vec3::new(1.0, 2.0, 3.0)),
        ("a", Vec3::new(1.0, 2.0, 1.0)),
        ("b", Vec3::new(-2.0, 2.0, 1.0)),
    ];
    assert_eq!(got.len(), 3);
    for ((name, p), (want_name, q)) in got.iter().zip(want) {
        assert_eq!(name, want_name);
        assert!(p.abs_diff_eq(q, 1e-5), "{name}: {p} vs {q}");
    }
    let rest = export_positions(&skeleton, motion.frame(1));
    assert!(rest[1].1.abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-6));
    assert!(rest[2].1.abs_diff_eq(Vec3::new(2.0, 3.0, 0.0), 1e-6));
    let asf = parse_asf(SMALL_ASF, "small.asf").unwrap();
    assert_eq!(asf.bones[0].limits, vec![(-180.0, 180.0)]);
}

fn rot(axis: usize, degrees: f64) -> DMat3 {
    let r = degrees.to_radians();
    match axis {
        0 => DMat3::from_rotation_x(r),
        1 => DMat3::from_rotation_y(r),
        _ => DMat3::from_rotation_z(r),
    }
}

/// The ASF/AMC article's `cal_global_coord`, written again in f64 from the article: for each bone, its
/// vector in its own axis frame, then up to the root: rotate by the dof (x, then y, then z),
/// by the bone's axis, add the parent's direction × length, undo the parent's axis; finally the
/// root's rotation and translation. CMU files use `axis … XYZ` and root order TX TY TZ RX RY RZ.
fn acclaim_article_positions(
    asf: &bvhview::acclaim::Asf,
    amc_frame: &[(String, Vec<f64>)],
) -> Vec<(String, DVec3)> {
    let axis = |i: usize| {
        let a = asf.bones[i].axis;
        rot(2, a[2]) * rot(1, a[1]) * rot(0, a[0])
    };
    let dof = |i: usize| -> [f64; 3] {
        let bone = &asf.bones[i];
        let mut xyz = [0.0; 3];
        if let Some((_, values)) = amc_frame.iter().find(|(n, _)| *n == bone.name) {
            for (d, v) in bone.dof.iter().zip(values) {
                xyz[format!("{d:?}").as_bytes()[1] as usize - b'x' as usize] = *v;
            }
        }
        xyz
    };
    let mut parent = vec![None; asf.bones.len()];
    for (p, children) in asf.children.iter().enumerate() {
        for &c in children {
            parent[c] = Some(p);
        }
    }
    let root = &amc_frame.iter().find(|(n, _)| n == "root").unwrap().1;
    let mut out = vec![("root".to_string(), DVec3::new(root[0], root[1], root[2]))];
    for i in 0..asf.bones.len() {
        let bone = &asf.bones[i];
        let vector = |j: usize| DVec3::from_array(asf.bones[j].direction) * asf.bones[j].length;
        let mut temp = axis(i).inverse() * vector(i);
        let mut current = i;
        loop {
            let [x, y, z] = dof(current);
            temp = rot(2, z) * (rot(1, y) * (rot(0, x) * temp));
            temp = axis(current) * temp;
            match parent[current] {
                Some(p) => {
                    temp += vector(p);
                    temp = axis(p).inverse() * temp;
                    current = p;
                }
                None => break,
            }
        }
        temp = rot(2, root[5]) * (rot(1, root[4]) * (rot(0, root[3]) * temp));
        temp += DVec3::new(root[0], root[1], root[2]);
        out.push((bone.name.clone(), temp));
    }
    out
}

/// The AMC frame `n` (1-based) as (bone, values), read simply.
fn amc_frame(text: &str, n: usize) -> Vec<(String, Vec<f64>)> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in text.lines().map(str::trim) {
        if line.chars().all(|c| c.is_ascii_digit()) && !line.is_empty() {
            if inside {
                break;
            }
            inside = line.parse::<usize>().unwrap() == n;
        } else if inside {
            let mut words = line.split_whitespace();
            let name = words.next().unwrap().to_string();
            out.push((name, words.map(|w| w.parse().unwrap()).collect()));
        }
    }
    out
}

#[test]
fn fk_matches_seed_004s_algorithm_on_a_repository_take() {
    check_fk_against_seed_004(&repo_data("asf_amc"), &[("heiden_12", "heiden_12_02_01")]);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn fk_matches_seed_004s_algorithm_on_whole_corpus_takes() {
    check_fk_against_seed_004(
        &shared_data("asf_amc"),
        &[
            ("simchoni_charleston", "simchoni_charleston_1"),
            ("heiden_12", "heiden_12_02_01"),
        ],
    );
}

fn check_fk_against_seed_004(folder: &std::path::Path, takes: &[(&str, &str)]) {
    for (asf_name, amc_name) in takes {
        let asf_path = folder.join(format!("{asf_name}.asf"));
        let amc_path = folder.join(format!("{amc_name}.amc"));
        let asf = bvhview::acclaim::load_asf(&asf_path, u64::MAX).unwrap();
        let loaded = crate::common::load_take(&asf_path, Some(&amc_path), None).unwrap();
        let amc_text = std::fs::read_to_string(&amc_path).unwrap();
        for n in [1, 50, 300] {
            let expected = acclaim_article_positions(&asf, &amc_frame(&amc_text, n));
            let got = export_positions(&loaded.skeleton, loaded.motion.frame(n - 1));
            assert_eq!(got.len(), expected.len());
            for (name, want) in &expected {
                let (_, p) = got
                    .iter()
                    .find(|(g, _)| g == name)
                    .unwrap_or_else(|| panic!("{name} missing"));
                assert!(
                    (p.as_dvec3() - *want).length() < 1e-3,
                    "{asf_name} frame {n} {name}: {p} vs {want}"
                );
            }
        }
    }
}

/// CMU's skeleton: the root, 30 bones and 7 End Sites.
const CMU_JOINTS: usize = 38;

#[test]
fn every_repository_pair_loads_and_converts_to_bvh_with_the_same_positions() {
    check_pairs(
        &repo_data("asf_amc"),
        &[("heiden_12", "heiden_12_02_01", 343, CMU_JOINTS)],
    );
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_pair_loads_and_converts_to_bvh_with_the_same_positions() {
    check_pairs(
        &shared_data("asf_amc"),
        &[
            ("heiden_12", "heiden_12_02_01", 343, CMU_JOINTS),
            // Not CMU's: tab-separated, 19 bones and 5 End Sites.
            ("pyasfamc_test", "pyasfamc_test", 300, 24),
            (
                "simchoni_charleston",
                "simchoni_charleston_1",
                506,
                CMU_JOINTS,
            ),
            (
                "simchoni_charleston",
                "simchoni_charleston_2",
                546,
                CMU_JOINTS,
            ),
            ("simchoni_lambada", "simchoni_lambada_1", 2180, CMU_JOINTS),
            (
                "simchoni_pirouette",
                "simchoni_pirouette_1",
                591,
                CMU_JOINTS,
            ),
        ],
    );
}

/// Each pair (ASF, AMC, frames, joints with End Sites) loads, and converts to a BVH whose every
/// point stands where the pair's does, on every frame.
fn check_pairs(folder: &std::path::Path, pairs: &[(&str, &str, usize, usize)]) {
    assert_eq!(
        files_in(folder, "amc").len(),
        pairs.len(),
        "a pair in {} is not tested",
        folder.display()
    );
    for &(asf_name, amc_name, frames, joints) in pairs {
        let asf_path = folder.join(format!("{asf_name}.asf"));
        let amc_path = folder.join(format!("{amc_name}.amc"));
        let loaded = crate::common::load_take(&asf_path, Some(&amc_path), None).unwrap();
        assert_eq!(loaded.motion.frame_count(), frames, "{amc_name}");
        assert_eq!(loaded.skeleton.joints.len(), joints, "{asf_name}");

        let out = crate::common::scratch_folder("x").join(format!("{amc_name}.bvh"));
        let status = crate::common::bvhview_command()
            .arg("convert")
            .arg(&asf_path)
            .arg("--motion")
            .arg(&amc_path)
            .arg("-o")
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        let bvh = bvhview::bvh::load_file(&out, Default::default()).unwrap();
        std::fs::remove_file(&out).unwrap();
        assert_eq!(bvh.motion.frame_count(), loaded.motion.frame_count());
        assert!(bvh.skeleton.joints.iter().all(|j| j.axis.is_none()));

        let rest =
            bvhview::model::pose::world_positions(&loaded.skeleton, &[], OffsetMode::Replace);
        let (low, high) = rest
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), p| (l.min(p.y), h.max(p.y)));
        let tolerance = 1e-4 * (high - low);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut worst = 0.0f32;
        for frame in 0..loaded.motion.frame_count() {
            world_matrices(
                &loaded.skeleton,
                loaded.motion.frame(frame),
                OffsetMode::Replace,
                &mut a,
            );
            world_matrices(
                &bvh.skeleton,
                bvh.motion.frame(frame),
                OffsetMode::Replace,
                &mut b,
            );
            for (m, n) in a.iter().zip(&b) {
                worst = worst.max(m.w_axis.truncate().distance(n.w_axis.truncate()));
            }
        }
        assert!(
            worst <= tolerance,
            "{amc_name}: worst distance {worst} > {tolerance}"
        );
    }
}

#[test]
fn frames_are_unlimited_and_radians_are_read() {
    let asf = parse_asf(
        &SMALL_ASF
            .replace("angle deg", "angle rad")
            .replace("0 0 90 XYZ", "0 0 1.5707963267948966 XYZ"),
        "r.asf",
    )
    .unwrap();
    let (skeleton, maps) = asf.to_skeleton();
    let mut amc = String::from(":FULLY-SPECIFIED\n:RADIANS\n");
    for n in 1..=6000 {
        amc.push_str(&format!(
            "{n}\nroot 1.5707963267948966 0 0 1 2 3\na 1.5707963267948966\n"
        ));
    }
    let motion = parse_amc(
        &amc,
        "long.amc",
        &maps,
        skeleton.channel_count(),
        asf.units.degrees,
        0.01,
    )
    .unwrap();
    assert_eq!(motion.frame_count(), 6000);
    let got = export_positions(&skeleton, motion.frame(5999));
    assert!(
        got[2].1.abs_diff_eq(Vec3::new(-2.0, 2.0, 1.0), 1e-5),
        "{}",
        got[2].1
    );
}

fn asf_error(text: &str) -> String {
    parse_asf(text, "t.asf").unwrap_err().to_string()
}

fn amc_error(text: &str) -> String {
    let (skeleton, maps) = parse_asf(SMALL_ASF, "small.asf").unwrap().to_skeleton();
    parse_amc(text, "t.amc", &maps, skeleton.channel_count(), true, 0.01)
        .unwrap_err()
        .to_string()
}

#[test]
fn malformed_asf_and_amc_give_line_and_column() {
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    a b\n", "    a c\n")),
        "t.asf:32:7: expected a bone named in :bonedata, found 'c'"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    a b\n", "    a b\n    b a\n")),
        "t.asf:33:7: 'a' already has a parent: the hierarchy is not a tree"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    root a\n    a b\n", "    a b\n    b a\n")),
        "t.asf:32:7: the hierarchy loops through 'a' and never reaches root"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    length 3\n", "")),
        "t.asf:27:3: 'b' (begun at line 22) ends without a length"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    direction 1 0 0\n", "")),
        "t.asf:20:3: 'a' (begun at line 13) ends without a direction"
    );
    assert_eq!(
        asf_error(&SMALL_ASF[..SMALL_ASF.find(":hierarchy").unwrap()]),
        "t.asf:29:1: missing section :hierarchy"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("    dof rx\n", "    dof rx rw\n")),
        "t.asf:19:12: expected rx, ry or rz, found 'rw'"
    );
    assert_eq!(
        asf_error(&SMALL_ASF.replace("length 2", "length two")),
        "t.asf:17:12: expected a number (length), found 'two'"
    );

    // The largest frame number, then any other: an error, not an overflow.
    let max = i64::MAX;
    assert_eq!(
        amc_error(&format!(":DEGREES\n{max}\nroot 0 0 0 0 0 0\na 0\n{max}\n")),
        format!("t.amc:5:1: expected the end (no frame number follows {max}), found '{max}'")
    );
    assert_eq!(
        amc_error(":DEGREES\n1\nroot 0 0 0 0 0 0\na 0\nc 1\n"),
        "t.amc:5:1: expected a bone of the ASF skeleton, found 'c'"
    );
    assert_eq!(
        amc_error(":DEGREES\n1\nroot 0 0 0 0 0 0\na 0 7\n"),
        "t.amc:4:5: 'a' has 1 dof in the ASF, found 2 values"
    );
    assert_eq!(
        amc_error(":DEGREES\n1\nroot 0 0 0 0 0\na 0\n"),
        "t.amc:3:1: 'root' has 6 dof in the ASF, found 5 values"
    );
    assert_eq!(
        amc_error(":DEGREES\n1\nroot 0 0 0 0 0 0\na 0\n3\n"),
        "t.amc:5:1: expected frame number 2, found '3'"
    );
    assert_eq!(
        amc_error(":DEGREES\n1\nroot 0 0 0 0 0 0\n2\n"),
        "t.amc:2:1: frame 1 has no line for 'a'"
    );
    assert_eq!(
        amc_error(":DEGREES\nroot 0 0 0 0 0 0\n"),
        "t.amc:2:1: expected a frame number, found 'root'"
    );
    assert_eq!(
        amc_error("1\r\nroot 0 0 0 0 0 x\r\na 0\r\n"),
        "t.amc:2:16: expected a number, found 'x'"
    );
}

#[test]
fn every_command_takes_an_asf_amc_pair() {
    let asf = data("asf_amc/heiden_12.asf").display().to_string();
    let amc = data("asf_amc/heiden_12_02_01.amc").display().to_string();
    let run = |args: &[&str]| {
        crate::common::bvhview_command()
            .args(args)
            .output()
            .unwrap()
    };
    let print = run(&["print", &asf, "--motion", &amc]);
    assert!(print.status.success());
    assert!(String::from_utf8(print.stdout).unwrap().starts_with(
        "root : 0.000000,0.000000,0.000000 -1- zyx\n -lhipjoint : 0.000000,0.000000,0.000000 -0- \n"
    ));
    let info = run(&["info", &asf, "--motion", &amc, "--frame-time", "0.01"]);
    let text = String::from_utf8(info.stdout).unwrap();
    assert!(
        text.contains("frame time:       0.01 s (100.00 frames per second)\n"),
        "{text}"
    );
    let positions = run(&[
        "positions",
        &asf,
        "--motion",
        &amc,
        "--frames",
        "0",
        "--scale",
        "2",
    ]);
    let csv = String::from_utf8(positions.stdout).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 1 + 31, "the root and 30 bone ends");
    assert!(
        rows[2].starts_with("0,lhipjoint,") && rows[3].starts_with("0,lfemur,"),
        "{csv}"
    );
    let unscaled = run(&["positions", &asf, "--motion", &amc, "--frames", "0"]);
    let first = |csv: &str| {
        csv.lines()
            .nth(1)
            .unwrap()
            .split(',')
            .nth(3)
            .unwrap()
            .parse::<f32>()
            .unwrap()
    };
    assert_eq!(
        first(&csv),
        2.0 * first(&String::from_utf8(unscaled.stdout).unwrap())
    );
    // An ASF alone is its rest pose; an AMC alone is an error naming the fix.
    assert!(run(&["info", &asf]).status.success());
    let alone = run(&["info", &amc]);
    assert_eq!(alone.status.code(), Some(2));
    assert!(
        String::from_utf8(alone.stderr)
            .unwrap()
            .contains("give its skeleton: bvhview COMMAND SKELETON.asf --motion")
    );
    let picture = crate::common::scratch_folder("asf").join("asf.png");
    let snap = run(&[
        "snapshot",
        &asf,
        "--motion",
        &amc,
        "--frame",
        "10",
        "--fit",
        "--size",
        "64x64",
        "-o",
        picture.to_str().unwrap(),
    ]);
    assert!(
        snap.status.success(),
        "{}",
        String::from_utf8_lossy(&snap.stderr)
    );
    std::fs::remove_file(picture).unwrap();
}

// Acclaim's `direction` is a unit vector and `length` the bone's length. A file
// whose directions are longer drew blown up ("stands 496588.812 tall"), without a word.
#[test]
fn directions_that_are_not_unit_vectors_are_normalised_with_one_warning() {
    let asf = edge("asf_direction_not_unit.asf");
    let out = crate::common::bvhview_command()
        .args(["positions", asf.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        "frame,joint,x,y,z\n0,root,0,0,0\n0,spine,0,4,0\n0,head,0,4,1\n",
        "spine is its length 4 long, head 1"
    );
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.starts_with(&format!(
            "bvhview: {}: warning: 2 bones' directions are not unit vectors (the first, 'spine' \
             at line 16, is 1000 long): normalised (each bone's length is its 'length')\n",
            asf.display()
        )),
        "{stderr}"
    );

    // One bone off: named alone. Rounding in the last printed digits is not worth a word.
    let one = parse_asf(
        &SMALL_ASF.replace("direction 0 1 0", "direction 0 0.5 0"),
        "t.asf",
    )
    .unwrap();
    assert_eq!(one.bones[1].direction, [0.0, 1.0, 0.0]);
    assert_eq!(
        one.warnings,
        [
            "bone 'b' (line 22): direction is 0.5 long, not a unit vector: normalised (the bone's \
          length is its 'length')"
        ]
    );
    let rounded = parse_asf(
        &SMALL_ASF.replace("direction 0 1 0", "direction 0 0.99999 0"),
        "t.asf",
    )
    .unwrap();
    assert_eq!(rounded.bones[1].direction, [0.0, 0.99999, 0.0]);
    assert!(rounded.warnings.is_empty());
    // Components far below or above 1 are scaled, not squared into 0 or infinity.
    let tiny = parse_asf(
        &SMALL_ASF.replace("direction 0 1 0", "direction 0 1e-200 0"),
        "t.asf",
    )
    .unwrap();
    assert_eq!(tiny.bones[1].direction, [0.0, 1.0, 0.0]);
}

#[test]
fn a_direction_of_zero_length_is_an_error_at_its_line_and_column() {
    assert_eq!(
        asf_error(&SMALL_ASF.replace("direction 0 1 0", "direction 0 0.0 -0")),
        "t.asf:25:15: expected a direction along the bone (a unit vector), found '0 0.0 -0'"
    );
}

// CMU names a subject's skeleton `07.asf` and its takes `07_05.amc`; a take
// without its skeleton is listed as such, not failed.
#[test]
fn info_on_a_folder_pairs_takes_by_cmu_subject_and_notes_unpaired_ones() {
    let dir = crate::common::scratch_folder("cmu");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("lone")).unwrap();
    std::fs::copy(data("asf_amc/heiden_12.asf"), dir.join("07.asf")).unwrap();
    let take = data("asf_amc/heiden_12_02_01.amc");
    std::fs::copy(&take, dir.join("07_05.amc")).unwrap();
    std::fs::copy(&take, dir.join("12_01.amc")).unwrap();
    std::fs::copy(&take, dir.join("lone/walk.amc")).unwrap();
    let out = crate::common::bvhview_command()
        .args(["info", dir.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let d = dir.display();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[..3],
        [
            format!("ok     {d}/07.asf + {d}/07_05.amc: 31 joints, 343 frames, 2.9 s"),
            format!("note   {d}/12_01.amc: unpaired: no skeleton (12.asf) in its folder"),
            format!("note   {d}/lone/walk.amc: unpaired: no skeleton (walk.asf) in its folder"),
        ],
        "{text}"
    );
    assert!(
        lines[3].starts_with("3 files: 1 ok, 2 unpaired, 0 failed; "),
        "{}",
        lines[3]
    );
    assert_eq!(out.status.code(), Some(0), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}
