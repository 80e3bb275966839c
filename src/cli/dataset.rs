//! `bvhview dataset`: a folder of takes compiled into training arrays (`crate::dataset`).

use super::wrote;
use crate::dataset::{self, Options};
use crate::io::error::Error;
use crate::model::pose::RotationKind;
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct DatasetArgs {
    /// The folder of takes (.bvh, .fbx, .gltf, .glb, and .asf/.amc pairs; subfolders too).
    dir: PathBuf,
    /// The dataset folder to make (it must not exist, or be empty).
    #[arg(short, long)]
    output: PathBuf,
    /// The one frame rate every clip is resampled to (default: 30; with --features humanml3d,
    /// HumanML3D's 20).
    #[arg(long)]
    fps: Option<f64>,
    /// How local rotations are written.
    #[arg(long, value_enum, default_value_t)]
    rotations: RotationsArg,
    /// Positions relative to the root's place on the floor (x and z) in each frame.
    #[arg(long)]
    root_relative: bool,
    /// The points foot contacts are given for, by name as the dataset names them (End Sites
    /// are `<parent>_End`), separated by commas. Default: the ankle and the toe of each leg, as
    /// `info`'s `body:` line reads them (a body without two feet: guessed from the rest pose,
    /// with a warning).
    #[arg(long, value_delimiter = ',')]
    feet: Option<Vec<String>>,
    /// A foot point is in contact when it is at most this many metres above the floor (the
    /// lowest foot point within a second of the frame)...
    #[arg(long, default_value_t = 0.05)]
    contact_height: f32,
    /// ...and moves slower than this many metres per second.
    #[arg(long, default_value_t = 0.5)]
    contact_speed: f32,
    /// Put each clip's lowest foot point (over the whole clip) on y = 0.
    #[arg(long)]
    ground: bool,
    /// Hold each take's planted feet where they landed first (as `convert --lock-feet`).
    #[arg(long)]
    lock_feet: bool,
    /// With --rotations quat: choose each frame's quaternion sign against the previous frame's,
    /// so that they run continuously along time (default: w ≥ 0 in every frame).
    #[arg(long)]
    quat_continuous: bool,
    /// Threads (default: every core).
    #[arg(long)]
    threads: Option<usize>,
    /// Files larger than this many bytes are skipped.
    #[arg(long, default_value_t = crate::take::DEFAULT_MAX_SIZE)]
    max_size: u64,
    /// The units every take's lengths are in, over the guess: mm, cm, m, in, ft, or metres per
    /// unit (the manifest records that they were given).
    #[arg(long, value_name = "UNITS", value_parser = super::convert::parse_units)]
    units: Option<crate::model::stance::Units>,
    /// The axis every take stands along, over the guess (the manifest records that it was
    /// given).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
    /// The units every length is written in: mm, cm, m, in, ft, or metres per unit (default
    /// metres; the manifest records them). Contact thresholds and metrics stay in metres;
    /// `--features humanml3d` is metres by its definition.
    #[arg(long, value_name = "UNITS", value_parser = super::convert::parse_units)]
    out_units: Option<crate::model::stance::Units>,
    /// Retarget every take onto this skeleton first (a file, or the built-in `smpl22`), so that
    /// the folder makes one group; takes whose map misses a required role are skipped.
    #[arg(long, value_name = "TARGET")]
    onto: Option<String>,
    #[command(flatten)]
    onto_stated: super::OntoStated,
    /// With --onto: override every take's guessed joint map, as `retarget --map` does: SRC=DST
    /// (SRC= leaves a source joint out), or a TOML or JSON file of such pairs. A file's
    /// `[stated.FINGERPRINT]` sections (`units = "cm"`, `up = "z"`) say what each rig's takes
    /// are, with or without --onto. Repeatable.
    #[arg(long, value_name = "FILE|SRC=DST")]
    map: Vec<String>,
    /// With --onto: put on it takes whose body is not two-legged like the target's (a
    /// four-legged take onto a person, or the reverse), which are skipped otherwise.
    #[arg(long, requires = "onto")]
    any_body: bool,
    /// With --onto: keep takes whose retarget's check finds a side crossed or a width
    /// collapsed (skipped otherwise), each with a warning in the manifest.
    #[arg(long, requires = "onto")]
    force: bool,
    /// What each take is written as: bvhview's arrays grouped by skeleton, or HumanML3D's
    /// 263-value vectors in its folder layout (new_joint_vecs/ID.npy, new_joints/ID.npy,
    /// Mean.npy, Std.npy, all.txt; with --onto smpl22), as its own pipeline makes them.
    #[arg(long, value_enum, default_value_t)]
    features: FeaturesArg,
}

