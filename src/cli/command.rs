//! The clap command and the dispatch to `cli/`, one file per command; errors mapped to exit
//! codes (0 success, 2 bad input, 1 anything else).

use crate::cli;
use crate::io::error::Error;
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "bvhview",
    version,
    about = "Load, look at, snapshot and export motion capture: BVH, ASF/AMC, FBX and glTF",
    args_conflicts_with_subcommands = true,
    after_help = cli::viewer::WINDOW_KEYS
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    viewer: cli::viewer::ViewerArgs,
    /// Say nothing on stderr about what was written.
    #[arg(short, long, global = true)]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Print the joint tree exactly as the article's BVH::print() does.
    #[command(
        after_help = "Examples:\n  bvhview print walk.bvh\n  bvhview print character.fbx --take 1\n  bvhview print 07.asf --motion 07_05.amc"
    )]
    Print(cli::print::PrintArgs),
    /// Summarise a file (joints, channels, frames, timing, rotation orders, warnings), or every
    /// BVH, ASF/AMC, FBX and glTF take under a folder, one line each, on all cores.
    #[command(
        after_help = "Examples:\n  bvhview info walk.bvh\n  bvhview info scene.glb\n  bvhview info mocap/          (every take under it, on all cores)"
    )]
    Info(cli::info::InfoArgs),
    /// Write the world position of every joint and End Site (ASF: every bone's end) per frame.
    #[command(
        after_help = "Examples:\n  bvhview positions walk.bvh -o walk.csv\n  bvhview positions run.fbx --format json -o run.json"
    )]
    Positions(cli::positions::PositionsArgs),
    /// Draw offscreen (no display needed): one frame as PNG, or with --frames a sequence as an
    /// animated GIF or APNG, an MP4 video, or as one PNG per frame in a folder.
    #[command(
        after_help = "Examples:\n  bvhview snapshot walk.bvh --frame 10 -o walk.png\n  bvhview snapshot dance.glb --frames 0..120 -o dance.gif"
    )]
    Snapshot(cli::snapshot::SnapshotArgs),
    /// Print the GL calls one display() makes for a frame, in C, one per line.
    #[command(
        after_help = "Examples:\n  bvhview trace walk.bvh --frame 0\n  bvhview trace jump.fbx --frame 5"
    )]
    Trace(cli::trace::TraceArgs),
    /// Compare two PNG pictures: how many pixels differ (exit 1 if any), and optionally a
    /// picture of where.
    Diff(cli::diff::DiffArgs),
    /// The two-bone, three-quad linear blend skinning demo: in a window (right-drag bends the
    /// second bone), or offscreen with -o.
    SkinDemo(cli::skin_demo::SkinDemoArgs),
    /// Write a take (BVH, ASF + AMC, FBX or glTF) as BVH or glTF (.glb, .gltf), trimmed, resampled,
    /// scaled, turned, mirrored, in place or grounded on the way if asked.
    #[command(
        after_help = "Examples:\n  bvhview convert walk.bvh -o walk.glb\n  bvhview convert run.fbx --fps 30 -o run.bvh\n  bvhview convert mocap/ --to gltf -o mocap_gltf/"
    )]
    Convert(cli::convert::ConvertArgs),
    /// Compile every take (BVH, ASF/AMC, FBX, glTF) under a folder into training arrays on all cores: one frame rate, Y up,
    /// metres; positions, rotations, root translations, velocities, foot contacts, as
    /// manifest.json plus .npy files per skeleton topology. Takes that fail are skipped and listed.
    #[command(
        after_help = "Examples:\n  bvhview dataset mocap/ -o mocap.ds\n  bvhview dataset mixed/ --onto smpl22 -o mixed.ds"
    )]
    Dataset(cli::dataset::DatasetArgs),
    /// Put a take's motion on another skeleton (a file, or the built-in `smpl22`): joints
    /// matched by role from their names, rest poses aligned, written as BVH or glTF.
    #[command(
        after_help = "Examples:\n  bvhview retarget walk.bvh --onto smpl22 -o walk_smpl.bvh\n  bvhview retarget dance.fbx --onto hero.glb --show-map"
    )]
    Retarget(cli::retarget::RetargetArgs),
    /// Turn joint positions (frames × joints × 3: a motion model's output, a pose estimator's,
    /// HumanML3D's joints) into a take on a skeleton: rotations in its own channels, each bone
    /// laid along the data's, written as BVH or glTF.
    #[command(after_help = "Examples:
  bvhview solve sample.npy --onto smpl22 --fps 20 -o sample.bvh
  bvhview solve walk.csv --onto walk.bvh --fps 120 -o back.bvh")]
    Solve(cli::solve::SolveArgs),
    /// How plausible a motion is, in the numbers papers report: foot skating (GMD's skating
    /// ratio), PhysDiff's penetration, floating and sliding, jitter and bone-length drift; per
    /// take, or a table for a folder.
    #[command(after_help = "Examples:
  bvhview metrics walk.bvh
  bvhview metrics generated/ -o metrics.csv
  bvhview metrics sample.npy --fps 20 --floor 0")]
    Metrics(cli::metrics::MetricsArgs),
    /// Write the man page or shell completions on stdout, made from this command's own help.
    #[command(
        after_help = "Install them with, for example:\n  bvhview generate man -o ~/.local/share/man/man1/bvhview.1\n  bvhview generate complete-bash -o ~/.local/share/bash-completion/completions/bvhview\n  bvhview generate complete-zsh -o ~/.zfunc/_bvhview\n  bvhview generate complete-fish -o ~/.config/fish/completions/bvhview.fish"
    )]
    Generate(cli::generate::GenerateArgs),
}

