//! How plausible a motion is, in the numbers papers on generated motion report: foot skating
//! (guided-motion-diffusion's `calculate_skating_ratio`), ground penetration, floating and
//! foot sliding (PhysDiff's Penetrate, Float and Skate, and their sum Phys-Err), jitter (the
//! mean jerk of every joint) and bone-length drift (for positions, whose bones may stretch).
//!
//! Everything is measured on joint positions in metres standing along +y, at the take's own
//! rate, against one floor: a height given (`0` for HumanML3D's and AMASS's conventions), or
//! read from the motion (the median of the lowest point over the frames a foot is planted).
//! The definitions, with their sources:
//! - **Skating ratio** (Karunratanakul et al., *Guided Motion Diffusion*, 2023, their
//!   `calculate_skating_ratio`): a foot (its toe joint) is in contact between two frames when
//!   it is under 5 cm above the floor in both; it skates when it then moves faster than
//!   0.5 m/s across the floor, both between those frames and on average over 5 of them
//!   (centred, the frames past the ends counting 0); the ratio is the share of frame pairs in
//!   which either foot skates.
//! - **Penetrate** (Yuan et al., *PhysDiff*, 2023): per frame, how far the lowest point is
//!   below the floor (0 above it), in millimetres, averaged over every frame.
//! - **Float** (PhysDiff): per frame, how far the lowest point is above the floor where that is
//!   more than 5 mm (0 otherwise), in millimetres, averaged over every frame.
//! - **Skate** (PhysDiff): per pair of frames, the mean distance across the floor the foot
//!   points in contact in both frames moved (0 without one), in millimetres, averaged.
//! - **Jitter**: the mean over every joint and frame of the jerk (the third difference of the
//!   position times the rate cubed), in metres per second cubed.
//! - **Bone drift**: per bone, the spread of its length over the frames (longest less
//!   shortest, over the mean); the largest.

use crate::io::error::Error;
use glam::DVec3;

/// The thresholds the metrics are measured with; the defaults are the papers'.
///
/// ```
/// let defaults = bvhview::metrics::Thresholds::default();
/// assert_eq!((defaults.contact_height, defaults.skate_speed), (0.05, 0.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// A foot point under this height above the floor touches it (metres; GMD's 5 cm).
    pub contact_height: f64,
    /// A foot in contact moving faster than this across the floor skates (m/s; GMD's 0.5).
    pub skate_speed: f64,
    /// Frames the skating speed is averaged over (GMD's 5).
    pub window: usize,
    /// The lowest point floats when it is more than this above the floor (metres; PhysDiff's
    /// 5 mm).
    pub float_tolerance: f64,
    /// The floor's height; `None`: read from the motion.
    pub floor: Option<f64>,
}

impl Default for Thresholds {
    fn default() -> Thresholds {
        Thresholds {
            contact_height: 0.05,
            skate_speed: 0.5,
            window: 5,
            float_tolerance: 0.005,
            floor: None,
        }
    }
}

/// One foot's figures.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let figure = bvhview::metrics::figure_of_take(&walk)?;
/// let measured = bvhview::metrics::measure(&figure, &Default::default())?;
/// let left = &measured.feet[0];
/// assert_eq!(left.name, "LeftToe");
/// assert!(left.skating_pairs <= left.contact_pairs);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Foot {
    /// Its point's name.
    pub name: String,
    /// Frame pairs in which it touches the floor in both frames.
    pub contact_pairs: usize,
    /// Of those, the pairs in which it skates.
    pub skating_pairs: usize,
    /// Its mean speed across the floor while in contact (m/s).
    pub mean_slide: f64,
}

