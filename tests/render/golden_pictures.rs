//! Golden pictures of files the article cannot load (6-channel joints, CR-only line endings, a
//! 173-joint rig, a root written JOINT) and of the opt-in styles, under tests/snapshots/.
//! `BVHVIEW_BLESS=1 cargo test --test render golden_pictures` rewrites them; look at every one before committing.

use crate::common;
use bvhview::model::pose::OffsetMode;
use bvhview::render::scene::{self, Scene};
use bvhview::render::{Image, Look, SnapshotOptions, draw::Style};
use common::*;
use std::path::{Path, PathBuf};

struct Case {
    name: &'static str,
    input: &'static str,
    options: SnapshotOptions,
    /// The AMC for an ASF input.
    motion: Option<&'static str>,
}

fn case(name: &'static str, input: &'static str, options: SnapshotOptions) -> Case {
    Case {
        name,
        input,
        options,
        motion: None,
    }
}

fn cases() -> Vec<Case> {
    let base = SnapshotOptions::default();
    vec![
        case("walk__f0", "assets/walk.bvh", base),
        case(
            "walk__f10__both__fit__a0.6",
            "assets/walk.bvh",
            SnapshotOptions {
                frame: 10,
                style: Style::Both,
                fit: true,
                angle: 0.6,
                ..base
            },
        ),
        case(
            "walk__f10__step5__fit__a0.6",
            "assets/walk.bvh",
            SnapshotOptions {
                frame: 10,
                step: Some(5),
                fit: true,
                angle: 0.6,
                ..base
            },
        ),
        case(
            "bandai_wave__f10",
            "bvh/bandai_dataset-2_wave-left-hand_active_011.bvh",
            SnapshotOptions { frame: 10, ..base },
        ),
        case(
            "opencollar_run__f15",
            "bvh/opencollar_run.bvh",
            SnapshotOptions { frame: 15, ..base },
        ),
        case(
            "makehuman_tpose__sticks__fit__add__a0",
            "bvh/makehuman_tpose.bvh",
            SnapshotOptions {
                style: Style::Sticks,
                fit: true,
                offset_mode: OffsetMode::Add,
                angle: 0.0,
                ..base
            },
        ),
        case(
            "alinen_samba__f300__fit__320x240",
            "bvh/alinen_samba_dancing.bvh",
            SnapshotOptions {
                frame: 300,
                fit: true,
                width: 320,
                height: 240,
                ..base
            },
        ),
        case(
            "walk__f10__skin__fit__a0.6",
            "assets/walk.bvh",
            SnapshotOptions {
                frame: 10,
                skin: true,
                fit: true,
                angle: 0.6,
                ..base
            },
        ),
        case(
            "bvh11__f400__skin__fit__a1.2",
            "bvh/bvh11_131_01.bvh",
            SnapshotOptions {
                frame: 400,
                skin: true,
                fit: true,
                angle: 1.2,
                ..base
            },
        ),
        case(
            "walk__f10__studio__both",
            "assets/walk.bvh",
            SnapshotOptions {
                frame: 10,
                style: Style::Both,
                look: Look::Studio,
                ..base
            },
        ),
        case(
            "makehuman_walk1__f7__studio__zup__a0.6",
            "bvh/makehuman_walk1.bvh",
            SnapshotOptions {
                frame: 7,
                style: Style::Both,
                look: Look::Studio,
                up: bvhview::model::pose::Up::Z,
                angle: 0.6,
                ..base
            },
        ),
        case(
            "bvh11__f400__studio__follow__a1.2",
            "bvh/bvh11_131_01.bvh",
            SnapshotOptions {
                frame: 400,
                look: Look::Studio,
                follow: true,
                angle: 1.2,
                ..base
            },
        ),
        Case {
            motion: Some("asf_amc/simchoni_charleston_1.amc"),
            ..case(
                "cmu_charleston__f200__both__fit__a1.2",
                "asf_amc/simchoni_charleston.asf",
                SnapshotOptions {
                    frame: 200,
                    style: Style::Both,
                    fit: true,
                    angle: 1.2,
                    ..base
                },
            )
        },
    ]
}

fn input_path(input: &str) -> PathBuf {
    if input.starts_with("assets/") {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(input)
    } else if repo_data(input).exists() {
        repo_data(input)
    } else {
        shared_data(input)
    }
}

