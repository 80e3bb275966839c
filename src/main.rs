//! The `bvhview` command line: parses arguments, calls the library, maps errors to exit codes
//! (0 success, 2 bad input, 1 anything else).

use bvhview::error::Error;
use bvhview::export::{self, Format, PositionsOptions};
use bvhview::input::{self, Loaded};
use bvhview::pose::{OffsetMode, Up};
use bvhview::render::draw::Style;
use bvhview::render::paint::{Clock, Shown};
use bvhview::render::window::ViewerOptions;
use bvhview::render::{Look, Overlay, SnapshotOptions};
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand, ValueEnum};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "bvhview",
    version,
    about = "Load, look at, snapshot and export BVH and ASF/AMC motion capture",
    args_conflicts_with_subcommands = true,
    after_help = WINDOW_KEYS
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// A .bvh file, or an .asf skeleton, to show in a window (default: the bundled walk);
    /// several files stand side by side on one timeline.
    files: Vec<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// Start with the stick figure (B toggles it).
    #[arg(long, value_enum, default_value_t)]
    style: StyleArg,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// Start with a generated skin around the bones (K toggles it).
    #[arg(long)]
    skin: bool,
    /// Start in the studio look (V switches).
    #[arg(long, value_enum, default_value_t)]
    look: LookArg,
    /// The file's up axis (default: guessed from the rest pose; O switches the offset mode).
    #[arg(long, value_enum)]
    up: Option<UpArg>,
    /// Say nothing on stderr about what was written.
    #[arg(short, long, global = true)]
    quiet: bool,
}

/// `--offset-mode`: how a joint's position channels combine with its OFFSET.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum OffsetModeArg {
    /// Position channels replace the matching OFFSET components (the article, Blender, bvhio).
    #[default]
    Replace,
    /// Position channels are added to the OFFSET (three.js).
    Add,
}

impl From<OffsetModeArg> for OffsetMode {
    fn from(arg: OffsetModeArg) -> OffsetMode {
        match arg {
            OffsetModeArg::Replace => OffsetMode::Replace,
            OffsetModeArg::Add => OffsetMode::Add,
        }
    }
}

/// `--style`: how joints are drawn.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum StyleArg {
    /// A sphere per joint and End Site (the article).
    #[default]
    Points,
    /// A line from each joint to each child, unlit, green.
    Sticks,
    /// Both.
    Both,
}

impl From<StyleArg> for Style {
    fn from(arg: StyleArg) -> Style {
        match arg {
            StyleArg::Points => Style::Points,
            StyleArg::Sticks => Style::Sticks,
            StyleArg::Both => Style::Both,
        }
    }
}

/// `--look`: the article's picture, or the studio's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
enum LookArg {
    /// The article's picture: black, grey spheres, its camera and floor.
    #[default]
    Article,
    /// A grid floor at the take's lowest point, shadows, bones coloured by side (left blue,
    /// right orange), a camera that frames the whole take.
    Studio,
}

impl From<LookArg> for Look {
    fn from(arg: LookArg) -> Look {
        match arg {
            LookArg::Article => Look::Article,
            LookArg::Studio => Look::Studio,
        }
    }
}

/// `--format` of `positions`.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum FormatArg {
    /// `frame,joint,x,y,z`, one joint per line.
    #[default]
    Csv,
    /// `{"frame_time":…,"joints":[…],"frames":[{"frame":0,"positions":[[x,y,z],…]},…]}`.
    Json,
}

impl From<FormatArg> for Format {
    fn from(arg: FormatArg) -> Format {
        match arg {
            FormatArg::Csv => Format::Csv,
            FormatArg::Json => Format::Json,
        }
    }
}

/// The window's keys, for `bvhview --help`.
const WINDOW_KEYS: &str = "\
Keys in the window:
  W             next frame (the article)
  S             previous frame
  A / D         turn the camera (the article)
  Space         play / pause in real time at the files' frame time
  Home / End    first / last frame
  + / -         play faster / slower (0.1x to 4x)
  L             loop on / off
  mouse drag    turn and tilt; Shift+drag or middle drag: pan; wheel: zoom
  F             frame the whole skeleton / back to the article's camera
  C             the article's camera, as at the start
  V             the studio look on / off; T: its camera follows the root
  O             position channels replace / are added to OFFSET
  I / H         the HUD and timeline (click or drag on it to seek) / the help on and off
  N             joint names on / off
  B             next style: spheres, stick figure, both
  K             generated skin on / off
  J / Shift+J   step through the recursion one joint at a time (Esc: whole picture)
  R             load the files again (a file that no longer loads keeps its last picture)
  P             write the picture shown to NAME_frameNNNNN.png
  drop a file   add it beside the others
  Esc           quit (the article)";

/// Options that come with any input file.
#[derive(Args, Clone, Debug)]
struct Source {
    /// The AMC motion for an ASF skeleton (without it: the rest pose).
    #[arg(long, value_name = "TAKE.amc")]
    motion: Option<PathBuf>,
    /// Seconds per frame, overriding the file (AMC files have none: default 1/120).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    frame_time: Option<f64>,
    /// Refuse input files larger than this (bytes; K, M, G suffixes), before reading them.
    #[arg(long, value_name = "SIZE", default_value = "8G", value_parser = parse_max_size)]
    max_size: u64,
}

