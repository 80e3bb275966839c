//! The one exact Euler split, which every rotation turned into channel angles goes through: a
//! rotation turned into three channel angles in 64-bit floats, from a normalised rotation, exact at
//! and near ±90° of the middle axis (the gimbal lock) for all six orders.
//!
//! Why not `glam`'s `to_euler`: it reads the angles off a quaternion assumed to be of length 1, and
//! near the lock its first and third angles come from two numbers that are both rounding noise. A
//! 32-bit quaternion a hair off length 1 that turns a child 90° about the middle axis of ZYX split
//! as `180 89.99999 180`, which puts the child 25° away from where the file has it. Here the middle
//! angle is taken with `atan2` against the length of the other two (never `asin`), and the first
//! angle is solved from the rotation with the third already removed, so the three angles multiply
//! back to the rotation whatever the middle one is.

use crate::model::skeleton::RotationOrder;
use glam::{DMat3, DQuat, DVec3};

/// How far from the lock (the cosine of the middle angle) the third angle is still read off
/// the rotation; closer, it keeps the previous frame's value (or 0), as only the first and
/// third together are defined there.
pub(crate) const LOCK: f64 = 1e-9;

/// The axes of `order` as indices (x 0, y 1, z 2), in file order: the channels multiply as
/// `R(first) · R(second) · R(third)`.
pub fn axes(order: RotationOrder) -> [usize; 3] {
    match order {
        RotationOrder::Xyz => [0, 1, 2],
        RotationOrder::Xzy => [0, 2, 1],
        RotationOrder::Yxz => [1, 0, 2],
        RotationOrder::Yzx => [1, 2, 0],
        RotationOrder::Zxy => [2, 0, 1],
        RotationOrder::Zyx => [2, 1, 0],
    }
}

/// +1 when axes `i` then `j` turn as x then y do (x y z, y z x, z x y), −1 the other way.
pub fn handedness(i: usize, j: usize) -> f64 {
    if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 }
}

/// The angles in radians, in file order, of the channels of `order` that multiply to `q`.
/// `previous` (the angles of the frame before, if any) keeps the split continuous: each angle
/// is moved by whole turns to the nearest of the previous one, and at the lock the third angle
/// keeps its previous value.
pub fn split(q: DQuat, order: RotationOrder, previous: Option<[f64; 3]>) -> [f64; 3] {
    let [i, j, k] = axes(order);
    let m = DMat3::from_quat(q.normalize());
    // m.col(c)[r] is row r, column c.
    let at = |row: usize, column: usize| m.col(column)[row];
    let sign = handedness(i, j);
    // Not `hypot`: retargeting's eight-lane copy (src/retarget/fast/) computes the same.
    let cos_middle = (at(i, i) * at(i, i) + at(i, j) * at(i, j)).sqrt();
    let middle = (sign * at(i, k)).atan2(cos_middle);
    let third = if cos_middle > LOCK {
        (-sign * at(i, j)).atan2(at(i, i))
    } else {
        previous.map_or(0.0, |p| p[2])
    };
    // The first angle from the rotation with the third taken off: R(first) · R(second) is
    // what is left, and its column j is R(first) applied to axis j. Column j of R_k(−third) is
    // cos(third) along j and sign · sin(third) along i.
    let (sin, cos) = third.sin_cos();
    let column = |row: usize| at(row, i) * (sign * sin) + at(row, j) * cos;
    let first = (sign * column(k)).atan2(column(j));
    let mut angles = [first, middle, third];
    if let Some(previous) = previous {
        let turn = std::f64::consts::TAU;
        for (angle, before) in angles.iter_mut().zip(previous) {
            *angle += ((before - *angle) / turn).round() * turn;
        }
    }
    angles
}

/// [`split`] as channel values: degrees in file order, rounded to 32 bits only at the end (an
/// edit's output row).
pub fn split_degrees(q: DQuat, order: RotationOrder) -> [f32; 3] {
    split(q, order, None).map(|angle| angle.to_degrees() as f32)
}

/// The rotation the channels of `order` make with `angles` (radians, file order).
pub fn compose(angles: [f64; 3], order: RotationOrder) -> DQuat {
    let [i, j, k] = axes(order);
    DQuat::from_axis_angle(unit(i), angles[0])
        * DQuat::from_axis_angle(unit(j), angles[1])
        * DQuat::from_axis_angle(unit(k), angles[2])
}

