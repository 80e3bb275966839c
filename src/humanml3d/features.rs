//! Joint positions to HumanML3D's feature vectors, as its `process_file` makes them: the
//! steps and quirks are in the docs of the module above ([`super`]).

use super::layout::{
    CHAINS, CONTACT_THRESHOLD, FACING_JOINTS, FOOT_POINTS, JOINTS, PARENTS, PARTS,
    REFERENCE_LENGTHS, REST_DIRECTIONS, WIDTH,
};
use super::recover::recover_from_ric;
use crate::io::error::Error;
use crate::solve::SMPL22_ORDER;
use glam::{DMat3, DQuat, DVec3};

/// A take in HumanML3D's representation, as its pipeline saves it.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// let bytes = std::fs::read("tests/humanml3d/new_joints_012314.npy").expect("in the repository");
/// let (_, points) = bvhview::solve::read_npy(&bytes, "new_joints_012314.npy")?;
/// let features = bvhview::humanml3d::features(&points)?;
/// // One vector per step between frames; the positions they stand for, frame by frame.
/// assert_eq!(features.frames(), 169);
/// assert_eq!(features.joints.len(), 169 * 22 * 3);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Features {
    /// The feature vectors, (frames − 1) × [`WIDTH`], frame after frame (`new_joint_vecs`).
    pub vectors: Vec<f32>,
    /// The joint positions the vectors stand for, (frames − 1) × 22 × 3 (`new_joints`): what
    /// [`recover_from_ric`] gives back from them.
    pub joints: Vec<f32>,
}

impl Features {
    /// Vectors (one per frame but the last of the take).
    pub fn frames(&self) -> usize {
        self.vectors.len() / WIDTH
    }
}

/// The spread of the Gaussian HumanML3D smooths the facing with, in frames.
const FACING_SMOOTHING: f64 = 20.0;

/// HumanML3D's feature vectors of a take: `positions` holds frames × 22 joint positions in SMPL's
/// order ([`SMPL22_ORDER`]), metres, y up, +z forward, at [`FPS`](crate::humanml3d::FPS).
///
/// ```
/// use bvhview::humanml3d;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // 120 frames of a walk on SMPL's 22 joints (metres, y up), as HumanML3D's `new_joints`.
/// let bytes = std::fs::read("tests/solve/walk_smpl22.npy").expect("the repository's file");
/// let (joints, points) = bvhview::solve::read_npy(&bytes, "walk_smpl22.npy")?;
/// let features = humanml3d::features(&points)?;
/// assert_eq!((joints, points.len() / joints, features.frames()), (22, 120, 119));
/// assert_eq!(features.vectors.len(), 119 * humanml3d::WIDTH);
/// # Ok(())
/// # }
/// ```
pub fn features(positions: &[DVec3]) -> Result<Features, Error> {
    if positions.is_empty() || !positions.len().is_multiple_of(JOINTS) {
        return Err(Error::usage(format!(
            "humanml3d: {} points are not whole frames of {JOINTS} joints",
            positions.len()
        )));
    }
    let frames = positions.len() / JOINTS;
    if frames < 2 {
        return Err(Error::usage(
            "humanml3d: a take of one frame has no vectors (each is a step to the next frame)",
        ));
    }
    if let Some(at) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::usage(format!(
            "humanml3d: frame {}, joint {}: not a finite position",
            at / JOINTS,
            SMPL22_ORDER[at % JOINTS]
        )));
    }
    let (mut points, mut directions) = uniform(positions, frames)?;
    place(&mut points, &mut directions)?;
    let rotations = inverse_kinematics(&points, &directions, frames)?;
    let vectors = vectors_of(&points, &rotations, frames);
    let joints = recover_from_ric(&vectors)?
        .iter()
        .flat_map(|p| p.as_vec3().to_array())
        .collect();
    Ok(Features { vectors, joints })
}

/// The names of [`SMPL22_ORDER`] as owned strings, the order [`features()`] reads.
pub fn joint_order() -> Vec<String> {
    SMPL22_ORDER.iter().map(|n| n.to_string()).collect()
}

