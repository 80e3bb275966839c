//! The studio look draws sticks with the spheres unless `--style` says
//! otherwise, and several takes stand at one height unless `--true-scale` keeps their true sizes.
//! Measured on the pictures `bvhview snapshot` writes.

use bvhview::render::Image;
use std::path::{Path, PathBuf};

fn snapshot(dir: &Path, name: &str, args: &[&str]) -> Image {
    let out = dir.join(name);
    let status = crate::common::bvhview_command()
        .arg("snapshot")
        .args(args)
        .args(["-q", "-o"])
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{args:?}");
    Image::read_png(&out).unwrap()
}

fn scratch(label: &str) -> PathBuf {
    crate::common::scratch_folder(label)
}

#[test]
fn the_studio_draws_sticks_with_the_spheres_by_default() {
    let dir = scratch("studio-style");
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let walk = walk.to_str().unwrap();
    let plain = snapshot(
        &dir,
        "plain.png",
        &[walk, "--frame", "10", "--look", "studio"],
    );
    let both = snapshot(
        &dir,
        "both.png",
        &[walk, "--frame", "10", "--look", "studio", "--style", "both"],
    );
    let points = snapshot(
        &dir,
        "points.png",
        &[
            walk, "--frame", "10", "--look", "studio", "--style", "points",
        ],
    );
    assert_eq!(plain.differing_pixels(&both), 0);
    assert!(plain.differing_pixels(&points) > 500);
    std::fs::remove_dir_all(dir).unwrap();
}

/// The studio's flat colours: backdrop, grid, shadow (as in tests/render/every_take_framed_in_studio.rs).
fn figure_columns(image: &Image) -> Vec<(u32, u32, u32)> {
    let flat = |p: &[u8]| {
        [[31u8, 33, 41], [76, 82, 97], [13, 13, 18]]
            .iter()
            .any(|c| c.iter().zip(p).all(|(a, b)| a.abs_diff(*b) <= 1))
    };
    // For each column holding the figure: its x, and the highest and lowest such pixel.
    (0..image.width)
        .filter_map(|x| {
            let rows: Vec<u32> = (0..image.height)
                .filter(|&y| {
                    let at = ((y * image.width + x) * 3) as usize;
                    !flat(&image.rgb[at..at + 3])
                })
                .collect();
            Some((x, *rows.first()?, *rows.last()?))
        })
        .collect()
}

/// The pixel height of each figure, left to right: runs of figure columns split at gaps of
/// more than 8 empty columns.
fn figure_heights(image: &Image) -> Vec<u32> {
    let mut figures: Vec<(u32, u32, u32)> = Vec::new();
    for (x, top, bottom) in figure_columns(image) {
        match figures.last_mut() {
            Some((last, t, b)) if x <= *last + 8 => {
                *last = x;
                *t = (*t).min(top);
                *b = (*b).max(bottom);
            }
            _ => figures.push((x, top, bottom)),
        }
    }
    figures.into_iter().map(|(_, t, b)| b - t + 1).collect()
}

#[test]
fn several_takes_stand_at_one_height_unless_true_scale() {
    let dir = scratch("studio-scale");
    // The walk in centimetres (1.66 m), and a child made from it: 0.008 of its size, which reads
    // as metres (1.33 m). Side by side along x at one depth, their pixel heights compare.
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let walk = walk.to_str().unwrap();
    let child = dir.join("child.bvh");
    let status = crate::common::bvhview_command()
        .args(["convert", walk, "--scale", "0.008", "-q", "-o"])
        .arg(&child)
        .status()
        .unwrap();
    assert!(status.success());
    let child = child.to_str().unwrap();
    let ratio = |name: &str, extra: &[&str]| {
        let mut args = vec![walk, child, "--look", "studio", "--style", "sticks"];
        args.extend(extra);
        let heights = figure_heights(&snapshot(&dir, name, &args));
        assert_eq!(heights.len(), 2, "{name}: {heights:?}");
        heights[1] as f32 / heights[0] as f32
    };
    // Scaled to the first one's height (raw, the child would be 1.33 units beside 166).
    let common = ratio("common.png", &[]);
    assert!((0.97..1.03).contains(&common), "one height: {common}");
    // At their true sizes, by the units guessed for each: 1.33 m beside 1.66 m.
    let true_scale = ratio("true.png", &["--true-scale"]);
    assert!(
        (0.75..0.85).contains(&true_scale),
        "true sizes: {true_scale}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `--fit=take` keeps every joint of every frame in view from a camera that stays put; `--fit`
/// (the pose) follows the figure.
#[test]
fn fit_take_frames_the_whole_path_from_one_camera() {
    use bvhview::render::{SnapshotOptions, camera_for, framing};
    let walk = bvhview::Take::bundled().unwrap();
    let (skeleton, motion) = (&walk.skeleton, &walk.motion);
    let camera = |frame: usize, whole_take: bool| {
        let options = SnapshotOptions {
            frame,
            fit: true,
            whole_take,
            ..SnapshotOptions::default()
        };
        camera_for(skeleton, motion, walk.stance(options.offset_mode), &options).unwrap()
    };
    let last = motion.frame_count() - 1;
    let still = camera(0, true);
    assert_eq!(still, camera(last, true));
    assert_ne!(camera(0, false), camera(last, false));
    let matrix = framing::view_projection(&still, 600, 600);
    for frame in 0..=last {
        let points = bvhview::model::pose::world_positions(
            skeleton,
            motion.frame(frame),
            Default::default(),
        );
        for p in points {
            let (x, y) = framing::project(&matrix, p, 600, 600).expect("in front of the eye");
            assert!(
                (0.0..=600.0).contains(&x) && (0.0..=600.0).contains(&y),
                "{frame}: {x},{y}"
            );
        }
    }
}

/// `--fit` takes no word after it: the file that follows is the file (`--fit=take` names the
/// other framing).
#[test]
fn fit_is_a_flag_before_a_file() {
    let dir = scratch("fit-flag");
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let walk = walk.to_str().unwrap();
    for fit in ["--fit", "--fit=pose", "--fit=take"] {
        let out = dir.join("fit.png");
        let status = crate::common::bvhview_command()
            .args(["snapshot", fit, walk, "-q", "-o"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success(), "{fit}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}
