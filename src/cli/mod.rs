//! The command line's shared plumbing: the options every command that reads a take has, loading
//! with them, where a command writes and how it says so. Each command lives in its own file,
//! its arguments beside its body (`print.rs`, `info.rs`, …); `command.rs` builds the clap
//! command and dispatches. It lives in the library so the plumbing it shares with the readers
//! stays `pub(crate)`; `src/main.rs` only calls [`main`].

mod command;
pub use command::main;

pub(crate) mod character;
pub(crate) mod convert;
pub(crate) mod dataset;
pub(crate) mod diff;
pub(crate) mod generate;
pub(crate) mod info;
pub(crate) mod metrics;
pub(crate) mod positions;
pub(crate) mod print;
pub(crate) mod retarget;
pub(crate) mod skin_demo;
pub(crate) mod snapshot;
pub(crate) mod solve;
pub(crate) mod trace;
pub(crate) mod viewer;

pub(crate) use crate::io::error::Error;
use crate::io::message::{Argument, Spelling};
pub(crate) use crate::model::pose::{OffsetMode, Up};
pub(crate) use crate::render::Look;
pub(crate) use crate::render::draw::Style;
pub(crate) use crate::take::{self, Take};
pub(crate) use clap::{Args, ValueEnum};
pub(crate) use std::io::{self, BufWriter, Write};
pub(crate) use std::path::{Path, PathBuf};
pub(crate) use std::process::ExitCode;

/// `--offset-mode`: how a joint's position channels combine with its OFFSET.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub(crate) enum OffsetModeArg {
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
pub(crate) enum StyleArg {
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
pub(crate) enum LookArg {
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

/// Options that come with any input file.
#[derive(Args, Clone, Debug)]
pub(crate) struct Source {
    /// The AMC motion for an ASF skeleton (without it: the rest pose).
    #[arg(long, value_name = "TAKE.amc")]
    motion: Option<PathBuf>,
    /// The take of an FBX or glTF file that holds several, by name or by its index in
    /// `bvhview info` (default: the first).
    #[arg(long, value_name = "NAME|INDEX")]
    take: Option<String>,
    /// The format of a take read from standard input (`-`): bvh, fbx, gltf or glb (default:
    /// told by its first bytes).
    #[arg(long, value_name = "FORMAT", value_parser = ["bvh", "fbx", "gltf", "glb"])]
    from: Option<String>,
    /// Seconds per frame, overriding the file (AMC files have none: default 1/120).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    frame_time: Option<f64>,
    /// Refuse input files larger than this (bytes; K, M, G suffixes), before reading them.
    #[arg(long, value_name = "SIZE", default_value = "8G", value_parser = parse_max_size)]
    max_size: u64,
    /// The units the take's lengths are in, over the guess (`info` reads them): mm, cm, m, in,
    /// ft, or metres per unit. Every measure in metres takes them (floor, framing, heights,
    /// retarget scale).
    #[arg(long, value_name = "UNITS", value_parser = convert::parse_units)]
    units: Option<crate::model::stance::Units>,
    /// The axis the take stands along, over the guess: set from each command's own `--up`
    /// (the window's and `snapshot`'s set it only for an axis the take is turned from, x, -x,
    /// -y or -z; y and z are their view's).
    #[arg(skip)]
    up: Option<crate::model::pose::UpAxis>,
    /// The SMPL-family model file an AMASS take's body is read with (an .npz, or a folder with
    /// one per gender): the joints of the file's betas, not bvhview's built-in figure's
    /// lengths; as --character, its mesh.
    #[arg(long, value_name = "MODEL.npz|DIR")]
    body_model: Option<PathBuf>,
    /// The shape of a body model given as --character: its first betas, comma-separated (the
    /// rest zero). Without them: the mean shape, or an AMASS take's own betas.
    #[arg(
        long,
        value_name = "B1,B2,…",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub(crate) betas: Option<Vec<f64>>,
}

impl Source {
    /// How to open a take from these flags, on `threads` threads.
    pub(crate) fn open_options(&self, threads: usize) -> take::OpenOptions {
        take::OpenOptions {
            motion: self.motion.clone(),
            take: self.take.clone(),
            frame_time: self.frame_time,
            max_size: Some(self.max_size),
            threads: Some(threads),
            units: self.units,
            up: self.up,
            body_model: self.body_model.clone(),
            ..Default::default()
        }
    }
}

/// What the article's view says of a file whose rest pose stands along z: it is drawn as
/// written, as the article draws every file, and what stands it up.
const LYING_HINT: &str = "stands along z in its motion: drawn as written, as the article \
     draws every file (--up z or --look studio stands it up; V in the window)";

/// How the command line writes the library's arguments: `--max-size 8G`, and an opening of an
/// ASF skeleton with its motion as `bvhview COMMAND SKELETON.asf --motion WALK.amc`.
#[derive(Debug)]
pub(crate) struct Flags;

impl Spelling for Flags {
    fn argument(&self, argument: &Argument) -> String {
        // The one argument whose flag is not its name: a format is named by what it is read
        // from (`--from bvh`), beside `--to` for what is written.
        let flag = match argument.name {
            "format" => "from".to_string(),
            name => name.replace('_', "-"),
        };
        match &argument.value {
            Some(value) => format!("--{flag} {value}"),
            None => format!("--{flag}"),
        }
    }

