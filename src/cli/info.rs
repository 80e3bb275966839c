//! `bvhview info`: a take summed up, or every take under a folder, one line each.

use super::{OffsetModeArg, Source, load_or_default, load_quietly, write_text};
use crate::io::error::Error;
use crate::model::pose::OffsetMode;
use crate::take;
use clap::Args;
use std::io;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct InfoArgs {
    /// A take (.bvh, .fbx, .gltf, .glb, or an .asf skeleton with --motion), or a folder of them
    /// (default: the bundled walk).
    file: Option<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// How position channels combine with OFFSET (checked by the warnings).
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// The axis the take stands along, over the guess (`info` then says it was given).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
    /// List the built-in skeletons (each one a take every command reads by its name, such as
    /// `bvhview info smpl22`): joints, units and where it comes from.
    #[arg(long, conflicts_with = "file")]
    list_skeletons: bool,
}

pub(crate) fn run(mut args: InfoArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    if args.list_skeletons {
        write_text(&built_in_list()?)?;
        return Ok(ExitCode::SUCCESS);
    }
    let offset_mode = args.offset_mode.into();
    if let Some(dir) = args.file.as_deref().filter(|f| f.is_dir()) {
        return batch(dir, &args.source, offset_mode);
    }
    // The summary lists the file's warnings: they are not said again on stderr.
    let (name, loaded) = match args.file.as_deref() {
        Some(path) => (
            path.display().to_string(),
            load_quietly(path, &args.source)?,
        ),
        None => load_or_default(None, &args.source)?,
    };
    let name = match &args.source.motion {
        Some(take) => format!("{name} + {}", take.display()),
        None => name,
    };
    let mut text = crate::info::summary(&name, &loaded, offset_mode, &super::Flags);
    if let Some(path) = args
        .file
        .as_deref()
        .filter(|p| take::Format::from_path(p).is_some_and(|f| f.holds_several_takes()))
    {
        text.push_str(&takes_text(&take::takes(path, args.source.max_size)?));
    }
    write_text(&text)?;
    Ok(ExitCode::SUCCESS)
}

/// The built-in skeletons, one line each: name, joints, units as `info` reads them, source.
fn built_in_list() -> Result<String, Error> {
    let mut text = String::new();
    for &(name, about) in crate::retarget::BUILT_IN_ABOUT {
        let (skeleton, motion) = crate::retarget::built_in(name)
            .ok_or_else(|| Error::usage(format!("the built-in skeleton {name} does not load")))?;
        let built_in = take::Take::new(skeleton, motion, name.to_string());
        let stance = built_in.stance(OffsetMode::Replace);
        let skeleton = &built_in.skeleton;
        let joints = skeleton.joints.len() - skeleton.end_site_count();
        text.push_str(&format!(
            "{name}: {joints} joints, {}, {:.2} m tall at rest, {} up; {about}\n",
            stance.units.name,
            stance.height * stance.units.metres,
            match stance.up {
                crate::model::pose::Up::Y => "y",
                crate::model::pose::Up::Z => "z",
            }
        ));
    }
    Ok(text)
}

/// The takes of an FBX or glTF file, one line each, as `--take` picks them.
fn takes_text(takes: &[crate::model::reading::TakeInfo]) -> String {
    if takes.is_empty() {
        return "takes: none (the file's rest pose)\n".to_string();
    }
    let mut text = format!("takes: {} (--take NAME|INDEX)\n", takes.len());
    for (i, take) in takes.iter().enumerate() {
        text.push_str(&format!(
            "  {i}: '{}', {}, {} fps\n",
            take.name,
            crate::io::error::counted(take.frames, "frame"),
            (1.0 / take.frame_time * 1000.0).round() / 1000.0
        ));
    }
    text
}

/// `bvhview info DIR`: one line per file, in path order, a progress bar on a terminal, and a
/// summary. Exits 2 if any file failed (an unpaired AMC is a note, not a failure).
fn batch(dir: &Path, source: &Source, offset_mode: OffsetMode) -> Result<ExitCode, Error> {
    let started = std::time::Instant::now();
    let walk = crate::info::batch::collect(dir)?;
    for line in walk.skipped_lines() {
        super::note(format_args!("{line}"));
    }
    let items = walk.items;
    if items.is_empty() {
        return Err(Error::usage(format!(
            "{}: no .bvh, .fbx, .gltf, .glb, .npz, .asf or .amc files",
            dir.display()
        )));
    }
    let threads = crate::io::parallel::cores();
    let progress = super::Progress::new(items.len());
    if let Some(motion) = &source.motion {
        return Err(Error::usage(format!(
            "--motion {}: a folder pairs each AMC with its ASF itself",
            motion.display()
        )));
    }
    crate::limits::frame_time_option(source.frame_time)?;
    let settings = crate::info::batch::Settings {
        frame_time: source.frame_time,
        max_size: source.max_size,
        offset_mode,
        units: source.units,
        up: source.up,
    };
    let outcomes = crate::info::batch::run(items, threads, settings, |outcome, finished, _| {
        let line = match &outcome.result {
            Ok(Some(text)) => {
                let name = match &outcome.item.motion {
                    Some(amc) => format!("{} + {}", outcome.item.path.display(), amc.display()),
                    None => outcome.item.path.display().to_string(),
                };
                format!("ok     {name}: {text}")
            }
            // Motion without a skeleton is not a broken file: said, not counted as a failure.
            Ok(None) => format!(
                "note   {}: unpaired: no skeleton ({}) in its folder",
                outcome.item.path.display(),
                outcome.item.wanted_skeleton()
            ),
            Err(error) => format!("error  {}", super::said(error)),
        };
        progress.done();
        let mut out = io::stdout().lock();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
        progress.show(finished);
    });
    progress.done();
    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    let unpaired = outcomes
        .iter()
        .filter(|o| matches!(o.result, Ok(None)))
        .count();
    let bytes: u64 = outcomes.iter().map(|o| o.bytes).sum();
    let seconds = started.elapsed().as_secs_f64();
    let unpaired_part = if unpaired > 0 {
        format!(", {unpaired} unpaired")
    } else {
        String::new()
    };
    // Written, not println!'d: a reader that has gone (`| head -1`) ends the output quietly.
    let summary = writeln!(
        io::stdout().lock(),
        "{}: {} ok{unpaired_part}, {failed} failed; {:.1} MB in {seconds:.2} s ({:.0} MB/s)",
        crate::io::error::counted(outcomes.len(), "file"),
        outcomes.len() - failed - unpaired,
        bytes as f64 / 1e6,
        bytes as f64 / 1e6 / seconds.max(1e-9)
    );
    super::written(summary, None)?;
    Ok(if failed > 0 {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}