/// Whether every file a case reads is in the repository (assets/ or tests/data/).
fn in_repository(case: &Case) -> bool {
    let own = |input: &str| input.starts_with("assets/") || repo_data(input).exists();
    own(case.input) && case.motion.is_none_or(own)
}

/// The same view with an empty skeleton: background and floor (in the studio look, the take's
/// grid) only.
fn without_skeleton(bvh: &bvhview::take::Take, options: &SnapshotOptions) -> Image {
    let stage = (options.look == Look::Studio).then(|| {
        bvhview::render::studio::Stage::new(
            &bvh.skeleton,
            &bvh.motion,
            options.offset_mode,
            options.up,
        )
    });
    let stance = bvh.stance(options.offset_mode);
    let camera = bvhview::render::camera_for(&bvh.skeleton, &bvh.motion, stance, options).unwrap();
    let mut renderer = bvhview::render::Renderer::new(options.width, options.height).unwrap();
    let context = renderer.context();
    let empty = bvhview::Skeleton::default();
    let gl = &mut context.gl;
    scene::reshape(gl, options.width, options.height, &camera);
    let view = Scene {
        skeleton: &empty,
        frame: None,
        camera,
        style: options.style,
        offset_mode: options.offset_mode,
        skin: None,
        shown: None,
        sphere_radius: 1.0,
        up: bvhview::model::pose::Up::Y,
        origin: [0.0; 3],
        scale: 1.0,
        colours: None,
    };
    match stage.as_ref() {
        Some(stage) => {
            bvhview::render::studio::display(gl, std::slice::from_ref(&view), stage, options.height)
        }
        None => scene::display(gl, &view),
    }
    Image {
        width: options.width,
        height: options.height,
        rgb: context.read_rgb(),
    }
}

