//! FBX and glTF in: files made by others, read into the same Skeleton + Motion a BVH
//! loads into.
//!
//! - ufbx's own test files (tests/data/fbx/ufbx, MIT/Unlicense): what bvhview reads of each is
//!   pinned (joints, end sites, frames, fps), and the ASCII and binary saves of one scene agree;
//! - Blender's exports of repository BVH takes (tests/data/fbx, tests/data/gltf, made by
//!   tests/blender/export_fbx_gltf.py): every joint's world position in every frame within 1e-4
//!   of the figure's height of the source BVH's;
//! - bvhview's own glTF export read back: the take it was written from (1e-5 of the height).

use crate::common::bvhview_command;
use bvhview::model::pose::{OffsetMode, world_positions};
use bvhview::take::{self, Take};
use std::path::{Path, PathBuf};

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(path)
}

fn load(path: &Path) -> Take {
    crate::common::load_take(path, None, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn load_take(path: &Path, take: &str) -> Take {
    take::OpenOptions::new()
        .threads(1)
        .take(take)
        .open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The spread of frame 0's joints along their widest axis.
fn height(loaded: &Take) -> f32 {
    let points = world_positions(
        &loaded.skeleton,
        loaded.motion.frame(0),
        OffsetMode::Replace,
    );
    let (mut low, mut high) = (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN));
    for p in &points {
        low = low.min(*p);
        high = high.max(*p);
    }
    (high - low).max_element()
}

/// Name of each point as bvhview's exports name them: joints by name, End Sites `<parent>_End`
/// (a source BVH's End Site and an FBX leaf bone `<parent>_end` meet there).
fn point_names(loaded: &Take) -> Vec<String> {
    let joints = &loaded.skeleton.joints;
    joints
        .iter()
        .map(|j| match (j.end_site, j.parent) {
            (true, Some(p)) => format!("{}_End", joints[p].name),
            _ => j.name.clone(),
        })
        .collect()
}

/// An End Site at its joint (`OFFSET 0 0 0`, Mixamo's eyes): Blender gives every bone a length,
/// so its importer moves such a tail 0.1 along the bone's axis and its exports keep it there.
fn zero_length_end(joint: &bvhview::model::skeleton::Joint) -> bool {
    joint.end_site && joint.offset.length() < 1e-6
}

/// The worst distance, over `frames` frames and every point of `want` also in `got` (by name;
/// an End Site of `got` also by its own name, as a leaf joint of a glTF skin, which Blender's
/// exporter writes without the bone's tail), divided by `want`'s height; and how many points
/// were compared.
fn worst_relative(want: &Take, got: &Take, frames: usize) -> (f32, usize) {
    let want_names = point_names(want);
    let got_names = point_names(got);
    let pairs: Vec<(usize, usize)> = want_names
        .iter()
        .enumerate()
        .filter(|&(i, _)| !zero_length_end(&want.skeleton.joints[i]))
        .filter_map(|(i, n)| {
            got_names
                .iter()
                .position(|m| m == n)
                .or_else(|| {
                    let joints = &got.skeleton.joints;
                    joints.iter().position(|j| j.end_site && &j.name == n)
                })
                .map(|k| (i, k))
        })
        .collect();
    let size = height(want);
    let mut worst = 0.0f32;
    for f in 0..frames {
        let a = world_positions(&want.skeleton, want.motion.frame(f), OffsetMode::Replace);
        let b = world_positions(&got.skeleton, got.motion.frame(f), OffsetMode::Replace);
        for &(i, k) in &pairs {
            worst = worst.max((a[i] - b[k]).length() / size);
        }
    }
    (worst, pairs.len())
}

/// (file, joints, end sites, frames, frames per second) as bvhview reads them (joints without
/// the End Sites, as `info` counts them).
const UFBX_FILES: [(&str, usize, usize, usize, f64); 26] = [
    ("blender_279_bone_radius_6100_ascii.fbx", 4, 1, 250, 24.0),
    ("blender_279_bone_radius_7400_binary.fbx", 4, 1, 1, 24.0),
    ("max2009_cube_anim_5800_ascii.fbx", 1, 0, 61, 30.0),
    ("max2009_cube_anim_5800_binary.fbx", 1, 0, 61, 30.0),
    ("maya_anim_interpolation_7700_ascii.fbx", 1, 0, 61, 30.0),
    ("maya_anim_layers_7500_ascii.fbx", 1, 0, 120, 24.0),
    ("maya_anim_no_inherit_scale_7700_ascii.fbx", 4, 0, 34, 24.0),
    ("maya_anim_pivot_rotate_7700_ascii.fbx", 1, 0, 21, 24.0),
    ("maya_bone_radius_6100_ascii.fbx", 7, 1, 120, 24.0),
    ("maya_bone_radius_7500_ascii.fbx", 7, 1, 120, 24.0),
    ("maya_character_7500_binary.fbx", 49, 13, 120, 24.0),
    ("maya_post_rotate_order_6100_binary.fbx", 2, 0, 120, 24.0),
    ("maya_post_rotate_order_7500_ascii.fbx", 2, 0, 120, 24.0),
    ("maya_post_rotate_order_7500_binary.fbx", 2, 0, 120, 24.0),
    ("maya_human_ik_7400_binary.fbx", 49, 13, 120, 24.0),
    ("maya_rotation_order_6100_ascii.fbx", 6, 0, 120, 24.0),
    ("maya_rotation_order_6100_binary.fbx", 6, 0, 120, 24.0),
    ("maya_rotation_order_7500_ascii.fbx", 6, 0, 120, 24.0),
    ("maya_rotation_order_7500_binary.fbx", 6, 0, 120, 24.0),
    ("maya_scale_no_inherit_7700_ascii.fbx", 4, 0, 120, 24.0),
    ("maya_transform_animation_6100_ascii.fbx", 1, 0, 120, 24.0),
    ("maya_transform_animation_6100_binary.fbx", 1, 0, 120, 24.0),
    ("motionbuilder_pivot_7700_ascii.fbx", 1, 0, 151, 30.0),
    (
        "synthetic_anim_stack_no_props_7100_ascii.fbx",
        1,
        0,
        12,
        24.0,
    ),
    ("synthetic_pre_post_rotate_7500_ascii.fbx", 2, 0, 120, 24.0),
    (
        "synthetic_rotation_order_layers_7700_ascii.fbx",
        1,
        0,
        21,
        24.0,
    ),
];

#[test]
fn ufbx_test_files_read_as_pinned() {
    for (name, joints, end_sites, frames, fps) in UFBX_FILES {
        let loaded = load(&data("fbx/ufbx").join(name));
        let skeleton = &loaded.skeleton;
        let real = skeleton.joints.len() - skeleton.end_site_count();
        assert_eq!(real, joints, "{name}: joints");
        assert_eq!(skeleton.end_site_count(), end_sites, "{name}: end sites");
        assert_eq!(loaded.motion.frame_count(), frames, "{name}: frames");
        let got_fps = 1.0 / loaded.motion.frame_time;
        assert!((got_fps - fps).abs() < 1e-9, "{name}: {got_fps} fps");
        assert!(loaded.motion.data.iter().all(|v| v.is_finite()), "{name}");
        let rest = loaded
            .warnings
            .iter()
            .any(|w| w.to_string().contains("rest pose"));
        assert_eq!(rest, frames == 1, "{name}: {:?}", loaded.warnings);
    }
}

#[test]
fn ascii_and_binary_saves_of_one_scene_agree() {
    for (a, b) in [
        (
            "maya_rotation_order_7500_ascii",
            "maya_rotation_order_7500_binary",
        ),
        (
            "maya_rotation_order_6100_ascii",
            "maya_rotation_order_6100_binary",
        ),
        (
            "maya_rotation_order_6100_ascii",
            "maya_rotation_order_7500_ascii",
        ),
        (
            "maya_transform_animation_6100_ascii",
            "maya_transform_animation_6100_binary",
        ),
        (
            "max2009_cube_anim_5800_ascii",
            "max2009_cube_anim_5800_binary",
        ),
        (
            "maya_post_rotate_order_7500_ascii",
            "maya_post_rotate_order_6100_binary",
        ),
        (
            "maya_post_rotate_order_7500_ascii",
            "maya_post_rotate_order_7500_binary",
        ),
        ("maya_bone_radius_6100_ascii", "maya_bone_radius_7500_ascii"),
    ] {
        let first = load(&data("fbx/ufbx").join(format!("{a}.fbx")));
        let second = load(&data("fbx/ufbx").join(format!("{b}.fbx")));
        let frames = first.motion.frame_count();
        assert_eq!(frames, second.motion.frame_count(), "{a} {b}");
        let (worst, compared) = worst_relative(&first, &second, frames);
        assert_eq!(compared, first.skeleton.joints.len(), "{a} {b}");
        assert!(worst < 1e-5, "{a} vs {b}: {worst}");
    }
}

/// Maya's segment scale compensation makes ufbx add helper nodes and move each bone's
/// attribute onto its helper; the joints are still the file's bones, named and parented as in
/// the file. The HumanIK save of Maya's character (a helper above nearly every bone) reads as the
/// plain save does: the same 49 joints, and every point within 1e-6 of its height on all 120
/// frames (it was 62 roots, 49 of them `node<k>`).
#[test]
fn maya_scale_helpers_are_folded_into_the_files_bones() {
    let plain = load(&data("fbx/ufbx/maya_character_7500_binary.fbx"));
    let human_ik = load(&data("fbx/ufbx/maya_human_ik_7400_binary.fbx"));
    let names = |l: &Take| point_names(l);
    assert_eq!(names(&human_ik), names(&plain));
    let parents = |l: &Take| {
        l.skeleton
            .joints
            .iter()
            .map(|j| j.parent)
            .collect::<Vec<_>>()
    };
    assert_eq!(parents(&human_ik), parents(&plain));
    let (worst, compared) = worst_relative(&plain, &human_ik, 120);
    assert!(
        compared >= 49 && worst < 1e-6,
        "{worst} over {compared} points"
    );
    for name in [
        "maya_scale_no_inherit_7700_ascii.fbx",
        "maya_anim_no_inherit_scale_7700_ascii.fbx",
    ] {
        let chain = load(&data("fbx/ufbx").join(name));
        let joints: Vec<(&str, Option<usize>)> = chain
            .skeleton
            .joints
            .iter()
            .map(|j| (j.name.as_str(), j.parent))
            .collect();
        let want = [
            ("joint1", None),
            ("joint2", Some(0)),
            ("joint3", Some(1)),
            ("joint4", Some(2)),
        ];
        assert_eq!(joints, want, "{name}");
    }
}

/// FBX 5 files state no axes; Blender reads their coordinates as its Z up, and so does
/// bvhview (turned to Y up, front +Z), saying so. 3ds Max 2009's cube stands unturned at frame 0
/// in the file: here its root turns −90° about x, and it slides along x as in the file.
#[test]
fn fbx_5_files_without_axes_read_z_up_as_blender_reads_them() {
    for name in [
        "max2009_cube_anim_5800_ascii.fbx",
        "max2009_cube_anim_5800_binary.fbx",
    ] {
        let loaded = load(&data("fbx/ufbx").join(name));
        assert!(
            loaded
                .warnings
                .iter()
                .any(|w| w.to_string().contains("states no axes")),
            "{name}: {:?}",
            loaded.warnings
        );
        let root = &loaded.skeleton.joints[0];
        let first =
            bvhview::model::pose::local_rotation_f64(root, root.values(loaded.motion.frame(0)));
        let want = glam::DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        assert!(first.dot(want).abs() > 1.0 - 1e-12, "{name}: {first}");
        let last = loaded.motion.frame(loaded.motion.frame_count() - 1);
        assert!(
            (last[0] - 0.7).abs() < 1e-6 && last[1] == 0.0 && last[2] == 0.0,
            "{last:?}"
        );
    }
    let stated = load(&data("fbx/ufbx/maya_transform_animation_6100_ascii.fbx"));
    assert!(
        !stated
            .warnings
            .iter()
            .any(|w| w.to_string().contains("axes"))
    );
}

#[test]
fn a_file_with_several_takes_reads_each_by_name_or_index() {
    let path = data("fbx/ufbx/synthetic_anim_stack_no_props_7100_ascii.fbx");
    let takes = take::takes(&path, take::DEFAULT_MAX_SIZE).unwrap();
    assert_eq!(takes.len(), 3);
    let first = load(&path);
    assert!(
        first
            .warnings
            .iter()
            .any(|w| w.to_string().contains("3 takes"))
    );
    for (i, take) in takes.iter().enumerate() {
        let by_name = load_take(&path, &take.name);
        let by_index = load_take(&path, &i.to_string());
        assert_eq!(by_name.motion, by_index.motion, "{}", take.name);
        assert_eq!(by_name.motion.frame_count(), take.frames, "{}", take.name);
        assert!(by_name.warnings.is_empty(), "{:?}", by_name.warnings);
    }
    let error = take::OpenOptions::new()
        .threads(1)
        .max_size(u64::MAX)
        .take("nope")
        .open(&path)
        .unwrap_err();
    assert!(error.is_the_callers(), "exit 2: the input's fault");
    assert!(error.to_string().contains("no take 'nope'"), "{error}");
    let output = bvhview_command().arg("info").arg(&path).output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.contains("takes: 3"), "{text}");
}

/// Cameras, lights and camera switchers are never joints (the ASCII save of the
/// MotionBuilder actor read its seven Producer cameras and the Camera Switcher as a skeleton,
/// and Blender's three orthographic cameras were a skeleton of three joints).
#[test]
fn a_file_without_a_skeleton_says_so() {
    for name in [
        "motionbuilder_actor_7700_binary.fbx",
        "motionbuilder_actor_7700_ascii.fbx",
        "blender_402_ortho_scale_unit_7400_binary.fbx",
    ] {
        let path = data("fbx/ufbx").join(name);
        let error = crate::common::load_take(&path, None, None).unwrap_err();
        assert!(error.to_string().contains("no skeleton"), "{name}: {error}");
        assert!(error.is_the_callers(), "exit 2: the input's fault");
    }
}

/// The source BVH of each Blender export, and the frames exported.
const BLENDER_SOURCES: [&str; 3] = [
    "bvh11_131_01",
    "animateddrawings_rokoko_jesse_dance",
    "bvhpython_test_freebvh",
];

#[test]
fn blender_exports_read_back_as_their_source_bvh() {
    let mut checked = 0;
    for source in BLENDER_SOURCES {
        let bvh = load(&data("bvh").join(format!("{source}.bvh")));
        let mut files = vec![
            data("fbx").join(format!("{source}.fbx")),
            data("gltf").join(format!("{source}.glb")),
        ];
        let separate = data("gltf").join(format!("{source}.gltf"));
        if separate.exists() {
            files.push(separate);
        }
        for file in files {
            let read = load(&file);
            let frames = read.motion.frame_count();
            assert_eq!(
                frames,
                60.min(bvh.motion.frame_count()),
                "{}",
                file.display()
            );
            let fps_error = (read.motion.frame_time - bvh.motion.frame_time).abs();
            assert!(
                fps_error < 1e-6,
                "{}: {}",
                file.display(),
                read.motion.frame_time
            );
            let (worst, compared) = worst_relative(&bvh, &read, frames);
            // Every joint; an FBX also every End Site (its leaf bones).
            let skeleton = &bvh.skeleton;
            let joints = skeleton.joints.len() - skeleton.end_site_count();
            let zero_ends = skeleton
                .joints
                .iter()
                .filter(|j| zero_length_end(j))
                .count();
            let want = if file.extension().unwrap() == "fbx" {
                skeleton.joints.len() - zero_ends
            } else {
                joints
            };
            assert!(
                compared >= want,
                "{}: {compared} of {want} points matched by name",
                file.display()
            );
            assert!(
                worst < 1e-4,
                "{}: worst {worst} of the height",
                file.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 7);
}

#[test]
fn own_gltf_export_reads_back_as_the_take() {
    let dir = tempfile::tempdir().unwrap();
    for source in ["bvh11_131_01", "bvhpython_test_freebvh", "makehuman_walk1"] {
        let bvh_path = data("bvh").join(format!("{source}.bvh"));
        let glb = dir.path().join(format!("{source}.glb"));
        let status = bvhview_command()
            .args(["convert", "-q"])
            .arg(&bvh_path)
            .arg("-o")
            .arg(&glb)
            .status()
            .unwrap();
        assert!(status.success());
        let bvh = load(&bvh_path);
        let read = load(&glb);
        assert_eq!(
            read.motion.frame_count(),
            bvh.motion.frame_count(),
            "{source}"
        );
        let relative = (read.motion.frame_time / bvh.motion.frame_time - 1.0).abs();
        assert!(relative < 1e-5, "{source}: {}", read.motion.frame_time);
        assert_eq!(point_names(&read), point_names(&bvh), "{source}");
        let (worst, _) = worst_relative(&bvh, &read, bvh.motion.frame_count());
        assert!(worst < 1e-5, "{source}: worst {worst} of the height");
    }
}

#[test]
fn fbx_converts_to_a_bvh_that_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let fbx = data("fbx/bvh11_131_01.fbx");
    let out = dir.path().join("walk.bvh");
    let status = bvhview_command()
        .args(["convert", "-q"])
        .arg(&fbx)
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let read = load(&fbx);
    let bvh = load(&out);
    assert_eq!(bvh.motion.frame_count(), read.motion.frame_count());
    assert!((bvh.motion.frame_time - read.motion.frame_time).abs() < 1e-6);
    assert_eq!(
        bvh.skeleton.end_site_count(),
        read.skeleton.end_site_count()
    );
    assert!(bvh.skeleton.end_site_count() >= 5);
    let (worst, compared) = worst_relative(&read, &bvh, read.motion.frame_count());
    assert_eq!(compared, read.skeleton.joints.len());
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn fbx_converts_to_gltf_keeping_the_skeleton() {
    let dir = tempfile::tempdir().unwrap();
    let fbx = data("fbx/bvhpython_test_freebvh.fbx");
    let glb = dir.path().join("mixamo.glb");
    let status = bvhview_command()
        .args(["convert", "-q"])
        .arg(&fbx)
        .arg("-o")
        .arg(&glb)
        .status()
        .unwrap();
    assert!(status.success());
    let read = load(&fbx);
    let back = load(&glb);
    assert_eq!(point_names(&back), point_names(&read));
    assert_eq!(back.motion.frame_count(), read.motion.frame_count());
    let (worst, compared) = worst_relative(&read, &back, read.motion.frame_count());
    assert_eq!(compared, read.skeleton.joints.len());
    assert!(worst < 1e-5, "{worst}");
}
