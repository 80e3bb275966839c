//! Retargeting's fast pass (`retarget::retarget`, what the CLI, datasets and Python use) against
//! the plain one (`retarget::retarget_plain`) on real takes: every take of tests/data (and of
//! ../shared/data when it is there) onto the built-in skeleton, onto itself, onto a CMU ASF
//! skeleton (hinges, fixed axes) and onto sample skeletons turning in other orders (so the Euler
//! form follows the previous frame). The two differ only in `sin`, `cos` and `atan2` (fdlibm's
//! kernels against libm, both within an ulp), so their channel values, before the rounding to 32
//! bits, agree within [`DEGREES`] and their translations within [`RELATIVE`].

use crate::common;

use bvhview::model::pose::{OffsetMode, Up};
use bvhview::retarget::{self, Map, Ups};
use bvhview::{Motion, Skeleton};
use glam::{DQuat, DVec3};
use std::path::Path;

/// The rotation a joint's channel values give, fast against plain (radians).
const RADIANS: f64 = 1e-12;

/// Each rotation channel (degrees), divided by the cosine of the joint's middle angle for its
/// first and third (see where it is used).
const DEGREES: f64 = 1e-9;

/// Position channels (the carrier's translation), relative to the value (or to 1).
const RELATIVE: f64 = 1e-12;

/// At most this many frames of each take: enough poses, a debug build's time.
const FRAMES: usize = 600;

fn up_of(skeleton: &Skeleton, motion: &Motion) -> Up {
    bvhview::model::stance::Stance::guess(skeleton, motion, OffsetMode::Replace, None).up
}

/// Every take of a corpus folder: its .bvh files, and each .asf with the .amc files named after it.
fn takes(root: &Path) -> Vec<(String, Skeleton, Motion)> {
    let mut takes = Vec::new();
    for path in common::files_in(&root.join("bvh"), "bvh") {
        let loaded = crate::common::load_take(&path, None, None).unwrap();
        takes.push((path, loaded.skeleton, loaded.motion));
    }
    let asf = root.join("asf_amc");
    for skeleton in common::files_in(&asf, "asf") {
        let stem = skeleton.file_stem().unwrap().to_string_lossy().to_string();
        for amc in common::files_in(&asf, "amc") {
            if amc
                .file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(&stem)
            {
                let loaded = crate::common::load_take(&skeleton, Some(&amc), None).unwrap();
                takes.push((amc, loaded.skeleton, loaded.motion));
            }
        }
    }
    takes
        .into_iter()
        .map(|(path, skeleton, motion)| {
            let frames = motion.frame_count().min(FRAMES);
            let name = path.display().to_string();
            (name, skeleton, bvhview::edit::trim(&motion, 0..frames))
        })
        .collect()
}

/// The skeletons every take goes onto (besides its own): name, skeleton, up axis.
fn targets() -> Vec<(String, Skeleton, Up)> {
    let mut targets = Vec::new();
    let smpl = retarget::Target::load("smpl22", u64::MAX).unwrap();
    targets.push((smpl.name, smpl.skeleton, smpl.up));
    let asf = retarget::Target::load(
        &common::repo_data("asf_amc/heiden_12.asf")
            .display()
            .to_string(),
        u64::MAX,
    )
    .unwrap();
    targets.push((asf.name, asf.skeleton, asf.up));
    for family in ["rokoko", "daz_poser_secondlife", "bandai", "makehuman"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/body")
            .join(format!("{family}.bvh"));
        let target = retarget::Target::load(&path.display().to_string(), u64::MAX).unwrap();
        targets.push((target.name, target.skeleton, target.up));
    }
    targets
}

