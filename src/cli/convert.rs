//! `bvhview convert`: a take, edited, written as BVH or glTF; or every take under a folder, each
//! edited and written the same way into a new folder that mirrors it.

use super::{
    OffsetModeArg, Prepared, Progress, Source, TakeFormat, UpArg, check_output, finish_write,
    is_stdio, load_with_threads, open_output, write_take, wrote,
};
use crate::info::batch::Item;
use crate::io::error::Error;
use crate::model::pose::OffsetMode;
use crate::model::pose::UpAxis;
use crate::take;
use crate::take::Take;
use clap::Args;
use std::collections::{HashMap, HashSet};
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct ConvertArgs {
    /// A take (.bvh, .fbx, .gltf, .glb, or an .asf skeleton with its motion in --motion), or a
    /// folder: every take under it (subfolders too; ASF/AMC paired as `info DIR` pairs them).
    input: PathBuf,
    #[command(flatten)]
    source: Source,
    /// Keep only these frames: N, A..B (B left out), A..=B, A.. or ..B (applied first).
    #[arg(long)]
    frames: Option<String>,
    /// Smooth jitter: a zero-phase low-pass at this cutoff in Hz on every position channel and
    /// every joint's rotation (as a quaternion path), below half the frame rate (applied right
    /// after --frames, at the take's own rate).
    #[arg(long, value_name = "HZ")]
    smooth: Option<f64>,
    /// Resample to this many frames per second: rotations slerped, positions interpolated
    /// (applied second; any ratio, such as 120 to 100).
    #[arg(long)]
    fps: Option<f64>,
    /// Multiply every length, OFFSETs and position channels (applied third).
    #[arg(long, allow_negative_numbers = true)]
    scale: Option<f32>,
    /// The axis the file stands along, over the guess, as `info --up` reads it: y, z, x, -y,
    /// -z or -x (the last four turn the take to stand along y as it is read, said). To turn
    /// the take, --out-up.
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<UpArg>,
    /// Turn the take to stand along this axis from its own (as `info` reads it, or --up says
    /// it): y or z fourth, before the edits that stand on the floor; x, -y, -z or -x last,
    /// after every other edit. FBX is written y up and AMASS z up whatever the take.
    #[arg(long, value_enum, allow_hyphen_values = true)]
    out_up: Option<UpArg>,
    /// The mirror image across the body's middle (fifth): left and right joints swap their
    /// motion, every name and the skeleton's layout kept.
    #[arg(long)]
    mirror: bool,
    /// The mirror image made by renaming instead: every joint reflected where it is, Left and
    /// Right exchanged in the names (the same world positions by name, another joint order).
    #[arg(long, conflicts_with = "mirror")]
    mirror_rename: bool,
    /// With --mirror: counterparts over the guess, LEFT=RIGHT (both joints of the skeleton), or
    /// a TOML or JSON file of such pairs (a map file as `retarget --map` reads it: its
    /// `[skeleton.FINGERPRINT]` sections apply to that skeleton only). With --mirror-rename:
    /// OLD=NEW names.
    #[arg(long = "mirror-names", value_name = "PAIR|FILE")]
    mirror_names: Vec<String>,
    /// The rest pose reset (after --ground, before the layout options): `tpose`, arms level and
    /// out, legs straight down, spine up, by the reading of the body; every joint's world
    /// position kept on every frame.
    #[arg(long, value_enum, value_name = "POSE")]
    rest: Option<RestArg>,
    /// One channel layout (last, after every other edit): every root three positions then three
    /// rotations, every other joint three rotations. A non-root joint's position channels that
    /// never move go into its OFFSET (said); ones that move are refused by name.
    #[arg(long, value_enum, value_name = "LAYOUT")]
    channels: Option<ChannelsArg>,
    /// One Euler order for every joint's rotation channels (last): ZYX, YZX, ZXY, XZY, YXZ or
    /// XYZ, each joint's rotation split once into it (world positions kept).
    #[arg(long, value_enum, ignore_case = true, value_name = "ORDER")]
    order: Option<OrderArg>,
    /// The units to write in (last): mm, cm, m, in, ft, or metres per unit (`0.0254`). The take
    /// is scaled from its own units (as `info` reads them); FBX states them in
    /// `UnitScaleFactor` (default there: centimetres).
    #[arg(long, value_name = "UNITS", value_parser = parse_units)]
    out_units: Option<crate::model::stance::Units>,
    /// Names of a family (last): each joint the reading of the body maps onto a joint of this
    /// skeleton (a built-in one such as `smpl22`, or a file) takes its name; the rest keep
    /// theirs.
    #[arg(long, value_name = "FAMILY|FILE")]
    names: Option<String>,
    /// Names without an exporter's prefix (last): a namespace (`mixamorig:`, `Armature|`) and
    /// a prefix every joint shares up to a separator (`Bip01 `, `CC_Base_`).
    #[arg(long)]
    strip_prefix: bool,
    /// Hold each planted foot where it landed (two-bone IK on thigh and shin), and say how far
    /// the ankles slid during their contacts before and after (sixth).
    #[arg(long)]
    lock_feet: bool,
    /// Remove the roots' travel across the ground (seventh).
    #[arg(long)]
    in_place: bool,
    /// Move the take up or down so that the lowest point of its soles (each leg's ankle and
    /// what is below it, as `info`'s `body:` line reads the legs; its lowest point without two
    /// feet) is at 0 (last).
    #[arg(long)]
    ground: bool,
    /// How position channels combine with OFFSET (in a glTF output's translations).
    #[arg(long, value_enum, default_value_t)]
    offset_mode: OffsetModeArg,
    /// glTF only: add the viewer's generated skin as a mesh skinned to the joints.
    #[arg(long)]
    skin: bool,
    /// Put the take (after the edits, before --out-units) on another skeleton by role, as
    /// `retarget --onto` does: a file, or a built-in skeleton (`smpl22`; `smpl`, `smplh`,
    /// `smplx` for the SMPL family, whose -o out.npz writes AMASS's parameters; with
    /// --body-model, on that model with its betas fitted to the take's bones).
    #[arg(long, value_name = "TARGET", conflicts_with_all = ["character", "skin"])]
    onto: Option<String>,
    #[command(flatten)]
    onto_stated: super::OntoStated,
    /// glTF or FBX: put the take (after the edits) on a character (.fbx, .glb or .gltf with a
    /// skinned mesh), retargeted onto its skeleton by role, and write the character's mesh
    /// bound to it: the take plays on the character in any glTF viewer or engine. A character
    /// file converted to FBX keeps its own mesh without this.
    #[arg(long, value_name = "CHAR", conflicts_with = "skin")]
    character: Option<PathBuf>,
    #[command(flatten)]
    insisting: super::character::Insisting,
    /// The format a folder's takes are written in (a file's is its -o extension).
    #[arg(long, value_enum)]
    to: Option<TakeFormat>,
    /// Threads (default: every core): a folder converts one take per thread.
    #[arg(long)]
    threads: Option<usize>,
    /// The file to write: .bvh, glTF as .glb (binary) or .gltf (text, data inline), or .fbx
    /// (FBX 7.4 binary, in centimetres); `-` is
    /// standard output, in the format --to names. For a folder, the folder to make (it must not
    /// exist, or be empty).
    #[arg(short, long)]
    output: PathBuf,
}

