//! A body model's shape fitted to another skeleton: the betas whose bones are as long as the
//! source's, for a take put on the model and written as AMASS's parameters.
//!
//! A joint of the model is linear in the betas (`J_regressor · (v_template + shapedirs · β)`),
//! so each bone is `c + E β`; the lengths are fitted by Gauss-Newton with a light pull towards
//! the mean shape (`β = 0`), which keeps components the bones do not see at zero.

use super::model::BodyModel;
use super::{Body, ModelType};
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use glam::DVec3;

/// How many betas are fitted: the first ten, the components every model file has.
pub const FITTED_BETAS: usize = 10;

/// The pull towards the mean shape, in square metres a beta (a bone's length moves about a
/// centimetre a beta: this weighs a beta's square as a tenth of a millimetre's).
const PULL: f64 = 1e-8;

/// The relative miss at which a bone's pull on the fit starts to fade (Cauchy's scale): 10%.
const ROBUST: f64 = 0.1;

/// The model's figure shaped to the source: its skeleton (the built-in figure of the model's
/// type, the model's joints of the fitted betas), one rest frame, the body it is, and a line
/// saying how well the bones fit.
///
/// ```no_run
/// use bvhview::smpl::{fit, model::BodyModel};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let smplx = BodyModel::open("models/SMPLX_NEUTRAL.npz".as_ref(), None, None, u64::MAX)?;
/// let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let metres = f64::from(walk.stance(walk.offset_mode).units.metres);
/// let fitted = fit::shaped_to(&smplx, &walk.skeleton, metres)?;
/// println!("{}", fitted.said); // betas fitted …: 12.3% → 2.1% median length difference
/// assert_eq!(fitted.body.betas.len(), 10);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Fitted {
    /// The model's figure of the fitted shape, metres, Y up.
    pub skeleton: Skeleton,
    /// Its rest pose, one frame (the root where the model rests its pelvis).
    pub rest: Motion,
    /// The fitted body: model type, betas, the model's gender, its rest pelvis.
    pub body: Body,
    /// What was fitted, for the user.
    pub said: String,
}

/// `model` shaped to `source` (metres per unit `metres`): each model bone whose two joints
/// the map from `source` finds measured between those joints of the source at rest, and the
/// betas fitted to those lengths.
pub fn shaped_to(model: &BodyModel, source: &Skeleton, metres: f64) -> Result<Fitted, Error> {
    let (figure, index_of) = super::amass::figure(model.model)?;
    let map = crate::retarget::Map::guess(source, &figure);
    let mut world = Vec::new();
    let rest_row = vec![0.0f32; source.channel_count()];
    crate::model::pose::world_transforms_f64(
        source,
        &rest_row,
        crate::model::pose::OffsetMode::Add,
        &mut world,
    );
    let joint_of = |k: usize| index_of.iter().position(|&i| i == Some(k));
    let parents = model.parents();
    // Each model bone (joint k from its parent) the source measures, and how long it is there.
    let lengths: Vec<Option<f64>> = (0..model.model.joint_count())
        .map(|k| {
            let parent = parents[k]?;
            let (a, b) = (joint_of(parent)?, joint_of(k)?);
            let (a, b) = (map.source_of[a]?, map.source_of[b]?);
            let length = world[a].1.distance(world[b].1) * metres;
            (a != b).then_some(length)
        })
        .collect();
    shaped_to_lengths(model, &lengths)
}

