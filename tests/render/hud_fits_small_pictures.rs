//! The HUD and the labels fit any picture from 160×120 up: no line cut
//! mid-word, names shortened in the middle, fewer lines on small pictures, labels clear of
//! other text; golden pictures at 160×120, 240×240 and 600×600.

use crate::common;

use bvhview::model::pose::OffsetMode;
use bvhview::render::hud::{self, Hud, HudTake};
use bvhview::render::paint::{Painter, Shown};
use bvhview::render::text::Font;
use bvhview::render::trace::{Numbers, Recorder};
use bvhview::render::{Image, Look, Overlay, SnapshotOptions, draw::Style};
use common::repo_data;
use std::path::{Path, PathBuf};

const SIZES: [(u32, u32); 4] = [(160, 120), (240, 240), (320, 240), (600, 600)];
const LONG_NAME: &str = "amcbvhviewer_bvh2amc_bvh_animation.bvh";

fn hud<'a>(names: &'a [&'a str], other_mode_likely: bool) -> Hud<'a> {
    Hud {
        takes: names
            .iter()
            .map(|name| HudTake {
                name,
                frame: 1234,
                frames: 2752,
                frame_time: 1.0 / 120.0,
            })
            .collect(),
        time: 10.283,
        playing: true,
        speed: 0.75,
        looping: false,
        look: Look::Studio,
        follow: true,
        style: Style::Both,
        skin: true,
        fit: true,
        offset_mode: OffsetMode::Add,
        other_mode_likely,
        lying_along_z: true,
    }
}

#[test]
fn hud_lines_fit_every_picture_without_cutting_a_word() {
    let names = [
        LONG_NAME,
        "walk.bvh",
        "a_rather_long_second_name_of_a_take.bvh",
    ];
    for takes in [&names[..1], &names[..]] {
        let hud = hud(takes, true);
        let items = hud.items();
        // Every word a line may show: the long and short forms' words, and the names.
        let words: Vec<&str> = items
            .iter()
            .flat_map(|i| i.long.split(' ').chain(i.short.split(' ')))
            .collect();
        let mut counts = Vec::new();
        for size in SIZES {
            let font = Font::for_picture(size.0, size.1);
            let columns = font.columns(size.0);
            let lines = hud.lines(size);
            assert!(
                lines.len() <= hud::most_lines(size.1, font),
                "{size:?}: {lines:?}"
            );
            for line in &lines {
                assert!(
                    line.chars().count() <= columns,
                    "{size:?}: '{line}' over {columns}"
                );
                for word in line.split(' ').filter(|w| !w.is_empty()) {
                    let shortened_name = (word.contains("...")
                        && takes.iter().any(|n| {
                            let (head, tail) = word.split_once("...").unwrap();
                            n.starts_with(head) && n.ends_with(tail)
                        }))
                        || (word.len() <= 5 && takes.iter().any(|n| n.starts_with(word)));
                    assert!(
                        words.contains(&word) || shortened_name,
                        "{size:?}: '{word}' of '{line}' is cut"
                    );
                }
            }
            // The first take's name shows, whole or shortened in the middle (with several,
            // a short picture leaves the others' to their labels).
            for name in &takes[..1] {
                let shown = lines.iter().any(|l| {
                    l.trim() == *name
                        || l.split_once("...")
                            .is_some_and(|(h, t)| name.starts_with(h.trim()) && name.ends_with(t))
                });
                assert!(shown, "{size:?}: {name} not in {lines:?}");
            }
            counts.push(lines.len());
        }
        // Fewer lines on the smallest picture than on the article's 600×600.
        assert!(counts[0] < counts[3], "{counts:?}");
    }
}

/// A text run the recorder saw: where it starts and how many glyphs of which width.
#[derive(Debug, Clone, Copy)]
struct Run {
    x: i32,
    y: i32,
    glyphs: i32,
    cell: i32,
}

impl Run {
    fn overlaps(&self, other: &Run) -> bool {
        let (r1, r2) = (
            self.x + self.glyphs * self.cell,
            other.x + other.glyphs * other.cell,
        );
        self.x < r2 && other.x < r1 && self.y < other.y + other.cell && other.y < self.y + self.cell
    }
}

/// The text runs of a recorded picture, in drawing order.
fn runs(text: &str) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for line in text.lines() {
        if let Some(args) = line.strip_prefix("glWindowPos2i(") {
            let (x, y) = args.trim_end_matches(");").split_once(", ").unwrap();
            runs.push(Run {
                x: x.parse().unwrap(),
                y: y.parse().unwrap(),
                glyphs: 0,
                cell: 0,
            });
        } else if let Some(args) = line.strip_prefix("glBitmap(")
            && let Some(run) = runs.last_mut()
        {
            let width: i32 = args.split(',').next().unwrap().trim().parse().unwrap();
            if width > 0 {
                run.glyphs += 1;
                run.cell = width;
            }
        }
    }
    runs
}