pub(crate) fn run(mut args: ConvertArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    if !is_stdio(&args.input) && args.input.is_dir() {
        return run_folder(&args);
    }
    // `-o -`: standard output, in the format --to names (there is no extension to tell it).
    if is_stdio(&args.output) && args.to.is_none() {
        return Err(Error::usage(
            "-o -: name the format written to standard output with --to bvh, glb, gltf or fbx",
        ));
    }
    if !is_stdio(&args.output) {
        check_output(&args.output, &["bvh", "glb", "gltf", "fbx", "npz"])?;
    }
    let format = TakeFormat::of(&args.output);
    if let Some(to) = args.to
        && to != format
        && !is_stdio(&args.output)
        && !crate::io::output::written_in_place(&args.output)
    {
        return Err(Error::usage(format!(
            "--to {}: -o {} is a .{} file (--to is for a folder; a file is written in the \
             format its extension names)",
            to.extension(),
            args.output.display(),
            format.extension()
        )));
    }
    let format = args.to.unwrap_or(format);
    check_options(&args, format)?;
    let loaded = load_with_threads(&args.input, &args.source, threads(&args))?;
    say_up_is_the_files(&args, &loaded);
    for warning in &loaded.warnings {
        eprintln!(
            "bvhview: {}: warning: {}",
            args.input.display(),
            warning.spelled(&super::Flags)
        );
    }
    let character = match &args.character {
        Some(path) => super::character::load_all(std::slice::from_ref(path), 1, &args.source)?
            .pop()
            .flatten()
            .map(|character| (path.clone(), character)),
        // A character file converted to FBX keeps its mesh.
        None if format == TakeFormat::Fbx && !is_stdio(&args.input) && own_mesh_kept(&loaded) => {
            if let Some(axis) = UpArg::turned_when_read(args.up) {
                eprintln!(
                    "bvhview: {}: warning: its mesh is not written: --up {axis} turns the take \
                     as it is read, not its mesh; the take is",
                    args.input.display()
                );
                None
            } else {
                own_character(&args)
            }
        }
        None => None,
    };
    // A character file's own take is read as its character reads it: on the skeleton its mesh
    // is bound to (the bind pose's frames), which the edits then change.
    let loaded = match (&character, &args.character) {
        (Some((_, own)), None) => Take {
            warnings: loaded.warnings,
            ..own.take.clone()
        },
        _ => loaded,
    };
    // With a character, --out-units scales the take and the mesh together as they are written.
    let loaded = edit(&args, loaded, character.is_none())?;
    if let Some((path, character)) = character {
        return write_character(&args, format, loaded, &path, &character);
    }
    let label = super::TakeLabel {
        out_units: args.out_units,
        ..super::TakeLabel::of(&loaded)
    };
    write_take(
        &args.output,
        format,
        loaded.skeleton,
        loaded.motion,
        written_mode(&args),
        args.skin,
        Some(label),
    )
}

