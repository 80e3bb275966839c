//! HumanML3D's feature vectors made as its own pipeline makes them, checked
//! against its published pair (tests/humanml3d, MIT: `new_joints/012314.npy`, the processed
//! positions, and `new_joint_vecs/012314.npy`, the vectors its pipeline made).

use bvhview::humanml3d::{self, JOINTS, PARENTS, PARTS, REFERENCE_LENGTHS, WIDTH};
use glam::DVec3;
use std::path::Path;

fn pair() -> (Vec<DVec3>, Vec<f32>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/humanml3d");
    let joints = std::fs::read(root.join("new_joints_012314.npy")).unwrap();
    let (_, points) = bvhview::solve::read_npy(&joints, "new_joints").unwrap();
    let vectors = std::fs::read(root.join("new_joint_vecs_012314.npy")).unwrap();
    (
        points,
        humanml3d::read_vectors(&vectors, "new_joint_vecs").unwrap(),
    )
}

/// The reference bone lengths are those of every processed frame HumanML3D published.
#[test]
fn reference_lengths_are_humanml3ds() {
    let (points, _) = pair();
    let mut worst = 0.0f64;
    for pose in points.chunks(JOINTS) {
        for j in 1..JOINTS {
            let length = (pose[j] - pose[PARENTS[j]]).length();
            worst = worst.max((length - REFERENCE_LENGTHS[j]).abs());
        }
    }
    println!("reference lengths: worst difference {worst:.2e} m");
    assert!(worst < 3e-6, "{worst}");
}

/// HumanML3D's processed positions of a take (171 frames, of which it published 170), with the
/// last frame rebuilt from the last vector's joint velocities, run through the pipeline again
/// give its published vectors: the take is already uniform, on the floor, at the origin and
/// facing +z, so each placing step leaves it as it is, and every number must come out as its
/// pipeline (float32, PyTorch) made it.
#[test]
fn vectors_of_humanmls_own_positions_are_its_published_vectors() {
    let (mut points, published) = pair();
    let rows = published.len() / WIDTH;
    let last = &published[(rows - 1) * WIDTH..];
    // The root's rotation at the last published frame: its turns so far (half angles).
    let half: f64 = (0..rows - 1).map(|f| f64::from(published[f * WIDTH])).sum();
    let facing = glam::DQuat::from_xyzw(0.0, half.sin(), 0.0, half.cos());
    let before: Vec<DVec3> = points[(rows - 1) * JOINTS..].to_vec();
    for (j, at) in before.iter().enumerate() {
        let step = &last[193 + 3 * j..196 + 3 * j];
        let step = DVec3::new(step[0].into(), step[1].into(), step[2].into());
        points.push(*at + facing.inverse() * step);
    }
    let made = humanml3d::features(&points).unwrap();
    assert_eq!(made.frames(), rows);
    // Float32 rounding in HumanML3D's pipeline, and its contact threshold met exactly nowhere.
    let allowed = [
        ("root_turn", 1e-5),
        ("root_step", 1e-5),
        ("root_height", 1e-5),
        ("ric", 1e-5),
        ("rotations", 1e-5),
        ("velocities", 1e-5),
        ("contacts", 0.0),
    ];
    for ((name, start, width), (same, bound)) in PARTS.into_iter().zip(allowed) {
        assert_eq!(name, same);
        let mut worst = (0.0f32, 0usize);
        for f in 0..rows {
            for k in start..start + width {
                let d = (made.vectors[f * WIDTH + k] - published[f * WIDTH + k]).abs();
                if d > worst.0 {
                    worst = (d, f);
                }
            }
        }
        println!(
            "{name}: worst difference {:.2e} at frame {}",
            worst.0, worst.1
        );
        assert!(
            worst.0 <= bound,
            "{name}: {:.2e} at frame {}",
            worst.0,
            worst.1
        );
    }
    // And the positions the vectors stand for are the published ones.
    let worst = made
        .joints
        .chunks(3)
        .zip(&points)
        .map(|(m, p)| (DVec3::new(m[0].into(), m[1].into(), m[2].into()) - *p).length())
        .fold(0.0f64, f64::max);
    println!("new_joints: worst difference {worst:.2e} m");
    assert!(worst < 1e-4, "{worst}");
}