/// Runs the command line on this process's arguments.
pub fn main() -> ExitCode {
    if let Some(code) = mistyped_command() {
        return code;
    }
    // `--version` also names the row reader this machine runs (machines differ).
    let long_version = format!(
        "{}\nrow reader: {}",
        env!("CARGO_PKG_VERSION"),
        crate::bvh::rows::row_reader()
    );
    let parsed = Cli::command()
        .long_version(&*Box::leak(long_version.into_boxed_str()))
        .try_get_matches()
        .and_then(|matches| Cli::from_arg_matches(&matches));
    let cli = match parsed {
        Ok(cli) => cli,
        // Help and version go to stdout as clap writes them; mistakes get our one prefix.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            let text = e.render().to_string();
            let text = text.strip_prefix("error: ").unwrap_or(&text);
            eprint!("bvhview: {text}");
            return ExitCode::from(2);
        }
    };
    cli::QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    // Ctrl-C, kill or a closed terminal leave no half-written output behind.
    crate::io::output::remove_partials_on_signal();
    let result = match cli.command {
        None => cli::viewer::run(cli.viewer),
        Some(Command::Print(args)) => cli::print::run(args),
        Some(Command::Info(args)) => cli::info::run(args),
        Some(Command::Positions(args)) => cli::positions::run(args),
        Some(Command::Snapshot(args)) => cli::snapshot::run(args),
        Some(Command::Trace(args)) => cli::trace::run(args),
        Some(Command::Diff(args)) => cli::diff::run(args),
        Some(Command::SkinDemo(args)) => cli::skin_demo::run(args),
        Some(Command::Convert(args)) => cli::convert::run(args),
        Some(Command::Dataset(args)) => cli::dataset::run(args),
        Some(Command::Retarget(args)) => cli::retarget::run(args),
        Some(Command::Solve(args)) => cli::solve::run(args),
        Some(Command::Metrics(args)) => cli::metrics::run(args),
        Some(Command::Generate(args)) => cli::generate::run(args, Cli::command()),
    };
    match result {
        Ok(code) => code,
        Err(error) => report(&error),
    }
}

/// The error said as the command line says it (an argument by its flag), and its exit code:
/// 2 when the caller's input or request is at fault, 1 when the machine is.
fn report(error: &Error) -> ExitCode {
    eprintln!("bvhview: {}", cli::said(error));
    ExitCode::from(if error.is_the_callers() { 2 } else { 1 })
}

/// A mistyped command is taken for a file name (the window takes files): when the first word is
/// neither a file nor a command and has no extension, clap's own suggestion among the commands
/// is said in one line.
fn mistyped_command() -> Option<ExitCode> {
    let word = std::env::args().nth(1)?;
    let path = std::path::Path::new(&word);
    if word.starts_with('-') || path.exists() || !crate::take::extension(path).is_empty() {
        return None;
    }
    let commands =
        clap::Command::new("bvhview").subcommands(Cli::command().get_subcommands().cloned());
    let error = commands.try_get_matches_from(["bvhview", &word]).err()?;
    if error.kind() != ErrorKind::InvalidSubcommand {
        return None;
    }
    let Some(ContextValue::Strings(suggested)) = error.get(ContextKind::SuggestedSubcommand) else {
        return None;
    };
    let command = suggested.first()?;
    eprintln!(
        "bvhview: '{word}' is neither a file nor a command; did you mean `bvhview {command}`?"
    );
    Some(ExitCode::from(2))
}
