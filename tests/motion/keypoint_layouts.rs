//! A pose estimator's keypoints onto a skeleton (`solve --layout`): every take's joints written
//! as each layout's keypoints and solved back onto its own skeleton keep every limb bone's
//! direction (upper arms, forearms, thighs, shins) within 2° median; points a frame lacks are
//! filled and said; keypoints that cannot be a body are refused by name.

use crate::common::{data, files_in, shared_data};
use bvhview::Take;
use bvhview::model::pose::Up;
use bvhview::solve::layouts::{Keypoints, Layout, of_take, onto_skeleton, to_smpl};

/// SMPL's names of the limbs' bones: parent, child.
const LIMB_BONES: [(&str, &str); 8] = [
    ("left_shoulder", "left_elbow"),
    ("left_elbow", "left_wrist"),
    ("right_shoulder", "right_elbow"),
    ("right_elbow", "right_wrist"),
    ("left_hip", "left_knee"),
    ("left_knee", "left_ankle"),
    ("right_hip", "right_knee"),
    ("right_knee", "right_ankle"),
];

/// The median angle (degrees) between each limb bone of `take` and of its keypoints in
/// `layout` solved back onto its skeleton, over every frame and bone; `None` for a take whose
/// limbs the map does not all find.
fn round_trip(take: &Take, layout: Layout) -> Option<f64> {
    let (smpl, _) = bvhview::bvh::built_in::built_in("smpl22").unwrap();
    let map = bvhview::retarget::Map::guess(&take.skeleton, &smpl);
    let joint = |name: &str| {
        let k = smpl.joints.iter().position(|j| j.name == name)?;
        map.source_of[k]
    };
    let bones: Vec<(usize, usize)> = LIMB_BONES
        .iter()
        .map(|(a, b)| Some((joint(a)?, joint(b)?)))
        .collect::<Option<_>>()?;
    let stance = take.stance(take.offset_mode);
    let keypoints = of_take(take, layout, f64::from(stance.units.metres)).unwrap();
    // The take's own up axis stated, as a user states it (`--up`): a take drawn lying stays so.
    let up = match stance.up {
        Up::Y => glam::DVec3::Y,
        Up::Z => glam::DVec3::Z,
    };
    let placed = to_smpl(&keypoints, 0.3, Some(up), "keypoints").unwrap();
    let (positions, _) = onto_skeleton(&placed.positions, &take.skeleton).unwrap();
    let (motion, _) =
        bvhview::solve::solve(&take.skeleton, stance.up, &positions, Some(Up::Y.into())).unwrap();
    let solved = Take::new(take.skeleton.clone(), motion, "solved");
    let mut angles = Vec::new();
    for f in 0..take.frame_count() {
        // By joint (an ASF's exported points are not one a joint).
        let (a, b) = (take.joint_places(f), solved.joint_places(f));
        for &(p, c) in &bones {
            let (u, v) = (a[c] - a[p], b[c] - b[p]);
            angles.push(u.angle_between(v).to_degrees());
        }
    }
    angles.sort_by(f64::total_cmp);
    Some(angles[angles.len() / 2])
}

/// Every take of `files` that has a body's limbs, each layout: the worst median, and how many.
fn check(files: &[std::path::PathBuf]) {
    let (mut checked, mut worst) = (0, 0.0f64);
    for path in files {
        let Ok(take) = Take::open(path) else { continue };
        let take = take.trim(0..120);
        for layout in Layout::ALL {
            let Some(median) = round_trip(&take, layout) else {
                continue;
            };
            checked += 1;
            worst = worst.max(median);
            assert!(
                median < 2.0,
                "{} in {}: limb bones {median:.3}° median from the take's",
                path.display(),
                layout.label()
            );
        }
    }
    eprintln!("{checked} take × layout round trips: limb bones {worst:.4}° median at worst");
    assert!(checked >= 5 * 10, "only {checked} round trips");
}