    fn opening(&self, file: &str, with: &Argument) -> String {
        format!("bvhview COMMAND {file} {}", self.argument(with))
    }
}

/// An error as the command line says it: each argument by its flag (`--frame-time 0: …`).
pub(crate) fn said(error: &Error) -> String {
    error.spelled(&Flags)
}

/// `8G` → 8 GiB; plain numbers are bytes.
pub(crate) fn parse_max_size(text: &str) -> Result<u64, String> {
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

/// How a drawing command looks at the skeleton.
#[derive(Args, Clone, Copy, Debug)]
pub(crate) struct View {
    /// Camera angle around the Y axis in radians (default: the article's 10; 1.5708 when
    /// several files stand side by side along x).
    #[arg(long, allow_negative_numbers = true)]
    angle: Option<f32>,
    /// Spheres (the article's), the stick figure, or both (default: spheres; both in the
    /// studio look).
    #[arg(long, value_enum)]
    style: Option<StyleArg>,
    /// Frame the figure instead of using the article's fixed camera: the pose shown (`--fit`,
    /// `--fit=pose`) or every frame of the take (`--fit=take`).
    #[arg(long, value_enum, num_args = 0..=1, default_missing_value = "pose", require_equals = true)]
    fit: Option<FitArg>,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// The file's up axis (default: guessed from the motion in a framed or studio view, as
    /// written in the article's view; `info` prints the guess).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<UpArg>,
    /// With several files, keep each at its true size (lengths converted by the units guessed
    /// for each); by default they are scaled to the first one's height.
    #[arg(long)]
    true_scale: bool,
}

/// `--onto-units`, `--onto-up`: what the user says of the skeleton a take is put on.
#[derive(Args, Clone, Debug, Default)]
pub(crate) struct OntoStated {
    /// The units the target skeleton's lengths are in, over the guess (as `--units` says a
    /// take's): mm, cm, m, in, ft, or metres per unit. `--out-units` and the feet's thresholds
    /// take them.
    #[arg(long, value_name = "UNITS", value_parser = convert::parse_units, requires = "onto")]
    pub(crate) onto_units: Option<crate::model::stance::Units>,
    /// The axis the target skeleton stands along, over the guess (as `--up` says a take's):
    /// y, z, x, -y, -z or -x (the last four turn it to stand along y as it is read, so the
    /// take is written on the turned skeleton, y up).
    #[arg(long, value_enum, allow_hyphen_values = true, requires = "onto")]
    pub(crate) onto_up: Option<UpArg>,
}

impl OntoStated {
    /// Refuses them for a body model's own figure (`--body-model` with an SMPL-family
    /// target), whose units (metres) and axis (y) the model file says.
    pub(crate) fn refused_with_body_model(&self) -> Result<(), Error> {
        if self.onto_units.is_some() || self.onto_up.is_some() {
            return Err(Error::usage(
                "--onto-units and --onto-up say what a target file is; with --body-model the \
                 target is the model's own figure, in metres and y up as its file says",
            ));
        }
        Ok(())
    }

    /// The target named `onto` with what these say of it.
    pub(crate) fn target(
        &self,
        onto: &str,
        max_size: u64,
    ) -> Result<crate::retarget::Target, Error> {
        let mut options = take::OpenOptions::new().max_size(max_size);
        if let Some(units) = self.onto_units {
            options = options.units(units);
        }
        if let Some(up) = self.onto_up {
            options = options.up(crate::model::pose::UpAxis::from(up));
        }
        let target = crate::retarget::Target::open(onto, &options)?;
        // Said once, as a take's are (a target turned to stand along y, for one).
        for warning in &target.warnings {
            eprintln!("bvhview: {onto}: warning: {}", warning.spelled(&Flags));
        }
        Ok(target)
    }
}

/// `--fit`: what the framed camera keeps in the picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum FitArg {
    /// The pose shown, followed from frame to frame.
    Pose,
    /// Every joint of every frame: the take's whole path, from a camera that stays put.
    Take,
}

/// The style asked for, or the look's own: spheres in the article's, both in the studio's.
pub(crate) fn style_for(style: Option<StyleArg>, look: LookArg) -> Style {
    match (style, look) {
        (Some(style), _) => style.into(),
        (None, LookArg::Article) => Style::Points,
        (None, LookArg::Studio) => Style::Both,
    }
}

/// `--up`: the axis a file stands along.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum UpArg {
    /// Y up, as BVH files usually are (the article draws every file this way).
    #[value(alias = "+y")]
    Y,
    /// Z up (MakeHuman's files, for example).
    #[value(alias = "+z")]
    Z,
    /// X up: the take is turned to stand along y as it is read (said).
    #[value(alias = "+x")]
    X,
    /// −Y up (a camera's image axes): turned to y as it is read (said).
    #[value(name = "-y")]
    NegY,
    /// −Z up: turned to y as it is read (said).
    #[value(name = "-z")]
    NegZ,
    /// −X up: turned to y as it is read (said).
    #[value(name = "-x")]
    NegX,
}

impl From<UpArg> for crate::model::pose::UpAxis {
    fn from(arg: UpArg) -> crate::model::pose::UpAxis {
        use crate::model::pose::UpAxis;
        match arg {
            UpArg::Y => UpAxis::Y,
            UpArg::Z => UpAxis::Z,
            UpArg::X => UpAxis::X,
            UpArg::NegY => UpAxis::NegY,
            UpArg::NegZ => UpAxis::NegZ,
            UpArg::NegX => UpAxis::NegX,
        }
    }
}

impl UpArg {
    /// The axis a view stands the take along once it is read: y or z as given; y for the
    /// four a take is turned from as it is read ([`UpArg::turned_when_read`]).
    pub(crate) fn view(self) -> Up {
        crate::model::pose::UpAxis::from(self)
            .standing()
            .unwrap_or(Up::Y)
    }

