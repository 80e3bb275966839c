//! `bvhview snapshot`: a frame drawn offscreen as PNG, or a sequence as GIF, APNG or PNGs.

use super::{
    FitArg, LookArg, Progress, Source, View, check_output, load, paired_takes, parse_size,
    resolve_up, short_name, style_for, warn_offset_mode, wrote,
};
use crate::io::error::Error;
use crate::model::pose::{OffsetMode, Up};
use crate::render::paint::{Clock, Shown};
use crate::render::{Overlay, SnapshotOptions, animation};
use crate::take;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct SnapshotArgs {
    /// A take: .bvh, .fbx, .gltf, .glb or AMASS .npz, or an .asf skeleton (its motion with --motion, or
    /// the .amc right after it); several files stand side by side on one timeline.
    #[arg(required = true, num_args = 1..)]
    files: Vec<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// Frame to draw, from 0.
    #[arg(long, default_value_t = 0, conflicts_with = "frames")]
    frame: usize,
    /// Draw each take's rest pose (its OFFSETs, every channel at 0) instead of a frame; its up
    /// axis is still read from its motion.
    #[arg(long, conflicts_with_all = ["frames", "frame"])]
    rest: bool,
    /// A sequence instead: N, A..B (B left out), A..=B, A.. or ..B, written as -o says: an
    /// animated .gif, .apng or .png, an .mp4 video (H.264), or OUT/frame_NNNNN.png into a
    /// folder.
    #[arg(long)]
    frames: Option<String>,
    #[command(flatten)]
    view: View,
    /// Picture size, WIDTHxHEIGHT.
    #[arg(long, default_value = "600x600", value_parser = parse_size)]
    size: (u32, u32),
    /// Draw a generated skin around the bones, moved by linear blend skinning.
    #[arg(long)]
    skin: bool,
    /// Put the take on a character: an .fbx, .glb or .gltf with a skinned mesh, the take
    /// retargeted onto its skeleton by role and the mesh drawn skinned, lit. Once for every
    /// file, or once per file in their order.
    #[arg(long, value_name = "CHAR")]
    character: Vec<PathBuf>,
    #[command(flatten)]
    insisting: super::character::Insisting,
    /// Draw only the first K joints in the order the recursion reaches them, the last one
    /// highlighted, with its GL calls written beside (the window's J key).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    step: Option<u64>,
    /// Write the timeline along the bottom and the HUD bottom left above it (the file, the
    /// frame, its time, the rate, the display mode; top left with --step): the window's I key.
    #[arg(long)]
    hud: bool,
    /// The studio look: grid floor, shadows, bones coloured by side, the take framed.
    #[arg(long, value_enum, default_value_t)]
    look: LookArg,
    /// With --look studio, the camera follows the root (the window's T key).
    #[arg(long)]
    follow: bool,
    /// Write each joint's name beside it (the window's N key).
    #[arg(long)]
    names: bool,
    /// With several files, draw them one over the other instead of side by side (each where its
    /// file puts it, on the first one's floor; in the studio look the first in its
    /// colours, the others paler), so that one camera sees each from the same side.
    #[arg(long)]
    overlay: bool,
    /// Frames per second of an animated output, with --frames (default: the file's rate, at
    /// most 50 for GIF).
    #[arg(long)]
    fps: Option<f64>,
    /// The PNG to write; with --frames an animated .gif, .apng or .png, an .mp4 video, or a
    /// folder to write one PNG per frame into (created if missing; the folder it is in must
    /// exist).
    #[arg(short, long)]
    output: PathBuf,
}

/// Refuses the options that only a sequence (`--frames`) gives a meaning to, before any work:
/// an animated output asked for with one frame, and `--fps` where no animation is written.
fn check_sequence_options(
    args: &SnapshotArgs,
    animated: Option<animation::AnimationFormat>,
) -> Result<(), Error> {
    let output = args.output.display();
    let format = match take::extension(&args.output).as_str() {
        "gif" => Some("a GIF"),
        "apng" => Some("an APNG"),
        "mp4" => Some("an MP4 video"),
        _ => None,
    };
    #[cfg(not(feature = "video"))]
    if animated == Some(animation::AnimationFormat::Mp4) {
        return Err(crate::io::absent::without(
            "video",
            "MP4 video",
            &output.to_string(),
        ));
    }
    if args.frames.is_none()
        && let Some(format) = format
    {
        return Err(Error::usage(format!(
            "-o {output}: {format} needs --frames A..B (one frame is written as .png)"
        )));
    }
    if args.fps.is_some() {
        if args.frames.is_none() {
            return Err(Error::usage(
                "--fps needs --frames A..B: it is the rate of an animated .gif, .apng or .png, or an .mp4",
            ));
        }
        if animated.is_none() {
            return Err(Error::usage(format!(
                "--fps is the rate of an animation; -o {output} is a folder of PNGs, which has none"
            )));
        }
    }
    Ok(())
}

