//! `bvhview solve`: joint positions (a model's output, a pose estimator's) as a take on a
//! skeleton, written as BVH or glTF.

use super::{UpArg, check_output, note, parse_max_size};
use crate::io::error::Error;
use crate::retarget::Target;
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct SolveArgs {
    /// The positions: an .npy of frames × joints × 3 (float32 or float64), or the .csv `bvhview
    /// positions` writes.
    input: PathBuf,
    /// The skeleton to solve onto: a .bvh, .fbx, .gltf, .glb or .asf file (its motion is not
    /// used), or the built-in `smpl22`.
    #[arg(long, value_name = "SKELETON")]
    onto: String,
    #[command(flatten)]
    onto_stated: super::OntoStated,
    /// What the input holds: joint positions (the default), or HumanML3D's 263-value feature
    /// vectors (frames × 263 .npy, `new_joint_vecs`), recovered to positions as HumanML3D's
    /// `recover_from_ric` does.
    #[arg(long = "from", value_enum, default_value_t = SolveFrom::Positions)]
    from: SolveFrom,
    /// The .npy's joints in order: a layout (`smpl22`, the same as `humanml3d`: SMPL's 22 joints
    /// in SMPL's order), or names separated by commas. Without it, 22 joints are read in SMPL's
    /// order (and said).
    #[arg(long, value_name = "LAYOUT|A,B,…")]
    joints: Option<String>,
    /// The positions are a pose estimator's keypoints in this layout: h36m17 (Human3.6M's 17,
    /// as VideoPose3D and MotionBERT write them), coco17, mediapipe33, body25 (OpenPose) or
    /// smpl24; an .npy of frames × points × 3, or × 4 with a confidence last (as `positions
    /// --layout` writes it), a .json array of the same, or a positions .csv of its points. Each point goes to the
    /// skeleton's joint of its role; joints the layout lacks are placed from the others, points
    /// a frame lacks filled from the frames around, the figure stood up along +y; all said.
    #[arg(long, value_name = "LAYOUT", conflicts_with = "joints")]
    layout: Option<String>,
    /// With --layout: a point under this confidence counts as missing from its frame and is
    /// filled from the frames around it.
    #[arg(long, value_name = "C", default_value_t = 0.3, requires = "layout")]
    min_confidence: f64,
    /// Frames per second of the positions (neither an .npy nor the CSV holds it; HumanML3D's
    /// are 20).
    #[arg(long)]
    fps: f64,
    /// The positions' up axis, when it is not the skeleton's (HumanML3D's is y).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<UpArg>,
    /// Smooth jittery positions (a pose estimator's): a zero-phase low-pass at this cutoff in
    /// Hz on the solved root path and rotations, as `convert --smooth`.
    #[arg(long, value_name = "HZ")]
    smooth: Option<f64>,
    /// Refuse inputs larger than this (K, M, G suffixes).
    #[arg(long, value_name = "SIZE", default_value = "8G", value_parser = parse_max_size)]
    max_size: u64,
    /// The user's SMPL-family model file (an .npz, or a folder with a neutral one): the points
    /// are solved onto the model's own figure, its betas fitted to their bone lengths (no
    /// optimisation of the pose), and `-o out.npz` writes them with the betas.
    #[arg(long, value_name = "MODEL.npz|DIR")]
    body_model: Option<std::path::PathBuf>,
    /// The file to write: .bvh, glTF as .glb (binary) or .gltf (text, data inline), or .fbx.
    #[arg(short, long)]
    output: PathBuf,
    /// The units to write in: mm, cm, m, in, ft, or metres per unit (the result is in the
    /// target's own units without it).
    #[arg(long, value_name = "UNITS", value_parser = super::convert::parse_units)]
    out_units: Option<crate::model::stance::Units>,
}

/// `positions` without the points named in `placed` (joints a layout lacks, placed from its
/// other points).
fn measured_points(
    positions: &crate::solve::Positions,
    placed: &[String],
) -> Result<crate::solve::Positions, Error> {
    if placed.is_empty() {
        return Ok(positions.clone());
    }
    let keep: Vec<usize> = (0..positions.names.len())
        .filter(|&c| !placed.contains(&positions.names[c]))
        .collect();
    let count = positions.names.len();
    let points = positions
        .points
        .chunks_exact(count)
        .flat_map(|frame| keep.iter().map(|&c| frame[c]).collect::<Vec<_>>())
        .collect();
    let names = keep.iter().map(|&c| positions.names[c].clone()).collect();
    crate::solve::Positions::new(names, points, positions.frame_time)
}

/// What `solve` reads.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SolveFrom {
    /// Joint positions: an .npy of frames × joints × 3, or the positions CSV.
    Positions,
    /// HumanML3D's feature vectors: an .npy of frames × 263.
    Humanml3d,
}

