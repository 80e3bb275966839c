//! The `bvhview` command line: parses arguments, calls the library, maps errors to exit codes
//! (0 success, 2 bad input, 1 anything else).

use bvhview::bvh::{self, Bvh};
use bvhview::error::Error;
use bvhview::export::{self, Format, PositionsOptions};
use bvhview::pose::OffsetMode;
use bvhview::render::SnapshotOptions;
use bvhview::render::draw::Style;
use bvhview::render::window::ViewerOptions;
use clap::{Parser, Subcommand};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "bvhview",
    version,
    about = "Load, look at and export BVH motion capture",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A BVH file to show in a window (default: the bundled walk, assets/walk.bvh).
    file: Option<PathBuf>,
    /// Start with the stick figure (B toggles it).
    #[arg(long, value_enum, default_value_t)]
    style: Style,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetMode,
}

#[derive(Subcommand)]
enum Command {
    /// Print the joint tree exactly as the article's BVH::print() does.
    Print { file: PathBuf },
    /// Summarise a file: joints, channels, frames, timing, rotation orders, warnings.
    Info {
        /// The file (default: the bundled walk).
        file: Option<PathBuf>,
        /// How position channels combine with OFFSET (checked by the warnings).
        #[arg(long, value_enum, default_value_t)]
        offset_mode: OffsetMode,
    },
    /// Write the world position of every joint and End Site per frame.
    Positions {
        file: PathBuf,
        /// Frames to write: N, A..B (B excluded), A..=B, A.. or ..B (default: all).
        #[arg(long)]
        frames: Option<String>,
        #[arg(long, value_enum, default_value_t)]
        format: Format,
        /// Negate z (right-handed BVH to left-handed, as for Direct3D).
        #[arg(long)]
        left_handed: bool,
        /// How position channels combine with OFFSET.
        #[arg(long, value_enum, default_value_t)]
        offset_mode: OffsetMode,
        /// Output file (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Draw one frame offscreen (no display needed) and write it as PNG.
    Snapshot {
        file: PathBuf,
        /// Frame to draw, from 0.
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Camera angle around the Y axis in radians (the article starts at 10).
        #[arg(long, default_value_t = bvhview::render::scene::START_ANGLE, allow_negative_numbers = true)]
        angle: f32,
        /// Picture size, WIDTHxHEIGHT.
        #[arg(long, default_value = "600x600", value_parser = parse_size)]
        size: (u32, u32),
        /// Spheres (the article), the stick figure, or both.
        #[arg(long, value_enum, default_value_t)]
        style: Style,
        /// Frame the skeleton instead of using the article's fixed camera.
        #[arg(long)]
        fit: bool,
        /// How position channels combine with OFFSET.
        #[arg(long, value_enum, default_value_t)]
        offset_mode: OffsetMode,
        /// The PNG to write.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write a file back out as BVH.
    Convert {
        input: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
    },
}

/// `600x400` → (600, 400).
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 600x600, found '{text}'");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    bvhview::render::osmesa::check_size(w, h).map_err(|e| e.to_string())?;
    Ok((w, h))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("bvhview: {error}");
            ExitCode::from(error.exit_code() as u8)
        }
    }
}

/// Loads a file and reports its warnings on stderr.
fn load(path: &Path) -> Result<Bvh, Error> {
    let bvh = bvh::load_file(path)?;
    report_warnings(&path.display().to_string(), &bvh);
    Ok(bvh)
}

/// The named file, or the bundled walk; with the name to show.
fn load_or_default(path: Option<&Path>) -> Result<(String, Bvh), Error> {
    match path {
        Some(path) => Ok((path.display().to_string(), load(path)?)),
        None => {
            let bvh = bvh::load_bytes(bvhview::DEFAULT_MOTION, bvhview::DEFAULT_MOTION_NAME)?;
            Ok((bvhview::DEFAULT_MOTION_NAME.to_string(), bvh))
        }
    }
}