/// `30,-45` → (30, -45).
fn parse_bend(text: &str) -> Result<(f32, f32), String> {
    let bad = || format!("expected Y,Z in degrees such as 30,-45, found '{text}'");
    let (y, z) = text.split_once(',').ok_or_else(bad)?;
    let y: f32 = y.trim().parse().map_err(|_| bad())?;
    let z: f32 = z.trim().parse().map_err(|_| bad())?;
    if !(y.is_finite() && z.is_finite()) {
        return Err(bad());
    }
    Ok((y, z))
}

/// `8G` → 8 GiB; plain numbers are bytes.
fn parse_max_size(text: &str) -> Result<u64, String> {
    let bad = || format!("expected a size such as 500M or 8G, found '{text}'");
    let (number, unit) = match text.trim().char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&text.trim()[..i], c.to_ascii_uppercase()),
        _ => (text.trim(), 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        'T' => 40,
        _ => return Err(bad()),
    };
    let value: u64 = number.parse().map_err(|_| bad())?;
    value.checked_mul(1 << shift).ok_or_else(bad)
}

#[derive(Subcommand)]
enum Command {
    /// Print the joint tree exactly as the article's BVH::print() does.
    Print(PrintArgs),
    /// Summarise a file (joints, channels, frames, timing, rotation orders, warnings), or every
    /// BVH and ASF/AMC under a folder, one line each, on all cores.
    Info(InfoArgs),
    /// Write the world position of every joint and End Site (ASF: every bone's end) per frame.
    Positions(PositionsArgs),
    /// Draw one frame offscreen (no display needed) and write it as PNG.
    Snapshot(SnapshotArgs),
    /// Print the GL calls one display() makes for a frame, in C, one per line.
    Trace(TraceArgs),
    /// Compare two PNG pictures: how many pixels differ (exit 1 if any), and optionally a
    /// picture of where.
    Diff(DiffArgs),
    /// The two-bone, three-quad linear blend skinning demo: in a window (right-drag bends the
    /// second bone), or offscreen with -o.
    SkinDemo(SkinDemoArgs),
    /// Write a file (BVH, or ASF + AMC) as BVH.
    Convert(ConvertArgs),
}

#[derive(Args)]
struct PrintArgs {
    /// A .bvh file, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
}

#[derive(Args)]
struct InfoArgs {
    /// The file or folder (default: the bundled walk).
    file: Option<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// How position channels combine with OFFSET (checked by the warnings).
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
}

#[derive(Args)]
struct PositionsArgs {
    /// A .bvh file, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
    /// Frames to write: N, A..B (B excluded), A..=B, A.. or ..B (default: all).
    #[arg(long)]
    frames: Option<String>,
    /// The output format.
    #[arg(long, value_enum, default_value_t)]
    format: FormatArg,
    /// Negate z (right-handed to left-handed, as for Direct3D).
    #[arg(long)]
    left_handed: bool,
    /// Multiply every coordinate (default 1: the file's own units).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    scale: f32,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// Output file (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct SnapshotArgs {
    /// A .bvh file, or an .asf skeleton (its motion with --motion); several files stand side
    /// by side on one timeline.
    #[arg(required = true, num_args = 1..)]
    files: Vec<PathBuf>,
    #[command(flatten)]
    source: Source,
    /// Frame to draw, from 0.
    #[arg(long, default_value_t = 0, conflicts_with = "frames")]
    frame: usize,
    /// A sequence instead: N, A..B, A..=B, A.. or ..B, written as OUT/frame_NNNNN.png.
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
    /// Draw only the first K joints in the order the recursion reaches them, the last one
    /// highlighted, with its GL calls written beside (the window's J key).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(1..))]
    step: Option<u64>,
    /// Write the HUD top left (the file, the frame, its time, the rate, the display mode) and
    /// the timeline along the bottom (the window's I key).
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
    /// Frames per second of an animated output (default: the file's rate, at most 50 for GIF).
    #[arg(long, requires = "frames")]
    fps: Option<f64>,
    /// The PNG to write; with --frames an animated .gif, .apng or .png, or a folder to write one
    /// PNG per frame into (created if missing).
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct TraceArgs {
    /// A .bvh file, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
    /// Frame to draw, from 0.
    #[arg(long, default_value_t = 0)]
    frame: usize,
    #[command(flatten)]
    view: View,
    /// Indent each call by the depth of the matrix stack and say what it does: the joint, the
    /// MOTION columns it reads (the article's pFrame), where each sphere lands.
    #[arg(long)]
    explain: bool,
    /// The language of --explain's notes.
    #[arg(long, value_enum, default_value_t, requires = "explain")]
    lang: LanguageArg,
    /// How numbers are written: printf's %f (the article's code), or apitrace's %g with the
    /// whole run from init() on, to diff against a recording of the article's program.
    #[arg(long, value_enum, default_value_t)]
    numbers: NumbersArg,
}

/// `--lang` of `trace --explain`.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum LanguageArg {
    /// English.
    #[default]
    En,
    /// Traditional Chinese, in the article's terms.
    Zh,
}

/// `--numbers` of `trace`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
enum NumbersArg {
    /// printf's %f, six decimals: display() only.
    #[default]
    Printf,
    /// apitrace's %.7g / %.16g, from init() through display().
    Apitrace,
}

