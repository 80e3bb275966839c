//! `bvhview metrics`: how plausible a take is (foot skating, penetration, floating, sliding,
//! jitter, bone drift), per take, or as a table for a folder.

use super::{Source, check_output, note};
use crate::io::error::Error;
use crate::metrics::{Figure, Metrics, Thresholds, figure_of_take, measure};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Args)]
pub(crate) struct MetricsArgs {
    /// A take, or a folder of takes (as `info DIR` walks it), or an .npy of joint positions
    /// (frames × 22 × 3 in SMPL's order and metres, y up: HumanML3D's `new_joints`, a motion
    /// model's output; with --fps).
    input: PathBuf,
    #[command(flatten)]
    source: Source,
    /// The axis the take stands along, over the guess (as `info --up`): y, z, x, -y, -z or -x
    /// (the last four turn it to stand along y as it is read, said).
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<super::UpArg>,
    /// The floor's height in metres (0 for HumanML3D's and AMASS's motion, which stand on it);
    /// default: read from the motion, the median of the lowest point while a foot is planted.
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    floor: Option<f64>,
    /// A foot under this height above the floor touches it (metres; default GMD's 0.05).
    #[arg(long, value_name = "METRES", default_value_t = 0.05)]
    contact_height: f64,
    /// A foot in contact moving faster than this skates (m/s; default GMD's 0.5).
    #[arg(long, value_name = "M/S", default_value_t = 0.5)]
    skate_speed: f64,
    /// Frames the skating speed is averaged over (default GMD's 5).
    #[arg(long, value_name = "FRAMES", default_value_t = 5)]
    window: usize,
    /// The lowest point floats when it is more than this above the floor (metres; default
    /// PhysDiff's 0.005).
    #[arg(long, value_name = "METRES", default_value_t = 0.005)]
    float_tolerance: f64,
    /// Frames per second of an .npy of positions (it holds none; HumanML3D's are 20).
    #[arg(long)]
    fps: Option<f64>,
    /// Write the table: .csv or .json (one row per take, with the thresholds).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// The columns of the table, in order.
const COLUMNS: [&str; 14] = [
    "take",
    "frames",
    "fps",
    "skating_ratio",
    "penetrate_mm",
    "penetrate_worst_mm",
    "float_mm",
    "floating_frames",
    "skate_mm",
    "phys_err_mm",
    "jitter_m_s3",
    "bone_drift",
    "floor_m",
    "floor_from",
];

pub(crate) fn run(mut args: MetricsArgs) -> Result<ExitCode, Error> {
    args.source.up = args.up.map(Into::into);
    if let Some(output) = &args.output {
        check_output(output, &["csv", "json"])?;
    }
    let thresholds = Thresholds {
        contact_height: positive("contact-height", args.contact_height)?,
        skate_speed: positive("skate-speed", args.skate_speed)?,
        window: args.window.max(1),
        float_tolerance: positive("float-tolerance", args.float_tolerance)?,
        floor: match args.floor {
            Some(height) if !height.is_finite() => {
                return Err(Error::usage(format!(
                    "--floor {height}: a height in metres"
                )));
            }
            floor => floor,
        },
    };
    let mut rows: Vec<(String, Metrics)> = Vec::new();
    let mut failed = 0;
    if args.input.is_dir() {
        let walk = crate::info::batch::collect_takes(&args.input)?;
        for line in walk.skipped_lines() {
            note(format_args!("{line}"));
        }
        for item in walk.items.iter().filter(|i| !i.is_unpaired_motion()) {
            let shown = item
                .motion
                .as_deref()
                .unwrap_or(&item.path)
                .display()
                .to_string();
            let mut options = args.source.open_options(1);
            options.motion = item.motion.clone();
            // A take that does not load fails the run; one that is no two-legged body (a
            // prop, a hand) is skipped, said.
            let take = match options.open(&item.path) {
                Ok(take) => take,
                Err(why) => {
                    failed += 1;
                    eprintln!("bvhview: {}", super::said(&why));
                    continue;
                }
            };
            match figure_of_take(&take).and_then(|figure| measure(&figure, &thresholds)) {
                Ok(metrics) => rows.push((shown, metrics)),
                Err(why) => note(format_args!("skipped {}", super::said(&why))),
            }
        }
        if rows.is_empty() {
            return Err(Error::usage(format!(
                "{}: no take measured ({} that did not load)",
                args.input.display(),
                failed
            )));
        }
    } else {
        let mut thresholds = thresholds;
        let figure = if crate::take::extension(&args.input) == "npy" {
            if args.up.is_some() || args.source.units.is_some() {
                return Err(Error::usage(format!(
                    "{}: an .npy of positions is SMPL's joints in metres and y up, as \
                     HumanML3D's are; --up and --units say what a take is",
                    args.input.display()
                )));
            }
            // Positions in SMPL's order stand on y = 0, as HumanML3D's and GMD's do.
            if thresholds.floor.is_none() {
                thresholds.floor = Some(0.0);
                note(format_args!(
                    "{}: the floor at y = 0, as HumanML3D's positions stand (--floor says \
                     otherwise)",
                    args.input.display()
                ));
            }
            positions_figure(&args.input, args.fps, args.source.max_size)?
        } else {
            figure_of_take(&super::load(&args.input, &args.source)?)?
        };
        rows.push((
            args.input.display().to_string(),
            measure(&figure, &thresholds)?,
        ));
    }
    let mut out = std::io::stdout().lock();
    for (name, metrics) in &rows {
        let _ = writeln!(out, "{name}: {}", metrics.line());
    }
    if rows.len() > 1 {
        let mean = |f: &dyn Fn(&Metrics) -> f64| {
            rows.iter().map(|(_, m)| f(m)).sum::<f64>() / rows.len() as f64
        };
        let _ = writeln!(
            out,
            "{} takes (mean): skating ratio {:.4}; penetrate {:.2} mm; float {:.2} mm; skate \
             {:.2} mm; phys-err {:.2} mm; jitter {:.2} m/s³",
            rows.len(),
            mean(&|m| m.skating_ratio),
            mean(&|m| m.penetrate),
            mean(&|m| m.float),
            mean(&|m| m.skate),
            mean(&|m| m.phys_err()),
            mean(&|m| m.jitter)
        );
    }
    if let Some(path) = &args.output {
        let text = if crate::take::extension(path) == "json" {
            json(&rows, &thresholds)
        } else {
            csv(&rows)
        };
        crate::io::output::AtomicFile::write_whole(path, text.as_bytes())?;
        super::wrote(format_args!(
            "{}: {}",
            path.display(),
            crate::io::error::counted(rows.len(), "take")
        ));
    }
    Ok(if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn positive(flag: &str, value: f64) -> Result<f64, Error> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(Error::usage(format!("--{flag} {value}: a number above 0")))
    }
}

/// An .npy of SMPL's 22 joints, metres, y up, as a figure: its feet SMPL's (10, 11), its soles
/// the ankles and feet, SMPL's bones.
fn positions_figure(path: &Path, fps: Option<f64>, max_size: u64) -> Result<Figure, Error> {
    let Some(fps) = fps else {
        return Err(Error::usage(format!(
            "{}: an .npy holds no rate: give it with --fps (HumanML3D's is 20)",
            path.display()
        )));
    };
    let (positions, _) = crate::solve::read_positions(path, Some("smpl22"), 1.0 / fps, max_size)?;
    let names = positions.names.clone();
    let index = |n: &str| names.iter().position(|m| m == n);
    let point =
        |n: &str| index(n).ok_or_else(|| Error::usage(format!("{}: no {n}", path.display())));
    let parents = crate::smpl::ModelType::Smpl.parents();
    let bones = (1..names.len())
        .filter_map(|k| Some((parents.get(k).copied().flatten()?, k)))
        .collect();
    Ok(Figure {
        feet: vec![point("left_foot")?, point("right_foot")?],
        soles: ["left_ankle", "left_foot", "right_ankle", "right_foot"]
            .iter()
            .map(|n| point(n))
            .collect::<Result<_, _>>()?,
        bones,
        hips: index("pelvis"),
        names,
        points: positions.points,
        fps,
    })
}

fn csv(rows: &[(String, Metrics)]) -> String {
    let mut text = COLUMNS.join(",") + "\n";
    for (name, m) in rows {
        let quoted = format!("\"{}\"", name.replace('"', "\"\""));
        let drift = m.bone_drift.as_ref().map_or(0.0, |(d, _)| *d);
        text.push_str(&format!(
            "{quoted},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            m.frames,
            m.fps,
            m.skating_ratio,
            m.penetrate,
            m.penetrate_worst,
            m.float,
            m.floating_frames,
            m.skate,
            m.phys_err(),
            m.jitter,
            drift,
            m.floor,
            m.floor_from
        ));
    }
    text
}

fn json(rows: &[(String, Metrics)], thresholds: &Thresholds) -> String {
    let takes: Vec<serde_json::Value> = rows
        .iter()
        .map(|(name, m)| {
            serde_json::json!({
                "take": name,
                "frames": m.frames,
                "fps": m.fps,
                "skating_ratio": m.skating_ratio,
                "penetrate_mm": m.penetrate,
                "penetrate_worst_mm": m.penetrate_worst,
                "float_mm": m.float,
                "floating_frames": m.floating_frames,
                "skate_mm": m.skate,
                "phys_err_mm": m.phys_err(),
                "jitter_m_s3": m.jitter,
                "bone_drift": m.bone_drift.as_ref().map(|(d, b)| serde_json::json!({"spread": d, "bone": b})),
                "floor_m": m.floor,
                "floor_from": m.floor_from,
                "feet": m.feet.iter().map(|f| serde_json::json!({
                    "point": f.name,
                    "contact_pairs": f.contact_pairs,
                    "skating_pairs": f.skating_pairs,
                    "mean_slide_m_s": f.mean_slide,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    let document = serde_json::json!({
        "thresholds": {
            "contact_height_m": thresholds.contact_height,
            "skate_speed_m_s": thresholds.skate_speed,
            "window_frames": thresholds.window,
            "float_tolerance_m": thresholds.float_tolerance,
            "floor_m": thresholds.floor,
        },
        "takes": takes,
    });
    serde_json::to_string_pretty(&document).unwrap_or_default() + "\n"
}
