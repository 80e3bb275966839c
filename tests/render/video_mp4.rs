//! `snapshot --frames A..B -o OUT.mp4` checked by programs nobody here wrote: Debian's ffprobe
//! counts the frames and reads the rate, ffmpeg decodes every frame, and each decoded frame is
//! held to the PNG snapshot of the same frame (PSNR ≥ 35 dB), in the article's look, the studio
//! look at an odd size and a slower rate, and two takes overlaid.

/// `snapshot` of the walk's frames 0..2 with `options` into `walk.mp4` in `dir`, refused: the
/// message (exit 2, nothing written).
fn refused(dir: &std::path::Path, options: &[&str]) -> String {
    let video = dir.join("walk.mp4");
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/bvh/bvhparser_walk_01.bvh");
    let out = crate::common::bvhview_command()
        .arg("snapshot")
        .arg(&walk)
        .args(["--frames", "0..2"])
        .args(options)
        .arg("-o")
        .arg(&video)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(!video.exists());
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A build without the `video` feature says so, before drawing anything.
#[cfg(not(feature = "video"))]
#[test]
fn a_build_without_video_names_the_feature() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(
        refused(dir.path(), &[]),
        format!(
            "bvhview: {}: this bvhview was built without MP4 video (cargo feature `video`); build it with `--features video`\n",
            dir.path().join("walk.mp4").display()
        )
    );
}

#[cfg(feature = "video")]
mod with_video {
    use crate::common::video::*;

    use std::path::{Path, PathBuf};

    /// Runs `bvhview ARGS`, which must succeed; what it said on stderr.
    fn bvhview_stderr(args: &[&str]) -> String {
        let out = crate::common::bvhview(args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{args:?}: {stderr}");
        stderr
    }

    fn walk() -> String {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/bvh/bvhparser_walk_01.bvh")
            .display()
            .to_string()
    }

    fn png_rgb(path: &Path) -> Vec<u8> {
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buffer).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buffer.truncate(info.buffer_size());
        buffer
    }

    /// Writes `OUT.mp4` and the PNGs of frames `range` with the same options, then holds the video to
    /// them: frame k of the video is PNG `frames[k]`. Returns the worst PSNR and what bvhview said.
    fn video_against_pngs(
        name: &str,
        files: &[&str],
        options: &[&str],
        range: &str,
        size: (u32, u32),
        frames: &[usize],
    ) -> (f64, Probe, String) {
        let dir = tempfile::tempdir().unwrap();
        let video = dir.path().join(format!("{name}.mp4"));
        let pictures: PathBuf = dir.path().join("pictures");
        let size_text = format!("{}x{}", size.0, size.1);
        let mut args: Vec<&str> = vec!["snapshot"];
        args.extend(files);
        args.extend(options);
        args.extend(["--size", &size_text, "--frames", range]);
        let mut video_args = args.clone();
        video_args.extend(["-o", video.to_str().unwrap()]);
        let said = bvhview_stderr(&video_args);
        // The PNGs: the same options without --fps (a folder has no rate), each frame of the range.
        let mut png_args: Vec<&str> = Vec::new();
        let mut skip = false;
        for &arg in &args {
            if skip {
                skip = false;
            } else if arg == "--fps" {
                skip = true;
            } else {
                png_args.push(arg);
            }
        }
        png_args.extend(["-o", pictures.to_str().unwrap()]);
        bvhview_stderr(&png_args);
        let probe = probe(&video);
        let decoded = decoded(&video, size);
        assert_eq!(decoded.len(), frames.len(), "{name}: frames decoded");
        let mut worst = f64::INFINITY;
        for (k, (picture, &frame)) in decoded.iter().zip(frames).enumerate() {
            let png = png_rgb(&pictures.join(format!("frame_{frame:05}.png")));
            let db = psnr(picture, &png);
            assert!(
                db >= 35.0,
                "{name}: video frame {k} (frame {frame}) at {db:.2} dB"
            );
            worst = worst.min(db);
        }
        eprintln!(
            "{name}: {} frames, the worst {worst:.2} dB from its PNG",
            frames.len()
        );
        (worst, probe, said)
    }