#[derive(Args)]
struct DiffArgs {
    /// The first PNG picture.
    first: PathBuf,
    /// The second PNG picture, of the same size.
    second: PathBuf,
    /// Write the difference: differing pixels red, the rest dimmed.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct SkinDemoArgs {
    /// The second bone's bend about Y and Z, in degrees.
    #[arg(long, default_value = "0,0", value_parser = parse_bend, allow_hyphen_values = true)]
    bend: (f32, f32),
    /// Picture size, WIDTHxHEIGHT (the demo's window is 640x480).
    #[arg(long, default_value = "640x480", value_parser = parse_size)]
    size: (u32, u32),
    /// Draw offscreen into this PNG instead of opening a window.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct ConvertArgs {
    /// A .bvh file, or an .asf skeleton with its motion in --motion.
    input: PathBuf,
    #[command(flatten)]
    source: Source,
    /// Keep only these frames: N, A..B (B left out), A..=B, A.. or ..B (applied first).
    #[arg(long)]
    frames: Option<String>,
    /// Resample to this many frames per second: rotations slerped, positions interpolated
    /// (applied second; any ratio, such as 120 to 100).
    #[arg(long)]
    fps: Option<f64>,
    /// Multiply every length, OFFSETs and position channels (applied third).
    #[arg(long, allow_negative_numbers = true)]
    scale: Option<f32>,
    /// Turn the take to this up axis, from the one guessed from its rest pose (fourth).
    #[arg(long, value_enum)]
    up: Option<UpArg>,
    /// The mirror image: x negated, Left and Right exchanged in the names (fifth).
    #[arg(long)]
    mirror: bool,
    /// Remove the roots' travel across the ground (sixth).
    #[arg(long)]
    in_place: bool,
    /// Move the take up or down so that its lowest point is at 0 (last).
    #[arg(long)]
    ground: bool,
    /// How position channels combine with OFFSET (in a glTF output's translations).
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// glTF only: add the viewer's generated skin as a mesh skinned to the joints.
    #[arg(long)]
    skin: bool,
    /// The file to write: .bvh, or glTF as .glb (binary) or .gltf (text, data inline).
    #[arg(short, long)]
    output: PathBuf,
}

/// How a drawing command looks at the skeleton.
#[derive(Args, Clone, Copy, Debug)]
struct View {
    /// Camera angle around the Y axis in radians (default: the article's 10; with several
    /// files 1.5708, looking at them side by side along x).
    #[arg(long, allow_negative_numbers = true)]
    angle: Option<f32>,
    /// Spheres (the article), the stick figure, or both.
    #[arg(long, value_enum, default_value_t)]
    style: StyleArg,
    /// Frame the skeleton instead of using the article's fixed camera.
    #[arg(long)]
    fit: bool,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// The file's up axis: z stands a Z-up skeleton up (default: guessed from the rest pose, and
    /// said when it is z).
    #[arg(long, value_enum)]
    up: Option<UpArg>,
}

/// `--up`.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum UpArg {
    /// Y up, as BVH files usually are (the article draws every file this way).
    Y,
    /// Z up (MakeHuman's files, for example).
    Z,
}

impl From<UpArg> for Up {
    fn from(arg: UpArg) -> Up {
        match arg {
            UpArg::Y => Up::Y,
            UpArg::Z => Up::Z,
        }
    }
}

/// The up axis to draw `loaded` with: `--up` if given. Otherwise the article's view draws every
/// file as written, Y up, as the article's program does; a view that frames the take (`--fit`,
/// `--look studio`: `framed`) stands it up by the guess from its rest pose. Either way a file
/// that stands along z is said once on stderr, with what stands it up or draws it as written.
fn resolve_up(arg: Option<UpArg>, loaded: &Loaded, name: &str, framed: bool) -> Up {
    if let Some(arg) = arg {
        return arg.into();
    }
    let guess = Up::guess(&loaded.skeleton);
    if guess == Up::Z {
        if framed {
            eprintln!(
                "bvhview: {name}: stands taller along z than along y at rest: drawn Z-up \
                 (--up y draws it as written)"
            );
        } else {
            eprintln!("bvhview: {name}: {}", bvhview::render::hud::LYING_HINT);
        }
    }
    if framed { guess } else { Up::Y }
}

/// Says once on stderr when a file looks written for the other offset mode.
fn warn_offset_mode(loaded: &Loaded, mode: OffsetMode, name: &str) {
    if let Some(warning) =
        bvhview::info::offset_mode_warning(&loaded.skeleton, &loaded.motion, mode)
    {
        eprintln!("bvhview: {name}: warning: {warning}");
    }
}

/// `600x400` → (600, 400).
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 600x600, found '{text}'");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    bvhview::limits::picture_size(w, h).map_err(|e| e.to_string())?;
    Ok((w, h))
}