    /// The axis a view's `--up` has the take turned from as it is read: x, -x, -y or -z
    /// (y and z are drawn by turning the view, the take kept as written).
    pub(crate) fn turned_when_read(up: Option<UpArg>) -> Option<crate::model::pose::UpAxis> {
        up.map(crate::model::pose::UpAxis::from)
            .filter(|axis| axis.standing().is_none())
    }
}

/// The up axis to draw `loaded` with: `--up` if given. Otherwise the article's view draws every
/// file as written, Y up, as the article's program does; a view that frames the take (`--fit`,
/// `--look studio`: `framed`) stands it up by the guess from its motion. Either way a file that
/// stands along z is said once on stderr, with what stands it up or draws it as written.
pub(crate) fn resolve_up(
    arg: Option<UpArg>,
    stance: &crate::model::stance::Stance,
    name: &str,
    framed: bool,
) -> Up {
    if let Some(arg) = arg {
        return arg.view();
    }
    if stance.up == Up::Z {
        if framed {
            eprintln!(
                "bvhview: {name}: stands along z in its motion: drawn Z-up (--up y draws it as \
                 written)"
            );
        } else {
            eprintln!("bvhview: {name}: {}", LYING_HINT);
        }
    }
    if framed { stance.up } else { Up::Y }
}

/// Says once on stderr when a file looks written for the other offset mode.
pub(crate) fn warn_offset_mode(loaded: &Take, mode: OffsetMode, name: &str) {
    if let Some(warning) = crate::info::offset_mode_warning(&loaded.skeleton, &loaded.motion, mode)
    {
        eprintln!("bvhview: {name}: warning: {}", warning.spelled(&Flags));
    }
}

/// `600x400` → (600, 400).
pub(crate) fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT such as 600x600, found '{text}'");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    crate::limits::picture_size(w, h).map_err(|e| said(&e))?;
    Ok((w, h))
}