/// Two takes of tests/data (CMU's walk as cgspeed converted it, and CMU 131_01 as BVH 1.1
/// wrote it) in a folder of their own.
fn two_takes() -> tempfile::TempDir {
    let folder = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bvh");
    for name in ["bvhparser_walk_01.bvh", "bvh11_131_01.bvh"] {
        std::fs::copy(data.join(name), folder.path().join(name)).unwrap();
    }
    folder
}

fn humanml3d_options() -> dataset::Options {
    dataset::Options {
        fps: humanml3d::FPS,
        onto: Some(bvhview::retarget::Target::load("smpl22", u64::MAX).unwrap()),
        features: dataset::FeatureSet::HumanMl3d,
        ..dataset::Options::default()
    }
}

fn compile(folder: &Path, options: &dataset::Options, out: &Path) -> dataset::Summary {
    let takes = dataset::takes(folder).unwrap();
    let list = dataset::whole_list(folder, &takes);
    dataset::compile(folder, takes, options, 1, out, list, |_, _, _, _| true).unwrap()
}

fn floats(path: &Path) -> Vec<f32> {
    let bytes = std::fs::read(path).unwrap();
    bytes[128..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

use bvhview::dataset;

/// `dataset --onto smpl22 --features humanml3d`: per take the vectors of the positions the
/// arrays compile gives for it (same take, same skeleton, same rate), the positions they
/// stand for, and over the set HumanML3D's mean and part-wise spread.
#[test]
fn a_humanml3d_dataset_holds_each_takes_vectors_and_the_sets_mean_and_spread() {
    let folder = two_takes();
    let out = folder.path().join("humanml3d");
    let summary = compile(folder.path(), &humanml3d_options(), &out);
    assert_eq!((summary.clips, summary.groups), (2, 0));
    let arrays = folder.path().join("arrays");
    let plain = dataset::Options {
        features: dataset::FeatureSet::Arrays,
        ..humanml3d_options()
    };
    compile(folder.path(), &plain, &arrays);
    let arrays = dataset::read::open(&arrays).unwrap();
    let manifest = dataset::read::read_manifest(&out).unwrap();
    let group = &arrays.manifest.groups[0];
    let order: Vec<usize> = bvhview::solve::SMPL22_ORDER
        .iter()
        .map(|n| group.topology.joints.iter().position(|j| j == n).unwrap())
        .collect();
    let positions = &arrays.groups[0].arrays[0];
    let mut all = Vec::new();
    for (k, clip) in manifest.clips.iter().enumerate() {
        let id = clip.id.as_deref().unwrap();
        assert_eq!(id, format!("{k:06}"), "the take's place in the list");
        let entry = &arrays.manifest.clips[k];
        assert_eq!(entry.about.source, clip.about.source);
        let rows = positions
            .read_rows(entry.start..entry.start + entry.frames)
            .unwrap();
        let values: Vec<f32> = rows
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        let points = group.topology.joints.len();
        let smpl: Vec<DVec3> = values
            .chunks_exact(points * 3)
            .flat_map(|pose| {
                order.iter().map(move |&j| {
                    DVec3::new(
                        pose[3 * j].into(),
                        pose[3 * j + 1].into(),
                        pose[3 * j + 2].into(),
                    )
                })
            })
            .collect();
        let expected = humanml3d::features(&smpl).unwrap();
        let vectors = floats(&out.join(format!("new_joint_vecs/{id}.npy")));
        let joints = floats(&out.join(format!("new_joints/{id}.npy")));
        // Within float32 rounding: the compile picks the frames before retargeting them.
        let worst = |a: &[f32], b: &[f32]| {
            assert_eq!(a.len(), b.len());
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0f32, f32::max)
        };
        assert!(worst(&vectors, &expected.vectors) < 1e-5);
        assert!(worst(&joints, &expected.joints) < 1e-5);
        assert_eq!(clip.frames, entry.frames - 1);
        all.extend(vectors);
    }
    let ids = std::fs::read_to_string(out.join("all.txt")).unwrap();
    assert_eq!(ids, "000000\n000001\n");
    // numpy's mean and std (population) over every vector, the std then one per part.
    let rows = all.len() / WIDTH;
    let mean: Vec<f64> = (0..WIDTH)
        .map(|k| {
            (0..rows)
                .map(|r| f64::from(all[r * WIDTH + k]))
                .sum::<f64>()
                / rows as f64
        })
        .collect();
    let std: Vec<f64> = (0..WIDTH)
        .map(|k| {
            let spread: f64 = (0..rows)
                .map(|r| (f64::from(all[r * WIDTH + k]) - mean[k]).powi(2))
                .sum();
            (spread / rows as f64).sqrt()
        })
        .collect();
    let written_mean = floats(&out.join("Mean.npy"));
    let written_std = floats(&out.join("Std.npy"));
    for k in 0..WIDTH {
        assert!(
            (f64::from(written_mean[k]) - mean[k]).abs() < 1e-6,
            "mean {k}"
        );
    }
    for (name, start, width) in PARTS {
        let part = std[start..start + width].iter().sum::<f64>() / width as f64;
        for (k, &written) in written_std.iter().enumerate().skip(start).take(width) {
            assert!((f64::from(written) - part).abs() < 1e-6, "{name} std {k}");
        }
    }
}

/// Pieces of a HumanML3D compile merge into the folder one compile writes, file for file.
#[test]
fn humanml3d_pieces_merge_into_the_whole_compile() {
    let folder = two_takes();
    let options = humanml3d_options();
    let whole = folder.path().join("whole");
    compile(folder.path(), &options, &whole);
    let mut pieces = Vec::new();
    for k in 0..2 {
        let takes = dataset::takes(folder.path()).unwrap();
        let (run, list) = dataset::piece(folder.path(), takes, k, 2).unwrap();
        let out = folder.path().join(format!("piece_{k}"));
        dataset::compile(folder.path(), run, &options, 1, &out, list, |_, _, _, _| {
            true
        })
        .unwrap();
        pieces.push(out);
    }
    let merged = folder.path().join("merged");
    let summary = dataset::merge::merge(&pieces, &merged, dataset::merge::Join::Pieces).unwrap();
    assert_eq!(summary.clips, 2);
    for name in [
        "manifest.json",
        "Mean.npy",
        "Std.npy",
        "all.txt",
        "new_joint_vecs/000000.npy",
        "new_joint_vecs/000001.npy",
        "new_joints/000001.npy",
    ] {
        assert_eq!(
            std::fs::read(whole.join(name)).unwrap(),
            std::fs::read(merged.join(name)).unwrap(),
            "{name}"
        );
    }
    // Folders are numbered anew: the same dataset twice holds four clips.
    let twice = folder.path().join("twice");
    let summary = dataset::merge::merge(
        &[whole.clone(), whole.clone()],
        &twice,
        dataset::merge::Join::Folders,
    )
    .unwrap();
    assert_eq!(summary.clips, 4);
    let ids = std::fs::read_to_string(twice.join("all.txt")).unwrap();
    assert_eq!(ids, "000000\n000001\n000002\n000003\n");
}

/// What HumanML3D's vectors cannot be made of is refused before any take is read; a
/// HumanML3D folder made by someone else is checked as any dataset is.
#[test]
fn humanml3d_refuses_what_it_cannot_make_and_hostile_folders() {
    let wrong = [
        dataset::Options {
            onto: None,
            ..humanml3d_options()
        },
        dataset::Options {
            fps: 30.0,
            ..humanml3d_options()
        },
        dataset::Options {
            root_relative: true,
            ..humanml3d_options()
        },
    ];
    let said: Vec<String> = wrong
        .iter()
        .map(|o| o.check().unwrap_err().to_string())
        .collect();
    assert!(
        said[0].contains("features humanml3d: needs onto smpl22"),
        "{}",
        said[0]
    );
    assert!(said[1].contains("20 fps"), "{}", said[1]);
    assert!(said[2].contains("root_relative has no part"), "{}", said[2]);

    let folder = two_takes();
    let out = folder.path().join("humanml3d");
    compile(folder.path(), &humanml3d_options(), &out);
    // The arrays' reader says what the folder is.
    let error = dataset::read::open(&out).unwrap_err().to_string();
    assert!(error.contains("HumanML3D's layout"), "{error}");
    // A clip's file swapped for a link to a file outside is not followed.
    let file = out.join("new_joint_vecs/000001.npy");
    let outside = folder.path().join("outside.npy");
    std::fs::rename(&file, &outside).unwrap();
    std::os::unix::fs::symlink(&outside, &file).unwrap();
    let opened = dataset::humanml3d::open(&out).unwrap();
    let error = opened.features(1).unwrap_err().to_string();
    assert!(error.contains("000001.npy"), "{error}");
    std::fs::remove_file(&file).unwrap();
    // A file cut short.
    let bytes = std::fs::read(&outside).unwrap();
    std::fs::write(&file, &bytes[..bytes.len() - 4]).unwrap();
    let error = opened.features(1).unwrap_err().to_string();
    assert!(error.contains("bytes where float32"), "{error}");
    // A last clip whose vector count lies past any file's size: refused, no overflow.
    std::fs::write(&file, &bytes).unwrap();
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    let lying = manifest.replacen("\"frames\": 57,", "\"frames\": 9000000000000000000,", 1);
    assert_ne!(lying, manifest, "the last clip's vectors");
    std::fs::write(out.join("manifest.json"), &lying).unwrap();
    let error = dataset::humanml3d::open(&out)
        .unwrap()
        .features(1)
        .unwrap_err()
        .to_string();
    assert!(error.contains("more than any file holds"), "{error}");
    std::fs::write(out.join("manifest.json"), &manifest).unwrap();
    // An ID that is not six digits.
    let manifest = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    std::fs::write(
        out.join("manifest.json"),
        manifest.replace("\"000001\"", "\"../x\""),
    )
    .unwrap();
    let error = dataset::humanml3d::open(&out).unwrap_err().to_string();
    assert!(error.contains("six digits"), "{error}");
}

/// The compile picks a 120 fps take's every sixth frame before retargeting it (the plain steps
/// retarget every frame, then pick): the same vectors, within float32 rounding, and the
/// manifest still gives the source's rate and frames.
#[test]
fn picking_frames_before_retargeting_gives_the_same_vectors() {
    let folder = two_takes();
    let options = humanml3d_options();
    let mut checked = 0;
    for item in dataset::takes(folder.path()).unwrap() {
        let fast = dataset::compile_take(folder.path(), &item, &options).unwrap();
        let plain = dataset::compile_take_plain(folder.path(), &item, &options).unwrap();
        // The retarget's check is measured on the frames each path retargets (picked first, or
        // all of them): the same figures within what those frames differ by.
        let (mut fast_about, mut plain_about) = (fast.about.clone(), plain.about.clone());
        let (c, d) = (
            fast_about.retarget_check.take().unwrap(),
            plain_about.retarget_check.take().unwrap(),
        );
        crate::fast_and_plain_posing_agree::near_metrics(
            "picked first",
            fast_about.metrics.take(),
            plain_about.metrics.take(),
        );
        assert_eq!(fast_about, plain_about);
        for (x, y) in [(c.hips, d.hips), (c.shoulders, d.shoulders)] {
            let (x, y) = (x.unwrap(), y.unwrap());
            assert!((x.turn - y.turn).abs() < 0.1, "{x:?} {y:?}");
            assert!((x.width - y.width).abs() < 1e-3, "{x:?} {y:?}");
            assert!(
                (x.source_width - y.source_width).abs() < 1e-3,
                "{x:?} {y:?}"
            );
        }
        assert!((c.bones_median - d.bones_median).abs() < 0.1, "{c:?} {d:?}");
        assert_eq!(c.refusal(), d.refusal());
        let (a, b) = (fast.humanml3d.unwrap(), plain.humanml3d.unwrap());
        assert_eq!(a.vectors.len(), b.vectors.len());
        let worst = a
            .vectors
            .iter()
            .zip(&b.vectors)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        println!("{}: worst difference {worst:.1e}", item.path.display());
        assert!(worst < 1e-5, "{worst}");
        checked += 1;
    }
    assert_eq!(checked, 2);
}