fn main() -> ExitCode {
    // A mistyped command would be taken for a file name: say what was probably meant instead.
    if let Some(word) = std::env::args().nth(1)
        && !word.starts_with('-')
        && !COMMANDS.contains(&word.as_str())
        && !Path::new(&word).exists()
        && input::extension(Path::new(&word)).is_empty()
        && let Some(command) = meant_command(&word)
    {
        eprintln!(
            "bvhview: '{word}' is neither a file nor a command; did you mean `bvhview {command}`?"
        );
        return ExitCode::from(2);
    }
    // `--version` also names the row reader this machine runs (machines differ).
    let long_version = format!(
        "{}\nrow reader: {}",
        env!("CARGO_PKG_VERSION"),
        bvhview::bvh::rows::row_reader()
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
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    // Ctrl-C, kill or a closed terminal leave no half-written output behind.
    bvhview::output::remove_partials_on_signal();
    let result = match cli.command {
        None => viewer(
            cli.files,
            cli.source,
            cli.style,
            cli.offset_mode,
            cli.skin,
            cli.up,
            cli.look,
        ),
        Some(Command::Print(args)) => print(args),
        Some(Command::Info(args)) => info(args),
        Some(Command::Positions(args)) => positions(args),
        Some(Command::Snapshot(args)) => snapshot(args),
        Some(Command::Trace(args)) => trace(args),
        Some(Command::Diff(args)) => diff(args),
        Some(Command::SkinDemo(args)) => skin_demo(args),
        Some(Command::Convert(args)) => convert(args),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            eprintln!("bvhview: {error}");
            ExitCode::from(error.exit_code() as u8)
        }
    }
}

/// `-q`: no line about what was written.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The one line on stderr that says what a command wrote.
fn wrote(what: std::fmt::Arguments) {
    if !QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("bvhview: wrote {what}");
    }
}

/// Refuses an output whose extension is not one the command writes, before any work.
/// A FIFO, a character device or a path under /dev or /proc (`/dev/stdout`, `/dev/fd/3`) is
/// taken whatever its name: it is written to where it is.
fn check_output(path: &Path, formats: &[&str]) -> Result<(), Error> {
    use std::os::unix::fs::FileTypeExt;
    let extension = input::extension(path);
    let special = path.starts_with("/dev")
        || path.starts_with("/proc")
        || std::fs::metadata(path)
            .is_ok_and(|m| m.file_type().is_fifo() || m.file_type().is_char_device());
    if special || formats.contains(&extension.as_str()) {
        return Ok(());
    }
    let list: Vec<String> = formats.iter().map(|f| format!(".{f}")).collect();
    Err(Error::Usage(format!(
        "-o {}: this command writes {}",
        path.display(),
        list.join(" or ")
    )))
}

/// A progress bar on stderr while a long write runs, when stderr is a terminal.
struct Progress {
    total: usize,
    on_terminal: bool,
}

impl Progress {
    fn new(total: usize) -> Progress {
        use std::io::IsTerminal;
        Progress {
            total,
            on_terminal: io::stderr().is_terminal()
                && !QUIET.load(std::sync::atomic::Ordering::Relaxed),
        }
    }

    fn show(&self, done: usize) {
        if self.on_terminal {
            let width = 30;
            let filled = done * width / self.total.max(1);
            eprint!(
                "\r[{}{}] {done}/{}",
                "#".repeat(filled),
                "-".repeat(width - filled),
                self.total
            );
        }
    }

    fn done(&self) {
        if self.on_terminal {
            eprint!("\r\x1b[2K");
        }
    }
}

/// The subcommands, for a suggestion when a mistyped one is taken for a file.
const COMMANDS: &[&str] = &[
    "print",
    "info",
    "positions",
    "snapshot",
    "trace",
    "diff",
    "skin-demo",
    "convert",
];

/// The command `word` was most likely meant to be: a letter or two away from one.
fn meant_command(word: &str) -> Option<&'static str> {
    fn distance(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut previous = row[0];
            row[0] = i + 1;
            for (j, &cb) in b.iter().enumerate() {
                let substitute = previous + usize::from(ca != cb);
                previous = row[j + 1];
                row[j + 1] = substitute.min(row[j] + 1).min(row[j + 1] + 1);
            }
        }
        row[b.len()]
    }
    COMMANDS
        .iter()
        .map(|&c| (distance(word, c), c))
        .filter(|&(d, _)| d <= 2)
        .min()
        .map(|(_, c)| c)
}

/// Loads a file (with its motion) and reports its warnings on stderr.
fn load(path: &Path, source: &Source) -> Result<Loaded, Error> {
    let loaded = load_quietly(path, source)?;
    for warning in &loaded.warnings {
        eprintln!("bvhview: {}: warning: {warning}", path.display());
    }
    Ok(loaded)
}

/// Loads a file (with its motion), its warnings left to the caller.
fn load_quietly(path: &Path, source: &Source) -> Result<Loaded, Error> {
    input::load_checked(
        path,
        source.motion.as_deref(),
        source.frame_time,
        bvhview::cores(),
        source.max_size,
    )
}

/// The named file, or the bundled walk; with the name to show.
fn load_or_default(path: Option<&Path>, source: &Source) -> Result<(String, Loaded), Error> {
    match path {
        Some(path) => Ok((path.display().to_string(), load(path, source)?)),
        None => {
            if source.motion.is_some() {
                return Err(Error::Usage("--motion needs an ASF skeleton file".into()));
            }
            bvhview::limits::frame_time_option(source.frame_time)?;
            let mut walk = input::default_motion()?;
            if let Some(time) = source.frame_time {
                walk.motion.frame_time = time;
            }
            Ok((bvhview::DEFAULT_MOTION_NAME.to_string(), walk))
        }
    }
}