/// `-q`: no line about what was written.
pub(crate) static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The one line on stderr that says what a command wrote.
pub(crate) fn wrote(what: std::fmt::Arguments) {
    if !QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("bvhview: wrote {what}");
    }
}

/// A line on stderr that `-q` silences: what a folder walk or a compile skipped.
pub(crate) fn note(line: std::fmt::Arguments) {
    if !QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("{line}");
    }
}

/// Refuses an output whose extension is not one the command writes, before any work.
/// A FIFO, a character device or a path under /dev or /proc (`/dev/stdout`, `/dev/fd/3`) is
/// taken whatever its name: it is written to where it is.
pub(crate) fn check_output(path: &Path, formats: &[&str]) -> Result<(), Error> {
    let extension = take::extension(path);
    if crate::io::output::written_in_place(path) || formats.contains(&extension.as_str()) {
        return Ok(());
    }
    let list: Vec<String> = formats.iter().map(|f| format!(".{f}")).collect();
    Err(Error::usage(format!(
        "-o {}: this command writes {}",
        path.display(),
        list.join(" or ")
    )))
}

/// A progress bar on stderr while a long write runs, when stderr is a terminal.
pub(crate) struct Progress {
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

    /// Clears the bar: at the end, and before a line is said under it.
    fn done(&self) {
        if self.on_terminal {
            eprint!("\r\x1b[2K");
        }
    }
}

/// Loads a file (with its motion) and reports its warnings on stderr.
pub(crate) fn load(path: &Path, source: &Source) -> Result<Take, Error> {
    let loaded = load_quietly(path, source)?;
    for warning in &loaded.warnings {
        eprintln!(
            "bvhview: {}: warning: {}",
            path.display(),
            warning.spelled(&Flags)
        );
    }
    Ok(loaded)
}

/// Loads a file (with its motion), its warnings left to the caller.
pub(crate) fn load_quietly(path: &Path, source: &Source) -> Result<Take, Error> {
    load_with_threads(path, source, crate::io::parallel::cores())
}

/// The takes of a list of files (the window, `snapshot`), each with its motion: an `.amc` right
/// after an `.asf` is that skeleton's motion, so ASF/AMC takes stand beside others
/// (`a.asf a.amc b.bvh`); `--motion` still gives the motion of one ASF alone.
pub(crate) fn paired_takes(
    files: &[PathBuf],
    source: &Source,
) -> Result<Vec<(PathBuf, Option<PathBuf>)>, Error> {
    let is = |path: &Path, extension: &str| take::extension(path) == extension;
    let mut takes = Vec::with_capacity(files.len());
    let mut k = 0;
    while k < files.len() {
        let path = &files[k];
        if is(path, "asf") && files.get(k + 1).is_some_and(|next| is(next, "amc")) {
            if source.motion.is_some() {
                return Err(Error::usage(format!(
                    "{}: give its motion once, as the .amc after it or with --motion",
                    path.display()
                )));
            }
            takes.push((path.clone(), Some(files[k + 1].clone())));
            k += 2;
        } else {
            takes.push((path.clone(), source.motion.clone()));
            k += 1;
        }
    }
    if takes.len() > 1 && source.motion.is_some() {
        return Err(Error::usage(
            "--motion goes with one ASF skeleton; to show ASF/AMC takes beside others, give \
             each .amc right after its .asf (a.asf a.amc b.bvh)",
        ));
    }
    Ok(takes)
}