/// What [`measure`] found.
///
/// ```
/// use bvhview::metrics::{Thresholds, figure_of_take, measure};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let measured = measure(&figure_of_take(&walk)?, &Thresholds::default())?;
/// assert!(measured.skating_ratio < 0.25);
/// assert_eq!(measured.phys_err(), measured.penetrate + measured.float + measured.skate);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Metrics {
    /// Frames measured.
    pub frames: usize,
    /// Their rate (frames a second).
    pub fps: f64,
    /// The floor's height (metres), and where it came from.
    pub floor: f64,
    /// `given` or `planted feet` or `lowest point`.
    pub floor_from: &'static str,
    /// Each foot.
    pub feet: Vec<Foot>,
    /// GMD's skating ratio: the share of frame pairs in which either foot skates.
    pub skating_ratio: f64,
    /// PhysDiff's Penetrate (mm), and the deepest frame's depth (mm).
    pub penetrate: f64,
    /// The deepest the lowest point goes under the floor (mm).
    pub penetrate_worst: f64,
    /// PhysDiff's Float (mm).
    pub float: f64,
    /// The share of frames that float: the lowest point above the floor by more than the
    /// tolerance, in a run of such frames that is not a flight (the hips falling as a thrown
    /// body falls, between 0.5 g and 1.5 g, over at least 3 frames).
    pub floating_frames: f64,
    /// PhysDiff's Skate (mm).
    pub skate: f64,
    /// Mean jerk (m/s³).
    pub jitter: f64,
    /// The largest spread of a bone's length over the frames (a fraction of its mean length),
    /// and the bone (child point's name).
    pub bone_drift: Option<(f64, String)>,
}

impl Metrics {
    /// PhysDiff's Phys-Err: Penetrate + Float + Skate (mm).
    pub fn phys_err(&self) -> f64 {
        self.penetrate + self.float + self.skate
    }

    /// One line of what was found, for a terminal.
    pub fn line(&self) -> String {
        let feet: Vec<String> = self
            .feet
            .iter()
            .map(|f| {
                format!(
                    "{} {}/{} pairs skating, {:.3} m/s sliding in contact",
                    f.name, f.skating_pairs, f.contact_pairs, f.mean_slide
                )
            })
            .collect();
        let drift = self.bone_drift.as_ref().map_or(String::new(), |(d, b)| {
            format!("; bone drift {:.2}% ({b})", 100.0 * d)
        });
        format!(
            "skating ratio {:.4}; penetrate {:.2} mm (worst {:.1}); float {:.2} mm ({:.1}% of \
             frames floating); skate {:.2} mm; phys-err {:.2} mm; jitter {:.2} m/s³{drift}; floor {:.4} m ({}); {} frames at \
             {:.2} fps ({})",
            self.skating_ratio,
            self.penetrate,
            self.penetrate_worst,
            self.float,
            100.0 * self.floating_frames,
            self.skate,
            self.phys_err(),
            self.jitter,
            self.floor,
            self.floor_from,
            self.frames,
            self.fps,
            feet.join("; ")
        )
    }
}

/// What is measured: points per frame (metres, standing along +y), which of them are the feet
/// (a point each: the toe, as GMD's SMPL joints 10 and 11 are), which are joints (for jitter),
/// and the bones (parent point, child point) for drift.
///
/// ```
/// use bvhview::metrics::{Figure, Thresholds, measure};
/// use glam::DVec3;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // Two points, a foot and a hip above it, gliding 0.8 m/s along x on the floor for 10 frames.
/// let points = (0..10)
///     .flat_map(|f| {
///         let x = f as f64 * 0.08;
///         [DVec3::new(x, 0.0, 0.0), DVec3::new(x, 1.0, 0.0)]
///     })
///     .collect();
/// let figure = Figure {
///     names: vec!["toe".into(), "hip".into()],
///     points,
///     feet: vec![0],
///     soles: vec![0],
///     bones: vec![(1, 0)],
///     hips: Some(1),
///     fps: 10.0,
/// };
/// let floor = Thresholds { floor: Some(0.0), ..Thresholds::default() };
/// let measured = measure(&figure, &floor)?;
/// // 7 of 9 pairs: at each end, the 5-frame mean counts 2 frames past it as 0 (0.48 m/s).
/// assert!((measured.skating_ratio - 7.0 / 9.0).abs() < 1e-12);
/// assert!((measured.skate - 80.0).abs() < 1e-9); // 8 cm a frame
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Each point's name.
    pub names: Vec<String>,
    /// Frame after frame, each point.
    pub points: Vec<DVec3>,
    /// The foot points.
    pub feet: Vec<usize>,
    /// The points planted feet rest on, for the floor read from the motion (the soles).
    pub soles: Vec<usize>,
    /// Bones: parent point, child point.
    pub bones: Vec<(usize, usize)>,
    /// The hips (the pelvis), whose path tells a jump from a hover; none: every airborne frame
    /// counts as floating.
    pub hips: Option<usize>,
    /// Frames a second.
    pub fps: f64,
}

