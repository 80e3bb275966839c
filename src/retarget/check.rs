//! The retarget checks its own answer: the output measured against its source with the same
//! reading of the body, so that a take put on a skeleton is either right or said not to be.
//! A side crossed (the left thigh where the source's right one is) or a width collapsed (both
//! thighs from one point) is refused; the rest is said in one line.

use crate::model::body::{Body, Limb};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::Skeleton;
use crate::retarget::align::{NO_WIDTH, Ups, hip_height, source_offset_mode, to_y_up};
use crate::retarget::map::Map;
use crate::retarget::measure::{direction_errors, quantile, standing};
use glam::{DQuat, DVec3};

/// An output's width (hips or shoulders) is collapsed when, as a fraction of its skeleton's own
/// at rest, it is less than this fraction of the source's width over the source's own at rest:
/// each follows its own proportions (a cartoon's pelvis of 0.36 legs on SMPL's of 0.16 is
/// right) and narrows as the source narrows (shoulders drawn in to hold something), but no
/// further (a map that put both thighs on one source joint brought them to 0.012 of 31).
pub const COLLAPSED: f64 = 0.5;

/// A pair of joints across the body (the thighs at the hips, the upper arms at the shoulders)
/// measured in the source and in the output.
///
/// ```
/// use bvhview::retarget::Across;
///
/// // A map that put both thighs on one source joint: 0.012 of a pelvis of 0.16 legs.
/// let hips = Across { source_width: 0.22, source_rest_width: 0.22, width: 0.012,
///                     rest_width: 0.16, turn: 3.0 };
/// assert!(hips.collapsed() && !hips.crossed());
/// // A cartoon's wide pelvis on SMPL's narrow one: each keeps its own proportions.
/// let cartoon = Across { source_width: 0.36, source_rest_width: 0.36, width: 0.16,
///                        rest_width: 0.16, turn: 2.0 };
/// assert!(!cartoon.collapsed());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Across {
    /// The distance between the two, in the source's legs' lengths (the median over frames).
    pub source_width: f64,
    /// The same in the output, in its own legs' lengths.
    pub width: f64,
    /// The output skeleton's own at rest (or, widest, in its take's poses), in its legs' lengths.
    pub rest_width: f64,
    /// The source skeleton's own at rest (or, widest, in the frames measured), in its legs.
    pub source_rest_width: f64,
    /// The angle in degrees between the source's left-to-right line and the output's, seen
    /// from above (the median over frames): near 0 when each side stands where the source's
    /// does, near 180 when the sides are crossed.
    pub turn: f64,
}

impl Across {
    /// The sides stand on the other side of the body from the source's.
    pub fn crossed(&self) -> bool {
        self.turn > 90.0
    }

    /// The output's width against its skeleton's own at rest is less than [`COLLAPSED`] of the
    /// source's against its own.
    pub fn collapsed(&self) -> bool {
        let kept = |width: f64, rest: f64| if rest > 0.0 { width / rest } else { 1.0 };
        kept(self.width, self.rest_width)
            < COLLAPSED * kept(self.source_width, self.source_rest_width)
    }

    /// The source's two sides stand on one point ([`NO_WIDTH`]).
    pub fn no_source_width(&self) -> bool {
        self.source_width < NO_WIDTH
    }
}

/// What a retarget's output measures against its source.
///
/// ```
/// use bvhview::Take;
/// use bvhview::retarget::{Insist, Target};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?.trim(0..60);
/// let target = Target::load("smpl22", u64::MAX)?;
/// let put = target.apply(&walk.name, &walk.skeleton, &walk.motion, &[], Insist::default(), 1)?;
/// let check = put.check;
/// assert!(check.refusal().is_none(), "{}", check.line());
/// assert!(check.hips.unwrap().turn < 10.0);
/// assert!(check.bones_median < 10.0, "the median bone within 10° of the source's");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Check {
    /// The thighs at the hips, when both skeletons have two.
    pub hips: Option<Across>,
    /// The upper arms at the shoulders, when both skeletons have two.
    pub shoulders: Option<Across>,
    /// Each mapped bone's direction against the source's, in degrees: the median over the
    /// bones and frames measured…
    pub bones_median: f64,
    /// … and the 99th percentile.
    pub bones_p99: f64,
    /// The hips' path along the floor over the source's scaled by the legs (1 when right;
    /// `None` for a source that travels less than a tenth of its legs).
    pub path: Option<f64>,
    /// How far the output's lowest foot stands from the source's floor, scaled, in the
    /// output's legs' lengths.
    pub floor: f64,
}