/// Whether a path names standard input or output: `-`, as Unix tools take it.
pub(crate) fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// [`load_quietly`] on `threads` threads; `-` reads the take from standard input (at most
/// `--max-size` bytes) in the format `--from` names or its first bytes tell.
pub(crate) fn load_with_threads(
    path: &Path,
    source: &Source,
    threads: usize,
) -> Result<Take, Error> {
    if !is_stdio(path) {
        if source.from.is_some() {
            return Err(Error::usage(format!(
                "--from is for standard input (-); {} is named by its extension",
                path.display()
            )));
        }
        return take::load_take(path, &source.open_options(threads));
    }
    if let Some(motion) = &source.motion {
        return Err(Error::usage(format!(
            "--motion {}: an ASF skeleton is read from a file, not standard input",
            motion.display()
        )));
    }
    use std::io::Read as _;
    let mut bytes = Vec::new();
    let limit = source.max_size;
    crate::io::read::Bounded::new(io::stdin().lock(), limit)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(Path::new("<stdin>"), e))?;
    let mut options = source.open_options(threads);
    if let Some(from) = &source.from {
        options.format = Some(take::Format::of_extension(from).ok_or_else(|| {
            Error::usage(format!(
                "--from {from}: bvhview reads bvh, fbx, gltf or glb from standard input"
            ))
        })?);
    }
    options.open_bytes(&bytes, "<stdin>")
}

/// The named file, or the bundled walk; with the name to show.
pub(crate) fn load_or_default(
    path: Option<&Path>,
    source: &Source,
) -> Result<(String, Take), Error> {
    match path {
        Some(path) => Ok((path.display().to_string(), load(path, source)?)),
        None => {
            if source.motion.is_some() {
                return Err(Error::usage("--motion needs an ASF skeleton file"));
            }
            if source.take.is_some() {
                return Err(Error::usage("--take needs an FBX or glTF file"));
            }
            crate::limits::frame_time_option(source.frame_time)?;
            let mut walk = take::Take::bundled()?;
            if let Some(time) = source.frame_time {
                walk.motion.frame_time = time;
            }
            // What the user says of it, as of any take.
            walk.given(source.units, source.up)?;
            Ok((crate::DEFAULT_MOTION_NAME.to_string(), walk))
        }
    }
}

/// Where a command writes: standard output, or a file that appears whole or not at all. It may
/// be written from any thread.
pub(crate) enum Output {
    Stdout(BufWriter<io::Stdout>),
    File(crate::io::output::AtomicFile),
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
pub(crate) fn open_output(path: Option<&Path>) -> Result<Output, Error> {
    Ok(match path {
        Some(path) => Output::File(crate::io::output::AtomicFile::create(path)?),
        None => Output::Stdout(BufWriter::new(io::stdout())),
    })
}

/// Ends a write: a file takes its name only if everything was written; a write error on stdout
/// that is a closed pipe (`| head`) ends quietly; others are reported.
pub(crate) fn finish_write(
    out: Output,
    result: io::Result<()>,
    path: Option<&Path>,
) -> Result<(), Error> {
    let result = match out {
        Output::Stdout(mut out) => result.and_then(|()| out.flush()),
        // Dropped uncommitted on an error: the temporary file goes, nothing takes the name.
        Output::File(file) => return written(result, path).and_then(|()| file.commit()),
    };
    written(result, path)
}

/// The error a failed write is reported as.
pub(crate) fn written(result: io::Result<()>, path: Option<&Path>) -> Result<(), Error> {
    match result {
        Ok(()) => Ok(()),
        Err(e) if path.is_none() && e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) if crate::positions::not_finite(&e).is_some() => Err(Error::usage(e.to_string())),
        Err(e) => Err(Error::output(path.unwrap_or(Path::new("<stdout>")), e)),
    }
}

pub(crate) fn write_text(text: &str) -> Result<(), Error> {
    let mut out = open_output(None)?;
    let result = out.write_all(text.as_bytes());
    finish_write(out, result, None)
}

/// A path's file name, for titles and the HUD.
pub(crate) fn short_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// The formats a take is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum TakeFormat {
    /// BVH text.
    Bvh,
    /// glTF 2.0, binary.
    Glb,
    /// glTF 2.0, JSON text with the data inline.
    Gltf,
    /// FBX 7.4, binary.
    Fbx,
    /// AMASS's `.npz`: SMPL-family parameters of a take on a SMPL-family skeleton.
    #[value(name = "npz")]
    Amass,
}

impl TakeFormat {
    /// By a file's extension: `.glb`, `.gltf`, else BVH.
    pub(crate) fn of(path: &Path) -> TakeFormat {
        match take::extension(path).as_str() {
            "glb" => TakeFormat::Glb,
            "gltf" => TakeFormat::Gltf,
            "fbx" => TakeFormat::Fbx,
            "npz" => TakeFormat::Amass,
            _ => TakeFormat::Bvh,
        }
    }