/// `model` shaped to joint positions, each named as the model names its joints (`pelvis`,
/// `left_hip`, …): each bone the positions have both joints of measured as its median length
/// over the frames, in the units (metres, centimetres, …) in which the bones come nearest the
/// model's mean body's.
pub fn shaped_to_positions(
    model: &BodyModel,
    positions: &crate::solve::Positions,
) -> Result<Fitted, Error> {
    let names = model.model.joint_names();
    let count = positions.names.len().max(1);
    let column = |name: &str| positions.names.iter().position(|n| n == name);
    let lengths: Vec<Option<f64>> = model
        .parents()
        .iter()
        .enumerate()
        .map(|(k, parent)| {
            let (a, b) = (column(&names[(*parent)?])?, column(&names[k])?);
            let mut seen: Vec<f64> = positions
                .points
                .chunks_exact(count)
                .map(|frame| frame[a].distance(frame[b]))
                .collect();
            seen.sort_by(f64::total_cmp);
            seen.get(seen.len() / 2).copied()
        })
        .collect();
    // Positions carry no units: those in which their bones come nearest the model's mean
    // body's (metres for a model's output, centimetres for a CMU take's `positions`).
    let mean = model.shaped(&[], &[])?.joints;
    let parents = model.parents();
    let (mut data, mut body) = (0.0, 0.0);
    for (k, length) in lengths.iter().enumerate() {
        if let (Some(length), Some(p)) = (length, parents[k]) {
            data += length;
            body += mean[k].distance(mean[p]);
        }
    }
    let units = crate::model::stance::Units::guess((1.7 * data / body.max(1e-12)) as f32);
    let metres = f64::from(units.metres);
    let lengths: Vec<Option<f64>> = lengths.iter().map(|l| l.map(|l| l * metres)).collect();
    let mut fitted = shaped_to_lengths(model, &lengths)?;
    if metres != 1.0 {
        fitted.said.push_str(&format!(
            " (the positions read as {}, by their size)",
            units.name
        ));
    }
    Ok(fitted)
}

/// `model` shaped to bone `lengths` (metres; one a joint, the bone from its parent, `None`
/// where not measured): the betas fitted, and the figure they make.
pub fn shaped_to_lengths(model: &BodyModel, lengths: &[Option<f64>]) -> Result<Fitted, Error> {
    let lengths: Vec<Option<f64>> = lengths
        .iter()
        .map(|l| l.filter(|l| l.is_finite() && *l > 0.0))
        .collect();
    let measured = lengths.iter().flatten().count();
    if measured < 3 {
        return Err(Error::usage(format!(
            "{}: the source's bones map onto {measured} of {}'s: too few to fit its shape",
            model.name,
            model.model.label()
        )));
    }
    let (figure, index_of) = super::amass::figure(model.model)?;
    let count = FITTED_BETAS.min(model.shape_count());
    let (betas, before, after) = fit(model, &lengths, count)?;
    let shaped = model.shaped(&betas, &[])?;
    let mut skeleton = figure;
    super::amass::model_offsets(&mut skeleton, &index_of, &shaped.joints);
    let channels = skeleton.channel_count();
    let mut row = vec![0.0f32; channels];
    let root = &skeleton.joints[0];
    for (c, channel) in root.channels.iter().enumerate() {
        if channel.is_position() {
            row[root.first_channel + c] = root.offset[channel.axis()];
        }
    }
    let said = if betas.iter().all(|b| *b == 0.0) {
        format!(
            "the mean shape of {} kept: no fit of its betas to the source's bone lengths \
             ({count} components, {measured} bones) lowers their median length difference, \
             {:.1}%",
            model.name,
            100.0 * before
        )
    } else {
        format!(
            "betas fitted to the source's bone lengths on {} ({count} components, {measured} \
             bones): {:.1}% → {:.1}% median length difference",
            model.name,
            100.0 * before,
            100.0 * after
        )
    };
    Ok(Fitted {
        skeleton,
        rest: Motion::new(1.0 / 30.0, channels, 1, row),
        body: Body {
            model: model.model,
            betas,
            gender: model.gender.clone(),
            rest_pelvis: Some(shaped.joints[0].to_array()),
        },
        said,
    })
}

