//! HumanML3D's 263-value feature vectors back to joint positions, as its own recovery
//! (`recover_from_ric` in its `motion_representation.ipynb`) gives them: the root's rotation
//! about y integrated from its angular velocity, its path from its velocity on the floor, its
//! height as written, and the 21 other joints from their root-relative positions ("ric"),
//! turned and carried with it. The rotations (6D) and velocities in the vectors are not read,
//! as that recovery does not read them. Then [`crate::solve::solve`] puts the positions on a
//! skeleton.
//!
//! A vector holds, in order: the root's angular velocity about y (1), its velocity on x and z
//! (2), its height (1), 21 joints' root-relative positions (63), 21 joints' rotations in 6D
//! (126), 22 joints' local velocities (66) and 4 foot contacts (4). HumanML3D keeps the root's
//! rotation as a quaternion `(cos a, 0, sin a, 0)` whose `a` is the integrated angle: the turn
//! about y is `2a` (its quirk: the angle comes from the quaternion's `y` part by `arcsin`, so
//! it is half the turn), and that is what is undone here.

use super::layout::{JOINTS, WIDTH};
use crate::io::error::Error;
use glam::{DQuat, DVec3};

/// The joint positions (frames × 22, SMPL's order, metres, y up) that `vectors` (frames × 263,
/// frame after frame) stand for, as HumanML3D's `recover_from_ric` gives them.
///
/// ```
/// let vectors = vec![0.0f32; 2 * bvhview::humanml3d::WIDTH];
/// let points = bvhview::humanml3d::recover_from_ric(&vectors).unwrap();
/// assert_eq!(points.len(), 2 * 22);
/// ```
pub fn recover_from_ric(vectors: &[f32]) -> Result<Vec<DVec3>, Error> {
    if vectors.is_empty() || !vectors.len().is_multiple_of(WIDTH) {
        return Err(Error::usage(format!(
            "humanml3d: {} values are not whole vectors of {WIDTH}",
            vectors.len()
        )));
    }
    if let Some(at) = vectors.iter().position(|v| !v.is_finite()) {
        return Err(Error::usage(format!(
            "humanml3d: vector {}, value {}: not a finite number",
            at / WIDTH,
            at % WIDTH
        )));
    }
    let joints = JOINTS;
    let frames = vectors.len() / WIDTH;
    let vector = |f: usize| &vectors[f * WIDTH..(f + 1) * WIDTH];
    let mut points = Vec::with_capacity(frames * joints);
    let (mut angle, mut root) = (0.0f64, DVec3::ZERO);
    for f in 0..frames {
        if f > 0 {
            // What the frame before says of the step to this one.
            let before = vector(f - 1);
            angle += f64::from(before[0]);
            let step = DVec3::new(f64::from(before[1]), 0.0, f64::from(before[2]));
            root += facing(angle).inverse() * step;
        }
        let here = vector(f);
        // As a matrix: it turns 21 joints.
        let turn = glam::DMat3::from_quat(facing(angle).inverse());
        let at = DVec3::new(root.x, f64::from(here[3]), root.z);
        points.push(at);
        for j in 0..joints - 1 {
            let local = DVec3::new(
                f64::from(here[4 + 3 * j]),
                f64::from(here[5 + 3 * j]),
                f64::from(here[6 + 3 * j]),
            );
            let moved = turn * local;
            points.push(DVec3::new(moved.x + at.x, moved.y, moved.z + at.z));
        }
    }
    Ok(points)
}

/// HumanML3D's root quaternion for the integrated angle `a`: `(w, x, y, z) = (cos a, 0, sin a,
/// 0)`, a turn of `2a` about y.
pub(super) fn facing(a: f64) -> DQuat {
    DQuat::from_xyzw(0.0, a.sin(), 0.0, a.cos())
}

/// The vectors in an `.npy` of frames × 263 (float32 or float64), frame after frame.
pub fn read_vectors(bytes: &[u8], shown: &str) -> Result<Vec<f32>, Error> {
    let refuse = |why: String| Error::decoding(shown, why);
    let (rows, points) = crate::solve::input::read_npy_rows(bytes, shown, WIDTH)?;
    if rows == 0 {
        return Err(refuse("no vectors".into()));
    }
    Ok(points.into_iter().map(|v| v as f32).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_root_keeps_its_joints_where_the_vectors_put_them() {
        let mut vector = vec![0.0f32; WIDTH];
        vector[3] = 0.875;
        vector[4..7].copy_from_slice(&[0.125, -0.25, 0.0]);
        let points = recover_from_ric(&vector).unwrap();
        assert_eq!(points[0], DVec3::new(0.0, 0.875, 0.0));
        assert_eq!(points[1], DVec3::new(0.125, -0.25, 0.0));
        assert!(recover_from_ric(&vector[..100]).is_err());
    }
}