/// Where a command writes: standard output, or a file that appears whole or not at all. It may
/// be written from any thread.
enum Output {
    Stdout(BufWriter<io::Stdout>),
    File(bvhview::output::AtomicFile),
}

impl Write for Output {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        match self {
            Output::Stdout(out) => out.write(bytes),
            Output::File(out) => out.write(bytes),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self {
            Output::Stdout(out) => out.flush(),
            Output::File(out) => out.flush(),
        }
    }
}

/// Opens the output (a file, or stdout when none is named).
fn open_output(path: Option<&Path>) -> Result<Output, Error> {
    Ok(match path {
        Some(path) => Output::File(bvhview::output::AtomicFile::create(path)?),
        None => Output::Stdout(BufWriter::new(io::stdout())),
    })
}

/// Ends a write: a file takes its name only if everything was written; a write error on stdout
/// that is a closed pipe (`| head`) ends quietly; others are reported.
fn finish_write(out: Output, result: io::Result<()>, path: Option<&Path>) -> Result<(), Error> {
    let result = match out {
        Output::Stdout(mut out) => result.and_then(|()| out.flush()),
        // Dropped uncommitted on an error: the temporary file goes, nothing takes the name.
        Output::File(file) => return written(result, path).and_then(|()| file.commit()),
    };
    written(result, path)
}

/// The error a failed write is reported as.
fn written(result: io::Result<()>, path: Option<&Path>) -> Result<(), Error> {
    match result {
        Ok(()) => Ok(()),
        Err(e) if path.is_none() && e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) if export::not_finite(&e).is_some() => Err(Error::Usage(e.to_string())),
        Err(e) => Err(Error::output(path.unwrap_or(Path::new("<stdout>")), e)),
    }
}

fn write_text(text: &str) -> Result<(), Error> {
    let mut out = open_output(None)?;
    let result = out.write_all(text.as_bytes());
    finish_write(out, result, None)
}

