//! `bvhview retarget`: one take's motion on another skeleton, written as BVH or glTF.

use super::*;
use bvhview::retarget::{self, Map, Ups};

#[derive(Args)]
pub(crate) struct RetargetArgs {
    /// The take to move: a .bvh file, or an .asf skeleton with its motion in --motion.
    input: PathBuf,
    #[command(flatten)]
    source: Source,
    /// The skeleton to put it on: a .bvh or .asf file (its motion is not used), or a built-in
    /// skeleton: `smpl22` (the 22 SMPL body joints of HumanML3D and most motion models).
    #[arg(long, value_name = "TARGET")]
    onto: String,
    /// Override the guessed joint map: SRC=DST (a source joint onto a target joint; SRC= leaves
    /// it out), or a TOML or JSON file of such pairs (what --show-map prints). Repeatable.
    #[arg(long, value_name = "FILE|SRC=DST")]
    map: Vec<String>,
    /// Print the map (as TOML --map reads) and the joints left unmapped, on stdout.
    #[arg(long)]
    show_map: bool,
    /// The file to write: .bvh, or glTF as .glb (binary) or .gltf (text, data inline).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// The target skeleton: a file, or a built-in one by name; with the name to show.
fn load_target(onto: &str, max_size: u64) -> Result<(String, Loaded), Error> {
    let path = Path::new(onto);
    if !path.exists()
        && let Some((skeleton, motion)) = retarget::built_in(onto)
    {
        return Ok((
            onto.to_string(),
            Loaded {
                skeleton,
                motion,
                warnings: Vec::new(),
                stated_units: None,
            },
        ));
    }
    if !path.exists() && input::extension(path).is_empty() {
        let names: Vec<&str> = retarget::BUILT_IN.iter().map(|(n, _)| *n).collect();
        return Err(Error::Usage(format!(
            "--onto {onto}: neither a file nor a built-in skeleton ({})",
            names.join(", ")
        )));
    }
    let loaded = input::load_checked(path, None, None, bvhview::cores(), max_size)?;
    Ok((path.display().to_string(), loaded))
}

/// The `--map` values as pairs, in order: files read, `SRC=DST` split.
fn map_pairs(values: &[String]) -> Result<Vec<(String, String)>, Error> {
    let mut pairs = Vec::new();
    for value in values {
        let path = Path::new(value);
        if path.is_file() {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            pairs.extend(retarget::parse_map(&text, value)?);
        } else if let Some(pair) = retarget::parse_pair(value) {
            pairs.push(pair);
        } else {
            return Err(Error::Usage(format!(
                "--map {value}: expected SRC=DST or a TOML or JSON map file"
            )));
        }
    }
    Ok(pairs)
}

pub(crate) fn run(args: RetargetArgs) -> Result<ExitCode, Error> {
    if let Some(output) = &args.output {
        check_output(output, &["bvh", "glb", "gltf"])?;
    } else if !args.show_map {
        return Err(Error::Usage(
            "retarget: give -o OUT.bvh|.glb|.gltf, or --show-map to see the map only".into(),
        ));
    }
    let pairs = map_pairs(&args.map)?;
    let loaded = load(&args.input, &args.source)?;
    let (target_name, target) = load_target(&args.onto, args.source.max_size)?;
    let mut map = Map::guess(&loaded.skeleton, &target.skeleton);
    map.apply(&pairs, &loaded.skeleton, &target.skeleton)?;
    if args.show_map {
        write_text(&map.show(&loaded.skeleton, &target.skeleton))?;
    }
    map.check(&args.input.display().to_string(), &target_name)?;
    let Some(output) = &args.output else {
        return Ok(ExitCode::SUCCESS);
    };
    let ups = Ups {
        source: loaded.stance(OffsetMode::Replace).up,
        target: target_up(&target),
    };
    let (skeleton, motion) = retarget::retarget(
        &loaded.skeleton,
        &loaded.motion,
        &target.skeleton,
        &map,
        ups,
    )?;
    write_take(output, skeleton, motion)
}

/// The up axis of the target: its take's, or its rest pose's when it has one frame or none.
pub(crate) fn target_up(target: &Loaded) -> Up {
    if target.motion.frame_count() > 1 {
        target.stance(OffsetMode::Replace).up
    } else {
        Up::guess(&target.skeleton)
    }
}