/// A file as the snapshot draws it: the take (dressed on its character when it has one),
/// with its name, the way up it is drawn and its stance.
struct Prepared {
    /// The file's name without its folders, as the HUD and the labels say it.
    name: String,
    take: take::Take,
    up: Up,
    stance: crate::model::stance::Stance,
}

pub(crate) fn run(mut args: SnapshotArgs) -> Result<ExitCode, Error> {
    args.source.up = super::UpArg::turned_when_read(args.view.up);
    let animated = animation::AnimationFormat::of(&args.output);
    check_options(&args, animated)?;
    let files = paired_takes(&args.files, &args.source)?;
    if args.overlay && files.len() < 2 {
        return Err(Error::usage(
            "--overlay draws several files one over the other: give two files or more",
        ));
    }
    let mode: OffsetMode = args.view.offset_mode.into();
    let framed_view = args.view.fit.is_some() || args.look == LookArg::Studio;
    let mut takes = load_takes(&args, &files, mode, framed_view)?;
    let mut characters = super::character::load_all(&args.character, files.len(), &args.source)?;
    for ((prepared, character), (file, _)) in takes.iter_mut().zip(&mut characters).zip(&files) {
        if let Some(character) = character {
            let (dressed, worn) =
                super::character::dress(character, &prepared.take, file, args.insisting.insist())?;
            *character = worn;
            prepared.stance = dressed.stance(mode.for_take(true));
            prepared.up = resolve_up(args.view.up, &prepared.stance, &prepared.name, framed_view);
            prepared.take = dressed;
        }
    }
    let shown: Vec<Shown> = takes
        .iter()
        .zip(&characters)
        .map(|(prepared, character)| Shown {
            skeleton: &prepared.take.skeleton,
            motion: &prepared.take.motion,
            up: prepared.up,
            stance: prepared.stance,
            mesh: character.as_ref().map(|c| &c.mesh),
        })
        .collect();
    let clock = Clock::new(&shown.iter().map(|t| t.motion).collect::<Vec<_>>());
    let options = snapshot_options(&args, mode, shown[0].up, files.len());
    let other_mode_likely = shown.iter().any(|take| {
        crate::info::offset_mode_warning(take.skeleton, take.motion, take.offset_mode(mode))
            .is_some()
    });
    let lying_along_z = args.view.up.is_none()
        && !framed_view
        && takes.iter().any(|prepared| prepared.stance.up == Up::Z);
    let overlay = |tick: usize| -> Overlay {
        overlay_at(
            tick,
            &args,
            &takes,
            &clock,
            &options,
            (other_mode_likely, lying_along_z),
        )
    };
    let output = &args.output;
    let Some(frames) = &args.frames else {
        return write_picture(&shown, &options, &overlay, output);
    };
    let range = crate::positions::parse_frames(frames, clock.count)?;
    if let Some(format) = animated {
        return write_animation(&args, format, range, &clock, &shown, &options, &overlay);
    }
    write_folder(output, range, &shown, &options, &overlay)
}

/// Refuses, before any work, an output and options that do not go together: a sequence
/// option without `--frames`, an output `--frames` cannot write, a rate or a video size out of
/// bounds.
fn check_options(
    args: &SnapshotArgs,
    animated: Option<animation::AnimationFormat>,
) -> Result<(), Error> {
    check_sequence_options(args, animated)?;
    match &args.frames {
        None => check_output(&args.output, &["png"])?,
        Some(_) if animated.is_none() && !take::extension(&args.output).is_empty() => {
            return Err(Error::usage(format!(
                "-o {}: --frames writes an animated .gif, .apng or .png, an .mp4 video, or one PNG per frame into a folder such as frames/",
                args.output.display()
            )));
        }
        Some(_) => {}
    }
    if let Some(fps) = args.fps {
        crate::limits::fps(fps, animated == Some(animation::AnimationFormat::Gif))?;
    }
    if animated == Some(animation::AnimationFormat::Mp4) {
        animation::check_video_size(args.size.0, args.size.1)?;
    }
    Ok(())
}