impl Check {
    /// Why the output cannot be stood behind, if it cannot: a side crossed or a width collapsed.
    pub fn refusal(&self) -> Option<String> {
        let mut why = Vec::new();
        for (name, across) in [("hips", self.hips), ("shoulders", self.shoulders)] {
            let Some(across) = across else { continue };
            if across.crossed() {
                why.push(format!(
                    "its {name}' sides are crossed ({:.0}° from the source's)",
                    across.turn
                ));
            }
            if across.collapsed() {
                why.push(format!(
                    "its {name} stand {} leg lengths apart where its skeleton has them {} apart \
                     at rest (the source's {} of {})",
                    brief(across.width),
                    brief(across.rest_width),
                    brief(across.source_width),
                    brief(across.source_rest_width)
                ));
            }
            if across.no_source_width() {
                why.push(format!(
                    "the source's {name} stand {} leg lengths apart: its reading of the body put \
                     both sides on one point",
                    brief(across.source_width)
                ));
            }
        }
        (!why.is_empty()).then(|| why.join(", and "))
    }

    /// The one line of what held: sides, widths, bones, path, floor.
    pub fn line(&self) -> String {
        let mut parts = Vec::new();
        let widths: Vec<String> = [("hips", self.hips), ("shoulders", self.shoulders)]
            .into_iter()
            .filter_map(|(name, across)| {
                let a = across?;
                Some(format!(
                    "{name} {} → {} legs{}",
                    brief(a.source_width),
                    brief(a.width),
                    if a.crossed() { " (sides crossed)" } else { "" }
                ))
            })
            .collect();
        if !widths.is_empty() {
            let crossed = [self.hips, self.shoulders]
                .iter()
                .flatten()
                .any(Across::crossed);
            parts.push(format!(
                "{}; {}",
                if crossed {
                    "sides crossed"
                } else {
                    "sides held"
                },
                widths.join(", ")
            ));
        }
        parts.push(format!(
            "bones {:.1}° median, {:.1}° p99 from the source's",
            self.bones_median, self.bones_p99
        ));
        if let Some(path) = self.path {
            parts.push(format!("path ×{path:.2}"));
        }
        parts.push(format!("feet {} legs from the floor", brief(self.floor)));
        format!("check: {}", parts.join("; "))
    }
}

fn brief(value: f64) -> String {
    crate::limits::brief(value)
}

/// At most this many frames, spread over the take, are measured.
const FRAMES_MEASURED: usize = 240;

/// [`Check`] of `output` (on `target`), retargeted from `source` by `map`. `target_poses`: poses
/// of the target's own take, whose widths count as its rest's where its rest pose has none
/// (Blender's FBX rest, every bone along +y).
pub fn check(
    source: &Skeleton,
    source_motion: &Motion,
    target: &Skeleton,
    output: &Motion,
    map: &Map,
    ups: Ups,
    target_poses: Option<&Motion>,
) -> Check {
    let frames = source_motion.frame_count().min(output.frame_count());
    let picked: Vec<usize> = if frames <= FRAMES_MEASURED {
        (0..frames).collect()
    } else {
        (0..FRAMES_MEASURED)
            .map(|i| i * (frames - 1) / (FRAMES_MEASURED - 1))
            .collect()
    };
    let source_cut = pick(source_motion, &picked);
    let output_cut = pick(output, &picked);
    let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
    let source_mode = source_offset_mode(source, source_motion);
    let (mut rest_s, mut rest_t) = (Vec::new(), Vec::new());
    world_transforms_f64(source, &[], OffsetMode::Replace, &mut rest_s);
    world_transforms_f64(target, &[], OffsetMode::Replace, &mut rest_t);
    let legs_s = legs(source, &map.source_body, &rest_s);
    let legs_t = legs(target, &map.target_body, &rest_t);
    let pair = |body: &Body, limb: Limb| match body.limbs.map(|side| side[limb as usize]) {
        [Some(left), Some(right)] => Some((left, right)),
        _ => None,
    };
    let across_of = |limb: Limb| -> Option<(usize, usize, usize, usize)> {
        let (sl, sr) = pair(&map.source_body, limb)?;
        let (tl, tr) = pair(&map.target_body, limb)?;
        Some((sl, sr, tl, tr))
    };
    let measured = [across_of(Limb::Thigh), across_of(Limb::UpperArm)];
    let mut target_poses_world = vec![rest_t.clone()];
    if let Some(poses) = target_poses {
        for frame in 0..poses.frame_count() {
            let mut world = Vec::new();
            world_transforms_f64(target, poses.frame(frame), OffsetMode::Replace, &mut world);
            target_poses_world.push(world);
        }
    }
    let source_rest_widths: Vec<f64> = measured
        .iter()
        .map(|joints| {
            joints.map_or(0.0, |(sl, sr, _, _)| {
                (rest_s[sr].1 - rest_s[sl].1).length() / legs_s
            })
        })
        .collect();
    let rest_widths: Vec<f64> = measured
        .iter()
        .map(|joints| {
            let Some((_, _, tl, tr)) = *joints else {
                return 0.0;
            };
            target_poses_world
                .iter()
                .map(|w| (w[tr].1 - w[tl].1).length() / legs_t)
                .fold(0.0, f64::max)
        })
        .collect();
    let samples = width_samples(
        (source, &source_cut, source_mode, us, legs_s),
        (target, &output_cut, ut, legs_t),
        &measured,
    );
    let across = |k: usize| across(&samples[k], rest_widths[k], source_rest_widths[k]);
    let errors: Vec<f64> = direction_errors(source, &source_cut, target, &output_cut, map, ups)
        .into_iter()
        .flatten()
        .filter(|e| e.is_finite())
        .collect();
    let standing = standing(source, source_motion, target, output, map, ups, 1.0);
    let path = (standing.source_path > 0.1 * legs_s && standing.ratio > 0.0)
        .then(|| standing.target_path / (standing.source_path * standing.ratio));
    let floor = if standing.source_floor.is_finite() && standing.target_floor.is_finite() {
        (standing.target_floor - standing.source_floor * standing.ratio).abs() / legs_t
    } else {
        0.0
    };
    Check {
        hips: across(0),
        shoulders: across(1),
        bones_median: quantile(&errors, 0.5),
        bones_p99: quantile(&errors, 0.99),
        path,
        floor,
    }
}

