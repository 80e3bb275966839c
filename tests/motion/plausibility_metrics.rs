//! How plausible a motion is (`bvhview metrics`): GMD's skating ratio equal to what GMD's own
//! code returned (tests/metrics), PhysDiff's Penetrate, Float and Skate equal to their
//! published definitions worked here from the positions, and inputs that cannot be measured
//! refused by name.

use crate::common::{bvhview, repo_data};
use bvhview::metrics::{Figure, Thresholds, measure};
use bvhview::solve::{SMPL22_ORDER, read_npy};
use glam::DVec3;
use std::path::Path;

fn repository(relative: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Positions of SMPL's 22 joints from an .npy of the repository.
fn positions(relative: &str) -> Vec<DVec3> {
    let bytes = std::fs::read(repository(relative)).unwrap();
    let (joints, points) = read_npy(&bytes, relative).unwrap();
    assert_eq!(joints, 22);
    points
}

/// The four motions of scripts/reference_metrics.py.
fn variants() -> Vec<(&'static str, Vec<DVec3>)> {
    let walk = positions("tests/solve/walk_smpl22.npy");
    let lowest = walk.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let grounded: Vec<DVec3> = walk
        .iter()
        .map(|p| DVec3::new(p.x, p.y - lowest, p.z))
        .collect();
    let sliding = grounded
        .iter()
        .enumerate()
        .map(|(i, p)| DVec3::new(p.x + 0.04 * (i / 22) as f64, p.y, p.z))
        .collect();
    let sunk = grounded
        .iter()
        .map(|p| DVec3::new(p.x, p.y - 0.03, p.z))
        .collect();
    vec![
        (
            "humanml3d",
            positions("tests/humanml3d/new_joints_012314.npy"),
        ),
        ("walk_grounded", grounded),
        ("walk_sliding", sliding),
        ("walk_sunk", sunk),
    ]
}

fn figure(points: Vec<DVec3>, fps: f64) -> Figure {
    let parents = bvhview::smpl::ModelType::Smpl.parents();
    Figure {
        names: SMPL22_ORDER.iter().map(|n| n.to_string()).collect(),
        points,
        feet: vec![10, 11],
        soles: vec![7, 10, 8, 11],
        bones: (1..22).map(|k| (parents[k].unwrap(), k)).collect(),
        hips: Some(0),
        fps,
    }
}

#[test]
fn the_skating_ratio_is_guided_motion_diffusions() {
    let bytes = std::fs::read(repository("tests/metrics/gmd_skating.npz")).unwrap();
    let reference = bvhview::smpl::npz::read(&bytes, "gmd_skating.npz").unwrap();
    let floor_at_zero = Thresholds {
        floor: Some(0.0),
        ..Thresholds::default()
    };
    for (name, points) in variants() {
        let (_, want) = reference.numbers(name).unwrap();
        let got = measure(&figure(points, 20.0), &floor_at_zero).unwrap();
        eprintln!("{name}: GMD {} bvhview {}", want[0], got.skating_ratio);
        assert!(
            (got.skating_ratio - want[0]).abs() < 1e-12,
            "{name}: {} against GMD's {}",
            got.skating_ratio,
            want[0]
        );
    }
}

/// PhysDiff's definitions, worked here from the positions: per frame, the lowest point's depth
/// under the floor, its height over it past the tolerance, and the mean horizontal displacement
/// of the foot points in contact in two adjacent frames; each averaged over the frames, in mm.
fn physdiff(
    points: &[DVec3],
    feet: &[usize],
    floor: f64,
    contact: f64,
    tolerance: f64,
) -> [f64; 3] {
    let frames: Vec<&[DVec3]> = points.chunks_exact(22).collect();
    let lowest: Vec<f64> = frames
        .iter()
        .map(|f| f.iter().map(|p| p.y).fold(f64::INFINITY, f64::min))
        .collect();
    let n = frames.len() as f64;
    let penetrate = lowest
        .iter()
        .map(|l| {
            if *l < floor {
                (floor - l) * 1000.0
            } else {
                0.0
            }
        })
        .sum::<f64>()
        / n;
    let float = lowest
        .iter()
        .map(|l| {
            if l - floor > tolerance {
                (l - floor) * 1000.0
            } else {
                0.0
            }
        })
        .sum::<f64>()
        / n;
    let mut skate = 0.0;
    for t in 0..frames.len() - 1 {
        let moved: Vec<f64> = feet
            .iter()
            .filter(|&&f| frames[t][f].y - floor < contact && frames[t + 1][f].y - floor < contact)
            .map(|&f| {
                let d = frames[t + 1][f] - frames[t][f];
                (d.x * d.x + d.z * d.z).sqrt() * 1000.0
            })
            .collect();
        if !moved.is_empty() {
            skate += moved.iter().sum::<f64>() / moved.len() as f64;
        }
    }
    [penetrate, float, skate / (frames.len() - 1) as f64]
}

#[test]
fn penetrate_float_and_skate_are_physdiffs() {
    for (name, points) in variants() {
        for floor in [0.0, 0.02, -0.01] {
            let thresholds = Thresholds {
                floor: Some(floor),
                ..Thresholds::default()
            };
            let got = measure(&figure(points.clone(), 20.0), &thresholds).unwrap();
            let want = physdiff(&points, &[10, 11], floor, 0.05, 0.005);
            for (what, g, w) in [
                ("penetrate", got.penetrate, want[0]),
                ("float", got.float, want[1]),
                ("skate", got.skate, want[2]),
            ] {
                assert!(
                    (g - w).abs() < 1e-9,
                    "{name} floor {floor}: {what} {g} against {w}"
                );
            }
            assert!((got.phys_err() - want.iter().sum::<f64>()).abs() < 1e-9);
        }
    }
}

#[test]
fn the_command_measures_positions_takes_and_folders() {
    let out = bvhview(&[
        "metrics",
        repository("tests/humanml3d/new_joints_012314.npy")
            .to_str()
            .unwrap(),
        "--fps",
        "20",
        "--floor",
        "0",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("skating ratio 0.1361;"), "{stdout}");
    let folder = crate::common::scratch_folder("metrics");
    let table = folder.join("metrics.json");
    let out = bvhview(&[
        "metrics",
        repo_data("bvh").to_str().unwrap(),
        "-o",
        table.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&table).unwrap()).unwrap();
    let takes = document["takes"].as_array().unwrap();
    assert!(takes.len() >= 10, "{} takes", takes.len());
    assert_eq!(document["thresholds"]["skate_speed_m_s"], 0.5);
    assert!(String::from_utf8_lossy(&out.stdout).contains("takes (mean): skating ratio"));
}

#[test]
fn positions_that_cannot_be_measured_are_refused_by_name() {
    let mut points = positions("tests/humanml3d/new_joints_012314.npy");
    points[3 * 22 + 4] = DVec3::NAN;
    let said = measure(&figure(points, 20.0), &Thresholds::default())
        .unwrap_err()
        .to_string();
    assert!(
        said.contains("point left_knee of frame 3 is not a finite position"),
        "{said}"
    );
    let said = measure(&figure(Vec::new(), 20.0), &Thresholds::default())
        .unwrap_err()
        .to_string();
    assert!(said.contains("no frames"), "{said}");
    let out = bvhview(&[
        "metrics",
        repository("tests/humanml3d/new_joints_012314.npy")
            .to_str()
            .unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("give it with --fps"));
}

/// A dataset's clips carry the figures `metrics` gives the take at the dataset's rate.
#[test]
fn a_datasets_clips_carry_their_metrics() {
    let folder = crate::common::scratch_folder("dataset-metrics");
    let takes = folder.join("takes");
    std::fs::create_dir(&takes).unwrap();
    std::fs::copy(repo_data("bvh/bvh11_131_01.bvh"), takes.join("walk.bvh")).unwrap();
    let out = folder.join("walk.ds");
    let run = bvhview(&[
        "dataset",
        takes.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    let clip = &manifest["clips"][0]["metrics"];
    let at_30 = folder.join("walk30.bvh");
    let run = bvhview(&[
        "convert",
        takes.join("walk.bvh").to_str().unwrap(),
        "--fps",
        "30",
        "-o",
        at_30.to_str().unwrap(),
    ]);
    assert!(run.status.success());
    let take = bvhview::Take::open(&at_30).unwrap();
    let measured = measure(
        &bvhview::metrics::figure_of_take(&take).unwrap(),
        &Thresholds::default(),
    )
    .unwrap();
    for (key, value) in [
        ("skating_ratio", measured.skating_ratio),
        ("penetrate_mm", measured.penetrate),
        ("float_mm", measured.float),
        ("skate_mm", measured.skate),
    ] {
        let written = clip[key].as_f64().unwrap();
        // The dataset's positions are 32-bit floats, the BVH's 32-bit channels: near, not equal.
        assert!(
            (written - value).abs() <= 1e-3 * value.abs().max(1.0),
            "{key}: {written} against {value}"
        );
    }
}

/// A jump is not floating, a hover is: frames above the floor count as floating only where the
/// hips do not fall as a thrown body falls.
#[test]
fn a_jump_is_a_flight_and_a_hover_floats() {
    let fps = 30.0;
    // 60 frames: standing 20, then 20 in the air, then standing 20.
    let body = |air: &dyn Fn(f64) -> f64| -> Vec<DVec3> {
        (0..60)
            .flat_map(|f| {
                let lift = if (20..40).contains(&f) {
                    air((f - 20) as f64 / fps)
                } else {
                    0.0
                };
                // A foot, and the hips a metre above it.
                [DVec3::new(0.0, lift, 0.0), DVec3::new(0.0, 1.0 + lift, 0.0)]
            })
            .collect()
    };
    let figure = |points| Figure {
        names: vec!["toe".into(), "hips".into()],
        points,
        feet: vec![0],
        soles: vec![0],
        bones: vec![(1, 0)],
        hips: Some(1),
        fps,
    };
    let floor = Thresholds {
        floor: Some(0.0),
        ..Thresholds::default()
    };
    // Thrown up at 3.3 m/s: in the air for 0.67 s, as gravity has it.
    let jump = measure(
        &figure(body(&|t| (3.3 * t - 0.5 * 9.81 * t * t).max(0.001))),
        &floor,
    )
    .unwrap();
    let hover = measure(&figure(body(&|_| 0.2)), &floor).unwrap();
    assert_eq!(jump.floating_frames, 0.0, "{}", jump.line());
    assert!(
        (hover.floating_frames - 20.0 / 60.0).abs() < 1e-12,
        "{}",
        hover.line()
    );
    assert!(jump.float > 0.0 && hover.float > 0.0);
}
