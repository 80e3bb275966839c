//! Every real BVH file loads, with the counts and values its text holds: the repository's own
//! corpus (tests/data/bvh) always, the whole corpus (../shared/data/bvh) when it is there.

use crate::common;
use bvhview::{Channel, RotationOrder};
use common::*;

#[test]
fn every_repository_file_loads_with_consistent_shape() {
    check_shapes(&repo_data("bvh"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_whole_corpus_file_loads_with_consistent_shape() {
    check_shapes(&shared_data("bvh"));
}

fn check_shapes(folder: &std::path::Path) {
    for path in files_in(folder, "bvh") {
        let bvh =
            bvhview::bvh::load_file(&path, Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let skeleton = &bvh.skeleton;
        assert!(!skeleton.joints.is_empty(), "{}", path.display());
        assert_eq!(
            bvh.motion.data.len(),
            bvh.motion.frame_count() * skeleton.channel_count(),
            "{}",
            path.display()
        );
        // Pre-order: parents before children; columns follow the CHANNELS lines in file order.
        let mut next_column = 0;
        for (i, joint) in skeleton.joints.iter().enumerate() {
            if let Some(parent) = joint.parent {
                assert!(parent < i);
                assert!(skeleton.joints[parent].children.contains(&i));
            }
            assert_eq!(joint.first_channel, next_column, "{}", joint.name);
            next_column += joint.channels.len();
            if joint.end_site {
                assert!(joint.channels.is_empty() && joint.children.is_empty());
            }
        }
    }
}

/// What a file's text says: its name, joints (End Sites included), End Sites, channels, frames,
/// frame time, the first three values of frame 0 and the last value of the last frame (NaN: not
/// checked).
struct Facts(&'static str, usize, usize, usize, usize, f64, [f32; 3], f32);

const FACTS: &[Facts] = &[
    Facts(
        "assimp_01_01",
        38,
        7,
        96,
        2752,
        0.0083333,
        [9.3722, 17.8693, -17.3198],
        -0.9244,
    ),
    Facts(
        "bvh11_131_01",
        38,
        7,
        96,
        994,
        0.0083333,
        [5.23, 16.9002, -33.8986],
        19.734,
    ),
    Facts(
        "bvhpython_test_mocapbank",
        24,
        5,
        60,
        455,
        0.033333,
        [-44.0003, 93.5663, 229.0256],
        -7.44,
    ),
    Facts(
        "opencollar_run",
        26,
        6,
        63,
        31,
        0.033333,
        [0.0, 46.2002, 0.0],
        0.0,
    ),
    Facts(
        "animateddrawings_rokoko_jesse_dance",
        73,
        13,
        183,
        1007,
        0.01,
        [-6.2023, 87.7332, -161.6986],
        22.6186,
    ),
    Facts(
        "makehuman_tpose",
        222,
        49,
        951,
        1,
        0.041667,
        [0.0, 0.6394, 0.027754],
        0.0,
    ),
    Facts(
        "bandai_dataset-1_dance-short_normal_001",
        27,
        5,
        132,
        1901,
        0.0333333,
        [0.0, 0.0, 0.0],
        -16.5734,
    ),
    Facts(
        "alinen_t-pose",
        66,
        13,
        162,
        1,
        0.033333,
        [0.0, 100.0, 0.0],
        -0.0,
    ),
    Facts(
        "assimp_Boxing_Toes",
        26,
        5,
        66,
        3069,
        0.01,
        [f32::NAN; 3],
        f32::NAN,
    ),
    Facts(
        "opencollar_oc_stand_boy01",
        24,
        5,
        60,
        100,
        0.033333,
        [f32::NAN; 3],
        f32::NAN,
    ),
];

#[test]
fn counts_and_values_match_the_repository_files() {
    let mut checked = 0;
    for facts in FACTS {
        let path = repo_data(&format!("bvh/{}.bvh", facts.0));
        if path.exists() {
            check_facts(facts, &path);
            checked += 1;
        }
    }
    assert_eq!(checked, 7, "files of FACTS in tests/data/bvh");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn counts_and_values_match_the_whole_corpus_files() {
    for facts in FACTS {
        check_facts(facts, &shared_data(&format!("bvh/{}.bvh", facts.0)));
    }
}

fn check_facts(facts: &Facts, path: &std::path::Path) {
    let &Facts(name, joints, end_sites, channels, frames, frame_time, first, last) = facts;
    let bvh = load_path(path);
    assert_eq!(bvh.skeleton.joints.len(), joints, "{name} joints");
    assert_eq!(bvh.skeleton.end_site_count(), end_sites, "{name} end sites");
    assert_eq!(bvh.skeleton.channel_count(), channels, "{name} channels");
    assert_eq!(bvh.motion.frame_count(), frames, "{name} frames");
    assert_eq!(bvh.motion.frame_time, frame_time, "{name} frame time");
    if !first[0].is_nan() {
        assert_eq!(&bvh.motion.frame(0)[..3], &first, "{name} first values");
        assert_eq!(*bvh.motion.data.last().unwrap(), last, "{name} last value");
    }
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn exponents_are_read() {
    let bvh = load_path(&shared_data(
        "bvh/bandai_dataset-1_dance-short_normal_001.bvh",
    ));
    let offsets: Vec<f32> = bvh.skeleton.joints.iter().map(|j| j.offset.y).collect();
    assert!(offsets.contains(&1.87007e-05));
    let row = bvh.motion.frame(0);
    assert_eq!(row[row.len() - 2], 1.4744e-05);
}

#[test]
fn names_keep_colons_and_dots() {
    let bvh = load("bvh/bvhpython_test_freebvh.bvh");
    assert_eq!(bvh.skeleton.joints[0].name, "mixamorig:Hips");
    let long = bvh
        .skeleton
        .joints
        .iter()
        .find(|j| j.name == "mixamorig:LeftHandMiddle1");
    assert!(
        long.is_some(),
        "names are not cut to the article's 24 bytes"
    );
    let makehuman = load("bvh/makehuman_tpose.bvh");
    assert_eq!(makehuman.skeleton.joints[1].name, "pelvis.R");
}

#[test]
fn per_joint_rotation_orders_and_position_channels() {
    let bvh = load("bvh/bvh11_131_01.bvh");
    let order = |name: &str| {
        bvh.skeleton
            .joints
            .iter()
            .find(|j| j.name == name)
            .unwrap()
            .rotation_order
    };
    assert_eq!(order("Hips"), Some(RotationOrder::Zyx));
    assert_eq!(order("LeftElbow"), Some(RotationOrder::Zxy));

    let run = load("bvh/opencollar_run.bvh");
    let orders: std::collections::BTreeSet<_> = run
        .skeleton
        .joints
        .iter()
        .filter_map(|j| j.rotation_order)
        .collect();
    assert_eq!(orders.len(), 4, "XZY, YZX, ZYX and XYZ in one CR-only file");

    let makehuman = load("bvh/makehuman_tpose.bvh");
    let six = makehuman
        .skeleton
        .joints
        .iter()
        .filter(|j| j.channels.len() == 6)
        .count();
    assert_eq!(six, 144, "position channels on 143 joints below the root");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn position_channels_on_every_joint_of_bandai() {
    let bandai = load_path(&shared_data(
        "bvh/bandai_dataset-2_wave-left-hand_active_011.bvh",
    ));
    let six = bandai
        .skeleton
        .joints
        .iter()
        .filter(|j| j.channels.len() == 6)
        .count();
    assert_eq!(six, 22);
    assert!(
        bandai.skeleton.joints[1].channels[..3]
            .iter()
            .all(|c| c.is_position())
    );
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn root_written_joint_and_end_sites_written_joint_site() {
    let bvh = load_path(&shared_data("bvh/alinen_t-pose.bvh"));
    let root = &bvh.skeleton.joints[0];
    assert_eq!(root.name, "Beta:Hips");
    assert_eq!(root.parent, None);
    assert_eq!(
        root.channels[..3],
        [Channel::Xposition, Channel::Yposition, Channel::Zposition]
    );
    let site = bvh
        .skeleton
        .joints
        .iter()
        .find(|j| j.name == "Site")
        .unwrap();
    assert!(site.end_site && site.channels.is_empty());
}

#[test]
fn mixed_line_endings_and_lf_only_lines_inside_crlf() {
    for name in ["bvhparser_walk_01", "bvh11_131_01"] {
        let bvh = load(&format!("bvh/{name}.bvh"));
        assert_eq!(bvh.skeleton.channel_count(), 96, "{name}");
        assert!(bvh.warnings.is_empty(), "{name}: {:?}", bvh.warnings);
    }
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn mixed_line_endings_in_deep_motion_editing_example() {
    let path = shared_data("bvh/deepmotionediting_blender_example.bvh");
    let bvh = load_path(&path);
    assert_eq!(bvh.skeleton.channel_count(), 96);
    assert!(bvh.warnings.is_empty(), "{:?}", bvh.warnings);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn one_extra_row_after_frames_warns_and_keeps_the_count() {
    let boxing = load_path(&shared_data("bvh/assimp_Boxing_Toes.bvh"));
    assert_eq!(boxing.motion.frame_count(), 3069);
    assert_eq!(boxing.warnings.len(), 1);
    assert!(
        boxing.warnings[0].starts_with("1 extra row after the 3069"),
        "{}",
        boxing.warnings[0]
    );
}

#[test]
fn a_trailer_of_short_rows_after_frames_warns_and_keeps_the_count() {
    let stand = load("bvh/opencollar_oc_stand_boy01.bvh");
    assert_eq!(stand.warnings.len(), 1);
    assert!(
        stand.warnings[0].starts_with("24 extra rows after the 100"),
        "{}",
        stand.warnings[0]
    );
}