/// The input file's own character (its skinned mesh), read as `--character` reads one, or
/// none: a file without a mesh, or one whose mesh cannot be skinned (then said: the take is
/// written without it).
fn own_character(
    args: &ConvertArgs,
) -> Option<(PathBuf, std::sync::Arc<crate::character::Character>)> {
    let mut options = crate::take::OpenOptions::new().max_size(args.source.max_size);
    if let Some(take) = &args.source.take {
        options = options.take(take.as_str());
    }
    // What the user said of the file (a turning --up never comes here: see `run`).
    if let Some(units) = args.source.units {
        options = options.units(units);
    }
    if let Some(up) = args.source.up {
        options = options.up(up);
    }
    match crate::character::Character::open_if_any(&args.input, &options) {
        Ok(character) => {
            character.map(|character| (args.input.clone(), std::sync::Arc::new(character)))
        }
        Err(why) => {
            eprintln!(
                "bvhview: {}: warning: its mesh is not written ({}); the take is",
                args.input.display(),
                super::said(&why)
            );
            None
        }
    }
}

/// Whether two skeletons are one rig: the same joints (names aside) with the same parents,
/// channels, OFFSETs and axes; a mesh bound to one is bound to the other.
fn same_rig(a: &crate::Skeleton, b: &crate::Skeleton) -> bool {
    a.joints.len() == b.joints.len()
        && a.joints.iter().zip(&b.joints).all(|(a, b)| {
            a.parent == b.parent
                && a.channels == b.channels
                && a.offset == b.offset
                && a.axis == b.axis
                && a.end_site == b.end_site
        })
}

/// Whether two skeletons have the same joints, by name and parent, and bones of the same
/// lengths (within 32-bit rounding), however they are turned.
fn same_bones(a: &crate::Skeleton, b: &crate::Skeleton) -> bool {
    a.joints.len() == b.joints.len()
        && a.joints.iter().zip(&b.joints).all(|(a, b)| {
            let (x, y) = (a.offset.length(), b.offset.length());
            a.name == b.name && a.parent == b.parent && (x - y).abs() <= 1e-6 * x.max(y).max(1.0)
        })
}

/// Whether `take` comes from a file that may hold a skinned mesh of its own (FBX or glTF).
fn own_mesh_kept(take: &Take) -> bool {
    matches!(
        take.format,
        Some(crate::take::Format::Fbx | crate::take::Format::Gltf)
    )
}

/// `loaded` (after the edits) put on `character` (read from `path`) and written with the
/// character's mesh: glTF or FBX.
fn write_character(
    args: &ConvertArgs,
    format: TakeFormat,
    loaded: Take,
    path: &Path,
    character: &std::sync::Arc<crate::character::Character>,
) -> Result<ExitCode, Error> {
    let own = args.character.is_none();
    let mut character = character.clone();
    let mut dressed = if own {
        // The file's own take, edited: its mesh goes with it while the edits keep the rig.
        if !same_rig(&loaded.skeleton, &character.take.skeleton) {
            eprintln!(
                "bvhview: {}: warning: its mesh is not written: the edits changed the skeleton \
                 it is bound to (its OFFSETs, channels or joints)",
                args.input.display()
            );
            let mut loaded = loaded;
            if let Some(units) = args.out_units {
                loaded = super::in_units(&args.input.display().to_string(), loaded, units)?;
            }
            let label = super::TakeLabel {
                out_units: args.out_units,
                ..super::TakeLabel::of(&loaded)
            };
            let mode = written_mode(args);
            return write_take(
                &args.output,
                format,
                loaded.skeleton,
                loaded.motion,
                mode,
                false,
                Some(label),
            );
        }
        Take {
            offset_mode: OffsetMode::Replace,
            ..loaded
        }
    } else {
        let (dressed, worn) =
            super::character::dress(&character, &loaded, &args.input, args.insisting.insist())?;
        character = worn;
        dressed
    };
    let mut mesh = std::borrow::Cow::Borrowed(&character.mesh);
    if let Some(units) = args.out_units {
        let own_units = dressed.stance(OffsetMode::Replace).units.metres;
        let factor = (f64::from(own_units) / f64::from(units.metres)) as f32;
        dressed = super::in_units(&args.input.display().to_string(), dressed, units)?;
        mesh = std::borrow::Cow::Owned(character.mesh.scaled(factor));
    }
    if mesh.pose_blend.is_some() && format == TakeFormat::Fbx {
        eprintln!(
            "bvhview: {}: warning: the body model's pose blend shapes are not written (bvhview's \
             FBX has no blend shapes yet; a .glb keeps them as morph targets): the mesh moves by \
             its skin alone",
            args.output.display(),
        );
    }
    let units = args.out_units;
    let bytes = match format {
        TakeFormat::Fbx => fbx_character(&dressed, &mesh, units, &args.output)?,
        _ => {
            let container = match format {
                TakeFormat::Gltf => crate::gltf::Container::Gltf,
                _ => crate::gltf::Container::Glb,
            };
            let cut = crate::model::mesh::vertices_past_written_influences(&mesh);
            if cut > 0 {
                eprintln!(
                    "bvhview: {}: warning: {cut} of {} mesh vertices have more than {} skin \
                     influences: the strongest {} are written, scaled to sum to 1 (glTF viewers \
                     read at most 4 or 8)",
                    path.display(),
                    character.mesh.vertex_count(),
                    crate::model::mesh::MAX_WRITTEN_INFLUENCES,
                    crate::model::mesh::MAX_WRITTEN_INFLUENCES
                );
            }
            crate::gltf::to_gltf_character(&dressed.skeleton, &dressed.motion, &mesh, container)?
        }
    };
    let target = (!is_stdio(&args.output)).then_some(args.output.as_path());
    let mut out = open_output(target)?;
    let result = out.write_all(&bytes);
    finish_write(out, result, target)?;
    wrote(format_args!(
        "{}: {} on {} ({} vertices)",
        args.output.display(),
        crate::io::error::counted(dressed.motion.frame_count(), "frame"),
        path.display(),
        character.mesh.vertex_count()
    ));
    Ok(ExitCode::SUCCESS)
}