/// Loads each file (an ASF with its AMC), saying on stderr what it looks written for and which
/// way it stands, in the order given.
fn load_takes(
    args: &SnapshotArgs,
    files: &[(PathBuf, Option<PathBuf>)],
    mode: OffsetMode,
    framed_view: bool,
) -> Result<Vec<Prepared>, Error> {
    let mut takes = Vec::with_capacity(files.len());
    for (file, motion) in files {
        let source = Source {
            motion: motion.clone(),
            ..args.source.clone()
        };
        let mut loaded = load(file, &source)?;
        let name = file.display().to_string();
        // On a character the retarget reads the file in the mode it was written for: no advice
        // about --offset-mode, which does not apply.
        if args.character.is_empty() {
            warn_offset_mode(&loaded, mode, &name);
        }
        let stance = loaded.stance(mode);
        let up = resolve_up(args.view.up, &stance, &name, framed_view);
        if args.rest {
            let motion = &loaded.motion;
            loaded.motion = crate::Motion::new(motion.frame_time, motion.channels, 0, Vec::new());
        }
        takes.push(Prepared {
            name: short_name(file),
            take: loaded,
            up,
            stance,
        });
    }
    Ok(takes)
}

/// What every picture is drawn with, from the arguments: `up` is the first take's, and `count`
/// files share the view.
fn snapshot_options(
    args: &SnapshotArgs,
    mode: OffsetMode,
    up: Up,
    count: usize,
) -> SnapshotOptions {
    SnapshotOptions {
        up,
        skin: args.skin,
        step: args.step.map(|k| usize::try_from(k).unwrap_or(usize::MAX)),
        frame: args.frame,
        angle: args
            .view
            .angle
            .unwrap_or_else(|| crate::render::paint::start_angle(count)),
        width: args.size.0,
        height: args.size.1,
        // A character's mesh alone unless a style is asked for (its rig may hold controls
        // that are not part of the body).
        style: if args.character.is_empty() || args.view.style.is_some() {
            style_for(args.view.style, args.look)
        } else {
            crate::render::draw::Style::Points
        },
        fit: args.view.fit.is_some(),
        offset_mode: mode,
        look: args.look.into(),
        follow: args.follow,
        whole_take: args.view.fit == Some(FitArg::Take),
        true_scale: args.view.true_scale,
        overlaid: args.overlay,
    }
}

/// What is written over the picture of `tick`: the names with `--names`; with `--hud` the
/// timeline, each take's label when there are several, and the HUD's lines (`hints`: whether a
/// take looks written for the other offset mode, and whether one lies along z).
fn overlay_at(
    tick: usize,
    args: &SnapshotArgs,
    takes: &[Prepared],
    clock: &Clock,
    options: &SnapshotOptions,
    (other_mode_likely, lying_along_z): (bool, bool),
) -> Overlay {
    let mut overlay = Overlay {
        names: args.names,
        ..Overlay::default()
    };
    if !args.hud {
        return overlay;
    }
    overlay.timeline = Some((tick, clock.count));
    if takes.len() > 1 {
        overlay.labels = takes.iter().map(|prepared| prepared.name.clone()).collect();
    }
    overlay.lines = crate::render::hud::Hud {
        takes: takes
            .iter()
            .map(|prepared| crate::render::hud::HudTake {
                name: &prepared.name,
                frame: clock.frame_of(&prepared.take.motion, tick),
                frames: prepared.take.motion.frame_count(),
                frame_time: prepared.take.motion.frame_time,
            })
            .collect(),
        time: clock.seconds(tick),
        playing: false,
        speed: 1.0,
        looping: true,
        look: options.look,
        follow: options.follow,
        style: options.style,
        skin: options.skin,
        fit: options.fit,
        offset_mode: options.offset_mode,
        other_mode_likely,
        lying_along_z,
    }
    .lines((options.width, options.height));
    overlay
}

/// One frame, `options.frame`, drawn offscreen and written as a PNG.
fn write_picture(
    shown: &[Shown],
    options: &SnapshotOptions,
    overlay: &dyn Fn(usize) -> Overlay,
    output: &std::path::Path,
) -> Result<ExitCode, Error> {
    let image = crate::render::Renderer::new(options.width, options.height)?.render_all(
        shown,
        options,
        &overlay(options.frame),
    )?;
    image.write_png(output)?;
    wrote(format_args!(
        "{} ({}x{})",
        output.display(),
        image.width,
        image.height
    ));
    Ok(ExitCode::SUCCESS)
}