    /// The extension its files have.
    pub(crate) fn extension(self) -> &'static str {
        match self {
            TakeFormat::Bvh => "bvh",
            TakeFormat::Glb => "glb",
            TakeFormat::Gltf => "gltf",
            TakeFormat::Fbx => "fbx",
            TakeFormat::Amass => "npz",
        }
    }
}

/// What an FBX file says of the take beyond its joints: the take's name, and the units its
/// file stated (an ASF's), which the FBX's units are worked out from.
pub(crate) struct TakeLabel {
    pub(crate) name: String,
    // Read by the FBX writer only.
    #[cfg_attr(not(feature = "fbx"), allow(dead_code))]
    pub(crate) stated_units: Option<crate::model::stance::Units>,
    /// The units an FBX file is written in (`--out-units`; default centimetres).
    #[cfg_attr(not(feature = "fbx"), allow(dead_code))]
    pub(crate) out_units: Option<crate::model::stance::Units>,
    /// The SMPL-family body the take holds (an AMASS file's betas and gender).
    pub(crate) body: Option<crate::smpl::Body>,
    /// The up axis the user gave (`--up`, `--onto-up`): the FBX and AMASS writers turn the take
    /// from it, not from the guess.
    pub(crate) stated_up: Option<Up>,
}

impl TakeLabel {
    /// `take`'s name in its file (or its file's), and its stated units.
    pub(crate) fn of(take: &Take) -> TakeLabel {
        TakeLabel {
            name: take.take_label(),
            stated_units: take.stated_units,
            out_units: None,
            body: take.body.clone(),
            stated_up: take.stated_up,
        }
    }

    /// `skeleton` and `motion` as the take this label names: its name (and take name), its
    /// stated units, position channels meeting the OFFSET by `mode`.
    pub(crate) fn take(
        &self,
        skeleton: crate::Skeleton,
        motion: crate::Motion,
        mode: OffsetMode,
    ) -> Take {
        let mut take = Take::new(skeleton, motion, self.name.clone());
        take.offset_mode = mode;
        take.take_name = Some(self.name.clone());
        take.stated_units = self.stated_units;
        take.stated_up = self.stated_up;
        take.body = self.body.clone();
        take
    }

    /// A take made by a command, named after the file it goes to.
    pub(crate) fn output(path: &Path) -> TakeLabel {
        TakeLabel {
            name: stem_of(path),
            stated_units: None,
            out_units: None,
            body: None,
            stated_up: None,
        }
    }
}

/// `take` in `units` (`--out-units`), scaled from its own (as its stance reads them), which it
/// then states; said on stderr under `name`.
pub(crate) fn in_units(
    name: &str,
    mut take: Take,
    units: crate::model::stance::Units,
) -> Result<Take, Error> {
    let own = take.stance(OffsetMode::Replace);
    let factor = (f64::from(own.units.metres) / f64::from(units.metres)) as f32;
    if factor != 1.0 {
        (take.skeleton, take.motion) = crate::edit::scale(&take.skeleton, &take.motion, factor)?;
    }
    note(format_args!(
        "{name}: {} ({}) written in {} (×{factor})",
        own.units.name,
        own.units_sureness.word(),
        units.name,
    ));
    take.stated_units = Some(units);
    Ok(take)
}

/// What an edit (`--lock-feet`, `--smooth`) did to a take, in `bvhview metrics`' figures: one
/// line, before → after; nothing for a take the metrics cannot measure (no two feet).
pub(crate) fn effect(
    what: &str,
    skeleton: &crate::Skeleton,
    before: &crate::Motion,
    after: &crate::Motion,
    like: &Take,
) -> Option<String> {
    let measured = |motion: &crate::Motion| {
        let take = like.edited(skeleton.clone(), motion.clone(), true);
        let figure = crate::metrics::figure_of_take(&take).ok()?;
        crate::metrics::measure(&figure, &crate::metrics::Thresholds::default()).ok()
    };
    // Nothing to say of an edit that changed nothing, or of one frame (no motion to measure).
    if before == after || before.frame_count() < 2 {
        return None;
    }
    let (a, b) = (measured(before)?, measured(after)?);
    Some(format!(
        "{what}: skating ratio {:.4} → {:.4}; skate {:.2} → {:.2} mm; penetrate {:.2} → {:.2} \
         mm; float {:.2} → {:.2} mm; jitter {:.1} → {:.1} m/s³ (as bvhview metrics measures)",
        a.skating_ratio,
        b.skating_ratio,
        a.skate,
        b.skate,
        a.penetrate,
        b.penetrate,
        a.float,
        b.float,
        a.jitter,
        b.jitter
    ))
}