fn report_warnings(name: &str, bvh: &Bvh) {
    for warning in &bvh.warnings {
        eprintln!("bvhview: {name}: warning: {warning}");
    }
}

/// Opens the output (a file, or stdout when none is named).
fn open_output(path: Option<&Path>) -> Result<Box<dyn Write>, Error> {
    Ok(match path {
        Some(path) => Box::new(BufWriter::new(
            std::fs::File::create(path).map_err(|e| Error::io(path, e))?,
        )),
        None => Box::new(BufWriter::new(io::stdout().lock())),
    })
}

/// A write error on stdout that is a closed pipe (`| head`) ends quietly; others are reported.
fn finish_write(result: io::Result<()>, path: Option<&Path>) -> Result<(), Error> {
    match result {
        Ok(()) => Ok(()),
        Err(e) if path.is_none() && e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::io(path.unwrap_or(Path::new("<stdout>")), e)),
    }
}

fn run(cli: Cli) -> Result<(), Error> {
    match cli.command {
        None => {
            // Say there is no display before loading anything.
            bvhview::render::window::check_environment()?;
            let (name, bvh) = load_or_default(cli.file.as_deref())?;
            let name = Path::new(&name)
                .file_name()
                .map_or(name.clone(), |n| n.to_string_lossy().into_owned());
            let options = ViewerOptions {
                name,
                offset_mode: cli.offset_mode,
                style: cli.style,
            };
            bvhview::render::window::run(&bvh.skeleton, &bvh.motion, options)
        }
        Some(Command::Print { file }) => {
            let bvh = load(&file)?;
            let mut out = open_output(None)?;
            let result = out
                .write_all(bvh::print::print(&bvh.skeleton).as_bytes())
                .and_then(|()| out.flush());
            finish_write(result, None)
        }
        Some(Command::Info { file, offset_mode }) => {
            let (name, bvh) = load_or_default(file.as_deref())?;
            let summary = bvhview::info::summary(&name, &bvh, offset_mode);
            let mut out = open_output(None)?;
            finish_write(
                out.write_all(summary.as_bytes()).and_then(|()| out.flush()),
                None,
            )
        }
        Some(Command::Positions {
            file,
            frames,
            format,
            left_handed,
            offset_mode,
            output,
        }) => {
            let bvh = load(&file)?;
            let available = bvh.motion.frame_count().max(1);
            if bvh.motion.frame_count() == 0 {
                eprintln!(
                    "bvhview: {}: no frames; writing the rest pose",
                    file.display()
                );
            }
            let range = match frames {
                Some(text) => export::parse_frames(&text, available)?,
                None => 0..available,
            };
            if let Some(warning) = bvhview::info::offset_mode_warning(&bvh, offset_mode) {
                eprintln!("bvhview: {}: warning: {warning}", file.display());
            }
            let options = PositionsOptions {
                format,
                offset_mode,
                left_handed,
            };
            let mut out = open_output(output.as_deref())?;
            let result =
                export::write_positions(&mut out, &bvh.skeleton, &bvh.motion, range, &options)
                    .and_then(|()| out.flush());
            finish_write(result, output.as_deref())
        }
        Some(Command::Snapshot {
            file,
            frame,
            angle,
            size,
            style,
            fit,
            offset_mode,
            output,
        }) => {
            let bvh = load(&file)?;
            let options = SnapshotOptions {
                frame,
                angle,
                width: size.0,
                height: size.1,
                style,
                fit,
                offset_mode,
            };
            let image = bvhview::render::snapshot(&bvh.skeleton, &bvh.motion, &options)?;
            image.write_png(&output)
        }
        Some(Command::Convert { input, output }) => {
            let bvh = load(&input)?;
            let mut out = open_output(Some(&output))?;
            let result = bvh::writer::write_bvh(&mut out, &bvh.skeleton, &bvh.motion)
                .and_then(|()| out.flush());
            finish_write(result, Some(&output))
        }
    }
}