/// The frames of `range`, sampled at `--fps` (or the default rate for the format), drawn and
/// written as one animated GIF, APNG or MP4; then what was written, at what rate and size.
fn write_animation(
    args: &SnapshotArgs,
    format: animation::AnimationFormat,
    range: std::ops::Range<usize>,
    clock: &Clock,
    shown: &[Shown],
    options: &SnapshotOptions,
    overlay: &dyn Fn(usize) -> Overlay,
) -> Result<ExitCode, Error> {
    let output = &args.output;
    let fps = args
        .fps
        .unwrap_or_else(|| animation::default_fps(clock.step, format));
    let ticks = animation::sampled_frames(range, clock.step, fps)?;
    let mut renderer = crate::render::Renderer::new(options.width, options.height)?;
    let progress = Progress::new(ticks.len());
    let size = (options.width, options.height);
    // Each picture is encoded on another core while the next one is drawn.
    animation::drawn_and_written(
        ticks.len(),
        |i, spare| {
            progress.show(i + 1);
            let frame = ticks[i];
            let options = SnapshotOptions { frame, ..*options };
            renderer.render_frame(shown, &options, &overlay(frame), spare)
        },
        |pictures| animation::write(output, format, size, fps, pictures, ticks.len()),
    )?;
    progress.done();
    // H.264's pictures have even sides: say so where the video is not the size asked.
    let even = animation::encoded_size(size.0, size.1);
    let resized = if format == animation::AnimationFormat::Mp4 && even != size {
        format!(
            " ({}x{}: H.264 needs even sides, the last column or row repeats)",
            even.0, even.1
        )
    } else {
        String::new()
    };
    let (rate, asked) = rate_said(format, fps);
    wrote(format_args!(
        "{}: {} at {rate} per second{asked}{resized}",
        output.display(),
        crate::io::error::counted(ticks.len(), "frame")
    ));
    Ok(ExitCode::SUCCESS)
}

/// The rate an animation is written at, as said after it, and the one asked beside it when
/// they differ. An MP4's rate is whole ticks over whole ticks, so it may not be the rate asked.
fn rate_said(format: animation::AnimationFormat, fps: f64) -> (String, String) {
    match format {
        #[cfg(feature = "video")]
        animation::AnimationFormat::Mp4 => {
            let written = crate::render::video::written_rate(fps);
            // Thousandths as every rate was said before; else seven figures (a third of a
            // frame a second, written as 1/3, is 0.3333333, not sixteen threes).
            let shown = match (written * 1000.0).round() / 1000.0 == written {
                true => format!("{written:.3}"),
                false => format!("{written:.7}").trim_end_matches('0').to_string(),
            };
            // Within the ten parts in a million a take's frame time is written to.
            let asked = match (written - fps).abs() <= 1e-5 * fps {
                true => String::new(),
                false => format!(" (the nearest an MP4's whole ticks hold to the {fps} asked)"),
            };
            (shown, asked)
        }
        _ => (format!("{fps:.3}"), String::new()),
    }
}

/// The frames of `range` as one PNG each, `frame_NNNNN.png`, into a new (or empty) folder made
/// whole or not at all.
fn write_folder(
    output: &std::path::Path,
    range: std::ops::Range<usize>,
    shown: &[Shown],
    options: &SnapshotOptions,
    overlay: &dyn Fn(usize) -> Overlay,
) -> Result<ExitCode, Error> {
    // The folder itself may be new, as a file may; the folders it is in must exist (a missing
    // one is refused as it is for `-o /no/such/x.png`).
    if output.exists() && !output.is_dir() {
        // A file or a device without an animated extension (`-o /dev/full`): not a folder.
        return Err(Error::usage(format!(
            "-o {}: is not a folder; --frames writes an animated .gif, .apng or .png, an .mp4 \
             video, or one PNG per frame into a folder",
            output.display()
        )));
    }
    // Made whole or not at all, as a file is: pictures of an earlier run left beside these
    // (more frames then, or other names) would read as one sequence, so an existing folder must
    // be empty, and one another user owns in a shared folder is refused (they could plant
    // links in it while the pictures are written).
    let folder = crate::io::output::NewFolder::create(
        output,
        "the pictures go into a new (or empty) folder",
    )?;
    // One offscreen context for the whole sequence.
    let mut renderer = crate::render::Renderer::new(options.width, options.height)?;
    let digits = (range.end.max(1) - 1).to_string().len().max(5);
    let count = range.len();
    let first = range.start;
    let name = |frame: usize| format!("frame_{frame:0digits$}.png");
    // Each picture is encoded and written on another core while the next one is drawn.
    animation::drawn_and_written(
        count,
        |i, spare| {
            let frame = first + i;
            let options = SnapshotOptions { frame, ..*options };
            renderer.render_frame(shown, &options, &overlay(frame), spare)
        },
        |pictures| {
            for (i, picture) in pictures.enumerate() {
                let name = name(first + i);
                // Messages name the picture where it is going, not the temporary folder.
                let shown = output.join(&name);
                let bytes = picture?.png_fast(&shown)?;
                crate::io::output::in_partial_folder(|| {
                    std::fs::write(folder.path().join(&name), bytes)
                })
                .map_err(|e| Error::output(&shown, e))?;
            }
            Ok(())
        },
    )?;
    folder.commit()?;
    wrote(format_args!(
        "{} into {}",
        crate::io::error::counted(count, "picture"),
        output.display()
    ));
    Ok(ExitCode::SUCCESS)
}