fn three_takes() -> Vec<(String, bvhview::take::Take)> {
    [
        "bvh/bvh11_131_01.bvh",
        "bvh/opencollar_run.bvh",
        "bvh/bvhpython_test_freebvh.bvh",
    ]
    .iter()
    .map(|f| {
        let name = Path::new(f)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        (
            name,
            crate::common::load_take(&repo_data(f), None, None).unwrap(),
        )
    })
    .collect()
}

#[test]
fn labels_never_overlap_other_text() {
    let takes = three_takes();
    let shown: Vec<Shown> = takes
        .iter()
        .map(|(_, l)| Shown {
            skeleton: &l.skeleton,
            motion: &l.motion,
            up: bvhview::model::pose::Up::Y,
            stance: l.stance(OffsetMode::Replace),
            mesh: None,
        })
        .collect();
    let names: Vec<&str> = takes.iter().map(|(n, _)| n.as_str()).collect();
    for size in SIZES {
        for look in [Look::Article, Look::Studio] {
            for frame in [0, 30] {
                let options = SnapshotOptions {
                    frame,
                    width: size.0,
                    height: size.1,
                    look,
                    angle: std::f32::consts::FRAC_PI_2,
                    ..SnapshotOptions::default()
                };
                let overlay = Overlay {
                    lines: hud(&names, false).lines(size),
                    timeline: Some((frame, 100)),
                    names: false,
                    labels: names.iter().map(|n| n.to_string()).collect(),
                };
                let mut recorder = Recorder::new(Numbers::Printf);
                Painter::default()
                    .paint(&mut recorder, &shown, &options, &overlay, None)
                    .unwrap();
                let runs = runs(&recorder.text());
                // The labels come first, then the HUD's lines (render::draw_overlay's order).
                let (labels, lines) = runs.split_at(names.len());
                assert_eq!(lines.len(), overlay.lines.len());
                for (i, label) in labels.iter().enumerate() {
                    assert!(label.glyphs > 0, "{size:?} {look:?}: label {i} empty");
                    assert!(
                        label.x >= 0 && label.x + label.glyphs * label.cell <= size.0 as i32,
                        "{size:?} {look:?}: label {i} {label:?} leaves the picture"
                    );
                    for other in labels[i + 1..].iter().chain(lines) {
                        assert!(
                            !label.overlaps(other),
                            "{size:?} {look:?} frame {frame}: label {label:?} over {other:?}"
                        );
                    }
                }
            }
        }
    }
}

fn golden(name: &str, args: &[&str], size: (u32, u32)) {
    let exe = env!("CARGO_BIN_EXE_bvhview");
    let dir = crate::common::scratch_folder("hud-fit");
    let out = dir.join(format!("{name}.png"));
    let status = std::process::Command::new(exe)
        .arg("snapshot")
        .args(args)
        .args([
            "--hud",
            "-q",
            "--size",
            &format!("{}x{}", size.0, size.1),
            "-o",
        ])
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{name}");
    let ours = Image::read_png(&out).unwrap();
    let path: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots")
        .join(format!("{name}.png"));
    if std::env::var_os("BVHVIEW_BLESS").is_some() {
        ours.write_png(&path).unwrap();
        return;
    }
    let expected = Image::read_png(&path).unwrap_or_else(|e| panic!("{e} (BVHVIEW_BLESS=1)"));
    let differing = ours.differing_pixels(&expected);
    let allowed = (size.0 * size.1) as usize / 1000;
    println!(
        "drift {name}: {differing} of {} pixels differ (at most {allowed})",
        size.0 * size.1
    );
    assert!(differing <= allowed, "{name}: {differing} pixels differ");
}