/// A dressed take and its character's mesh as FBX bytes, or what this build lacks.
fn fbx_character(
    dressed: &Take,
    mesh: &crate::model::mesh::Mesh,
    units: Option<crate::model::stance::Units>,
    output: &Path,
) -> Result<Vec<u8>, Error> {
    #[cfg(feature = "fbx")]
    {
        let _ = output;
        let written = match units {
            Some(units) => dressed.fbx_character_in(mesh, units)?,
            None => dressed.fbx_character(mesh)?,
        };
        for change in &written.renamed {
            eprintln!(
                "bvhview: {}: joint {change} (an FBX name holds no control character)",
                output.display()
            );
        }
        Ok(written.bytes)
    }
    #[cfg(not(feature = "fbx"))]
    {
        let _ = (dressed, mesh, units);
        Err(crate::io::absent::without(
            "fbx",
            "FBX",
            &output.display().to_string(),
        ))
    }
}

/// The threads asked for, at least 1.
fn threads(args: &ConvertArgs) -> usize {
    args.threads
        .unwrap_or_else(crate::io::parallel::cores)
        .max(1)
}

/// Refuses options that could not apply to any take, before anything is read.
fn check_options(args: &ConvertArgs, format: TakeFormat) -> Result<(), Error> {
    // A BVH file has no mesh; FBX out writes a character's mesh, not the viewer's generated
    // skin (a picture aid, not a character).
    match format {
        TakeFormat::Bvh if args.skin => {
            return Err(Error::usage(
                "--skin needs a glTF output (.glb or .gltf); a BVH file has no mesh",
            ));
        }
        TakeFormat::Bvh if args.character.is_some() => {
            return Err(Error::usage(
                "--character needs a glTF or FBX output (.glb, .gltf or .fbx); a BVH file has no \
                 mesh",
            ));
        }
        TakeFormat::Fbx if args.skin => {
            return Err(Error::usage(
                "--skin needs a glTF output (.glb or .gltf): FBX out writes a character's own \
                 mesh (--character CHAR), not the viewer's generated skin",
            ));
        }
        _ => {}
    }
    // FBX states Y up and AMASS is Z up: their writers turn the take to it.
    let own_axis = match format {
        TakeFormat::Fbx => Some(("y", UpArg::Y, "FBX")),
        TakeFormat::Amass => Some(("z", UpArg::Z, "AMASS .npz")),
        _ => None,
    };
    if let (Some(out_up), Some((name, axis, what))) = (args.out_up, own_axis)
        && out_up != axis
    {
        return Err(Error::usage(format!(
            "--out-up {}: {what} is written {name} up whatever the take (its writer turns it)",
            crate::model::pose::UpAxis::from(out_up)
        )));
    }
    if let Some(fps) = args.fps {
        crate::limits::fps(fps, false)?;
    }
    if let Some(factor) = args.scale
        && !(factor.is_finite() && factor != 0.0)
    {
        return Err(Error::usage(format!(
            "--scale {factor}: expected a finite number other than 0"
        )));
    }
    Ok(())
}

/// `convert --up` says what the file is, as every command's `--up` does; before, it turned the
/// take. Where the axis given is not the one the motion reads, say how to turn it.
fn say_up_is_the_files(args: &ConvertArgs, loaded: &Take) {
    let Some(given) = args.up.map(UpAxis::from).and_then(UpAxis::standing) else {
        return;
    };
    if args.out_up.is_some() {
        // Both said: what the file is, and what to turn it to.
        return;
    }
    let guessed = crate::model::stance::Stance::guess(
        &loaded.skeleton,
        &loaded.motion,
        OffsetMode::Replace,
        None,
    );
    if guessed.up != given {
        super::note(format_args!(
            "{}: --up {} says the file stands along {} (its motion reads {}); --out-up {} \
             turns a take",
            args.input.display(),
            UpAxis::from(given),
            UpAxis::from(given),
            UpAxis::from(guessed.up),
            UpAxis::from(given),
        ));
    }
}