#[test]
fn snapshots_of_repository_files_match_their_golden_pictures() {
    let cases: Vec<Case> = cases().into_iter().filter(in_repository).collect();
    assert_eq!(cases.len(), 10);
    check_goldens(cases);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn snapshots_of_whole_corpus_files_match_their_golden_pictures() {
    let cases: Vec<Case> = cases().into_iter().filter(|c| !in_repository(c)).collect();
    assert_eq!(cases.len(), 3);
    check_goldens(cases);
}

fn check_goldens(cases: Vec<Case>) {
    let bless = std::env::var_os("BVHVIEW_BLESS").is_some();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    for case in cases {
        let motion = case.motion.map(input_path);
        let bvh =
            crate::common::load_take(&input_path(case.input), motion.as_deref(), None).unwrap();
        let ours = bvhview::render::snapshot(&bvh.skeleton, &bvh.motion, &case.options).unwrap();
        let golden = dir.join(format!("{}.png", case.name));
        if bless {
            ours.write_png(&golden).unwrap();
            continue;
        }
        let expected =
            Image::read_png(&golden).unwrap_or_else(|e| panic!("{e} (run with BVHVIEW_BLESS=1)"));
        let differing = ours.differing_pixels(&expected);
        let allowed = (ours.width * ours.height) as usize / 1000;
        println!(
            "drift {}: {differing} of {} pixels differ (at most {allowed})",
            case.name,
            ours.width * ours.height
        );
        assert!(
            differing <= allowed,
            "{}: {differing} pixels differ (at most {allowed})",
            case.name
        );
        // The skeleton must show: the same camera without it gives a clearly different picture.
        let empty = without_skeleton(&bvh, &case.options);
        let skeleton_pixels = ours.differing_pixels(&empty);
        assert!(
            skeleton_pixels > 100,
            "{}: only {skeleton_pixels} pixels show the skeleton",
            case.name
        );
    }
}

/// The skinning tutorial's demo (two bones moving three quads) at a few bends, against golden pictures; the middle quad's vertices
/// sit halfway between the two bones' transforms.
#[test]
fn skin_demo_matches_its_golden_pictures() {
    let bless = std::env::var_os("BVHVIEW_BLESS").is_some();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    for (name, bend) in [
        ("skin_demo__0_0", (0.0, 0.0)),
        ("skin_demo__30_45", (30.0, 45.0)),
        ("skin_demo__-60_90", (-60.0, 90.0)),
    ] {
        let ours = bvhview::render::skin_demo::render(bend, 640, 480).unwrap();
        let golden = dir.join(format!("{name}.png"));
        if bless {
            ours.write_png(&golden).unwrap();
            continue;
        }
        let expected = Image::read_png(&golden).unwrap();
        let differing = ours.differing_pixels(&expected);
        println!("drift {name}: {differing} of 307200 pixels differ (at most 307)");
        assert!(differing <= 307, "{name}: {differing} pixels differ");
    }
    // Bend Z by 90°: bone 2 takes (1, 4) to (-1, 4); half and half puts it at (0, 4).
    let skinned = bvhview::render::skin_demo::skinned((0.0, 90.0));
    assert!(
        skinned[6].abs_diff_eq(glam::Vec3::new(0.0, 4.0, 0.0), 1e-5),
        "{}",
        skinned[6]
    );
    // The top of the blue quad follows bone 2 alone: (1, 6) turns to (-3, 4).
    assert!(
        skinned[10].abs_diff_eq(glam::Vec3::new(-3.0, 4.0, 0.0), 1e-5),
        "{}",
        skinned[10]
    );
    // The bottom of the yellow quad stays with bone 1.
    assert_eq!(skinned[0], glam::Vec3::new(-1.0, 0.0, 0.0));
}

/// With `--fit`, every file's skeleton shows at its middle frame, whatever its units: lit pixels
/// where the same view without the skeleton has none.
fn check_fit_shows_every_file(folder: &Path, pairs: &[(&str, &str)]) {
    let mut inputs: Vec<(PathBuf, Option<PathBuf>)> = files_in(&folder.join("bvh"), "bvh")
        .into_iter()
        .map(|path| (path, None))
        .collect();
    for (asf, amc) in pairs {
        let folder = folder.join("asf_amc");
        inputs.push((folder.join(asf), Some(folder.join(amc))));
    }
    for (path, motion) in inputs {
        let loaded = crate::common::load_take(&path, motion.as_deref(), None).unwrap();
        let options = SnapshotOptions {
            frame: loaded.motion.frame_count() / 2,
            fit: true,
            ..SnapshotOptions::default()
        };
        let picture =
            bvhview::render::snapshot(&loaded.skeleton, &loaded.motion, &options).unwrap();
        let figure = picture.differing_pixels(&without_skeleton(&loaded, &options));
        println!("figure {}: {figure} pixels", path.display());
        assert!(
            figure >= 40,
            "{}: only {figure} pixels show the skeleton",
            path.display()
        );
    }
}

#[test]
fn with_fit_every_repository_file_shows_its_skeleton() {
    check_fit_shows_every_file(&repo_data(""), &[("heiden_12.asf", "heiden_12_02_01.amc")]);
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn with_fit_every_whole_corpus_file_shows_its_skeleton() {
    check_fit_shows_every_file(
        &shared_data(""),
        &[
            ("heiden_12.asf", "heiden_12_02_01.amc"),
            ("simchoni_charleston.asf", "simchoni_charleston_1.amc"),
            ("simchoni_lambada.asf", "simchoni_lambada_1.amc"),
            ("simchoni_pirouette.asf", "simchoni_pirouette_1.amc"),
        ],
    );
}

/// The sequence path (`Renderer::render_frame`, the buffer handed over and turned into a picture
/// elsewhere, then drawn into again) gives the pictures `render_all` gives, frame after frame.
#[test]
fn frames_drawn_for_a_sequence_equal_single_pictures() {
    let take = crate::common::load_take(&repo_data("bvh/bvh11_131_01.bvh"), None, None).unwrap();
    let shown = [bvhview::render::paint::Shown {
        skeleton: &take.skeleton,
        motion: &take.motion,
        up: bvhview::model::pose::Up::Y,
        stance: take.stance(OffsetMode::Replace),
        mesh: None,
    }];
    let mut sequence = bvhview::render::Renderer::new(200, 150).unwrap();
    let mut single = bvhview::render::Renderer::new(200, 150).unwrap();
    let mut spare = None;
    for (frame, look) in [
        (0, Look::Article),
        (5, Look::Studio),
        (400, Look::Article),
        (9, Look::Studio),
    ] {
        let options = SnapshotOptions {
            frame,
            look,
            width: 200,
            height: 150,
            ..SnapshotOptions::default()
        };
        let overlay = bvhview::render::Overlay::default();
        let drawn = sequence
            .render_frame(&shown, &options, &overlay, spare.take())
            .unwrap();
        let (picture, buffer) = drawn.into_image();
        spare = Some(buffer);
        let want = single.render_all(&shown, &options, &overlay).unwrap();
        assert_eq!(picture.differing_pixels(&want), 0, "frame {frame}");
    }
}