fn unit(axis: usize) -> DVec3 {
    [DVec3::X, DVec3::Y, DVec3::Z][axis]
}

#[cfg(test)]
mod tests {
    use super::*;

    const ORDERS: [RotationOrder; 6] = [
        RotationOrder::Xyz,
        RotationOrder::Xzy,
        RotationOrder::Yxz,
        RotationOrder::Yzx,
        RotationOrder::Zxy,
        RotationOrder::Zyx,
    ];

    /// The angle between two rotations, in radians (by `atan2`: `acos` of a dot product near 1
    /// cannot tell angles under 1e-8 apart).
    fn apart(a: DQuat, b: DQuat) -> f64 {
        let d = a.normalize().conjugate() * b.normalize();
        2.0 * d.xyz().length().atan2(d.w.abs())
    }

    /// Exactly at ±90° of the middle axis, near it (89.99°, 89.9999°) and away from it, for
    /// every order: the angles multiply back to the rotation within 1e-12 rad, and the middle
    /// angle is the one given.
    #[test]
    fn the_split_multiplies_back_at_and_near_the_lock_in_every_order() {
        for order in ORDERS {
            for middle in [90.0, -90.0, 89.99, -89.99, 89.9999, 45.0, 0.0, -120.0f64] {
                for (first, third) in [
                    (0.0f64, 0.0f64),
                    (30.0, -70.0),
                    (-170.0, 10.0),
                    (179.0, 179.0),
                ] {
                    let given = [first.to_radians(), middle.to_radians(), third.to_radians()];
                    let q = compose(given, order);
                    let got = split(q, order, None);
                    let error = apart(compose(got, order), q);
                    assert!(
                        error < 1e-12,
                        "{order:?} {first} {middle} {third}: {error} rad"
                    );
                    if middle.abs() <= 90.0 {
                        assert!(
                            (got[1] - given[1]).abs() < 1e-7,
                            "{order:?} {middle}: middle {}",
                            got[1].to_degrees()
                        );
                    }
                }
            }
        }
    }

    /// A 32-bit quaternion a hair off length 1 (as files store them), at the lock: the split
    /// still multiplies back to it within what 32 bits hold.
    #[test]
    fn a_rounded_quaternion_at_the_lock_splits_to_itself() {
        for order in ORDERS {
            for middle in [90.0f64, -90.0, 89.99] {
                let exact = compose([0.7, middle.to_radians(), -0.2], order);
                let rounded = exact.as_quat() * 1.000_000_1;
                let got = split(rounded.as_dquat(), order, None);
                let error = apart(compose(got, order), exact);
                assert!(error < 1e-6, "{order:?} {middle}: {error} rad");
            }
        }
    }

    /// A child turned exactly 90° about the middle axis of ZYX once came out at (0, 1, 0) instead
    /// of (−0.906, 0.423, 0).
    #[test]
    fn a_child_turned_90_degrees_about_the_middle_axis_stays_where_it_is() {
        let q = compose(
            [25f64.to_radians(), 90f64.to_radians(), 0.0],
            RotationOrder::Zyx,
        );
        let rounded = q.as_quat().as_dquat();
        let got = split(rounded, RotationOrder::Zyx, None);
        let child = compose(got, RotationOrder::Zyx) * DVec3::new(0.0, 0.0, 1.0);
        let want = q * DVec3::new(0.0, 0.0, 1.0);
        assert!((child - want).length() < 1e-6, "{child} against {want}");
    }

    /// At the lock the third angle keeps the previous frame's, and every angle moves by whole
    /// turns to stay near the previous one.
    #[test]
    fn the_split_is_continuous_with_the_previous_frame() {
        let order = RotationOrder::Zyx;
        let q = compose([0.3, std::f64::consts::FRAC_PI_2, 0.5], order);
        let got = split(q, order, Some([0.2, 1.5, 0.5]));
        assert!((got[2] - 0.5).abs() < 1e-12, "{got:?}");
        assert!(apart(compose(got, order), q) < 1e-12);
        let q = compose([3.1, 0.2, -3.1], order);
        let got = split(
            q,
            order,
            Some([3.1 + 2.0 * std::f64::consts::TAU, 0.2, -3.1]),
        );
        assert!(
            (got[0] - (3.1 + 2.0 * std::f64::consts::TAU)).abs() < 1e-9,
            "{got:?}"
        );
    }
}