/// A command's result (`retarget`, `solve`) written at `output`, in `units` when asked; `body`
/// the SMPL-family body it is on (betas fitted to its source), for an AMASS file.
pub(crate) fn write_result(
    output: &Path,
    skeleton: crate::Skeleton,
    motion: crate::Motion,
    units: Option<crate::model::stance::Units>,
    body: Option<crate::smpl::Body>,
    target: &crate::retarget::Target,
) -> Result<ExitCode, Error> {
    let format = TakeFormat::of(output);
    let mut take = Take::new(skeleton, motion, stem_of(output));
    // It stands as the target does, in its units: as the user said them, if at all.
    target.state_on(&mut take);
    let mut label = TakeLabel {
        body,
        // The take is named after the file it goes to, dots and all.
        name: stem_of(output),
        ..TakeLabel::of(&take)
    };
    if let Some(units) = units {
        take = in_units(&output.display().to_string(), take, units)?;
        label.stated_units = Some(units);
        label.out_units = Some(units);
    }
    write_take(
        output,
        format,
        take.skeleton,
        take.motion,
        OffsetMode::Replace,
        false,
        Some(label),
    )
}

/// A take ready to be written in a format, everything that could refuse it done first, so that a
/// take that cannot be written leaves no file: glTF and FBX encoded; BVH with its ASF axes baked
/// into the rotation channels and checked (it is written as it streams out). One take, one
/// file: `convert` and `retarget` write through here, `convert DIR` too.
pub(crate) struct Prepared {
    skeleton: crate::Skeleton,
    motion: crate::Motion,
    format: TakeFormat,
    /// The glTF or FBX file; `None` for BVH.
    encoded: Option<Vec<u8>>,
    /// FBX: the names it could not hold, `old → new`.
    fbx_renamed: Vec<String>,
}

impl Prepared {
    /// `mode` and `skin` are the glTF and FBX writers' (how position channels combine, whether
    /// a skin is generated); `label` names the take inside an FBX file.
    pub(crate) fn new(
        format: TakeFormat,
        skeleton: crate::Skeleton,
        motion: crate::Motion,
        mode: OffsetMode,
        skin: bool,
        label: &TakeLabel,
    ) -> Result<Prepared, Error> {
        let container = match format {
            TakeFormat::Glb => crate::gltf::Container::Glb,
            TakeFormat::Gltf => crate::gltf::Container::Gltf,
            TakeFormat::Fbx => return Prepared::fbx(skeleton, motion, mode, label),
            TakeFormat::Amass => return Prepared::amass(skeleton, motion, mode, label),
            TakeFormat::Bvh => {
                // BVH has no fixed bone axis: bake ASF axes into the rotation channels.
                let (skeleton, motion) =
                    crate::edit::baked_for_bvh(&skeleton, &motion)?.unwrap_or((skeleton, motion));
                crate::bvh::writer::check(&skeleton, &motion)?;
                return Ok(Prepared {
                    skeleton,
                    motion,
                    format,
                    encoded: None,
                    fbx_renamed: Vec::new(),
                });
            }
        };
        let bytes = crate::gltf::to_gltf(&skeleton, &motion, mode, container, skin)?;
        Ok(Prepared {
            skeleton,
            motion,
            format,
            encoded: Some(bytes),
            fbx_renamed: Vec::new(),
        })
    }

    /// FBX: its units and up axis as the take's stance reads them.
    #[cfg(feature = "fbx")]
    fn fbx(
        skeleton: crate::Skeleton,
        motion: crate::Motion,
        mode: OffsetMode,
        label: &TakeLabel,
    ) -> Result<Prepared, Error> {
        let take = label.take(skeleton, motion, mode);
        let written = match label.out_units {
            Some(units) => take.fbx_in(units)?,
            None => take.fbx()?,
        };
        Ok(Prepared {
            skeleton: take.skeleton,
            motion: take.motion,
            format: TakeFormat::Fbx,
            encoded: Some(written.bytes),
            fbx_renamed: written.renamed,
        })
    }

