//! `bvhview positions`: the world position of every joint and End Site, per frame, as CSV or JSON.

use super::{
    OffsetModeArg, Source, check_output, finish_write, is_stdio, load, open_output, wrote,
};
use crate::io::error::Error;
use crate::model::pose::OffsetMode;
use crate::positions::{PositionsFormat, PositionsOptions};
use crate::take;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// `--format` of `positions`.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
enum FormatArg {
    /// `frame,joint,x,y,z`, one joint per line.
    #[default]
    Csv,
    /// `{"frame_time":…,"joints":[…],"frames":[{"frame":0,"positions":[[x,y,z],…]},…]}`.
    Json,
}

impl From<FormatArg> for PositionsFormat {
    fn from(arg: FormatArg) -> PositionsFormat {
        match arg {
            FormatArg::Csv => PositionsFormat::Csv,
            FormatArg::Json => PositionsFormat::Json,
        }
    }
}

#[derive(Args)]
pub(crate) struct PositionsArgs {
    /// A take: .bvh, .fbx, .gltf, .glb or AMASS .npz, or an .asf skeleton (its motion with --motion).
    file: PathBuf,
    #[command(flatten)]
    source: Source,
    /// The axis the take stands along, over the guess (as `info --up`): positions are written
    /// in the file's own axes for y and z; x, -y, -z and -x turn the take to stand along y as
    /// it is read (said), so the positions come out y up.
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
    /// Frames to write: N, A..B (B excluded), A..=B, A.. or ..B (default: all).
    #[arg(long)]
    frames: Option<String>,
    /// The output format (default: JSON for an output named .json, else CSV).
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Negate z (right-handed to left-handed, as for Direct3D).
    #[arg(long)]
    left_handed: bool,
    /// Multiply every coordinate (default 1: the file's own units).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    scale: f32,
    /// The units to write in: mm, cm, m, in, ft, or metres per unit; the take's own units are
    /// what `info` reads (the factor is said on stderr, and --scale multiplies on top).
    #[arg(long, value_name = "UNITS", value_parser = super::convert::parse_units, conflicts_with = "vertices")]
    out_units: Option<crate::model::stance::Units>,
    /// How position channels combine with OFFSET.
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// Output file (`-` or none: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Put the take on a character (.fbx, .glb or .gltf with a skinned mesh): retargeted onto
    /// its skeleton by role; with --vertices, its skinned mesh is written.
    #[arg(long, value_name = "CHAR")]
    character: Option<PathBuf>,
    #[command(flatten)]
    insisting: super::character::Insisting,
    /// Write the joints as a pose estimator's keypoints of this layout (h36m17, coco17,
    /// mediapipe33, body25, smpl24): an .npy of frames × points × 4 (x, y, z in metres, and a
    /// confidence: 1, or 0 with NaN where the skeleton has no such point, as a face's), each
    /// point at the joint of its role; `solve --layout` reads it back.
    #[arg(long, value_name = "LAYOUT", conflicts_with_all = ["vertices", "character"])]
    layout: Option<String>,
    /// With --character, write the skinned mesh's vertices instead of the joints: CSV
    /// `frame,vertex,x,y,z`, JSON (with the triangles), or an .npy array (frames, vertices, 3)
    /// of float32, in the character's units (metres).
    #[arg(long, requires = "character")]
    vertices: bool,
}

pub(crate) fn run(mut args: PositionsArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    // `-o -` is standard output, as no -o is.
    if args.output.as_deref().is_some_and(is_stdio) {
        args.output = None;
    }
    if let Some(output) = &args.output {
        let formats: &[&str] = if args.layout.is_some() {
            &["npy"]
        } else if args.vertices {
            &["csv", "json", "npy"]
        } else {
            &["csv", "json"]
        };
        check_output(output, formats)?;
    }
    let (loaded, character) = load_dressed(&args)?;
    if args.vertices && (args.left_handed || args.scale != 1.0 || args.format.is_some()) {
        return Err(Error::usage(
            "--vertices writes the character's units as they are, its format told by -o              (.csv, .json, .npy): --left-handed, --scale and --format are for joints",
        ));
    }
    let available = loaded.motion.frame_count().max(1);
    if loaded.motion.frame_count() == 0 {
        eprintln!(
            "bvhview: {}: no frames; writing the rest pose",
            args.file.display()
        );
    }
    let range = match &args.frames {
        Some(text) => crate::positions::parse_frames(text, available)?,
        None => 0..available,
    };
    let mut scale = args.scale;
    if !(scale.is_finite() && scale != 0.0) {
        return Err(Error::usage(format!(
            "--scale {scale}: expected a finite number other than 0"
        )));
    }
    if let Some(units) = args.out_units {
        let own = loaded.stance(OffsetMode::from(args.offset_mode)).units;
        let factor = (f64::from(own.metres) / f64::from(units.metres)) as f32;
        super::note(format_args!(
            "{}: {} written in {} (×{factor})",
            args.file.display(),
            own.name,
            units.name
        ));
        scale *= factor;
    }
    let offset_mode = OffsetMode::from(args.offset_mode).for_take(character.is_some());
    if let Some(warning) =
        crate::info::offset_mode_warning(&loaded.skeleton, &loaded.motion, offset_mode)
    {
        eprintln!(
            "bvhview: {}: warning: {}",
            args.file.display(),
            warning.spelled(&super::Flags)
        );
    }
    if let Some(character) = character.as_deref().filter(|_| args.vertices) {
        return write_vertices(&args, character, &loaded, range);
    }
    if let Some(layout) = &args.layout {
        return write_keypoints(&args, layout, &loaded, range);
    }
    write_joints(&args, &loaded, range, offset_mode, scale)
}