/// The edits, in this order: trim, smooth, resample, scale, up axis (y or z), mirror, lock
/// feet, in place, ground, rest, layout, names, onto; an up axis other than y or z last.
fn edit(args: &ConvertArgs, mut loaded: Take, in_out_units: bool) -> Result<Take, Error> {
    let before = loaded.skeleton.clone();
    if let Some(frames) = &args.frames {
        let range = crate::positions::parse_frames(frames, loaded.motion.frame_count())?;
        loaded.motion = crate::edit::trim(&loaded.motion, range);
    }
    if let Some(cutoff) = args.smooth {
        let smoothed = crate::edit::smooth(&loaded.skeleton, &loaded.motion, cutoff)?;
        let said = super::effect(
            "--smooth",
            &loaded.skeleton,
            &loaded.motion,
            &smoothed,
            &loaded,
        );
        if let Some(line) = said {
            super::note(format_args!("{}: {line}", args.input.display()));
        }
        loaded.motion = smoothed;
    }
    if let Some(fps) = args.fps {
        loaded.motion = crate::edit::resample(&loaded.skeleton, &loaded.motion, fps)?;
    }
    if let Some(factor) = args.scale {
        (loaded.skeleton, loaded.motion) =
            crate::edit::scale(&loaded.skeleton, &loaded.motion, factor)?;
        // Scaled, its lengths are no longer in the units stated or given: guessed again.
        loaded.stated_units = None;
        loaded.units_given = false;
    }
    // The take's up axis as guessed from its motion or given (scaling changes no axis).
    let mut up = loaded.stance(OffsetMode::Replace).up;
    // With --onto, the take stands as its target does: any turn comes after it.
    let turned_now = args
        .out_up
        .and_then(|axis| UpAxis::from(axis).standing())
        .filter(|_| args.onto.is_none());
    if let Some(target) = turned_now {
        (loaded.skeleton, loaded.motion) =
            crate::edit::reorient(&loaded.skeleton, &loaded.motion, up, target)?;
        up = target;
        loaded.stated_up = loaded.stated_up.map(|_| target);
    }
    if args.mirror || args.mirror_rename {
        let options = crate::edit::MirrorOptions {
            rename: args.mirror_rename,
            names: super::retarget::map_pairs(&args.mirror_names)?
                .for_skeleton(&loaded.skeleton)
                .into_iter()
                .collect(),
        };
        (loaded.skeleton, loaded.motion) =
            crate::edit::mirror(&loaded.skeleton, &loaded.motion, &options)?;
    }
    if args.lock_feet {
        let metres = f64::from(loaded.stance(OffsetMode::Replace).units.metres);
        let (motion, locked) = crate::edit::lock_feet(
            &loaded.skeleton,
            &loaded.motion,
            OffsetMode::Replace,
            up,
            metres,
            &crate::edit::LockFeet::default(),
        )?;
        super::note(format_args!(
            "{}: {}",
            locked.heading(),
            locked.summary(&loaded.skeleton)
        ));
        let said = super::effect(
            "--lock-feet",
            &loaded.skeleton,
            &loaded.motion,
            &motion,
            &loaded,
        );
        if let Some(line) = said {
            super::note(format_args!("{}: {line}", args.input.display()));
        }
        loaded.motion = motion;
    }
    if args.in_place {
        loaded.motion = crate::edit::in_place(&loaded.skeleton, &loaded.motion, up);
    }
    if args.ground {
        (loaded.skeleton, loaded.motion) =
            crate::edit::ground(&loaded.skeleton, &loaded.motion, OffsetMode::Replace, up)?;
    }
    // How position channels count from here: the T-pose rest writes whole translations.
    let mut mode: OffsetMode = args.offset_mode.into();
    if let Some(RestArg::Tpose) = args.rest {
        let said;
        (loaded.skeleton, loaded.motion, said) =
            crate::edit::rest_tpose(&loaded.skeleton, &loaded.motion, mode, up)?;
        mode = OffsetMode::Replace;
        for line in said {
            super::note(format_args!("{}: {line}", args.input.display()));
        }
    }
    let wanted = canonical_asked(args);
    if wanted.any() {
        let said;
        (loaded.skeleton, loaded.motion, said) =
            crate::edit::canonical(&loaded.skeleton, &loaded.motion, mode, &wanted)?;
        for line in said {
            super::note(format_args!("{}: {line}", args.input.display()));
        }
    }
    if let Some(family) = &args.names {
        let family = crate::retarget::Target::load(family, args.source.max_size)?;
        let said;
        (loaded.skeleton, said) =
            crate::retarget::names_of_family(&loaded.skeleton, &family.skeleton)?;
        for line in said {
            super::note(format_args!("{}: {line}", args.input.display()));
        }
    }
    if !same_bones(&loaded.skeleton, &before) {
        // Its lengths or joints changed: no longer the body an AMASS file said (a turn, as
        // `--up` makes, keeps it).
        loaded.body = None;
    }
    if let Some(onto) = &args.onto {
        let (target, body) =
            super::retarget::target_for(onto, &args.onto_stated, &args.source, &loaded)?;
        let name = args.input.display().to_string();
        let (skeleton, motion, check) =
            super::retarget::put_onto(&loaded, &name, &target, &[], Default::default())?;
        super::note(format_args!(
            "{name} onto {}: {}",
            target.name,
            check.line()
        ));
        let mut put = loaded.edited(skeleton, motion, false);
        put.offset_mode = OffsetMode::Replace;
        // On the target, it is what the user said of the target, if anything.
        target.state_on(&mut put);
        put.body = body;
        loaded = put;
        up = target.up;
    }
    // A turn to an axis the stances do not stand along comes after every edit that stands on
    // the floor (each turns with the take, so the order changes nothing else); with --onto,
    // every turn does, from the target's axis.
    if let Some(target) = args
        .out_up
        .map(UpAxis::from)
        .filter(|a| a.standing().is_none() || args.onto.is_some())
    {
        (loaded.skeleton, loaded.motion) =
            crate::edit::reorient(&loaded.skeleton, &loaded.motion, up, target)?;
        loaded.stated_up = target.standing();
    }
    if let Some(units) = args.out_units.filter(|_| in_out_units) {
        loaded = super::in_units(&args.input.display().to_string(), loaded, units)?;
    }
    Ok(loaded)
}

