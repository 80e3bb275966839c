//! Rotations as numbers: a joint's rotation written as a quaternion, a matrix, 6D or Euler
//! angles, and read back from them.

use super::channels::local_rotation;
use super::lanes::{FkPlan, FkScratch, LANES};
use super::mode::OffsetMode;
use crate::model::skeleton::{Joint, Skeleton};
use glam::{Mat4, Vec3};

/// How a joint's local rotation is written as numbers (Python's `local_rotations(kind=…)`, the
/// dataset's `--rotations`).
///
/// ```
/// use bvhview::model::pose::RotationKind;
///
/// let kind = RotationKind::parse("6d").unwrap();
/// assert_eq!((kind, kind.width(), kind.name()), (RotationKind::SixD, 6, "6d"));
/// assert_eq!(RotationKind::Matrix.width(), 9);
/// assert_eq!(RotationKind::parse("euler_zxy"), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotationKind {
    /// (w, x, y, z), w ≥ 0.
    Quat,
    /// The 3 × 3 matrix, row after row.
    Matrix,
    /// The matrix's first two columns one after the other (Zhou et al. 2019).
    SixD,
    /// The joint's rotation channels in its file order, in degrees (0 past the ones it has).
    Euler,
    /// The rotation vector: the unit axis times the angle in radians (at most π).
    AxisAngle,
}

impl RotationKind {
    /// Every name [`RotationKind::parse`] takes, as messages list them.
    pub const NAMES: &'static str = "\"quat\", \"matrix\", \"6d\", \"euler\" or \"axis_angle\"";

    /// The kind a name means (`quat`, `matrix`, `6d`, `euler`, `axis_angle`); `None` for any
    /// other text.
    pub fn parse(text: &str) -> Option<RotationKind> {
        match text {
            "quat" => Some(RotationKind::Quat),
            "matrix" => Some(RotationKind::Matrix),
            "6d" => Some(RotationKind::SixD),
            "euler" => Some(RotationKind::Euler),
            "axis_angle" => Some(RotationKind::AxisAngle),
            _ => None,
        }
    }

    /// The name [`RotationKind::parse`] reads back.
    pub fn name(self) -> &'static str {
        match self {
            RotationKind::Quat => "quat",
            RotationKind::Matrix => "matrix",
            RotationKind::SixD => "6d",
            RotationKind::Euler => "euler",
            RotationKind::AxisAngle => "axis_angle",
        }
    }

    /// Numbers per rotation.
    pub fn width(self) -> usize {
        match self {
            RotationKind::Quat => 4,
            RotationKind::Matrix => 9,
            RotationKind::SixD => 6,
            RotationKind::Euler | RotationKind::AxisAngle => 3,
        }
    }
}

/// The rotation matrix `kind` numbers stand for, as [`write_rotation`] writes them: a quaternion
/// normalised, a 6D pair made orthonormal again (Gram-Schmidt). `None` for Euler angles, whose
/// meaning is the joint's own channel order.
pub fn rotation_of_numbers(kind: RotationKind, numbers: &[f32]) -> Option<glam::Mat3> {
    match kind {
        RotationKind::Quat => Some(glam::Mat3::from_quat(
            glam::Quat::from_xyzw(numbers[1], numbers[2], numbers[3], numbers[0]).normalize(),
        )),
        RotationKind::Matrix => Some(glam::Mat3::from_cols_slice(numbers).transpose()),
        RotationKind::SixD => {
            let a = Vec3::new(numbers[0], numbers[1], numbers[2]).normalize_or_zero();
            let b = Vec3::new(numbers[3], numbers[4], numbers[5]);
            let b = (b - a * a.dot(b)).normalize_or_zero();
            Some(glam::Mat3::from_cols(a, b, a.cross(b)))
        }
        RotationKind::AxisAngle => {
            let vector = Vec3::new(numbers[0], numbers[1], numbers[2]);
            Some(glam::Mat3::from_quat(glam::Quat::from_scaled_axis(vector)))
        }
        RotationKind::Euler => None,
    }
}

/// Why `kind` numbers (finite ones) stand for no rotation, if they do not: a quaternion of
/// (nearly) zero length, which normalises to NaN; a matrix that is not a rotation (columns not
/// orthonormal within 1e-3, or a reflection); a 6D pair with a zero or parallel column. Euler
/// angles and rotation vectors always make a rotation.
pub fn rotation_numbers_problem(kind: RotationKind, numbers: &[f32]) -> Option<String> {
    // Shorter than this, a quaternion or a column is rounding noise, not a direction.
    const SHORTEST: f64 = 1e-6;
    const TOLERANCE: f64 = 1e-3;
    let length = |v: &[f32]| v.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt();
    match kind {
        RotationKind::Quat => {
            let length = length(&numbers[..4]);
            (length < SHORTEST).then(|| {
                format!("a quaternion of length {length:e} (zero or too small to normalise)")
            })
        }
        RotationKind::Matrix => {
            let m = |r: usize, c: usize| f64::from(numbers[r * 3 + c]);
            let mut worst: f64 = 0.0;
            for a in 0..3 {
                for b in 0..3 {
                    let dot: f64 = (0..3).map(|r| m(r, a) * m(r, b)).sum();
                    let want = if a == b { 1.0 } else { 0.0 };
                    worst = worst.max((dot - want).abs());
                }
            }
            let det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
                - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
                + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
            (worst > TOLERANCE || (det - 1.0).abs() > 3.0 * TOLERANCE).then(|| {
                format!(
                    "not a rotation matrix (determinant {det:.6}, columns orthonormal only \
                     within {worst:.2e}; a rotation's are within {TOLERANCE})"
                )
            })
        }
        RotationKind::SixD => {
            let a = Vec3::new(numbers[0], numbers[1], numbers[2]).as_dvec3();
            let b = Vec3::new(numbers[3], numbers[4], numbers[5]).as_dvec3();
            let (la, lb) = (a.length(), b.length());
            let apart = if la > 0.0 && lb > 0.0 {
                a.cross(b).length() / (la * lb)
            } else {
                0.0
            };
            (la < SHORTEST || lb < SHORTEST || apart < SHORTEST).then(|| {
                format!(
                    "a 6D pair whose columns are zero or parallel (lengths {la:e} and {lb:e}): \
                     no rotation"
                )
            })
        }
        RotationKind::Euler | RotationKind::AxisAngle => None,
    }
}

