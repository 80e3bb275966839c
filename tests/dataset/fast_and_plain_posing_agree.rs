//! The dataset's fast posing (`dataset::compile_take`: channels to quaternions once) against the
//! plain one (`dataset::compile_take_plain`: the take scaled, turned, baked and resampled step by
//! step as `convert` does, Euler angles between): the same clip within float rounding, for every
//! take, every rotation kind, a kept rate and an interpolated one.

use bvhview::dataset::{self, Clip, Options};
use bvhview::model::pose::RotationKind;
use glam::{Mat3, Quat};
use std::path::Path;

/// The rotation a clip's numbers stand for; Euler angles through the group skeleton's channels.
fn rotation(clip: &Clip, kind: RotationKind, joint: usize, numbers: &[f32]) -> Mat3 {
    if let Some(m) = bvhview::model::pose::rotation_of_numbers(kind, numbers) {
        return m;
    }
    let skeleton = clip.skeleton.as_ref().unwrap();
    let axes = skeleton.joints[joint]
        .channels
        .iter()
        .filter(|c| c.is_rotation())
        .map(|c| c.axis());
    axes.zip(numbers)
        .fold(Mat3::IDENTITY, |m, (axis, &degrees)| {
            let turn = match axis {
                0 => Quat::from_rotation_x(degrees.to_radians()),
                1 => Quat::from_rotation_y(degrees.to_radians()),
                _ => Quat::from_rotation_z(degrees.to_radians()),
            };
            m * Mat3::from_quat(turn)
        })
}

/// The worst differences between the two clips of one take, as fractions of the figure's
/// height (positions, translations), of the height per second (velocities) and as matrix
/// elements (rotations); and how many foot contacts differ.
#[derive(Debug, Default)]
struct Worst {
    positions: f32,
    rotations: f32,
    velocities: f32,
    contacts: usize,
}

/// Two paths' metrics of one clip, within what 32-bit positions differ by.
pub(crate) fn near_metrics(
    name: &str,
    a: Option<bvhview::dataset::ClipMetrics>,
    b: Option<bvhview::dataset::ClipMetrics>,
) {
    let (Some(a), Some(b)) = (&a, &b) else {
        assert_eq!(a, b, "{name}: metrics");
        return;
    };
    for (what, x, y, within) in [
        ("skating ratio", a.skating_ratio, b.skating_ratio, 0.01),
        ("penetrate", a.penetrate_mm, b.penetrate_mm, 0.1),
        ("float", a.float_mm, b.float_mm, 1.0),
        ("skate", a.skate_mm, b.skate_mm, 0.1),
        ("floor", a.floor_m, b.floor_m, 1e-3),
    ] {
        assert!((x - y).abs() <= within, "{name}: {what} {x} against {y}");
    }
    assert!((a.jitter_m_s3 - b.jitter_m_s3).abs() <= 1e-3 * a.jitter_m_s3.max(1.0));
}

fn worst_of(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

fn compare(name: &str, fast: &Clip, plain: &Clip, kind: RotationKind, fps: f64) -> Worst {
    assert_eq!(fast.frames, plain.frames, "{name}: frames");
    assert_eq!(fast.topology, plain.topology, "{name}: topology");
    // The metrics are measured on each path's positions (32-bit floats that differ in their
    // last places): near, not equal.
    let (mut fast_about, mut plain_about) = (fast.about.clone(), plain.about.clone());
    near_metrics(name, fast_about.metrics.take(), plain_about.metrics.take());
    assert_eq!(fast_about, plain_about, "{name}: about");
    assert_eq!(
        fast.rest_offsets, plain.rest_offsets,
        "{name}: rest offsets"
    );
    assert_eq!(fast.skeleton, plain.skeleton, "{name}: skeleton");
    let heights = plain.positions.iter().skip(1).step_by(3);
    let (low, high) = heights.fold((f32::MAX, f32::MIN), |(l, h), &y| (l.min(y), h.max(y)));
    let height = (high - low).max(0.1);
    let width = kind.width();
    let mut rotations: f32 = 0.0;
    for (k, (x, y)) in fast
        .rotations
        .chunks(width)
        .zip(plain.rotations.chunks(width))
        .enumerate()
    {
        let joint = fast.topology.rotated[k % fast.topology.rotated.len()] as usize;
        let (x, y) = (
            rotation(fast, kind, joint, x),
            rotation(plain, kind, joint, y),
        );
        rotations = rotations.max(worst_of(&x.to_cols_array(), &y.to_cols_array()));
    }
    let positions = [
        worst_of(&fast.positions, &plain.positions),
        worst_of(&fast.translations, &plain.translations),
        worst_of(&fast.root_translations, &plain.root_translations),
    ];
    Worst {
        positions: positions.into_iter().fold(0.0, f32::max) / height,
        rotations,
        velocities: worst_of(&fast.velocities, &plain.velocities) / height / fps as f32,
        contacts: fast
            .contacts
            .iter()
            .zip(&plain.contacts)
            .filter(|(a, b)| a != b)
            .count(),
    }
}

fn every_take_agrees(dir: &Path) {
    let items = dataset::takes(dir).unwrap();
    let mut compared = 0;
    let mut overall = Worst::default();
    for fps in [30.0, 24.0] {
        for kind in [
            RotationKind::SixD,
            RotationKind::Quat,
            RotationKind::Matrix,
            RotationKind::Euler,
            RotationKind::AxisAngle,
        ] {
            let options = Options {
                fps,
                rotations: kind,
                ..Options::default()
            };
            for item in &items {
                let name = format!("{} at {fps} fps, {}", item.path.display(), kind.name());
                let fast = dataset::compile_take(dir, item, &options);
                let plain = dataset::compile_take_plain(dir, item, &options);
                let (fast, plain) = match (fast, plain) {
                    (Ok(fast), Ok(plain)) => (fast, plain),
                    (Err(fast), Err(plain)) => {
                        assert_eq!(fast.to_string(), plain.to_string(), "{name}");
                        continue;
                    }
                    (fast, plain) => panic!(
                        "{name}: one compiles, one does not: {:?} / {:?}",
                        fast.err(),
                        plain.err()
                    ),
                };
                let worst = compare(&name, &fast, &plain, kind, fps);
                // The plain steps round through 32-bit Euler angles twice on the way (bone axes
                // baked, then resampled), which along a long chain of an ASF skeleton comes to
                // about 1e-5 of the height.
                assert!(worst.positions < 3e-5, "{name}: {worst:?}");
                assert!(worst.velocities < 1e-3, "{name}: {worst:?}");
                assert!(worst.rotations < 1e-4, "{name}: {worst:?}");
                // A foot exactly at a threshold may tip either way.
                assert!(
                    worst.contacts * 1000 <= fast.contacts.len().max(1000),
                    "{name}: {worst:?} of {}",
                    fast.contacts.len()
                );
                overall.positions = overall.positions.max(worst.positions);
                overall.rotations = overall.rotations.max(worst.rotations);
                overall.velocities = overall.velocities.max(worst.velocities);
                overall.contacts += worst.contacts;
                compared += 1;
            }
        }
    }
    println!(
        "fast against plain posing: {compared} clips of {}; worst {overall:?}",
        dir.display()
    );
    assert!(compared >= items.len(), "{compared} compared");
}

#[test]
fn fast_posing_equals_the_plain_steps_on_every_repository_take() {
    every_take_agrees(Path::new("tests/data"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn fast_posing_equals_the_plain_steps_on_every_corpus_take() {
    every_take_agrees(Path::new("../shared/data"));
}