/// The betas (`count` of them) whose bones are `lengths` long, and the median relative length
/// difference before (the mean shape) and after; the mean shape itself when no fit lowers it.
fn fit(
    model: &BodyModel,
    lengths: &[Option<f64>],
    count: usize,
) -> Result<(Vec<f64>, f64, f64), Error> {
    let parents = model.parents();
    let mean = model.shaped(&[], &[])?.joints;
    // Each component's move of every joint: J(e_l) − J(0).
    let moves: Vec<Vec<DVec3>> = (0..count)
        .map(|l| {
            let mut unit = vec![0.0; l + 1];
            unit[l] = 1.0;
            let joints = model.shaped(&unit, &[])?.joints;
            Ok(joints.iter().zip(&mean).map(|(j, m)| *j - *m).collect())
        })
        .collect::<Result<_, Error>>()?;
    let bone = |k: usize, betas: &[f64]| -> DVec3 {
        let p = parents[k].unwrap_or(k);
        let mut b = mean[k] - mean[p];
        for (l, moved) in moves.iter().enumerate() {
            b += (moved[k] - moved[p]) * betas[l];
        }
        b
    };
    let spread = |betas: &[f64]| {
        let mut off: Vec<f64> = lengths
            .iter()
            .enumerate()
            .filter_map(|(k, l)| Some((bone(k, betas).length() - (*l)?).abs() / (*l)?))
            .collect();
        off.sort_by(f64::total_cmp);
        off.get(off.len() / 2).copied().unwrap_or(0.0)
    };
    // What is minimised: each length's relative miss (what the line printed measures, so a
    // short bone counts as much as a long one) through Cauchy's ρ(r) = ln(1 + (r/c)²), so that
    // the few bones two skeletons define differently (a collar, a hip joint) do not pull every
    // other bone off, and the pull towards the mean shape.
    let rho = |r: f64| (1.0 + (r / ROBUST).powi(2)).ln();
    let cost = |betas: &[f64]| {
        let misses: f64 = lengths
            .iter()
            .enumerate()
            .filter_map(|(k, l)| Some(rho((bone(k, betas).length() - (*l)?) / (*l)?)))
            .sum();
        misses + PULL * betas.iter().map(|b| b * b).sum::<f64>()
    };
    let mut betas = vec![0.0; count];
    for _ in 0..50 {
        let mut normal = vec![vec![0.0; count]; count];
        let mut rhs = vec![0.0; count];
        for (k, length) in lengths.iter().enumerate() {
            let Some(length) = *length else { continue };
            let b = bone(k, &betas);
            let along = b.normalize_or_zero();
            let miss = (b.length() - length) / length;
            // Iteratively reweighted: Cauchy's weight 1 / (1 + (r/c)²), as a square root on
            // the row and the residual.
            let weight = (1.0 / (1.0 + (miss / ROBUST).powi(2))).sqrt();
            let residual = weight * miss;
            let p = parents[k].unwrap_or(k);
            let row: Vec<f64> = moves
                .iter()
                .map(|m| weight * along.dot(m[k] - m[p]) / length)
                .collect();
            for i in 0..count {
                rhs[i] -= row[i] * residual;
                for j in 0..count {
                    normal[i][j] += row[i] * row[j];
                }
            }
        }
        for i in 0..count {
            normal[i][i] += PULL;
            rhs[i] -= PULL * betas[i];
        }
        let Some(step) = solve(normal, rhs) else {
            break;
        };
        // The step, halved until it lowers the cost (Gauss-Newton overshoots where a bone's
        // direction turns); past ±5 a body model's shape is no body's.
        let now = cost(&betas);
        let mut scale = 1.0;
        let mut taken = None;
        while scale > 1e-4 {
            let tried: Vec<f64> = betas
                .iter()
                .zip(&step)
                .map(|(b, s)| (b + scale * s).clamp(-5.0, 5.0))
                .collect();
            if cost(&tried) < now {
                taken = Some(tried);
                break;
            }
            scale /= 2.0;
        }
        let Some(tried) = taken else { break };
        let moved = tried
            .iter()
            .zip(&betas)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        betas = tried;
        if moved < 1e-9 {
            break;
        }
    }
    // What the line prints is the median: a fit that does not lower it keeps the mean shape.
    let (before, after) = (spread(&vec![0.0; count]), spread(&betas));
    if after > before {
        return Ok((vec![0.0; count], before, before));
    }
    Ok((betas, before, after))
}

/// `a x = b` by Gaussian elimination with partial pivoting; `None` for a singular `a`.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for (offset, row) in lower.iter_mut().enumerate() {
            let factor = row[col] / pivot_row[col];
            for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= factor * p;
            }
            b[col + 1 + offset] -= factor * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let sum: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - sum) / a[row][row];
    }
    Some(x)
}

/// The model type a built-in target names (`smpl24`, `smplh52`, `smplx55`; `smpl22` and the
/// aliases `smpl`, `smplh`, `smplx` by their skeletons), if it names one.
pub fn model_type_of_target(onto: &str) -> Option<ModelType> {
    let name = crate::bvh::built_in::name_of(onto)?;
    match name {
        "smpl22" => None,
        _ => ModelType::ALL.into_iter().find(|m| m.built_in() == name),
    }
}