#[test]
fn a_takes_keypoints_solved_back_keep_its_limbs_in_every_layout() {
    check(&files_in(&data("bvh"), "bvh"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn the_whole_corpus_keypoints_solved_back_keep_their_limbs() {
    check(&files_in(&shared_data("bvh"), "bvh"));
}

/// Keypoints of `layout` from a frames × points × 4 array.
fn keypoints(layout: Layout, frames: usize, value: impl Fn(usize, usize) -> [f64; 4]) -> Keypoints {
    let count = layout.points().len();
    let value = &value;
    let values: Vec<f64> = (0..frames)
        .flat_map(|f| (0..count).flat_map(move |p| value(f, p)))
        .collect();
    Keypoints::new(layout, &[frames, count, 4], &values, 1.0 / 30.0, "k.npy").unwrap()
}

#[test]
fn points_a_frame_lacks_are_filled_from_the_frames_around_and_said() {
    let walk = Take::open(data("bvh/bvh11_131_01.bvh"))
        .unwrap()
        .trim(0..30);
    let metres = f64::from(walk.stance(walk.offset_mode).units.metres);
    let good = of_take(&walk, Layout::Coco17, metres).unwrap();
    let count = 17;
    let elbow = Layout::Coco17
        .points()
        .iter()
        .position(|p| *p == "left_elbow")
        .unwrap();
    let broken = keypoints(Layout::Coco17, 30, |f, p| {
        let at = good.points[f * count + p];
        let confidence = good.confidence[f * count + p];
        match (p == elbow, f) {
            (true, 10) => [f64::NAN, f64::NAN, f64::NAN, 1.0],
            (true, 11) => [at.x, at.y, at.z, 0.1],
            _ => [at.x, at.y, at.z, confidence],
        }
    });
    let placed = to_smpl(&broken, 0.3, None, "k.npy").unwrap();
    assert!(
        placed
            .said
            .iter()
            .any(|s| s.starts_with("left_elbow: 2 of 30 frames filled")),
        "{:?}",
        placed.said
    );
    assert!(
        placed
            .said
            .iter()
            .any(|s| s.contains("coco17 has no pelvis")),
        "{:?}",
        placed.said
    );
    // Filled between frames 9 and 12: a third and two thirds of the way.
    let column = placed
        .positions
        .names
        .iter()
        .position(|n| n == "left_elbow")
        .unwrap();
    let names = placed.positions.names.len();
    let got = placed.positions.points[10 * names + column];
    let (before, after) = (
        good.points[9 * count + elbow],
        good.points[12 * count + elbow],
    );
    assert!((got - before.lerp(after, 1.0 / 3.0)).length() < 1e-12);
}

#[test]
fn keypoints_that_cannot_be_a_body_are_refused_by_name() {
    // A limb in no frame.
    let no_knee = keypoints(Layout::H36m17, 4, |_, p| match p {
        2 => [f64::NAN; 4],
        _ => [p as f64, 1.0 + p as f64, 0.0, 1.0],
    });
    let said = to_smpl(&no_knee, 0.3, None, "k.npy")
        .unwrap_err()
        .to_string();
    assert!(
        said.contains("h36m17's right_knee is in no frame"),
        "{said}"
    );
    // The wrong count of points, no frames, the wrong shape.
    let refused = |shape: &[usize]| {
        let values = vec![0.0; shape.iter().product()];
        Keypoints::new(Layout::Coco17, shape, &values, 1.0 / 30.0, "k.npy")
            .unwrap_err()
            .to_string()
    };
    assert!(refused(&[3, 18, 3]).contains("18 points a frame; coco17 has 17"));
    assert!(refused(&[0, 17, 3]).contains("no frames of coco17 keypoints"));
    assert!(refused(&[3, 17, 2]).contains("frames × points × 3 (or × 4"));
}

#[test]
fn a_figure_lying_or_upside_down_is_stood_up_and_said() {
    let walk = Take::open(data("bvh/bvh11_131_01.bvh"))
        .unwrap()
        .trim(0..10);
    let metres = f64::from(walk.stance(walk.offset_mode).units.metres);
    let upright = of_take(&walk, Layout::Body25, metres).unwrap();
    // A camera's y points down: every point turned half a turn about x.
    let mut camera = upright.clone();
    for p in &mut camera.points {
        *p = glam::DVec3::new(p.x, -p.y, -p.z);
    }
    let placed = to_smpl(&camera, 0.3, None, "k.npy").unwrap();
    assert!(
        placed.said.iter().any(|s| s.contains("stands along -y")),
        "{:?}",
        placed.said
    );
    let straight = to_smpl(&upright, 0.3, None, "k.npy").unwrap();
    for (a, b) in placed
        .positions
        .points
        .iter()
        .zip(&straight.positions.points)
    {
        assert!((*a - *b).length() < 1e-9);
    }
}

/// Each layout's points in its published order, pinned here apart from the library's tables:
/// a swapped entry in both directions of the round trip would not show there.
#[test]
fn each_layouts_points_are_its_published_order() {
    let pinned: [(Layout, &[(usize, &str)]); 5] = [
        (
            Layout::H36m17,
            &[
                (0, "pelvis"),
                (1, "right_hip"),
                (3, "right_ankle"),
                (4, "left_hip"),
                (8, "thorax"),
                (10, "head_top"),
                (11, "left_shoulder"),
                (13, "left_wrist"),
                (16, "right_wrist"),
            ],
        ),
        (
            Layout::Coco17,
            &[
                (0, "nose"),
                (3, "left_ear"),
                (5, "left_shoulder"),
                (6, "right_shoulder"),
                (9, "left_wrist"),
                (11, "left_hip"),
                (14, "right_knee"),
                (16, "right_ankle"),
            ],
        ),
        (
            Layout::Mediapipe33,
            &[
                (0, "nose"),
                (11, "left_shoulder"),
                (16, "right_wrist"),
                (23, "left_hip"),
                (28, "right_ankle"),
                (29, "left_heel"),
                (32, "right_foot_index"),
            ],
        ),
        (
            Layout::Body25,
            &[
                (1, "neck"),
                (2, "right_shoulder"),
                (7, "left_wrist"),
                (8, "mid_hip"),
                (11, "right_ankle"),
                (14, "left_ankle"),
                (19, "left_big_toe"),
                (24, "right_heel"),
            ],
        ),
        (
            Layout::Smpl24,
            &[
                (0, "pelvis"),
                (1, "left_hip"),
                (10, "left_foot"),
                (12, "neck"),
                (15, "head"),
                (21, "right_wrist"),
                (22, "left_hand"),
                (23, "right_hand"),
            ],
        ),
    ];
    for (layout, points) in pinned {
        for &(index, name) in points {
            assert_eq!(
                layout.points()[index],
                name,
                "{}'s point {index}",
                layout.label()
            );
        }
    }
}

/// An ASF/AMC take, whose exported points are not one a joint: its keypoints solved back keep
/// its limbs, and its metrics are measured on its joints.
#[test]
fn an_asf_takes_keypoints_and_metrics_are_its_joints() {
    let asf = data("asf_amc/heiden_12.asf");
    let take = bvhview::OpenOptions::new()
        .motion(data("asf_amc/heiden_12_02_01.amc"))
        .open(&asf)
        .unwrap()
        .trim(0..120);
    for layout in Layout::ALL {
        let median = round_trip(&take, layout).expect("a body's limbs");
        assert!(median < 2.0, "{}: {median}°", layout.label());
    }
    let figure = bvhview::metrics::figure_of_take(&take).unwrap();
    let measured = bvhview::metrics::measure(&figure, &Default::default()).unwrap();
    let feet: Vec<&str> = measured.feet.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(feet, ["ltoes", "rtoes"]);
}

/// Keypoint files that lie or hold what no layout is: refused with exit 2, naming what was
/// found, nothing written.
#[test]
fn hostile_keypoint_files_are_refused() {
    let folder = crate::common::scratch_folder("hostile-keypoints");
    // A header of `shape` over `values` float64s (the first one says more than it holds).
    let npy = |shape: &[usize], values: usize| {
        let data: Vec<u8> = (0..values).flat_map(|v| (v as f64).to_le_bytes()).collect();
        crate::common::npz::npy("<f8", shape, &data)
    };
    let walk = data("bvh/bvh11_131_01.bvh");
    for (name, bytes, said) in [
        // A header that promises a thousand frames over ten values.
        ("lying.npy", npy(&[1000, 17, 3], 10), "more than the file's"),
        (
            "eighteen.npy",
            npy(&[2, 18, 3], 108),
            "18 points a frame; coco17 has 17",
        ),
        (
            "empty.npy",
            npy(&[0, 17, 3], 0),
            "no frames of coco17 keypoints",
        ),
    ] {
        let path = folder.join(name);
        std::fs::write(&path, bytes).unwrap();
        let out = folder.join(format!("{name}.bvh"));
        let run = crate::common::bvhview(&[
            "solve",
            path.to_str().unwrap(),
            "--layout",
            "coco17",
            "--fps",
            "30",
            "--onto",
            walk.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(said), "{name}: {stderr}");
        assert!(!out.exists(), "{name}: wrote {}", out.display());
    }
}