/// Asserts the bounds over a corpus's takes, prints the largest differences seen, and returns
/// how many pairs it compared.
fn compare(root: &Path) -> usize {
    let targets = targets();
    let mut worst = Worst::default();
    let mut pairs = 0;
    for (source_name, source, motion) in takes(root) {
        let own = (source_name.clone(), source.clone(), up_of(&source, &motion));
        for (target_name, target, target_up) in targets.iter().chain([&own]) {
            let map = Map::guess(&source, target);
            if map.check(&source_name, target_name).is_err() {
                continue;
            }
            let ups = Ups {
                source: up_of(&source, &motion),
                target: *target_up,
            };
            let fast = retarget::retargeted_values(&source, &motion, target, &map, ups, 2, true);
            let plain = retarget::retargeted_values(&source, &motion, target, &map, ups, 2, false);
            assert_eq!(fast.len(), plain.len());
            let channels = target.channel_count();
            for frame in 0..motion.frame_count() {
                let row =
                    |values: &[f64]| values[frame * channels..(frame + 1) * channels].to_vec();
                let (fast, plain) = (row(&fast), row(&plain));
                for joint in &target.joints {
                    let what = |column: usize| {
                        format!(
                            "{source_name} → {target_name}: frame {frame}, {} column {column}: fast {}, plain {}",
                            joint.name, fast[column], plain[column]
                        )
                    };
                    let columns = joint.first_channel..joint.first_channel + joint.channels.len();
                    let mut rotations = Vec::new();
                    for (channel, column) in joint.channels.iter().zip(columns) {
                        if channel.is_position() {
                            let off =
                                (fast[column] - plain[column]).abs() / plain[column].abs().max(1.0);
                            assert!(off <= RELATIVE, "{}", what(column));
                            worst.translation = worst.translation.max(off);
                        } else {
                            rotations.push((channel.axis(), column));
                        }
                    }
                    // The rotation the values give: within a few ulps of each other, however
                    // the angles split it.
                    let turn = |values: &[f64]| {
                        rotations
                            .iter()
                            .fold(DQuat::IDENTITY, |q, &(axis, column)| {
                                q * DQuat::from_axis_angle(
                                    DVec3::AXES[axis],
                                    values[column].to_radians(),
                                )
                            })
                    };
                    let apart = (turn(&fast) * turn(&plain).inverse()).xyz().length().asin() * 2.0;
                    assert!(apart <= RADIANS, "{} {apart}", what(joint.first_channel));
                    worst.rotation = worst.rotation.max(apart);
                    // Each angle: near gimbal lock (the middle angle of three near ±90°) the first
                    // and third split the rotation badly, by about the rounding over the cosine of
                    // the middle one, in the plain pass as much as in the fast one.
                    let middle = match rotations[..] {
                        [_, (_, column), _] => plain[column].to_radians().cos().abs(),
                        _ => 1.0,
                    };
                    for (i, &(_, column)) in rotations.iter().enumerate() {
                        let off = (fast[column] - plain[column]).abs();
                        let bound = match i {
                            1 => DEGREES,
                            _ if middle < 1e-6 => continue,
                            _ => DEGREES / middle.min(1.0),
                        };
                        assert!(
                            off <= bound,
                            "{} (cos of the middle angle {middle})",
                            what(column)
                        );
                        worst.angle = worst.angle.max(off * middle.min(1.0));
                    }
                }
            }
            // And the take written is the fast pass's values, rounded to 32 bits.
            let (_, written) = retarget::retarget(&source, &motion, target, &map, ups, 2).unwrap();
            assert!(
                written.data.iter().zip(&fast).all(|(&w, &f)| w == f as f32),
                "{source_name} → {target_name}"
            );
            pairs += 1;
        }
    }
    println!(
        "{}: {pairs} pairs; fast and plain part by at most {:e} rad in a joint's rotation, {:e}° \
         times the cosine of the middle angle in a value, {:e} of a translation",
        root.display(),
        worst.rotation,
        worst.angle,
        worst.translation
    );
    pairs
}

/// The largest differences seen.
#[derive(Default)]
struct Worst {
    rotation: f64,
    angle: f64,
    translation: f64,
}

#[test]
fn the_fast_pass_gives_the_plain_pass_s_values_on_the_repository_s_takes() {
    let pairs = compare(&common::repo_data(""));
    assert!(pairs >= 40, "{pairs} pairs");
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn the_fast_pass_gives_the_plain_pass_s_values_on_the_whole_corpus() {
    let pairs = compare(&common::shared_data(""));
    assert!(pairs >= 60, "{pairs} pairs");
}

/// A take whose path does not fit in 32 bits once scaled: both passes refuse it with the same
/// error, and neither panics.
#[test]
fn a_path_too_long_for_32_bits_is_refused_by_both_passes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/body/cmu.bvh");
    let loaded = crate::common::load_take(&path, None, None).unwrap();
    let (source, mut motion) = (loaded.skeleton, loaded.motion);
    let root = &source.joints[0];
    for frame in 0..motion.frame_count() {
        for (i, channel) in root.channels.iter().enumerate() {
            if channel.is_position() {
                motion.data[frame * motion.channels + root.first_channel + i] = f32::MAX;
            }
        }
    }
    // The same skeleton, twice as large: the path scales by 2.
    let mut target = source.clone();
    for joint in &mut target.joints {
        joint.offset *= 2.0;
    }
    let map = Map::guess(&source, &target);
    let ups = Ups {
        source: up_of(&source, &motion),
        target: up_of(&source, &motion),
    };
    let fast = retarget::retarget(&source, &motion, &target, &map, ups, 2).unwrap_err();
    let plain = retarget::retarget_plain(&source, &motion, &target, &map, ups, 2).unwrap_err();
    assert_eq!(fast.to_string(), plain.to_string());
    assert!(
        fast.to_string().contains("too large for a 32-bit float"),
        "{fast}"
    );
}