/// `--features`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub(crate) enum FeaturesArg {
    /// bvhview's arrays, grouped by skeleton topology.
    #[default]
    Arrays,
    /// HumanML3D's feature vectors (text-to-motion models' training data).
    #[value(name = "humanml3d")]
    HumanMl3d,
}

/// `--rotations`.
#[derive(Clone, Copy, Debug, Default, ValueEnum)]
pub(crate) enum RotationsArg {
    /// (w, x, y, z), w ≥ 0.
    Quat,
    /// 3 × 3 matrices.
    Matrix,
    /// The matrix's first two columns (Zhou et al. 2019).
    #[default]
    #[value(name = "6d")]
    SixD,
    /// Each joint's rotation channels in its file order, degrees.
    Euler,
    /// The rotation vector: unit axis times angle in radians.
    #[value(name = "axis_angle")]
    AxisAngle,
}

impl From<RotationsArg> for RotationKind {
    fn from(arg: RotationsArg) -> RotationKind {
        match arg {
            RotationsArg::Quat => RotationKind::Quat,
            RotationsArg::Matrix => RotationKind::Matrix,
            RotationsArg::SixD => RotationKind::SixD,
            RotationsArg::Euler => RotationKind::Euler,
            RotationsArg::AxisAngle => RotationKind::AxisAngle,
        }
    }
}

/// Compiles; each skipped take is said on stderr with its `path:line:column`. Exits 2, writing
/// nothing, when no take could be compiled; 0 otherwise (the manifest lists what was skipped).
pub(crate) fn run(args: DatasetArgs) -> Result<ExitCode, Error> {
    let features = match args.features {
        FeaturesArg::Arrays => dataset::FeatureSet::Arrays,
        FeaturesArg::HumanMl3d => dataset::FeatureSet::HumanMl3d,
    };
    let default_fps = match features {
        dataset::FeatureSet::HumanMl3d => crate::humanml3d::FPS,
        dataset::FeatureSet::Arrays => Options::default().fps,
    };
    let options = Options {
        fps: args.fps.unwrap_or(default_fps),
        features,
        rotations: args.rotations.into(),
        root_relative: args.root_relative,
        feet: args.feet,
        contact_height: args.contact_height,
        contact_speed: args.contact_speed,
        ground: args.ground,
        quat_continuous: args.quat_continuous,
        lock_feet: args.lock_feet,
        map: super::retarget::map_pairs(&args.map)?,
        max_size: args.max_size,
        units: args.units,
        up: args.up.map(Into::into),
        onto: args
            .onto
            .as_deref()
            .map(|onto| args.onto_stated.target(onto, args.max_size))
            .transpose()?,
        any_body: args.any_body,
        force: args.force,
        out_units: args.out_units,
    };
    // Options are checked before the folder is read (`Writer::create` checks them again).
    options.check()?;
    let walk = dataset::walk(&args.dir)?;
    for line in walk.skipped_lines() {
        super::note(format_args!("{line}"));
    }
    let items = walk.items;
    let takes = dataset::whole_list(&args.dir, &items);
    let threads = args
        .threads
        .unwrap_or_else(crate::io::parallel::cores)
        .max(1);
    let progress = super::Progress::new(items.len());
    let summary = dataset::compile(
        &args.dir,
        items,
        &options,
        threads,
        &args.output,
        takes,
        |_, error, finished, _| {
            // A line goes on a line of its own, the bar drawn again below it.
            progress.done();
            if let Some(error) = error {
                super::note(format_args!("skipped {}", super::said(error)));
            }
            progress.show(finished);
            true
        },
    )?;
    progress.done();
    let layout = match features {
        dataset::FeatureSet::HumanMl3d => "HumanML3D's layout".to_string(),
        dataset::FeatureSet::Arrays => crate::io::error::counted(summary.groups, "topology group"),
    };
    wrote(format_args!(
        "{}: {}, {} at {} fps in {layout}; {} skipped",
        args.output.display(),
        crate::io::error::counted(summary.clips, "clip"),
        crate::io::error::counted(
            summary.frames,
            match features {
                dataset::FeatureSet::HumanMl3d => "vector",
                dataset::FeatureSet::Arrays => "frame",
            }
        ),
        crate::limits::show(options.fps),
        summary.skipped.len()
    ));
    Ok(ExitCode::SUCCESS)
}