/// The take of `args.file`, and the character it is put on with `--character` (the take then
/// retargeted onto the character's skeleton).
fn load_dressed(
    args: &PositionsArgs,
) -> Result<
    (
        take::Take,
        Option<std::sync::Arc<crate::character::Character>>,
    ),
    Error,
> {
    let loaded = load(&args.file, &args.source)?;
    let character = match &args.character {
        Some(path) => super::character::load_all(std::slice::from_ref(path), 1, &args.source)?
            .pop()
            .flatten(),
        None => None,
    };
    Ok(match &character {
        Some(character) => {
            let (loaded, worn) =
                super::character::dress(character, &loaded, &args.file, args.insisting.insist())?;
            (loaded, Some(worn))
        }
        None => (loaded, character),
    })
}

/// `--vertices`: the character's skinned vertices in the frames of `range`, as CSV, JSON or
/// `.npy` by -o's extension; then what was written.
/// `--layout`: the joints as a layout's keypoints, an .npy of frames × points × 4 (float32).
fn write_keypoints(
    args: &PositionsArgs,
    layout: &str,
    loaded: &take::Take,
    range: std::ops::Range<usize>,
) -> Result<ExitCode, Error> {
    use crate::solve::layouts::{Layout, of_take};
    let layout =
        Layout::parse(layout).map_err(|why| Error::usage(format!("--layout {layout}: {why}")))?;
    let Some(output) = args.output.as_deref() else {
        return Err(Error::usage(
            "--layout: an .npy array goes to a file (-o OUT.npy)",
        ));
    };
    let mode = OffsetMode::from(args.offset_mode);
    let metres = f64::from(loaded.stance(mode).units.metres);
    let mut trimmed = loaded.trim(range.clone());
    trimmed.offset_mode = mode;
    let keypoints = of_take(&trimmed, layout, metres)?;
    let count = layout.points().len();
    let frames = keypoints.points.len() / count;
    let mut bytes = crate::io::npy::header("<f4", &[frames, count, 4], 0);
    for (point, confidence) in keypoints.points.iter().zip(&keypoints.confidence) {
        for value in [point.x, point.y, point.z, *confidence] {
            bytes.extend((value as f32).to_le_bytes());
        }
    }
    let mut out = open_output(Some(output))?;
    let result = out.write_all(&bytes).and_then(|()| out.flush());
    finish_write(out, result, Some(output))?;
    let absent = keypoints.confidence[..count]
        .iter()
        .filter(|c| **c == 0.0)
        .count();
    wrote(format_args!(
        "{}: {} × {count} {} keypoints{}",
        output.display(),
        crate::io::error::counted(frames, "frame"),
        layout.label(),
        match absent {
            0 => String::new(),
            n => format!(" ({n} the skeleton has not: NaN, confidence 0)"),
        }
    ));
    Ok(ExitCode::SUCCESS)
}

fn write_vertices(
    args: &PositionsArgs,
    character: &crate::character::Character,
    loaded: &take::Take,
    range: std::ops::Range<usize>,
) -> Result<ExitCode, Error> {
    let format = match args.output.as_deref().map(take::extension).as_deref() {
        Some("json") => crate::character::VertexFormat::Json,
        Some("npy") => crate::character::VertexFormat::Npy,
        _ => crate::character::VertexFormat::Csv,
    };
    let output = args.output.as_deref();
    if format == crate::character::VertexFormat::Npy && output.is_none() {
        return Err(Error::usage(
            "--vertices: an .npy array goes to a file (-o OUT.npy)",
        ));
    }
    let mut out = open_output(output)?;
    let result = crate::character::write_vertices(
        &mut out,
        character,
        &loaded.skeleton,
        &loaded.motion,
        range.clone(),
        format,
    )
    .and_then(|()| out.flush());
    finish_write(out, result, output)?;
    if let Some(path) = output {
        wrote(format_args!(
            "{}: {} × {}",
            path.display(),
            crate::io::error::counted(range.len(), "frame"),
            match character.mesh.vertex_count() {
                1 => "1 vertex".to_string(),
                n => format!("{n} vertices"),
            }
        ));
    }
    Ok(ExitCode::SUCCESS)
}

/// The world position of every joint and End Site in the frames of `range`, as CSV or JSON,
/// times `scale`; then what was written.
fn write_joints(
    args: &PositionsArgs,
    loaded: &take::Take,
    range: std::ops::Range<usize>,
    offset_mode: OffsetMode,
    scale: f32,
) -> Result<ExitCode, Error> {
    let options = PositionsOptions {
        format: args
            .format
            .unwrap_or_else(|| match args.output.as_deref().map(take::extension) {
                Some(extension) if extension == "json" => FormatArg::Json,
                _ => FormatArg::Csv,
            })
            .into(),
        offset_mode,
        left_handed: args.left_handed,
        scale,
    };
    let output = args.output.as_deref();
    let mut out = open_output(output)?;
    let result = crate::positions::write_positions(
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
        let points = crate::positions::export_points(&loaded.skeleton).len();
        wrote(format_args!(
            "{}: {} × {}",
            path.display(),
            crate::io::error::counted(frames, "frame"),
            crate::io::error::counted(points, "point")
        ));
    }
    Ok(ExitCode::SUCCESS)
}
