//! Every take drawn with `snapshot --fit --look studio --hud` at its first,
//! middle and last frame (and at the middle one with `--follow`) shows its whole figure inside
//! the picture, clear of the HUD (bottom left, above the timeline), and at least a third of the
//! picture tall (or wide, for a figure lying along the floor). Measured on the pictures
//! `bvhview` writes, from the colours of their pixels: the studio's backdrop, grid and shadows are
//! each one flat colour, so whatever else lies outside the HUD's lines and the timeline is the
//! figure.

use crate::common;

use bvhview::render::Image;
use common::{asf_of, files_in, repo_data, shared_data};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The studio's flat colours (studio.rs), as 8-bit values: backdrop, grid, shadow.
const FLAT: [[u8; 3]; 3] = [[31, 33, 41], [76, 82, 97], [13, 13, 18]];

fn flat(pixel: &[u8]) -> bool {
    FLAT.iter()
        .any(|c| c.iter().zip(pixel).all(|(a, b)| a.abs_diff(*b) <= 1))
}

/// What one picture shows of the figure: its box in pixels from the top-left corner (left,
/// top, right, bottom, inclusive), and the row where the HUD begins.
#[derive(Debug)]
struct Seen {
    figure: Option<(u32, u32, u32, u32)>,
    hud_top: u32,
}

/// The figure's box: pixels that are not one of the studio's flat colours, nor the HUD's lines,
/// above the timeline. `hud_lines`: how many lines the HUD drew.
fn measure(image: &Image, hud_lines: usize) -> Seen {
    use bvhview::render::hud::{Place, reserved};
    let size = (image.width, image.height);
    let font = bvhview::render::text::Font::for_picture(image.width, image.height);
    let (_, hud_room) = reserved(hud_lines, font, Place::for_picture(size, true, false));
    let hud_top = image.height - hud_room.ceil() as u32;
    let bar = bvhview::render::timeline::Bar::for_picture(image.width, image.height);
    // The timeline and its mark, in rows from the top.
    let bar_top = image.height - (bar.top + 4.0) as u32;
    let mut figure: Option<(u32, u32, u32, u32)> = None;
    for y in 0..bar_top {
        for x in 0..image.width {
            let at = ((y * image.width + x) * 3) as usize;
            let pixel = &image.rgb[at..at + 3];
            // The HUD's lines: white text on near-black bands, bottom left.
            let in_hud = y >= hud_top && (pixel == [255, 255, 255] || flat(pixel));
            if flat(pixel) || in_hud {
                continue;
            }
            figure = Some(match figure {
                None => (x, y, x, y),
                Some((l, t, r, b)) => (l.min(x), t.min(y), r.max(x), b.max(y)),
            });
        }
    }
    Seen { figure, hud_top }
}

/// How many lines the HUD of one take has at 600×600: what `snapshot --hud` draws (the test
/// reads them back from the HUD's own layout, which the picture's text follows).
fn hud_lines(file: &Path, motion: Option<&Path>) -> usize {
    let loaded = crate::common::load_take(file, motion, None).unwrap();
    let name = file.file_name().unwrap().to_string_lossy().into_owned();
    let other_mode_likely = bvhview::info::offset_mode_warning(
        &loaded.skeleton,
        &loaded.motion,
        bvhview::model::pose::OffsetMode::Replace,
    )
    .is_some();
    let hud = bvhview::render::hud::Hud {
        takes: vec![bvhview::render::hud::HudTake {
            name: &name,
            frame: 0,
            frames: loaded.motion.frame_count(),
            frame_time: loaded.motion.frame_time,
        }],
        time: 0.0,
        playing: false,
        speed: 1.0,
        looping: true,
        look: bvhview::render::Look::Studio,
        follow: false,
        style: bvhview::render::draw::Style::Both,
        skin: false,
        fit: true,
        offset_mode: bvhview::model::pose::OffsetMode::Replace,
        other_mode_likely,
        lying_along_z: false,
    };
    hud.lines((600, 600)).len()
}

/// Draws every take at three frames and checks each picture; prints the census.
fn census(label: &str, takes: &[(PathBuf, Option<PathBuf>)]) {
    let exe = env!("CARGO_BIN_EXE_bvhview");
    let dir = crate::common::scratch_folder(&format!("census-{label}"));
    let mut failures = Vec::new();
    let mut smallest = f32::MAX;
    for (file, motion) in takes {
        let loaded = crate::common::load_take(file, motion.as_deref(), None).unwrap();
        let last = loaded.motion.frame_count().max(1) - 1;
        let lines = hud_lines(file, motion.as_deref());
        let name = motion
            .as_deref()
            .unwrap_or(file)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let mut row = format!("census {name:48}");
        // The first, middle and last frames framed on the pose, and the middle one again with
        // the camera following the root (T, `--follow`).
        for (frame, follow) in [
            (0, false),
            (last / 2, false),
            (last, false),
            (last / 2, true),
        ] {
            let out = dir.join("census.png");
            let mut command = Command::new(exe);
            command.arg("snapshot").arg(file);
            if let Some(motion) = motion {
                command.arg("--motion").arg(motion);
            }
            if follow {
                command.arg("--follow");
            }
            let status = command
                .args(["--fit", "--look", "studio", "--hud", "-q", "--frame"])
                .arg(frame.to_string())
                .arg("-o")
                .arg(&out)
                .stderr(std::process::Stdio::null())
                .status()
                .unwrap();
            assert!(status.success(), "{name} frame {frame}");
            let image = Image::read_png(&out).unwrap();
            let seen = measure(&image, lines);
            let Some((left, top, right, bottom)) = seen.figure else {
                failures.push(format!("{name} frame {frame}: no figure"));
                continue;
            };
            let (tall, wide) = (bottom - top + 1, right - left + 1);
            // The figure's longer side counts: a standing figure's height, and the width of one
            // lying along the floor (usdbvhanim_test_bvh.bvh's last frame, a chain of three
            // joints on the floor: framed above the HUD, the camera's tilt shows it 33% tall and
            // 80% wide).
            let (tall_share, wide_share) = (
                tall as f32 / image.height as f32,
                wide as f32 / image.width as f32,
            );
            let share = tall_share.max(wide_share);
            smallest = smallest.min(share);
            row.push_str(&format!(
                "  f{frame}{}: {:3.0}% tall, {:3.0}% wide",
                if follow { " follow" } else { "" },
                tall_share * 100.0,
                wide_share * 100.0
            ));
            let inside = left > 0 && right < image.width - 1 && top > 0;
            if !inside || bottom >= seen.hud_top || share < 1.0 / 3.0 {
                failures.push(format!(
                    "{name} frame {frame}: box {left},{top}..{right},{bottom}, HUD from row {}, {:.0}%",
                    seen.hud_top,
                    share * 100.0
                ));
            }
        }
        println!("{row}");
    }
    println!(
        "census: {} takes, smallest figure {:.0}%",
        takes.len(),
        smallest * 100.0
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn takes_in(root: &Path) -> Vec<(PathBuf, Option<PathBuf>)> {
    let mut takes: Vec<_> = files_in(&root.join("bvh"), "bvh")
        .into_iter()
        .map(|f| (f, None))
        .collect();
    for amc in files_in(&root.join("asf_amc"), "amc") {
        let asf = asf_of(&amc);
        takes.push((asf, Some(amc)));
    }
    takes
}

#[test]
fn every_repository_take_is_framed_clear_of_the_hud() {
    census("repository", &takes_in(&repo_data("")));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_corpus_take_is_framed_clear_of_the_hud() {
    census("corpus", &takes_in(&shared_data("")));
}