/// `uniform_skeleton`: each bone along its own direction at the reference length, the root's
/// path scaled by the reference legs over the take's (the right thigh and shin at the first
/// frame, as HumanML3D measures them). With each bone's unit direction (the root's is zero).
fn uniform(positions: &[DVec3], frames: usize) -> Result<(Vec<DVec3>, Vec<DVec3>), Error> {
    let first = &positions[..JOINTS];
    let length = |j: usize| (first[j] - first[PARENTS[j]]).length();
    let legs = length(5) + length(8);
    if legs.is_nan() || legs <= 0.0 {
        return Err(Error::usage(
            "humanml3d: the right thigh and shin have no length at the first frame, so the take \
             cannot be scaled to the reference skeleton",
        ));
    }
    let scale = (REFERENCE_LENGTHS[5] + REFERENCE_LENGTHS[8]) / legs;
    let mut out = vec![DVec3::ZERO; positions.len()];
    let mut directions = vec![DVec3::ZERO; positions.len()];
    for f in 0..frames {
        let frame = f * JOINTS..(f + 1) * JOINTS;
        let (from, to, along) = (
            &positions[frame.clone()],
            &mut out[frame.clone()],
            &mut directions[frame],
        );
        to[0] = from[0] * scale;
        for chain in CHAINS {
            for pair in chain.windows(2) {
                let (parent, joint) = (pair[0], pair[1]);
                along[joint] = bone_direction(from, parent, joint, f)?;
                to[joint] = to[parent] + along[joint] * REFERENCE_LENGTHS[joint];
            }
        }
    }
    Ok((out, directions))
}

/// The unit direction from `parent` to `joint` in one frame's `pose`, or why there is none.
fn bone_direction(
    pose: &[DVec3],
    parent: usize,
    joint: usize,
    frame: usize,
) -> Result<DVec3, Error> {
    let bone = pose[joint] - pose[parent];
    let length = bone.length();
    match length > 0.0 {
        true => Ok(bone / length),
        false => Err(Error::usage(format!(
            "humanml3d: frame {frame}: {} is where {} is; the bone between has no direction",
            SMPL22_ORDER[joint], SMPL22_ORDER[parent]
        ))),
    }
}

/// `process_file`'s placing: the lowest point of the whole take on y = 0, the root's first
/// place at x = z = 0, and the take turned about y so that the first frame faces +z (from the
/// hips and the shoulders, right minus left).
fn place(points: &mut [DVec3], directions: &mut [DVec3]) -> Result<(), Error> {
    let floor = points.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let origin = DVec3::new(points[0].x, floor, points[0].z);
    points.iter_mut().for_each(|p| *p -= origin);
    let [right_hip, left_hip, right_shoulder, left_shoulder] = FACING_JOINTS;
    let across =
        (points[right_hip] - points[left_hip]) + (points[right_shoulder] - points[left_shoulder]);
    let forward = horizontal(DVec3::Y.cross(across.normalize_or_zero())).ok_or_else(|| {
        Error::usage(
            "humanml3d: frame 0: the hips and shoulders give no facing (they lie along the up \
             axis)",
        )
    })?;
    let turn = between(forward, DVec3::Z);
    let turn = DMat3::from_quat(turn);
    points.iter_mut().for_each(|p| *p = turn * *p);
    directions.iter_mut().for_each(|d| *d = turn * *d);
    Ok(())
}

/// `v` made unit length, or `None` when it has none to speak of.
fn horizontal(v: DVec3) -> Option<DVec3> {
    let length = v.length();
    (length > 1e-12).then(|| v / length)
}

/// HumanML3D's `qbetween` of two unit directions: the quaternion turning `from` to `to`,
/// `(|from||to| + from·to, from × to)` normalised, so its `w` is never negative. Exactly opposite directions (where it
/// gives NaN) turn half a turn about an axis perpendicular to `from`.
fn between(from: DVec3, to: DVec3) -> DQuat {
    let axis = from.cross(to);
    // `|from||to|` is 1: every direction turned here is a unit vector.
    let w = 1.0 + from.dot(to);
    let q = glam::DVec4::new(axis.x, axis.y, axis.z, w);
    let length = q.length();
    if length > 1e-12 {
        let q = q / length;
        return DQuat::from_xyzw(q.x, q.y, q.z, q.w);
    }
    let perpendicular = from.any_orthonormal_vector();
    DQuat::from_xyzw(perpendicular.x, perpendicular.y, perpendicular.z, 0.0)
}

