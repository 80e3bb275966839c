//! `bvhview retarget`: one take's motion on another skeleton, written as BVH or glTF.

use super::{Source, check_output, load, write_text};
use crate::io::error::Error;
use crate::retarget::{self, Insist, Map, Target};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct RetargetArgs {
    /// The take to move: .bvh, .fbx, .gltf, .glb or AMASS .npz, or an .asf skeleton with its motion in
    /// --motion.
    input: PathBuf,
    #[command(flatten)]
    source: Source,
    #[command(flatten)]
    onto_stated: super::OntoStated,
    /// The axis the take stands along, over the guess (the retarget turns it up by it).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
    /// The skeleton to put it on: a .bvh, .fbx, .gltf, .glb or .asf file (its motion is not used), or a built-in
    /// skeleton: `smpl22` (the 22 SMPL body joints of HumanML3D and most motion models).
    #[arg(long, value_name = "TARGET")]
    onto: String,
    /// Override the guessed joint map: SRC=DST (a source joint onto a target joint; SRC= leaves
    /// it out), or a TOML or JSON file of such pairs (what --show-map prints; pairs for one
    /// skeleton under `[skeleton.FINGERPRINT]`, as `info` prints it). Repeatable.
    #[arg(long, value_name = "FILE|SRC=DST")]
    map: Vec<String>,
    /// Retarget a body that does not stand on two legs (a quadruped with human joint names)
    /// onto one that does, or the reverse, which is refused otherwise; the result is not held
    /// to a person's widths either.
    #[arg(long)]
    any_body: bool,
    /// Hold each planted foot of the result where it landed (as `convert --lock-feet`), and say
    /// how far the ankles slid during their contacts before and after.
    #[arg(long)]
    lock_feet: bool,
    /// Write the result even when its check finds a side crossed or a width collapsed (it is
    /// refused otherwise, exit 2); the check's line says what was wrong.
    #[arg(long)]
    force: bool,
    /// Print the map (as TOML --map reads) and the joints left unmapped, on stdout.
    #[arg(long)]
    show_map: bool,
    /// The file to write: .bvh, glTF as .glb (binary) or .gltf (text, data inline), or .fbx.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The units to write in: mm, cm, m, in, ft, or metres per unit (the result is in the
    /// target's own units without it).
    #[arg(long, value_name = "UNITS", value_parser = super::convert::parse_units)]
    out_units: Option<crate::model::stance::Units>,
}

/// The `--map` values as pairs, in order: files read (their `[skeleton.…]` sections kept for
/// the skeleton they name), `SRC=DST` split.
pub(crate) fn map_pairs(values: &[String]) -> Result<retarget::MapPairs, Error> {
    let mut pairs = retarget::MapPairs::default();
    for value in values {
        let path = Path::new(value);
        // A regular file only (a FIFO or a device is not a map), read up to 16 MiB.
        if path.is_file() {
            let bytes = crate::io::read::read_file(path, 16 << 20)?;
            let text = std::str::from_utf8(&bytes).map_err(|e| {
                let (line, column) = crate::io::lines::line_column(&bytes, e.valid_up_to());
                Error::Parse {
                    path: value.clone(),
                    line,
                    column,
                    message: "not UTF-8 text: a map file is TOML or JSON".to_string(),
                }
            })?;
            pairs.extend(retarget::parse_map_pairs(text, value)?);
        } else if let Some(pair) = retarget::parse_pair(value) {
            pairs.all.push(pair);
        } else {
            return Err(Error::usage(format!(
                "--map {value}: expected SRC=DST or a TOML or JSON map file"
            )));
        }
    }
    Ok(pairs)
}

/// The skeleton `onto` names; with `--body-model` and a SMPL-family built-in (`smpl22`,
/// `smpl`, `smplh`, `smplx` …), the model's own figure with its betas fitted to `loaded`'s
/// bones (said), and the body it is.
pub(crate) fn target_for(
    onto: &str,
    stated: &super::OntoStated,
    source: &Source,
    loaded: &crate::Take,
) -> Result<(Target, Option<crate::smpl::Body>), Error> {
    let family = crate::bvh::built_in::name_of(onto)
        .filter(|name| name.starts_with("smpl") && !Path::new(onto).exists());
    let (Some(path), Some(_)) = (&source.body_model, family) else {
        return Ok((stated.target(onto, source.max_size)?, None));
    };
    stated.refused_with_body_model()?;
    let wanted = crate::smpl::fit::model_type_of_target(onto);
    let model = crate::smpl::open_model(path, None, wanted, source.max_size)?;
    let metres = f64::from(loaded.stance(loaded.offset_mode).units.metres);
    let fitted = crate::smpl::fit::shaped_to(&model, &loaded.skeleton, metres)?;
    super::note(format_args!("{} onto {onto}: {}", loaded.name, fitted.said));
    let name = format!("{onto} ({})", model.name);
    Ok((
        Target::new(name, fitted.skeleton, &fitted.rest),
        Some(fitted.body),
    ))
}