    #[test]
    fn a_video_holds_every_frame_at_the_take_s_rate_in_the_article_s_look() {
        let frames: Vec<usize> = (0..120).collect();
        let (worst, probe, said) =
            video_against_pngs("article", &[&walk()], &[], "0..120", (640, 480), &frames);
        assert_eq!(probe.codec, "h264");
        assert_eq!((probe.width, probe.height), (640, 480));
        assert_eq!(probe.rate, "120/1", "the take's 120 frames a second");
        assert_eq!(probe.frames, 120);
        // One second exactly (a movie counted in milliseconds stated 0.96).
        assert_eq!(probe.seconds, 1.0);
        assert!(
            said.ends_with("120 frames at 120.000 per second\n"),
            "{said}"
        );
        // Grey spheres on black: nearly lossless.
        assert!(worst > 45.0, "{worst:.2} dB");
    }

    #[test]
    fn an_odd_size_at_a_slower_rate_in_the_studio_look() {
        // 120 frames a second shown at 30: every fourth frame.
        let frames: Vec<usize> = (0..60).step_by(4).collect();
        let (_, probe, said) = video_against_pngs(
            "studio",
            &[&walk()],
            &["--look", "studio", "--fps", "30"],
            "0..60",
            (641, 481),
            &frames,
        );
        assert_eq!((probe.width, probe.height), (642, 482), "even sides");
        assert_eq!(probe.rate, "30/1");
        assert_eq!(probe.frames, 15);
        assert!(
        said.ends_with("15 frames at 30.000 per second (642x482: H.264 needs even sides, the last column or row repeats)\n"),
        "{said}"
    );
    }

    #[test]
    fn two_takes_overlaid_and_side_by_side() {
        let tiny = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/oracle/inputs/tiny_crlf.bvh")
            .display()
            .to_string();
        let frames: Vec<usize> = (0..3).collect();
        for (name, options) in [
            ("overlay", vec!["--overlay", "--look", "studio"]),
            ("beside", vec!["--hud"]),
        ] {
            let (_, probe, _) = video_against_pngs(
                name,
                &[&walk(), &tiny],
                &options,
                "0..3",
                (320, 240),
                &frames,
            );
            assert_eq!(probe.frames, 3, "{name}");
        }
    }

    /// `--fps 0.0137` was written (and said) as 0.014, thousandths of a
    /// frame a second; now the track's ticks hold it exactly, as ffprobe reads it, and a rate
    /// no decimal holds (a third) as the nearest whole ticks.
    #[test]
    fn a_video_is_written_at_the_rate_asked_or_says_the_one_written() {
        let dir = tempfile::tempdir().unwrap();
        let video = dir.path().join("slow.mp4");
        for (fps, said, rate) in [
            ("0.0137", "0.0137 per second", "137/10000"),
            // Within ten parts in a million of a third: written as one, said as asked.
            ("0.3333333", "0.3333333 per second", "1/3"),
        ] {
            let stderr = bvhview_stderr(&[
                "snapshot",
                &walk(),
                "--frames",
                "0..3",
                "--fps",
                fps,
                "--size",
                "32x32",
                "-o",
                video.to_str().unwrap(),
            ]);
            assert_eq!(
                stderr,
                format!("bvhview: wrote {}: 1 frame at {said}\n", video.display())
            );
            assert_eq!(probe(&video).rate, rate);
        }
    }

    #[test]
    fn a_video_too_large_for_the_encoder_is_refused_before_any_drawing() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(
            super::refused(dir.path(), &["--size", "4000x100"]),
            "bvhview: an MP4 of 4000x100: the H.264 encoder (OpenH264) takes pictures up to 3840x2160 (or 2160x3840)\n"
        );
        // OpenH264 refuses sides under 16 pixels: said before drawing, not as its own error.
        assert_eq!(
            super::refused(dir.path(), &["--size", "8x600"]),
            "bvhview: an MP4 of 8x600: the H.264 encoder (OpenH264) takes pictures of 16x16 and more\n"
        );
    }

    /// A take on a character (the studio look: the mesh skinned and lit) on film, every
    /// frame held to its PNG.
    #[test]
    fn a_video_of_a_take_on_a_character_holds_every_frame() {
        let character = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/characters/capsule_mixamo.fbx")
            .display()
            .to_string();
        let frames: Vec<usize> = (0..30).collect();
        let options = ["--character", character.as_str(), "--look", "studio"];
        let (worst, probe, _) = video_against_pngs(
            "character",
            &[&walk()],
            &options,
            "0..30",
            (320, 240),
            &frames,
        );
        assert_eq!(probe.codec, "h264");
        assert_eq!(probe.frames, 30);
        assert!(worst >= 35.0);
    }
}