/// `--out-units`: a unit's name or a number of metres per unit.
pub(crate) fn parse_units(text: &str) -> Result<crate::model::stance::Units, String> {
    crate::model::stance::Units::named(text).ok_or_else(|| {
        format!("expected mm, cm, m, in, ft or a number of metres per unit from 1e-9 to 1000, not '{text}'")
    })
}

/// The canonical layout the options ask for.
fn canonical_asked(args: &ConvertArgs) -> crate::edit::Canonical {
    crate::edit::Canonical {
        root6_rot3: args.channels.is_some(),
        order: args.order.map(OrderArg::order),
        strip_prefix: args.strip_prefix,
    }
}

/// How the written take's position channels combine with OFFSET: as `--offset-mode` says,
/// but replacing it once `--channels` or `--rest` made the positions whole translations.
fn written_mode(args: &ConvertArgs) -> OffsetMode {
    match (args.channels, args.rest) {
        (None, None) => args.offset_mode.into(),
        _ => OffsetMode::Replace,
    }
}

/// `--rest`: the rest poses there are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RestArg {
    /// Arms level and out, legs straight down, spine up.
    Tpose,
}

/// `--channels`: the one layout there is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ChannelsArg {
    /// Every root three positions then three rotations, every other joint three rotations.
    #[value(name = "root6,rot3")]
    Root6Rot3,
}

/// `--order`: the six Euler orders, named as BVH lists the channels (outermost first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum OrderArg {
    Zyx,
    Yzx,
    Zxy,
    Xzy,
    Yxz,
    Xyz,
}

impl OrderArg {
    fn order(self) -> crate::model::skeleton::RotationOrder {
        use crate::model::skeleton::RotationOrder as R;
        match self {
            OrderArg::Zyx => R::Zyx,
            OrderArg::Yzx => R::Yzx,
            OrderArg::Zxy => R::Zxy,
            OrderArg::Xzy => R::Xzy,
            OrderArg::Yxz => R::Yxz,
            OrderArg::Xyz => R::Xyz,
        }
    }
}

/// A take converted in memory, for the folder: what to write and what to say.
struct Converted {
    bytes: Vec<u8>,
    warnings: Vec<String>,
    renamed: Vec<(String, String)>,
}

/// What became of one take of a folder.
enum Outcome {
    Converted(Converted),
    /// Not a take that converts (an AMC with no skeleton beside it): said, not a failure.
    Skipped(String),
    /// `path: reason`.
    Failed(String),
}