/// The metrics of `figure` with `thresholds`.
pub fn measure(figure: &Figure, thresholds: &Thresholds) -> Result<Metrics, Error> {
    let count = figure.names.len();
    if count == 0 || figure.points.is_empty() || !figure.points.len().is_multiple_of(count) {
        return Err(Error::usage("metrics: no frames of points to measure"));
    }
    if !(figure.fps > 0.0 && figure.fps.is_finite()) {
        return Err(Error::usage(format!(
            "metrics: a rate of {} frames a second",
            figure.fps
        )));
    }
    let outside = figure
        .feet
        .iter()
        .chain(&figure.soles)
        .chain(figure.bones.iter().flat_map(|(a, b)| [a, b]))
        .chain(&figure.hips)
        .find(|&&p| p >= count);
    if let Some(p) = outside {
        return Err(Error::usage(format!(
            "metrics: point {p} named, and a frame holds {count}"
        )));
    }
    if let Some(i) = figure.points.iter().position(|p| !p.is_finite()) {
        return Err(Error::usage(format!(
            "metrics: point {} of frame {} is not a finite position",
            figure.names[i % count],
            i / count
        )));
    }
    let frames = figure.points.len() / count;
    let at = |f: usize, p: usize| figure.points[f * count + p];
    let lowest: Vec<f64> = (0..frames)
        .map(|f| (0..count).map(|p| at(f, p).y).fold(f64::INFINITY, f64::min))
        .collect();
    let (floor, floor_from) = match thresholds.floor {
        Some(height) => (height, "given"),
        None => read_floor(figure, &lowest),
    };
    let fps = figure.fps;
    let across = |a: DVec3, b: DVec3| ((b.x - a.x).powi(2) + (b.z - a.z).powi(2)).sqrt();
    let pairs = frames.saturating_sub(1);
    // GMD's skating, per foot.
    let mut skating_any = vec![false; pairs];
    let mut feet = Vec::new();
    let mut skate_sum = vec![0.0; pairs];
    let mut skate_count = vec![0usize; pairs];
    for &foot in &figure.feet {
        let speed: Vec<f64> = (0..pairs)
            .map(|t| across(at(t, foot), at(t + 1, foot)) * fps)
            .collect();
        let average = window_mean(&speed, thresholds.window);
        let low = |f: usize| at(f, foot).y - floor < thresholds.contact_height;
        let (mut contact_pairs, mut skating_pairs, mut slide) = (0, 0, 0.0);
        for t in 0..pairs {
            if !(low(t) && low(t + 1)) {
                continue;
            }
            contact_pairs += 1;
            slide += speed[t];
            skate_sum[t] += across(at(t, foot), at(t + 1, foot));
            skate_count[t] += 1;
            if speed[t] > thresholds.skate_speed && average[t] > thresholds.skate_speed {
                skating_pairs += 1;
                skating_any[t] = true;
            }
        }
        feet.push(Foot {
            name: figure.names[foot].clone(),
            contact_pairs,
            skating_pairs,
            mean_slide: if contact_pairs > 0 {
                slide / contact_pairs as f64
            } else {
                0.0
            },
        });
    }
    let mean = |values: &[f64]| {
        if values.is_empty() {
            0.0
        } else {
            values.iter().sum::<f64>() / values.len() as f64
        }
    };
    let skating_ratio = if pairs > 0 {
        skating_any.iter().filter(|&&s| s).count() as f64 / pairs as f64
    } else {
        0.0
    };
    let depth: Vec<f64> = lowest
        .iter()
        .map(|l| (floor - l).max(0.0) * 1000.0)
        .collect();
    let float: Vec<f64> = lowest
        .iter()
        .map(|l| {
            let above = l - floor;
            if above > thresholds.float_tolerance {
                above * 1000.0
            } else {
                0.0
            }
        })
        .collect();
    let airborne: Vec<bool> = lowest
        .iter()
        .map(|l| l - floor > thresholds.float_tolerance)
        .collect();
    let floating = floating_frames(&airborne, figure, frames);
    let skate: Vec<f64> = (0..pairs)
        .map(|t| match skate_count[t] {
            0 => 0.0,
            n => skate_sum[t] / n as f64 * 1000.0,
        })
        .collect();
    let jitter = jerk(figure, frames);
    let bone_drift = figure
        .bones
        .iter()
        .filter_map(|&(p, c)| {
            let lengths: Vec<f64> = (0..frames).map(|f| at(f, p).distance(at(f, c))).collect();
            let average = mean(&lengths);
            let (lo, hi) = lengths.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), l| {
                (lo.min(*l), hi.max(*l))
            });
            (average > 0.0).then(|| ((hi - lo) / average, figure.names[c].clone()))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    Ok(Metrics {
        frames,
        fps,
        floor,
        floor_from,
        feet,
        skating_ratio,
        penetrate: mean(&depth),
        penetrate_worst: depth.iter().fold(0.0, |m, d| m.max(*d)),
        float: mean(&float),
        floating_frames: floating as f64 / frames as f64,
        skate: mean(&skate),
        jitter,
        bone_drift,
    })
}

