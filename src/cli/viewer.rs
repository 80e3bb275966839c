//! `bvhview [FILES]`: the window, on the files or the bundled walk.

use super::{LookArg, OffsetModeArg, Source, StyleArg, UpArg};
#[cfg(feature = "window")]
use super::{
    QUIET, check_output, load_or_default, paired_takes, resolve_up, style_for, warn_offset_mode,
};
use crate::io::error::Error;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// The window's keys, for `bvhview --help`.
pub(crate) const WINDOW_KEYS: &str = "\
Keys in the window:
  W             next frame (the article)
  S             previous frame
  A / D         turn the camera (the article)
  Space         play / pause in real time at the files' frame time
  Home / End    first / last frame
  + / -         play faster / slower (0.1x to 4x)
  L             loop on / off
  mouse drag    turn and tilt; Shift+drag or middle drag: pan; wheel: zoom
  F             frame the pose shown / back to the article's camera
  C             the camera as at the start (the article's, or the studio's in the studio look)
  V             the studio look on / off; T: its camera follows the root
  O             position channels replace / are added to OFFSET
  I / H         the HUD and timeline (click or drag on it to seek) / the help on and off
  N             joint names on / off
  B             next style: spheres, stick figure, both
  K             generated skin on / off
  J / Shift+J   step through the recursion one joint at a time (Esc: whole picture)
  R             load the files again (a file that no longer loads keeps its last picture)
  P             write the picture shown to NAME_frameNNNNN.png
  M             record what the window shows into NAME_frameNNNNN.mp4 / stop and write it
  drop a file   add it beside the others
  Esc           quit (the article)";

/// What `bvhview` takes without a command: the files to show and how.
#[derive(Args)]
pub(crate) struct ViewerArgs {
    /// A take (.bvh, .fbx, .gltf, .glb, or an .asf skeleton, its .amc right after it) to show
    /// in a window (default: the bundled walk); several files stand side by side on one
    /// timeline.
    files: Vec<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// Spheres (the article's), the stick figure, or both (B switches; default: spheres, both
    /// in the studio look).
    #[arg(long, value_enum)]
    style: Option<StyleArg>,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// Start with a generated skin around the bones (K toggles it).
    #[arg(long)]
    skin: bool,
    /// Put the take on a character: an .fbx, .glb or .gltf with a skinned mesh, the take
    /// retargeted onto its skeleton by role and the mesh drawn skinned, lit. Once for every
    /// file, or once per file in their order.
    #[arg(long, value_name = "CHAR")]
    character: Vec<PathBuf>,
    #[command(flatten)]
    insisting: super::character::Insisting,
    /// Start in the studio look (V switches).
    #[arg(long, value_enum, default_value_t)]
    look: LookArg,
    /// With several files, keep each at its true size (lengths converted by the units guessed
    /// for each); by default they are scaled to the first one's height.
    #[arg(long)]
    true_scale: bool,
    /// The file's up axis (default: guessed from the motion in a framed or studio view, as
    /// written in the article's view; `info` prints the guess).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<UpArg>,
    /// Record what the window shows into this .mp4 from the start, at the take's rate (at most
    /// 60 frames a second); M stops and writes it (so does closing the window), M again starts
    /// another.
    #[arg(long)]
    record: Option<PathBuf>,
}

/// The window on a file (or the bundled walk): a build without the `window` feature has none.
#[cfg(not(feature = "window"))]
pub(crate) fn run(_: ViewerArgs) -> Result<ExitCode, Error> {
    Err(crate::render::without_window(
        crate::render::VIEWER_OFFSCREEN,
    ))
}

/// The window on a file (or the bundled walk).
#[cfg(feature = "window")]
pub(crate) fn run(args: ViewerArgs) -> Result<ExitCode, Error> {
    use crate::render::window::{TakeSource, ViewerOptions, ViewerTake};
    let ViewerArgs {
        files,
        source,
        style,
        offset_mode,
        skin,
        character,
        insisting,
        look,
        true_scale,
        up,
        record,
    } = args;
    if let Some(path) = &record {
        check_output(path, &["mp4"])?;
        #[cfg(not(feature = "video"))]
        return Err(crate::io::absent::without(
            "video",
            "MP4 video",
            &path.display().to_string(),
        ));
    }
    // Say there is no display before loading anything.
    crate::render::window::check_environment(crate::render::window::VIEWER_OFFSCREEN)?;
    let mut source = source;
    source.up = UpArg::turned_when_read(up);
    let files = paired_takes(&files, &source)?;
    let offset_mode = offset_mode.into();
    let mut takes = Vec::with_capacity(files.len().max(1));
    if files.is_empty() {
        let (name, loaded) = load_or_default(None, &source)?;
        for warning in &loaded.warnings {
            eprintln!(
                "bvhview: {name}: warning: {}",
                warning.spelled(&super::Flags)
            );
        }
        let stance = loaded.stance(offset_mode);
        resolve_up(up, &stance, &name, look == LookArg::Studio);
        takes.push(ViewerTake {
            up: up.map_or(stance.up, UpArg::view),
            stance,
            up_asked: up.map(UpArg::view),
            name,
            source: None,
            loaded,
            character: None,
        });
    }
    for (path, motion) in files {
        let take_source = TakeSource {
            path: path.clone(),
            motion,
            frame_time: source.frame_time,
            max_size: source.max_size,
            take: source.take.clone(),
            insist: insisting.insist(),
            body_model: source.body_model.clone(),
            units: source.units,
            up: source.up,
        };
        let mut take = ViewerTake::from_source(take_source, offset_mode, &super::Flags)?;
        let name = path.display().to_string();
        // On a character the retarget reads the file in the mode it was written for.
        if character.is_empty() {
            warn_offset_mode(&take.loaded, offset_mode, &name);
        }
        resolve_up(up, &take.stance, &name, look == LookArg::Studio);
        take.up = up.map_or(take.stance.up, UpArg::view);
        take.up_asked = up.map(UpArg::view);
        takes.push(take);
    }
    let characters = super::character::load_all(&character, takes.len(), &source)?;
    for (take, character) in takes.iter_mut().zip(characters) {
        if let Some(character) = character {
            let character = character.for_take(&take.loaded)?;
            take.put_on(character, offset_mode, &super::Flags)?;
        }
    }
    let options = ViewerOptions {
        offset_mode,
        // A character's mesh alone unless a style is asked for (its rig may hold controls).
        style: if character.is_empty() || style.is_some() {
            style_for(style, look)
        } else {
            crate::render::draw::Style::Points
        },
        skin,
        look: look.into(),
        quiet: QUIET.load(std::sync::atomic::Ordering::Relaxed),
        true_scale,
        style_chosen: style.is_some(),
        record,
        spelling: &super::Flags,
    };
    crate::render::window::run(takes, options)?;
    Ok(ExitCode::SUCCESS)
}