pub(crate) fn run(args: SolveArgs) -> Result<ExitCode, Error> {
    check_output(&args.output, &["bvh", "glb", "gltf", "fbx", "npz"])?;
    if !(args.fps > 0.0 && args.fps.is_finite() && args.fps <= 1000.0) {
        return Err(Error::usage(format!(
            "--fps {}: frames per second from above 0 to 1000",
            args.fps
        )));
    }
    let layout = match &args.layout {
        Some(name) => Some(
            crate::solve::layouts::Layout::parse(name)
                .map_err(|why| Error::usage(format!("--layout {name}: {why}")))?,
        ),
        None => None,
    };
    if layout.is_some() && args.from == SolveFrom::Humanml3d {
        return Err(Error::usage(
            "--from humanml3d: its 22 joints are SMPL's; --layout is for a pose estimator's \
             keypoints",
        ));
    }
    let mut placed_names: Vec<String> = Vec::new();
    let (positions, layout_note) = match (args.from, layout) {
        (_, Some(layout)) => {
            let keypoints = crate::solve::layouts::read_keypoints(
                &args.input,
                layout,
                1.0 / args.fps,
                args.max_size,
            )?;
            let shown = args.input.display().to_string();
            let up_given = args
                .up
                .map(|up| crate::model::pose::UpAxis::from(up).vector().as_dvec3());
            let placed =
                crate::solve::layouts::to_smpl(&keypoints, args.min_confidence, up_given, &shown)?;
            for line in &placed.said {
                note(format_args!("{shown}: {line}"));
            }
            placed_names = placed.placed;
            (placed.positions, None)
        }
        (SolveFrom::Positions, None) => crate::solve::read_positions(
            &args.input,
            args.joints.as_deref(),
            1.0 / args.fps,
            args.max_size,
        )?,
        (SolveFrom::Humanml3d, None) => {
            if args.joints.is_some() {
                return Err(Error::usage(
                    "--from humanml3d: its 22 joints are SMPL's, in SMPL's order; --joints is for \
                     positions",
                ));
            }
            let shown = args.input.display().to_string();
            let bytes = crate::solve::read_npy_file(&args.input, args.max_size)?;
            let vectors = crate::humanml3d::read_vectors(&bytes, &shown)?;
            let points =
                crate::humanml3d::recover_from_ric(&vectors).map_err(|e| e.about(&shown))?;
            let positions = crate::solve::Positions::new(
                crate::solve::joint_names("smpl22"),
                points,
                1.0 / args.fps,
            )
            .map_err(|e| e.about(&shown))?;
            (positions, None)
        }
    };
    if let Some(layout_note) = layout_note {
        eprintln!("bvhview: {}", layout_note.spelled(&super::Flags));
    }
    let (target, body) = match &args.body_model {
        Some(path) => {
            // The model's own figure, its betas fitted to the positions' bones: those of points
            // the data holds (a layout's joints placed from others are not measured).
            args.onto_stated.refused_with_body_model()?;
            let wanted = crate::smpl::fit::model_type_of_target(&args.onto);
            let model = crate::smpl::open_model(path, None, wanted, args.max_size)?;
            let measured = measured_points(&positions, &placed_names)?;
            let fitted = crate::smpl::fit::shaped_to_positions(&model, &measured)?;
            note(format_args!("{}: {}", args.input.display(), fitted.said));
            let name = format!("{} ({})", args.onto, model.name);
            let target = Target::new(name, fitted.skeleton, &fitted.rest);
            (target, Some(fitted.body))
        }
        None => (args.onto_stated.target(&args.onto, args.max_size)?, None),
    };
    // Keypoints stand along +y, named as SMPL's joints: each given to the target's joint of
    // its role.
    let (positions, data_up) = match layout {
        Some(_) => {
            let (renamed, unused) =
                crate::solve::layouts::onto_skeleton(&positions, &target.skeleton)?;
            if !unused.is_empty() {
                note(format_args!(
                    "{}: {} has no joint of the role of {}: not used",
                    args.input.display(),
                    target.name,
                    unused.join(", ")
                ));
            }
            (renamed, Some(crate::model::pose::UpAxis::Y))
        }
        None => (positions, args.up.map(Into::into)),
    };
    // What is printed is measured on what is written: after --smooth, and said where
    // smoothing made a figure worse.
    let (motion, solved, worse) = crate::solve::solve_smoothed(
        &target.skeleton,
        target.up,
        &positions,
        data_up,
        args.smooth,
    )?;
    for note in &solved.notes {
        eprintln!("bvhview: {}: warning: {note}", target.name);
    }
    let worse = worse.map_or(String::new(), |w| format!("; --smooth made worse: {w}"));
    note(format_args!(
        "solved: {}{worse}",
        solved.summary(&target.skeleton)
    ));
    if let Some(off) = solved.off_the_data_line(&target.skeleton) {
        // Bones of other lengths than the data's (or smoothing): each point where it stands off.
        let why = if args.smooth.is_some() {
            "the skeleton's bones are not the data's, or --smooth moved them"
        } else {
            "the skeleton's bones are not the data's"
        };
        note(format_args!("off the data ({why}): {off}"));
    }
    super::write_result(
        &args.output,
        target.skeleton.clone(),
        motion,
        args.out_units,
        body,
        &target,
    )
}