/// `convert DIR -o OUT --to FORMAT`: every take under DIR, loaded, edited and written as it
/// would be alone (the same bytes as `convert TAKE -o OUT/TAKE.FORMAT`), one take per thread,
/// into the new folder OUT at the take's path under DIR. OUT is made as `dataset` makes its
/// folder (`crate::io::output::NewFolder`): it must not exist or be empty, is filled under a
/// temporary name beside it and takes its name at the end, so a run that fails or is
/// interrupted leaves nothing. A take that fails is said (`failed PATH: reason`) and the others
/// are still written; the exit code is then 2. Output errors (a full disk) stop the run, with
/// nothing written.
fn run_folder(args: &ConvertArgs) -> Result<ExitCode, Error> {
    let dir = &args.input;
    let format = folder_format(args)?;
    let walk = crate::info::batch::collect_takes(dir)?;
    for line in walk.skipped_lines() {
        super::note(format_args!("{line}"));
    }
    let items = walk.items;
    let names = output_names(dir, &items, format);
    let folder = crate::io::output::NewFolder::create(
        &args.output,
        "converted takes go into a new (or empty) folder",
    )?;
    let total = items.len();
    let progress = Progress::new(total);
    let (mut converted, mut failed, mut skipped) = (0, 0, 0);
    let mut fatal = None;
    crate::io::parallel::map_in_order(
        total,
        threads(args),
        4 * threads(args),
        |index| convert_one(args, format, &items[index], &names[index]),
        |index, outcome| {
            let take = take_path(&items[index]);
            // Lines go on a line of their own, the bar drawn again below them.
            progress.done();
            match outcome {
                Outcome::Converted(done) => {
                    let name = names[index].as_ref().expect("converted takes have a name");
                    if let Err(error) = write_converted(args, &folder, take, name, &done) {
                        fatal = Some(error);
                        return false;
                    }
                    converted += 1;
                }
                Outcome::Skipped(line) => {
                    skipped += 1;
                    super::note(format_args!("skipped {line}"));
                }
                Outcome::Failed(line) => {
                    failed += 1;
                    eprintln!("failed {line}");
                }
            }
            progress.show(index + 1);
            true
        },
    );
    progress.done();
    if let Some(error) = fatal {
        return Err(error);
    }
    if converted == 0 {
        return Err(Error::usage(format!(
            "{}: no take could be converted ({} failed, {} skipped), so nothing was written",
            dir.display(),
            failed,
            skipped
        )));
    }
    folder.commit()?;
    wrote(format_args!(
        "{}: {} as .{}; {failed} failed, {} skipped",
        args.output.display(),
        crate::io::error::counted(converted, "take"),
        format.extension(),
        skipped + walk.skipped.len()
    ));
    Ok(if failed > 0 {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}

/// The format a folder's takes are written in (`--to`), once the options that mean nothing for
/// a folder are refused.
fn folder_format(args: &ConvertArgs) -> Result<TakeFormat, Error> {
    let dir = &args.input;
    if args.character.is_some() {
        return Err(Error::usage(format!(
            "{} is a folder: --character puts one take on a character (give a file)",
            dir.display()
        )));
    }
    let format = args.to.ok_or_else(|| {
        Error::usage(format!(
            "{} is a folder: say the format its takes are written in with --to bvh, glb, gltf or fbx \
             (-o names the folder to make)",
            dir.display()
        ))
    })?;
    check_options(args, format)?;
    if let Some(motion) = &args.source.motion {
        return Err(Error::usage(format!(
            "--motion {}: a folder pairs each AMC with its ASF itself",
            motion.display()
        )));
    }
    crate::limits::frame_time_option(args.source.frame_time)?;
    Ok(format)
}

/// Writes one converted take into the folder being made, as `name`: its warnings first, then
/// the joints it renamed to be written as BVH.
fn write_converted(
    args: &ConvertArgs,
    folder: &crate::io::output::NewFolder,
    take: &Path,
    name: &Path,
    done: &Converted,
) -> Result<(), Error> {
    for warning in &done.warnings {
        eprintln!("bvhview: {}: warning: {warning}", take.display());
    }
    let path = folder.path().join(name);
    let written = crate::io::output::in_partial_folder(|| {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::write(&path, &done.bytes)
    });
    if let Err(e) = written {
        return Err(Error::output(&args.output.join(name), e));
    }
    for (joint, written) in &done.renamed {
        eprintln!(
            "bvhview: {}: joint {joint:?} written as {written:?} (a BVH name \
             holds no whitespace or braces)",
            args.output.join(name).display()
        );
    }
    Ok(())
}

/// The file a take is named by: its AMC for an ASF/AMC pair, else its own.
fn take_path(item: &Item) -> &Path {
    item.motion.as_deref().unwrap_or(&item.path)
}

/// Loads, edits and encodes one take of a folder, on one thread. The take is loaded as
/// `convert TAKE` loads it: an FBX or glTF file's take is `--take`'s, or its first (the loader
/// says once that it has several), and a BVH or ASF/AMC take is its only one.
fn convert_one(
    args: &ConvertArgs,
    format: TakeFormat,
    item: &Item,
    name: &Result<PathBuf, String>,
) -> Outcome {
    let take = take_path(item);
    // `take: reason`, unless the reason already starts with the file it is about.
    let failed = |error: String| {
        let said = [take, item.path.as_path()]
            .iter()
            .any(|p| error.starts_with(&p.display().to_string()));
        match said {
            true => Outcome::Failed(error),
            false => Outcome::Failed(format!("{}: {error}", take.display())),
        }
    };
    if item.is_unpaired_motion() {
        return Outcome::Skipped(format!(
            "{}: motion without a skeleton ({} is not beside it)",
            take.display(),
            item.wanted_skeleton()
        ));
    }
    if let Err(reason) = name {
        return failed(reason.clone());
    }
    let pick =
        args.source.take.as_deref().filter(|_| {
            take::Format::from_path(&item.path).is_some_and(|f| f.holds_several_takes())
        });
    let options = take::OpenOptions {
        motion: item.motion.clone(),
        take: pick.map(String::from),
        frame_time: args.source.frame_time,
        max_size: Some(args.source.max_size),
        threads: Some(1),
        body_model: args.source.body_model.clone(),
        units: args.source.units,
        up: args.source.up,
        ..Default::default()
    };
    let result = take::load_take(&item.path, &options).and_then(|loaded| {
        let warnings: Vec<String> = loaded
            .warnings
            .iter()
            .map(|w| w.spelled(&super::Flags))
            .collect();
        let loaded = edit(args, loaded, true)?;
        let label = super::TakeLabel {
            out_units: args.out_units,
            ..super::TakeLabel::of(&loaded)
        };
        let prepared = Prepared::new(
            format,
            loaded.skeleton,
            loaded.motion,
            written_mode(args),
            args.skin,
            &label,
        )?;
        let mut bytes = Vec::new();
        prepared
            .write_to(&mut bytes)
            .map_err(|e| match crate::positions::not_finite(&e) {
                Some(_) => Error::usage(e.to_string()),
                None => Error::output(take, e),
            })?;
        Ok(Converted {
            bytes,
            warnings,
            renamed: prepared.renamed(),
        })
    });
    match result {
        Ok(done) => Outcome::Converted(done),
        Err(error) => failed(super::said(&error)),
    }
}

/// Where each take of `items` goes in the output folder: its path under `dir` with the format's
/// extension (`a/walk.fbx` → `a/walk.bvh`; an ASF/AMC take by its AMC, `07/07_05.bvh`). Two
/// takes of one folder that would share a name (`walk.bvh` and `walk.fbx`) each keep their own
/// extension before the new one (`walk.bvh.bvh`, `walk.fbx.bvh`), so no output replaces another.
/// A name still taken twice, or one that is also a folder of other outputs, is an error for its
/// take. An unpaired AMC (which is not converted) gets an error too.
fn output_names(dir: &Path, items: &[Item], format: TakeFormat) -> Vec<Result<PathBuf, String>> {
    let extension = format.extension();
    let relative = |item: &Item| {
        let take = take_path(item);
        take.strip_prefix(dir)
            .map(Path::to_path_buf)
            .unwrap_or_else(|_| take.file_name().map(PathBuf::from).unwrap_or_default())
    };
    // Not `with_extension`: it turns `..bvh` into `..`, the folder above.
    let short = |item: &Item| {
        let path = relative(item);
        let mut name = path.file_stem().unwrap_or_default().to_os_string();
        name.push(".");
        name.push(extension);
        path.with_file_name(name)
    };
    let long = |item: &Item| {
        let mut name = OsString::from(relative(item));
        name.push(".");
        name.push(extension);
        PathBuf::from(name)
    };
    let convertible = |item: &Item| !item.is_unpaired_motion();
    let mut shorts: HashMap<PathBuf, usize> = HashMap::new();
    for item in items.iter().filter(|item| convertible(item)) {
        *shorts.entry(short(item)).or_default() += 1;
    }
    let chosen: Vec<Option<PathBuf>> = items
        .iter()
        .map(|item| {
            convertible(item).then(|| {
                let name = short(item);
                match shorts[&name] {
                    1 => name,
                    _ => long(item),
                }
            })
        })
        .collect();
    let mut uses: HashMap<&Path, usize> = HashMap::new();
    let mut folders: HashSet<&Path> = HashSet::new();
    for name in chosen.iter().flatten() {
        *uses.entry(name).or_default() += 1;
        folders.extend(
            name.ancestors()
                .skip(1)
                .filter(|a| !a.as_os_str().is_empty()),
        );
    }
    chosen
        .iter()
        .map(|name| match name {
            None => Err("motion without a skeleton".to_string()),
            Some(name) if uses[name.as_path()] > 1 => Err(format!(
                "its output {} is another take's too (rename one of them)",
                name.display()
            )),
            Some(name) if folders.contains(name.as_path()) => Err(format!(
                "its output {} is a folder of other outputs (rename the take)",
                name.display()
            )),
            Some(name) => Ok(name.clone()),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(path: &str) -> Item {
        Item {
            path: PathBuf::from(path),
            motion: None,
        }
    }

    #[test]
    fn outputs_mirror_the_folder_and_clashing_names_keep_their_extension() {
        let items = [
            item("d/a/walk.bvh"),
            item("d/a/walk.fbx"),
            item("d/b/run.glb"),
            Item {
                path: PathBuf::from("d/c/07.asf"),
                motion: Some(PathBuf::from("d/c/07_05.amc")),
            },
            item("d/c/12_01.amc"),
        ];
        let names = output_names(Path::new("d"), &items, TakeFormat::Bvh);
        let names: Vec<Result<String, String>> = names
            .into_iter()
            .map(|n| n.map(|p| p.display().to_string()))
            .collect();
        assert_eq!(
            names,
            vec![
                Ok("a/walk.bvh.bvh".to_string()),
                Ok("a/walk.fbx.bvh".to_string()),
                Ok("b/run.bvh".to_string()),
                Ok("c/07_05.bvh".to_string()),
                Err("motion without a skeleton".to_string()),
            ]
        );
    }

    #[test]
    fn an_output_that_is_another_outputs_folder_or_taken_twice_is_refused() {
        // `x.bvh` the file and `x.bvh/` the folder; `y.fbx.bvh` made twice.
        let items = [
            item("d/x.bvh"),
            item("d/x.bvh/in.bvh"),
            item("d/y.bvh"),
            item("d/y.fbx"),
            item("d/y.fbx.bvh"),
        ];
        let names = output_names(Path::new("d"), &items, TakeFormat::Bvh);
        assert!(
            names[0]
                .as_ref()
                .unwrap_err()
                .contains("a folder of other outputs")
        );
        assert_eq!(names[1].as_deref(), Ok(Path::new("x.bvh/in.bvh")));
        assert_eq!(names[2].as_deref(), Ok(Path::new("y.bvh.bvh")));
        assert!(
            names[3]
                .as_ref()
                .unwrap_err()
                .contains("another take's too")
        );
        assert!(
            names[4]
                .as_ref()
                .unwrap_err()
                .contains("another take's too")
        );
    }
}
