//! `bvhview convert`: a take, edited, written as BVH or glTF.

use super::*;

#[derive(Args)]
pub(crate) struct ConvertArgs {
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
    /// Turn the take to this up axis from its own, as `info` guesses it (fourth).
    #[arg(long, value_enum)]
    up: Option<UpArg>,
    /// The mirror image across the body's middle (fifth): left and right joints swap their
    /// motion, every name and the skeleton's layout kept.
    #[arg(long)]
    mirror: bool,
    /// The mirror image made by renaming instead: every joint reflected where it is, Left and
    /// Right exchanged in the names (the same world positions by name, another joint order).
    #[arg(long, conflicts_with = "mirror")]
    mirror_rename: bool,
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

pub(crate) fn run(args: ConvertArgs) -> Result<ExitCode, Error> {
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
    // The take's up axis as guessed from its motion (scaling changes no axis).
    let mut up = loaded.stance(OffsetMode::Replace).up;
    if let Some(target) = args.up {
        let target = target.into();
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::reorient(&loaded.skeleton, &loaded.motion, up, target)?;
        up = target;
    }
    if args.mirror || args.mirror_rename {
        let options = bvhview::edit::MirrorOptions {
            rename: args.mirror_rename,
            ..Default::default()
        };
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::mirror(&loaded.skeleton, &loaded.motion, &options)?;
    }
    if args.in_place {
        loaded.motion = bvhview::edit::in_place(&loaded.skeleton, &loaded.motion, up);
    }
    if args.ground {
        (loaded.skeleton, loaded.motion) =
            bvhview::edit::ground(&loaded.skeleton, &loaded.motion, OffsetMode::Replace, up)?;
    }
    write_take(
        &args.output,
        loaded.skeleton,
        loaded.motion,
        args.offset_mode.into(),
        args.skin,
    )
}