#[test]
fn hud_pictures_match_their_goldens_at_three_sizes() {
    // A long file name: a copy of a repository take under the name the issue saw cut.
    let dir = crate::common::scratch_folder("hud-name");
    let long = dir.join(LONG_NAME);
    std::fs::copy(repo_data("bvh/bvh11_131_01.bvh"), &long).unwrap();
    let three: Vec<String> = [
        "bvh11_131_01.bvh",
        "opencollar_run.bvh",
        "bvhpython_test_freebvh.bvh",
    ]
    .iter()
    .map(|f| {
        repo_data(&format!("bvh/{f}"))
            .to_string_lossy()
            .into_owned()
    })
    .collect();
    for (size, tag) in [
        ((160, 120), "160x120"),
        ((240, 240), "240x240"),
        ((600, 600), "600x600"),
    ] {
        golden(
            &format!("hud__long_name__studio__{tag}"),
            &[long.to_str().unwrap(), "--frame", "400", "--look", "studio"],
            size,
        );
        let mut args: Vec<&str> = three.iter().map(String::as_str).collect();
        args.extend(["--frame", "30", "--look", "studio"]);
        golden(&format!("hud__three_takes__studio__{tag}"), &args, size);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// GUIDE's own `snapshot --frame 10 --fit --angle 0.6 --step 5 --size 300x300` drew
/// the step view's text in the big glyphs: cut at the right, over two thirds of the picture. It
/// is drawn in the picture's font now: every line whole, clear of the right edge, in the bottom
/// half.
#[test]
fn the_step_text_fits_a_small_picture() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("step.png");
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/walk.bvh");
    let run = crate::common::bvhview_command()
        .arg("snapshot")
        .arg(&walk)
        .args(["--frame", "10", "--fit", "--angle", "0.6", "--step", "5"])
        .args(["--size", "300x300", "-q", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let picture = Image::read_png(&out).unwrap();
    let (width, height) = (picture.width as usize, picture.height as usize);
    // The text is the only pure white in the picture.
    let white: Vec<(usize, usize)> = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| picture.rgb[3 * (y * width + x)..][..3] == [255, 255, 255])
        .collect();
    assert!(!white.is_empty(), "no step text drawn");
    let right = white.iter().map(|p| p.0).max().unwrap();
    let top = white.iter().map(|p| p.1).min().unwrap();
    let bottom = white.iter().map(|p| p.1).max().unwrap();
    assert!(
        right < width - 4,
        "the text reaches the right edge ({right} of {width})"
    );
    // Rows from the top: the text's band is in the bottom half.
    let band = bottom - top;
    assert!(band < height / 2, "the text covers {band} of {height} rows");
}

/// The HUD of one take in the article's view at 600×600, as `snapshot --hud` writes it.
fn article_hud(name: &str, frames: usize) -> Vec<String> {
    Hud {
        takes: vec![HudTake {
            name,
            frame: frames.saturating_sub(1),
            frames,
            frame_time: 1.0 / 30.0,
        }],
        time: 0.0,
        playing: false,
        speed: 1.0,
        looping: true,
        look: Look::Article,
        follow: false,
        style: Style::Points,
        skin: false,
        fit: false,
        offset_mode: OffsetMode::Replace,
        other_mode_likely: false,
        lying_along_z: false,
    }
    .lines((600, 600))
}

/// The HUD once sat top left, over the head of the bundled walk in the article's view. It sits
/// bottom left now, above the timeline, over the floor's near half: no joint of the walk (at
/// every frame) or of the repository's takes (at three frames) is drawn under its bands.
#[test]
fn the_hud_in_the_article_view_covers_no_joint() {
    let mut takes = vec![("walk.bvh".to_string(), bvhview::Take::bundled().unwrap())];
    for file in [
        "bvh11_131_01.bvh",
        "opencollar_run.bvh",
        "bvhpython_test_freebvh.bvh",
    ] {
        let take = bvhview::Take::open(repo_data(&format!("bvh/{file}"))).unwrap();
        takes.push((file.to_string(), take));
    }
    let size = (600, 600);
    let place = hud::Place::for_picture(size, true, false);
    assert!(matches!(place, hud::Place::BottomLeft(_)), "{place:?}");
    let mut renderer = bvhview::render::Renderer::new(size.0, size.1).unwrap();
    for (name, take) in &takes {
        let count = take.motion.frame_count();
        let lines = article_hud(name, count);
        let bands = hud::bands(size, &lines, place);
        assert_eq!(bands.len(), lines.len());
        let frames: Vec<usize> = if name == "walk.bvh" {
            (0..count).collect()
        } else {
            vec![0, count / 2, count - 1]
        };
        for frame in frames {
            let options = SnapshotOptions {
                frame,
                ..SnapshotOptions::default()
            };
            let picture = renderer
                .render(&take.skeleton, &take.motion, &options)
                .unwrap();
            for band in &bands {
                for up in band.bottom as u32..band.top as u32 {
                    let row = size.1 - 1 - up;
                    for x in band.left as u32..band.right as u32 {
                        let at = 3 * (row * size.0 + x) as usize;
                        // A sphere is lit grey; the floor and the clear colour are near black.
                        let pixel = &picture.rgb[at..at + 3];
                        assert!(
                            pixel.iter().all(|&c| c < 60),
                            "{name} frame {frame}: the HUD covers a joint at ({x}, {row}): {pixel:?}"
                        );
                    }
                }
            }
        }
    }
}