/// `inverse_kinematics_np(…, smooth_forward=True)`: per frame, the root's rotation (turning
/// the smoothed facing to +z; the identity at the first frame) then, chain by chain, each
/// joint's rotation relative to the chain's previous bone. Frames × 22 quaternions.
fn inverse_kinematics(
    points: &[DVec3],
    directions: &[DVec3],
    frames: usize,
) -> Result<Vec<DQuat>, Error> {
    // Its quirk: the hips' vector the other way round (the module's docs).
    let [right_hip, left_hip, right_shoulder, left_shoulder] = FACING_JOINTS;
    let forwards: Vec<DVec3> = points
        .chunks_exact(JOINTS)
        .map(|p| {
            let across = (p[left_hip] - p[right_hip]) + (p[right_shoulder] - p[left_shoulder]);
            DVec3::Y.cross(across.normalize_or_zero())
        })
        .collect();
    let smoothed = gaussian_nearest(&forwards, FACING_SMOOTHING);
    let mut rotations = vec![DQuat::IDENTITY; points.len()];
    for f in 0..frames {
        let root = match f {
            0 => DQuat::IDENTITY,
            _ => between(
                horizontal(smoothed[f]).ok_or_else(|| {
                    Error::usage(format!(
                        "humanml3d: frame {f}: the hips and shoulders give no facing"
                    ))
                })?,
                DVec3::Z,
            ),
        };
        let along = &directions[f * JOINTS..(f + 1) * JOINTS];
        let out = &mut rotations[f * JOINTS..(f + 1) * JOINTS];
        out[0] = root;
        for chain in CHAINS {
            let mut carried = root;
            for &joint in &chain[1..] {
                let rest = DVec3::from_array(REST_DIRECTIONS[joint]);
                let swing = between(rest, along[joint]);
                out[joint] = carried.conjugate() * swing;
                // HumanML3D carries `R · R_loc`, which is the swing itself.
                carried = swing;
            }
        }
    }
    Ok(rotations)
}

/// SciPy's `gaussian_filter1d(values, sigma, axis=0, mode='nearest')` on horizontal vectors: a
/// Gaussian of `sigma` frames cut at four of them, the first and last values repeated past the
/// ends.
fn gaussian_nearest(values: &[DVec3], sigma: f64) -> Vec<DVec3> {
    let radius = (4.0 * sigma + 0.5) as usize;
    let mut weights: Vec<f64> = (0..=2 * radius)
        .map(|k| {
            let x = k as f64 - radius as f64;
            (-0.5 * x * x / (sigma * sigma)).exp()
        })
        .collect();
    let total: f64 = weights.iter().sum();
    weights.iter_mut().for_each(|w| *w /= total);
    let last = values.len() - 1;
    let mut out = vec![DVec3::ZERO; values.len()];
    // Each axis padded with its end values, so that every output is one dot product with the
    // weights (in eight sums side by side, which the compiler keeps in vector registers).
    let mut padded = vec![0.0f64; values.len() + 2 * radius];
    // The facing has no y (it is `y × across`): x and z only.
    for axis in [0, 2] {
        for (k, p) in padded.iter_mut().enumerate() {
            *p = values[k.saturating_sub(radius).min(last)][axis];
        }
        for (i, o) in out.iter_mut().enumerate() {
            o[axis] = dot(&padded[i..i + weights.len()], &weights);
        }
    }
    out
}

/// `a · b`, summed in eight lanes.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            lanes[k] += x[k] * y[k];
        }
    }
    lanes.iter().sum::<f64>() + tail
}

/// The vectors, one per frame but the last, from the placed points and their rotations.
fn vectors_of(points: &[DVec3], rotations: &[DQuat], frames: usize) -> Vec<f32> {
    let pose = |f: usize| &points[f * JOINTS..(f + 1) * JOINTS];
    let root = |f: usize| rotations[f * JOINTS];
    let mut vectors = Vec::with_capacity((frames - 1) * WIDTH);
    for f in 0..frames - 1 {
        let (here, next) = (pose(f), pose(f + 1));
        let (turn, turn_next) = (root(f), root(f + 1));
        // As a matrix: it turns 43 points.
        let turning_now = DMat3::from_quat(turn);
        let start = vectors.len();
        // The root: its turn to the next frame (half the angle), its step turned by the next
        // frame's rotation, its height.
        let turning = turn_next * turn.conjugate();
        vectors.push(turning.y.clamp(-1.0, 1.0).asin() as f32);
        let step = turn_next * (next[0] - here[0]);
        vectors.extend([step.x as f32, step.z as f32, here[0].y as f32]);
        // The other joints relative to the root on the floor, in this frame's facing.
        let floor = DVec3::new(here[0].x, 0.0, here[0].z);
        for p in &here[1..] {
            vectors.extend((turning_now * (*p - floor)).as_vec3().to_array());
        }
        for q in &rotations[f * JOINTS + 1..(f + 1) * JOINTS] {
            let m = DMat3::from_quat(*q);
            vectors.extend(m.x_axis.as_vec3().to_array());
            vectors.extend(m.y_axis.as_vec3().to_array());
        }
        for (a, b) in here.iter().zip(next) {
            vectors.extend((turning_now * (*b - *a)).as_vec3().to_array());
        }
        for side in FOOT_POINTS {
            for j in side {
                let moved = (next[j] - here[j]).length_squared() < CONTACT_THRESHOLD;
                vectors.push(f32::from(u8::from(moved)));
            }
        }
        debug_assert_eq!(vectors.len() - start, WIDTH);
    }
    vectors
}