/// `bvhview info DIR`: one line per file, in path order, a progress bar on a terminal, and a
/// summary. Exits 2 if any file failed.
fn batch(dir: &Path, source: &Source, offset_mode: OffsetMode) -> Result<ExitCode, Error> {
    use std::io::IsTerminal;
    let started = std::time::Instant::now();
    let items = bvhview::batch::collect(dir)?;
    if items.is_empty() {
        return Err(Error::Usage(format!(
            "{}: no .bvh, .asf or .amc files",
            dir.display()
        )));
    }
    let threads = bvhview::cores();
    let progress = io::stderr().is_terminal();
    if let Some(motion) = &source.motion {
        return Err(Error::Usage(format!(
            "--motion {}: a folder pairs each AMC with its ASF itself",
            motion.display()
        )));
    }
    bvhview::limits::frame_time_option(source.frame_time)?;
    let settings = bvhview::batch::Settings {
        frame_time: source.frame_time,
        max_size: source.max_size,
        offset_mode,
    };
    let outcomes = bvhview::batch::run(items, threads, settings, |outcome, finished, total| {
        let line = match &outcome.result {
            Ok(text) => {
                let name = match &outcome.item.motion {
                    Some(amc) => format!("{} + {}", outcome.item.path.display(), amc.display()),
                    None => outcome.item.path.display().to_string(),
                };
                format!("ok     {name}: {text}")
            }
            Err(error) => format!("error  {error}"),
        };
        if progress {
            eprint!("\r\x1b[2K");
        }
        let mut out = io::stdout().lock();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
        if progress {
            let width = 30;
            let filled = finished * width / total.max(1);
            eprint!(
                "\r[{}{}] {finished}/{total}",
                "#".repeat(filled),
                "-".repeat(width - filled)
            );
        }
    });
    if progress {
        eprint!("\r\x1b[2K");
    }
    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    let bytes: u64 = outcomes.iter().map(|o| o.bytes).sum();
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "{} files: {} ok, {failed} failed; {:.1} MB in {seconds:.2} s ({:.0} MB/s)",
        outcomes.len(),
        outcomes.len() - failed,
        bytes as f64 / 1e6,
        bytes as f64 / 1e6 / seconds.max(1e-9)
    );
    Ok(if failed > 0 {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}

/// The window on a file (or the bundled walk).
fn viewer(
    files: Vec<PathBuf>,
    source: Source,
    style: StyleArg,
    offset_mode: OffsetModeArg,
    skin: bool,
    up: Option<UpArg>,
    look: LookArg,
) -> Result<ExitCode, Error> {
    use bvhview::render::window::{TakeSource, ViewerTake};
    // Say there is no display before loading anything.
    bvhview::render::window::check_environment()?;
    if files.len() > 1 && source.motion.is_some() {
        return Err(Error::Usage(
            "--motion goes with one ASF skeleton; to show an ASF/AMC take beside others, convert it to BVH first".into(),
        ));
    }
    let offset_mode = offset_mode.into();
    let mut takes = Vec::with_capacity(files.len().max(1));
    if files.is_empty() {
        let (name, loaded) = load_or_default(None, &source)?;
        resolve_up(up, &loaded, &name, look == LookArg::Studio);
        takes.push(ViewerTake {
            up: up.map_or_else(|| Up::guess(&loaded.skeleton), Up::from),
            up_asked: up.map(Up::from),
            name,
            source: None,
            loaded,
        });
    }
    for path in files {
        let take_source = TakeSource {
            path: path.clone(),
            motion: source.motion.clone(),
            frame_time: source.frame_time,
            max_size: source.max_size,
        };
        let mut take = ViewerTake::from_source(take_source)?;
        let name = path.display().to_string();
        warn_offset_mode(&take.loaded, offset_mode, &name);
        resolve_up(up, &take.loaded, &name, look == LookArg::Studio);
        take.up = up.map_or_else(|| Up::guess(&take.loaded.skeleton), Up::from);
        take.up_asked = up.map(Up::from);
        takes.push(take);
    }
    let options = ViewerOptions {
        offset_mode,
        style: style.into(),
        skin,
        look: look.into(),
        quiet: QUIET.load(std::sync::atomic::Ordering::Relaxed),
    };
    bvhview::render::window::run(takes, options)?;
    Ok(ExitCode::SUCCESS)
}

fn print(args: PrintArgs) -> Result<ExitCode, Error> {
    let loaded = load(&args.file, &args.source)?;
    write_text(&bvhview::bvh::print::print(&loaded.skeleton))?;
    Ok(ExitCode::SUCCESS)
}

fn info(args: InfoArgs) -> Result<ExitCode, Error> {
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
    write_text(&bvhview::info::summary(&name, &loaded, offset_mode))?;
    Ok(ExitCode::SUCCESS)
}

fn positions(args: PositionsArgs) -> Result<ExitCode, Error> {
    if let Some(output) = &args.output {
        check_output(output, &["csv", "json"])?;
    }
    let loaded = load(&args.file, &args.source)?;
    let available = loaded.motion.frame_count().max(1);
    if loaded.motion.frame_count() == 0 {
        eprintln!(
            "bvhview: {}: no frames; writing the rest pose",
            args.file.display()
        );
    }
    let range = match &args.frames {
        Some(text) => export::parse_frames(text, available)?,
        None => 0..available,
    };
    let scale = args.scale;
    if !(scale.is_finite() && scale != 0.0) {
        return Err(Error::Usage(format!(
            "--scale {scale}: expected a finite number other than 0"
        )));
    }
    let offset_mode = args.offset_mode.into();
    if let Some(warning) =
        bvhview::info::offset_mode_warning(&loaded.skeleton, &loaded.motion, offset_mode)
    {
        eprintln!("bvhview: {}: warning: {warning}", args.file.display());
    }
    let options = PositionsOptions {
        format: args.format.into(),
        offset_mode,
        left_handed: args.left_handed,
        scale,
    };
    let output = args.output.as_deref();
    let mut out = open_output(output)?;
    let result = export::write_positions(
        &mut out,
        &loaded.skeleton,
        &loaded.motion,
        range.clone(),
        &options,
    )
    .and_then(|()| out.flush());
    finish_write(out, result, output)?;
    if let Some(path) = output {
        let frames = range.len();
        let points = export::export_points(&loaded.skeleton).len();
        wrote(format_args!(
            "{}: {frames} frames × {points} points",
            path.display()
        ));
    }
    Ok(ExitCode::SUCCESS)
}

fn snapshot(args: SnapshotArgs) -> Result<ExitCode, Error> {
    use bvhview::render::animation;
    let animated = animation::Format::of(&args.output);
    match &args.frames {
        None => check_output(&args.output, &["png"])?,
        Some(_) if animated.is_none() && !input::extension(&args.output).is_empty() => {
            return Err(Error::Usage(format!(
                "-o {}: --frames writes an animated .gif, .apng or .png, or one PNG per frame into a folder such as frames/",
                args.output.display()
            )));
        }
        Some(_) => {}
    }
    if let Some(fps) = args.fps {
        bvhview::limits::fps(fps, animated == Some(animation::Format::Gif))?;
    }
    if args.files.len() > 1 && args.source.motion.is_some() {
        return Err(Error::Usage(
            "--motion goes with one ASF skeleton; to show an ASF/AMC take beside others, convert it to BVH first".into(),
        ));
    }
    let mode: OffsetMode = args.view.offset_mode.into();
    let framed_view = args.view.fit || args.look == LookArg::Studio;
    let mut takes = Vec::with_capacity(args.files.len());
    for file in &args.files {
        let loaded = load(file, &args.source)?;
        let name = file.display().to_string();
        warn_offset_mode(&loaded, mode, &name);
        let up = resolve_up(args.view.up, &loaded, &name, framed_view);
        takes.push((short_name(file), loaded, up));
    }
    let shown: Vec<Shown> = takes
        .iter()
        .map(|(_, loaded, up)| Shown {
            skeleton: &loaded.skeleton,
            motion: &loaded.motion,
            up: *up,
        })
        .collect();
    let clock = Clock::new(&shown.iter().map(|t| t.motion).collect::<Vec<_>>());
    let options = SnapshotOptions {
        up: shown[0].up,
        skin: args.skin,
        step: args.step.map(|k| usize::try_from(k).unwrap_or(usize::MAX)),
        frame: args.frame,
        angle: args
            .view
            .angle
            .unwrap_or_else(|| bvhview::render::paint::start_angle(args.files.len())),
        width: args.size.0,
        height: args.size.1,
        style: args.view.style.into(),
        fit: args.view.fit,
        offset_mode: mode,
        look: args.look.into(),
        follow: args.follow,
    };
    let output = &args.output;
    let other_mode_likely = takes.iter().any(|(_, loaded, _)| {
        bvhview::info::offset_mode_warning(&loaded.skeleton, &loaded.motion, mode).is_some()
    });
    let several = takes.len() > 1;
    let lying_along_z = args.view.up.is_none()
        && !framed_view
        && takes
            .iter()
            .any(|(_, loaded, _)| Up::guess(&loaded.skeleton) == Up::Z);
    let overlay = |tick: usize| -> Overlay {
        let mut overlay = Overlay {
            names: args.names,
            ..Overlay::default()
        };
        if !args.hud {
            return overlay;
        }
        overlay.timeline = Some((tick, clock.count));
        if several {
            overlay.labels = takes.iter().map(|(name, _, _)| name.clone()).collect();
        }
        overlay.lines = bvhview::render::hud::Hud {
            takes: takes
                .iter()
                .map(|(name, loaded, _)| bvhview::render::hud::HudTake {
                    name,
                    frame: clock.frame_of(&loaded.motion, tick),
                    frames: loaded.motion.frame_count(),
                    frame_time: loaded.motion.frame_time,
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
        .lines(bvhview::render::step::columns(options.width));
        overlay
    };
    let Some(frames) = &args.frames else {
        let image = bvhview::render::Renderer::new(options.width, options.height)?.render_all(
            &shown,
            &options,
            &overlay(options.frame),
        )?;
        image.write_png(output)?;
        wrote(format_args!(
            "{} ({}x{})",
            output.display(),
            image.width,
            image.height
        ));
        return Ok(ExitCode::SUCCESS);
    };
    let range = export::parse_frames(frames, clock.count)?;
    if let Some(format) = animated {
        let fps = args
            .fps
            .unwrap_or_else(|| animation::default_fps(clock.step, format));
        let ticks = animation::sampled_frames(range, clock.step, fps)?;
        let mut renderer = bvhview::render::Renderer::new(options.width, options.height)?;
        let progress = Progress::new(ticks.len());
        let pictures = ticks.iter().enumerate().map(|(i, &frame)| {
            progress.show(i + 1);
            renderer.render_all(
                &shown,
                &SnapshotOptions { frame, ..options },
                &overlay(frame),
            )
        });
        let size = (options.width, options.height);
        animation::write(output, format, size, fps, pictures, ticks.len())?;
        progress.done();
        wrote(format_args!(
            "{}: {} frames at {fps:.3} per second",
            output.display(),
            ticks.len()
        ));
        return Ok(ExitCode::SUCCESS);
    }
    std::fs::create_dir_all(output).map_err(|e| Error::output(output, e))?;
    // One offscreen context for the whole sequence.
    let mut renderer = bvhview::render::Renderer::new(options.width, options.height)?;
    let digits = (range.end.max(1) - 1).to_string().len().max(5);
    let count = range.len();
    for frame in range {
        let image = renderer.render_all(
            &shown,
            &SnapshotOptions { frame, ..options },
            &overlay(frame),
        )?;
        image.write_png(&output.join(format!("frame_{frame:0digits$}.png")))?;
    }
    wrote(format_args!("{count} pictures into {}", output.display()));
    Ok(ExitCode::SUCCESS)
}

/// A path's file name, for titles and the HUD.
fn short_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

fn trace(args: TraceArgs) -> Result<ExitCode, Error> {
    use bvhview::render::scene::{self, Scene};
    use bvhview::render::trace::{Language, Numbers, Recorder};
    let loaded = load(&args.file, &args.source)?;
    let values = bvhview::render::frame_values(&loaded.motion, args.frame)?;
    let View {
        angle,
        style,
        fit,
        offset_mode,
        up,
    } = args.view;
    let offset_mode = offset_mode.into();
    let up = resolve_up(up, &loaded, &args.file.display().to_string(), fit);
    let angle = angle.unwrap_or(scene::START_ANGLE);
    let camera = bvhview::render::camera_for(&loaded.skeleton, values, angle, fit, offset_mode, up);
    let numbers = match args.numbers {
        NumbersArg::Printf => Numbers::Printf,
        NumbersArg::Apitrace => Numbers::Apitrace,
    };
    let language = match args.lang {
        LanguageArg::En => Language::English,
        LanguageArg::Zh => Language::Chinese,
    };
    let mut recorder = if args.explain {
        Recorder::explaining(numbers, &loaded.skeleton, values, offset_mode, language)
    } else {
        Recorder::new(numbers)
    };
    if args.numbers == NumbersArg::Apitrace {
        // What a recording of the article's program holds: init, reshape, then display.
        scene::init(&mut recorder);
        scene::reshape(&mut recorder, 600, 600, &camera);
    }
    let view = Scene {
        skeleton: &loaded.skeleton,
        frame: values,
        camera,
        style: style.into(),
        offset_mode,
        skin: None,
        shown: None,
        sphere_radius: scene::sphere_radius(&camera, fit),
        up,
        origin: [0.0; 3],
        colours: None,
    };
    scene::display(&mut recorder, &view);
    write_text(&recorder.text())?;
    Ok(ExitCode::SUCCESS)
}

/// Exits 1 when the pictures differ, 0 when they are the same.
fn diff(args: DiffArgs) -> Result<ExitCode, Error> {
    use bvhview::render::Image;
    if let Some(output) = &args.output {
        check_output(output, &["png"])?;
    }
    let (a, b) = (
        Image::read_png(&args.first)?,
        Image::read_png(&args.second)?,
    );
    if (a.width, a.height) != (b.width, b.height) {
        return Err(Error::Usage(format!(
            "the pictures differ in size: {}x{} and {}x{}",
            a.width, a.height, b.width, b.height
        )));
    }
    let differing = a.differing_pixels(&b);
    let total = a.width as usize * a.height as usize;
    if let Some(path) = &args.output {
        a.difference(&b).write_png(path)?;
        wrote(format_args!("{}", path.display()));
    }
    let percent = differing as f64 * 100.0 / total as f64;
    write_text(&format!(
        "{differing} of {total} pixels differ ({percent:.3}%)\n"
    ))?;
    Ok(if differing > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn skin_demo(args: SkinDemoArgs) -> Result<ExitCode, Error> {
    match &args.output {
        Some(path) => {
            check_output(path, &["png"])?;
            let (width, height) = args.size;
            bvhview::render::skin_demo::render(args.bend, width, height)?.write_png(path)?;
            wrote(format_args!("{} ({width}x{height})", path.display()));
        }
        None => bvhview::render::window::run_skin_demo(args.bend)?,
    }
    Ok(ExitCode::SUCCESS)
}

fn convert(args: ConvertArgs) -> Result<ExitCode, Error> {
    check_output(&args.output, &["bvh", "glb", "gltf"])?;
    if args.skin && input::extension(&args.output) == "bvh" {
        return Err(Error::Usage(
            "--skin needs a glTF output (.glb or .gltf); a BVH file has no mesh".into(),
        ));
    }
    if let Some(fps) = args.fps {
        bvhview::limits::fps(fps, false)?;
    }
    if let Some(factor) = args.scale
        && !(factor.is_finite() && factor != 0.0)
    {
        return Err(Error::Usage(format!(
            "--scale {factor}: expected a finite number other than 0"
        )));
    }
    let mut loaded = load(&args.input, &args.source)?;
    // The edits, in this order: trim, resample, scale, up axis, mirror, in place, ground.
    if let Some(frames) = &args.frames {
        let range = export::parse_frames(frames, loaded.motion.frame_count())?;
        loaded.motion = bvhview::edit::trim(&loaded.motion, range);
    }
    if let Some(fps) = args.fps {
        loaded.motion = bvhview::edit::resample(&loaded.skeleton, &loaded.motion, fps)?;
    }
    if let Some(factor) = args.scale {
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::scale(&loaded.skeleton, &loaded.motion, factor)?;
    }
    let mut up = Up::guess(&loaded.skeleton);
    if let Some(target) = args.up {
        let target = target.into();
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::reorient(&loaded.skeleton, &loaded.motion, up, target)?;
        up = target;
    }
    if args.mirror {
        (loaded.skeleton, loaded.motion) = bvhview::edit::mirror(&loaded.skeleton, &loaded.motion);
    }
    if args.in_place {
        loaded.motion = bvhview::edit::in_place(&loaded.skeleton, &loaded.motion, up);
    }
    if args.ground {
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::ground(&loaded.skeleton, &loaded.motion, OffsetMode::Replace, up)?;
    }
    let output = &args.output;
    let container = match input::extension(output).as_str() {
        "glb" => Some(bvhview::gltf::Container::Glb),
        "gltf" => Some(bvhview::gltf::Container::Gltf),
        _ => None,
    };
    if let Some(container) = container {
        let bytes = bvhview::gltf::to_gltf(
            &loaded.skeleton,
            &loaded.motion,
            args.offset_mode.into(),
            container,
            args.skin,
        )?;
        let mut out = open_output(Some(output))?;
        let result = out.write_all(&bytes);
        finish_write(out, result, Some(output))?;
        wrote(format_args!(
            "{}: {} nodes, {} frames",
            output.display(),
            loaded.skeleton.joints.len(),
            loaded.motion.frame_count()
        ));
        return Ok(ExitCode::SUCCESS);
    }
    // BVH has no fixed bone axis: bake ASF axes into the rotation channels.
    let (skeleton, motion) = if loaded.skeleton.joints.iter().any(|j| j.axis.is_some()) {
        bvhview::edit::bake_axes(&loaded.skeleton, &loaded.motion)?
    } else {
        (loaded.skeleton, loaded.motion)
    };
    // Refused before the output is opened: a take that cannot be written leaves no file.
    bvhview::bvh::writer::check(&skeleton, &motion)?;
    let mut out = open_output(Some(output))?;
    let result = bvhview::bvh::writer::write_bvh(&mut out, &skeleton, &motion);
    finish_write(out, result, Some(output))?;
    for (name, written) in bvhview::bvh::writer::renamed(&skeleton) {
        eprintln!(
            "bvhview: {}: joint {name:?} written as {written:?} (a BVH name holds no \
             whitespace or braces)",
            output.display()
        );
    }
    wrote(format_args!(
        "{}: {} joints, {} frames",
        output.display(),
        skeleton.joints.iter().filter(|j| !j.end_site).count(),
        motion.frame_count()
    ));
    Ok(ExitCode::SUCCESS)
}