/// Gravity, metres a second squared.
const GRAVITY: f64 = 9.81;

/// How many frames float: airborne frames (`airborne`) in runs that are not a flight. A run is
/// a flight when the hips over it fall as a thrown body falls: the quadratic that best fits their
/// height curves down at between 0.5 g and 1.5 g. A run shorter than 3 frames shows no curve and
/// counts as a flight; without hips every airborne frame floats.
fn floating_frames(airborne: &[bool], figure: &Figure, frames: usize) -> usize {
    let count = figure.names.len();
    let mut floating = 0;
    let mut f = 0;
    while f < frames {
        if !airborne[f] {
            f += 1;
            continue;
        }
        let start = f;
        while f < frames && airborne[f] {
            f += 1;
        }
        let run = start..f;
        let flight = match figure.hips {
            None => false,
            Some(_) if run.len() < 3 => true,
            Some(hips) => {
                let heights: Vec<(f64, f64)> = run
                    .clone()
                    .map(|k| {
                        let t = (k - start) as f64 / figure.fps;
                        (t, figure.points[k * count + hips].y)
                    })
                    .collect();
                let curve = 2.0 * quadratic_term(&heights);
                (-1.5 * GRAVITY..=-0.5 * GRAVITY).contains(&curve)
            }
        };
        if !flight {
            floating += run.len();
        }
    }
    floating
}

/// The `a` of the least-squares `a t² + b t + c` through `points` (t, y), by Cramer's rule on
/// the normal equations.
fn quadratic_term(points: &[(f64, f64)]) -> f64 {
    // Sums of t⁰ … t⁴, and of y t⁰ … y t².
    let mut s = [0.0f64; 5];
    let mut r = [0.0f64; 3];
    for &(t, y) in points {
        let mut power = 1.0;
        for (k, slot) in s.iter_mut().enumerate() {
            *slot += power;
            if let Some(r) = r.get_mut(k) {
                *r += power * y;
            }
            power *= t;
        }
    }
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let whole = det([[s[4], s[3], s[2]], [s[3], s[2], s[1]], [s[2], s[1], s[0]]]);
    if whole.abs() < 1e-18 {
        return 0.0;
    }
    det([[r[2], s[3], s[2]], [r[1], s[2], s[1]], [r[0], s[1], s[0]]]) / whole
}