/// HumanML3D's `Std.npy` from the per-value spreads of a set of vectors: each part of the
/// vector ([`PARTS`]) gets the mean of its values' spreads, so that a part is scaled as one.
pub fn spread_by_part(std: &mut [f32]) {
    for (_, start, width) in PARTS {
        let part = &mut std[start..start + width];
        let mean = part.iter().map(|&v| f64::from(v)).sum::<f64>() / width as f64;
        part.iter_mut().for_each(|v| *v = mean as f32);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gaussian_is_scipys_on_a_step() {
        // SciPy: gaussian_filter1d([0]*100 + [1]*100, 20, mode="nearest") at 100 is 0.509974…
        let step: Vec<DVec3> = (0..200)
            .map(|i| DVec3::splat(f64::from(u8::from(i >= 100))))
            .collect();
        let smooth = gaussian_nearest(&step, 20.0);
        assert!((smooth[99].x + smooth[100].x - 1.0).abs() < 1e-12);
        assert!(
            (smooth[100].x - 0.509_974_124_277).abs() < 1e-11,
            "{}",
            smooth[100].x
        );
        assert!(smooth[10].x == 0.0 && (smooth[199].x - 1.0).abs() < 1e-12);
    }

    /// A figure in HumanML3D's rest pose (every bone along its rest direction at the
    /// reference length), standing still for three frames.
    #[test]
    fn standing_still_has_no_turn_no_step_and_both_feet_down() {
        let mut pose = [DVec3::new(0.0, 1.0, 0.0); JOINTS];
        for chain in CHAINS {
            for pair in chain.windows(2) {
                let rest = DVec3::from_array(REST_DIRECTIONS[pair[1]]);
                pose[pair[1]] = pose[pair[0]] + rest * REFERENCE_LENGTHS[pair[1]];
            }
        }
        let still: Vec<DVec3> = (0..3).flat_map(|_| pose).collect();
        let made = features(&still).unwrap();
        assert_eq!(made.frames(), 2);
        let first = &made.vectors[..WIDTH];
        assert_eq!(first[0..3], [0.0, 0.0, 0.0]);
        assert_eq!(first[259..263], [1.0, 1.0, 1.0, 1.0]);
        // Rest rotations are the identity: 6D (1, 0, 0, 0, 1, 0) for every joint.
        for joint in first[67..193].chunks(6) {
            assert_eq!(joint, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        }
        // The lowest point (a foot's tip) is on the floor; the root above it.
        let lowest = made.joints.chunks(3).map(|p| p[1]).fold(f32::MAX, f32::min);
        assert!(lowest.abs() < 1e-6, "{lowest}");
        assert!(made.vectors.iter().all(|v| v.is_finite()));
        assert!(features(&still[..JOINTS]).is_err());
    }

    #[test]
    fn between_turns_a_direction_onto_another_even_straight_back() {
        for (from, to) in [
            (DVec3::X, DVec3::Y),
            (
                DVec3::new(0.0, -1.0, 0.0),
                DVec3::new(0.3, -0.9, 0.1).normalize(),
            ),
            (DVec3::Z, -DVec3::Z),
            (DVec3::Y, -DVec3::Y),
        ] {
            let q = between(from, to);
            assert!(
                (q * from - to).length() < 1e-12,
                "{from} → {to}: {}",
                q * from
            );
            assert!(q.w >= 0.0);
        }
    }
}