/// `loaded` (read from `source_name`) put on `target` by role (`pairs` over the guessed map),
/// what the map could not carry and what was kept only as `insist` asks said as warnings; the
/// result and its check against the take.
pub(crate) fn put_onto(
    loaded: &crate::Take,
    source_name: &str,
    target: &Target,
    pairs: &[(String, String)],
    insist: Insist,
) -> Result<
    (
        crate::Skeleton,
        crate::model::motion::Motion,
        retarget::Check,
    ),
    Error,
> {
    let put = target.apply_up(
        source_name,
        &loaded.skeleton,
        &loaded.motion,
        loaded.stated_up,
        pairs,
        insist,
        crate::io::parallel::cores(),
    )?;
    for warning in &put.uncarried {
        eprintln!("bvhview: {source_name}: warning: {warning}");
    }
    if let Some(why) = &put.forced {
        eprintln!(
            "bvhview: {source_name} onto {}: warning: written as --force asks though {why}",
            target.name
        );
    }
    Ok((put.skeleton, put.motion, put.check))
}

pub(crate) fn run(mut args: RetargetArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    if let Some(output) = &args.output {
        check_output(output, &["bvh", "glb", "gltf", "fbx", "npz"])?;
    } else if !args.show_map {
        return Err(Error::usage(
            "retarget: give -o OUT.bvh|.glb|.gltf|.fbx, or --show-map to see the map only",
        ));
    }
    let loaded = load(&args.input, &args.source)?;
    let pairs = map_pairs(&args.map)?.for_skeleton(&loaded.skeleton);
    let (target, body) = target_for(&args.onto, &args.onto_stated, &args.source, &loaded)?;
    let source_name = args.input.display().to_string();
    if args.show_map {
        let mut map = Map::guess(&loaded.skeleton, &target.skeleton);
        map.apply(&pairs, &loaded.skeleton, &target.skeleton)?;
        write_text(&map.show(&loaded.skeleton, &target.skeleton))?;
        map.check(&source_name, &target.name)?;
    }
    let Some(output) = &args.output else {
        return Ok(ExitCode::SUCCESS);
    };
    let insist = Insist {
        any_body: args.any_body,
        force: args.force,
    };
    let (skeleton, motion, check) = put_onto(&loaded, &source_name, &target, &pairs, insist)?;
    let motion = if args.lock_feet {
        // The take on the target, as the user said the target is (else guessed again).
        let mut on_target = crate::Take::new(skeleton.clone(), motion.clone(), source_name.clone());
        target.state_on(&mut on_target);
        let (locked_motion, locked) = crate::retarget::lock_feet_from_source(&loaded, &on_target)?;
        super::note(format_args!(
            "{}: {}",
            locked.heading(),
            locked.summary(&skeleton)
        ));
        if let Some(line) = super::effect(
            "--lock-feet",
            &skeleton,
            &motion,
            &locked_motion,
            &on_target,
        ) {
            super::note(format_args!("{source_name} onto {}: {line}", target.name));
        }
        let motion = locked_motion;
        // The check is of what is written: measured again on the locked legs.
        let locked_check = target.measure(
            &source_name,
            &loaded.skeleton,
            &loaded.motion,
            loaded.stated_up,
            &pairs,
            &motion,
        )?;
        super::note(format_args!("{} (after --lock-feet)", locked_check.line()));
        // Held to what the result before the lock was held to.
        if let Some(why) = locked_check
            .refusal()
            .filter(|_| !args.any_body && !args.force)
        {
            return Err(Error::usage(format!(
                "{source_name} onto {}: not written: after --lock-feet {why} ({}); --force \
                 writes it anyway",
                target.name,
                locked_check.line()
            )));
        }
        motion
    } else {
        super::note(format_args!("{}", check.line()));
        motion
    };
    super::write_result(output, skeleton, motion, args.out_units, body, &target)
}