    /// AMASS's `.npz`: the take's units and up axis as its stance reads them.
    fn amass(
        skeleton: crate::Skeleton,
        motion: crate::Motion,
        mode: OffsetMode,
        label: &TakeLabel,
    ) -> Result<Prepared, Error> {
        let take = label.take(skeleton, motion, mode);
        let (bytes, said) = take.amass()?;
        for line in said {
            note(format_args!(
                "bvhview: {}: {}",
                label.name,
                line.spelled(&Flags)
            ));
        }
        Ok(Prepared {
            skeleton: take.skeleton,
            motion: take.motion,
            format: TakeFormat::Amass,
            encoded: Some(bytes),
            fbx_renamed: Vec::new(),
        })
    }

    /// FBX in a build without it: refused, naming the feature.
    #[cfg(not(feature = "fbx"))]
    fn fbx(
        _: crate::Skeleton,
        _: crate::Motion,
        _: OffsetMode,
        label: &TakeLabel,
    ) -> Result<Prepared, Error> {
        Err(crate::io::absent::without("fbx", "FBX", &label.name))
    }

    /// Writes the file.
    pub(crate) fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        match &self.encoded {
            Some(bytes) => out.write_all(bytes),
            None => crate::bvh::writer::write_bvh(out, &self.skeleton, &self.motion),
        }
    }

    /// Joints whose names a BVH file cannot hold, with the names written: (name, written).
    pub(crate) fn renamed(&self) -> Vec<(String, String)> {
        match self.format {
            TakeFormat::Bvh => crate::bvh::writer::renamed(&self.skeleton),
            _ => Vec::new(),
        }
    }

    /// Says on stderr, for the file written at `path`, which joints were renamed.
    pub(crate) fn say_renamed(&self, path: &Path) {
        for (name, written) in self.renamed() {
            eprintln!(
                "bvhview: {}: joint {name:?} written as {written:?} (a BVH name holds no \
                 whitespace or braces)",
                path.display()
            );
        }
        for renamed in &self.fbx_renamed {
            eprintln!(
                "bvhview: {}: joint {renamed} (an FBX name holds no control character)",
                path.display()
            );
        }
    }

    /// What the file holds: `31 joints, 60 frames` (BVH), `32 nodes, 60 frames` (glTF, FBX).
    pub(crate) fn summary(&self) -> String {
        let (count, what) = match self.format {
            TakeFormat::Bvh => (
                self.skeleton.joints.iter().filter(|j| !j.end_site).count(),
                "joint",
            ),
            _ => (self.skeleton.joints.len(), "node"),
        };
        format!(
            "{}, {}",
            crate::io::error::counted(count, what),
            crate::io::error::counted(self.motion.frame_count(), "frame")
        )
    }
}

/// A file's name without its extension (`Take` for `-`): what an FBX file calls the take it
/// holds when nothing else names it.
fn stem_of(output: &Path) -> String {
    output
        .file_stem()
        .filter(|_| !is_stdio(output))
        .map_or_else(|| "Take".to_string(), |s| s.to_string_lossy().into_owned())
}

/// Writes a take to `output` in `format` (as a rule the output's, [`TakeFormat::of`]), whole or
/// not at all, and says what was written: the one way a command that makes a take writes it.
/// `mode` and `skin` are the glTF writer's (how position channels combine, whether a skin is
/// generated); `label` names the take in an FBX file (else the output's name does).
pub(crate) fn write_take(
    output: &Path,
    format: TakeFormat,
    skeleton: crate::Skeleton,
    motion: crate::Motion,
    mode: OffsetMode,
    skin: bool,
    label: Option<TakeLabel>,
) -> Result<ExitCode, Error> {
    let label = label.unwrap_or_else(|| TakeLabel::output(output));
    let prepared = Prepared::new(format, skeleton, motion, mode, skin, &label)?;
    // `-o -`: standard output.
    let path = (!is_stdio(output)).then_some(output);
    let mut out = open_output(path)?;
    let result = prepared.write_to(&mut out);
    finish_write(out, result, path)?;
    prepared.say_renamed(output);
    wrote(format_args!("{}: {}", output.display(), prepared.summary()));
    Ok(ExitCode::SUCCESS)
}