/// The mean of `values` over a window of `size` centred on each (numpy's `uniform_filter1d`
/// with `mode='constant'`: values past the ends count as 0).
fn window_mean(values: &[f64], size: usize) -> Vec<f64> {
    let size = size.max(1);
    // scipy centres an even window one value to the left of the middle.
    let before = size / 2;
    // The sums of the values up to each index: a window's sum is a difference of two, and a
    // window longer than the values costs no more than the values.
    let mut running = Vec::with_capacity(values.len() + 1);
    running.push(0.0);
    for v in values {
        running.push(running.last().copied().unwrap_or(0.0) + v);
    }
    let n = values.len();
    (0..n)
        .map(|i| {
            let start = i.saturating_sub(before).min(n);
            let end = (i + (size - before)).min(n);
            (running[end] - running[start]) / size as f64
        })
        .collect()
}

/// The floor read from the motion: the median of the lowest point over the frames a sole
/// point is planted, or the lowest point of all without a planted frame.
fn read_floor(figure: &Figure, lowest: &[f64]) -> (f64, &'static str) {
    let count = figure.names.len();
    let frames = lowest.len();
    let tracks: Vec<Vec<DVec3>> = figure
        .soles
        .iter()
        .map(|&p| (0..frames).map(|f| figure.points[f * count + p]).collect())
        .collect();
    let planting = crate::model::body::contact::Planting::default();
    let planted = planting.frames_of(&tracks, DVec3::Y, 1.0 / figure.fps);
    let mut heights: Vec<f64> = (0..frames)
        .filter(|&f| planted.iter().any(|p| p[f]))
        .map(|f| lowest[f])
        .collect();
    if heights.is_empty() {
        return (
            lowest.iter().copied().fold(f64::INFINITY, f64::min),
            "lowest point",
        );
    }
    heights.sort_by(f64::total_cmp);
    (heights[heights.len() / 2], "planted feet")
}

/// The mean jerk of every joint (m/s³): the third difference of each point's position times
/// the rate cubed.
fn jerk(figure: &Figure, frames: usize) -> f64 {
    let count = figure.names.len();
    if frames < 4 {
        return 0.0;
    }
    let at = |f: usize, p: usize| figure.points[f * count + p];
    let cube = figure.fps.powi(3);
    let mut sum = 0.0;
    for f in 0..frames - 3 {
        for p in 0..count {
            let third = at(f + 3, p) - 3.0 * at(f + 2, p) + 3.0 * at(f + 1, p) - at(f, p);
            sum += third.length() * cube;
        }
    }
    sum / ((frames - 3) * count) as f64
}

/// A take as a figure to measure: every point (joints and End Sites) in metres, turned to
/// stand along +y, its feet the toes the body reading finds (else the ankles), its soles,
/// every bone.
pub fn figure_of_take(take: &crate::Take) -> Result<Figure, Error> {
    let stance = take.stance(take.offset_mode);
    let metres = f64::from(stance.units.metres);
    let turn = stance.up.to_y_up().as_dquat();
    let body = crate::model::body::Body::of(&take.skeleton);
    let hips = body.hips;
    let foot_points = body.foot_points(&take.skeleton);
    if foot_points.len() < 4 {
        return Err(Error::usage(format!(
            "{}: the body reading finds no two feet (ankle and toe each): its contacts cannot \
             be measured",
            take.name
        )));
    }
    // foot_points: each leg's ankle then toe, in joint order.
    let feet = vec![foot_points[1], foot_points[3]];
    let soles = body.sole_points(&take.skeleton);
    // Every joint's place (an index per joint, as the feet, soles and bones are: an ASF's
    // exported points are not one a joint).
    let frames = take.frame_count().max(1);
    let points = (0..frames)
        .flat_map(|f| take.joint_places(f))
        .map(|p| turn * (p * metres))
        .collect();
    let bones = take
        .skeleton
        .joints
        .iter()
        .enumerate()
        .filter_map(|(j, joint)| Some((joint.parent?, j)))
        .collect();
    Ok(Figure {
        names: take
            .skeleton
            .joints
            .iter()
            .map(|j| j.name.clone())
            .collect(),
        points,
        feet,
        soles,
        bones,
        hips,
        fps: take.fps(),
    })
}