/// `joint`'s local rotation ([`local_rotation`]) for its channel `values` as `kind` numbers, into
/// `out` (`kind.width()` long). No values (an End Site, the rest pose): the identity.
pub fn write_rotation(joint: &Joint, values: &[f32], kind: RotationKind, out: &mut [f32]) {
    if kind == RotationKind::Euler {
        out.fill(0.0);
        let angles = joint
            .channels
            .iter()
            .zip(values)
            .filter(|(c, _)| c.is_rotation())
            .map(|(_, &v)| v);
        for (slot, angle) in out.iter_mut().zip(angles) {
            *slot = angle;
        }
        return;
    }
    let rotation = if values.is_empty() {
        Mat4::IDENTITY
    } else {
        local_rotation(joint, values)
    };
    let m = glam::Mat3::from_mat4(rotation);
    match kind {
        RotationKind::Quat => {
            let q = glam::Quat::from_mat3(&m).normalize();
            let q = if q.w < 0.0 { -q } else { q };
            out.copy_from_slice(&[q.w, q.x, q.y, q.z]);
        }
        RotationKind::Matrix => out.copy_from_slice(&m.transpose().to_cols_array()),
        RotationKind::AxisAngle => {
            // w ≥ 0 keeps the angle in [0, π]: the shorter of the two ways round.
            let q = glam::Quat::from_mat3(&m).normalize();
            let q = if q.w < 0.0 { -q } else { q };
            out.copy_from_slice(&q.to_scaled_axis().to_array());
        }
        _ => {
            let (a, b) = (m.x_axis, m.y_axis);
            out.copy_from_slice(&[a.x, a.y, a.z, b.x, b.y, b.z]);
        }
    }
}

/// A local rotation given as a quaternion, as `kind` numbers (not Euler angles, whose meaning is
/// a joint's channel order), into `out`: the same numbers [`write_rotation`] writes for it.
pub fn write_quat(q: glam::Quat, kind: RotationKind, out: &mut [f32]) {
    // w ≥ 0: one of the two quaternions of each rotation, and an angle in [0, π].
    let q = q.normalize();
    let q = if q.w < 0.0 { -q } else { q };
    match kind {
        RotationKind::Quat => out.copy_from_slice(&[q.w, q.x, q.y, q.z]),
        RotationKind::AxisAngle => out.copy_from_slice(&q.to_scaled_axis().to_array()),
        RotationKind::Matrix => {
            out.copy_from_slice(&glam::Mat3::from_quat(q).transpose().to_cols_array())
        }
        RotationKind::SixD => {
            let m = glam::Mat3::from_quat(q);
            let (a, b) = (m.x_axis, m.y_axis);
            out.copy_from_slice(&[a.x, a.y, a.z, b.x, b.y, b.z]);
        }
        RotationKind::Euler => unreachable!("Euler angles need the joint's channel order"),
    }
}

/// Every joint's local rotation as `kind` numbers for the MOTION rows `frames` of `motion`, into
/// `out` (frames × joints × `kind.width()`): what [`write_rotation`] writes joint by joint, made
/// from the FK plan's quaternions eight frames at a time (Euler angles, which are the channel
/// values themselves, and a take without frames go joint by joint).
pub fn write_local_rotations(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    frames: &[usize],
    kind: RotationKind,
    out: &mut [f32],
) {
    let (joints, width) = (skeleton.joints.len(), kind.width());
    if joints == 0 {
        return;
    }
    if kind == RotationKind::Euler || motion.frame_count() == 0 {
        for (&frame, out) in frames.iter().zip(out.chunks_mut(joints * width)) {
            for (joint, slot) in skeleton.joints.iter().zip(out.chunks_exact_mut(width)) {
                let values = match motion.frame_count() {
                    0 => &[][..],
                    _ => joint.values(motion.frame(frame)),
                };
                write_rotation(joint, values, kind, slot);
            }
        }
        return;
    }
    let plan = FkPlan::new(skeleton, OffsetMode::Replace);
    let (mut rotations, mut translations) = (Vec::new(), Vec::new());
    let mut scratch = FkScratch::default();
    let mut rows: Vec<&[f32]> = Vec::with_capacity(LANES);
    for (batch, out) in frames
        .chunks(LANES)
        .zip(out.chunks_mut(LANES * joints * width))
    {
        rows.clear();
        rows.extend(batch.iter().map(|&frame| motion.frame(frame)));
        plan.locals_of_frames(&rows, &mut rotations, &mut translations, &mut scratch);
        for (&q, slot) in rotations.iter().zip(out.chunks_exact_mut(width)) {
            write_quat(q, kind, slot);
        }
    }
}