/// Per line across the body `measured` (source left and right, target left and right), per
/// frame of the cut takes: its width on the source and on the target (in legs), and the turn
/// between them along the floor in degrees (NaN where either stands upright).
fn width_samples(
    (source, source_cut, source_mode, us, legs_s): (&Skeleton, &Motion, OffsetMode, DQuat, f64),
    (target, output_cut, ut, legs_t): (&Skeleton, &Motion, DQuat, f64),
    measured: &[Option<(usize, usize, usize, usize)>; 2],
) -> [Vec<(f64, f64, f64)>; 2] {
    let mut samples: [Vec<(f64, f64, f64)>; 2] = [Vec::new(), Vec::new()];
    let (mut ws, mut wt) = (Vec::new(), Vec::new());
    for frame in 0..source_cut.frame_count().min(output_cut.frame_count()) {
        world_transforms_f64(source, source_cut.frame(frame), source_mode, &mut ws);
        world_transforms_f64(
            target,
            output_cut.frame(frame),
            OffsetMode::Replace,
            &mut wt,
        );
        for (k, joints) in measured.iter().enumerate() {
            let Some((sl, sr, tl, tr)) = *joints else {
                continue;
            };
            let a = us * (ws[sr].1 - ws[sl].1);
            let b = ut * (wt[tr].1 - wt[tl].1);
            let (fa, fb) = (DVec3::new(a.x, 0.0, a.z), DVec3::new(b.x, 0.0, b.z));
            // A line across the body that stands upright says nothing of the sides.
            if fa.length() < 0.2 * a.length() || fb.length() < 0.2 * b.length() {
                samples[k].push((a.length() / legs_s, b.length() / legs_t, f64::NAN));
                continue;
            }
            let turn = fa.angle_between(fb).to_degrees();
            samples[k].push((a.length() / legs_s, b.length() / legs_t, turn));
        }
    }
    samples
}

/// One line across the body measured over the frames (`values`, see [`width_samples`]), with
/// its widths at rest; `None` without frames.
fn across(values: &[(f64, f64, f64)], rest_width: f64, source_rest_width: f64) -> Option<Across> {
    if values.is_empty() {
        return None;
    }
    let column = |f: fn(&(f64, f64, f64)) -> f64| -> Vec<f64> {
        values.iter().map(f).filter(|v| v.is_finite()).collect()
    };
    let turns = column(|v| v.2);
    Some(Across {
        source_width: quantile(&column(|v| v.0), 0.5),
        width: quantile(&column(|v| v.1), 0.5),
        rest_width,
        source_rest_width: source_rest_width.max(column(|v| v.0).into_iter().fold(0.0, f64::max)),
        turn: if turns.is_empty() {
            0.0
        } else {
            quantile(&turns, 0.5)
        },
    })
}

/// The legs' length at rest, or the rest pose's largest spread without legs (1 when nothing
/// can be measured): what widths are counted in.
fn legs(skeleton: &Skeleton, body: &Body, rest: &[(DQuat, DVec3)]) -> f64 {
    let length = match body.hips {
        Some(hips) => hip_height(skeleton, body, hips, rest),
        None => body.leg_length(rest).unwrap_or(0.0),
    };
    if length > 1e-9 { length } else { 1.0 }
}

/// The frames `picked` of `motion`.
fn pick(motion: &Motion, picked: &[usize]) -> Motion {
    let mut data = Vec::with_capacity(picked.len() * motion.channels);
    for &frame in picked {
        data.extend_from_slice(motion.frame(frame));
    }
    Motion::new(motion.frame_time, motion.channels, picked.len(), data)
}
