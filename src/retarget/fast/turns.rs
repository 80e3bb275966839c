//! The turns the fast pass works out in lanes: a bone onto its source chord, a point by a
//! quaternion, the axes of an Euler order, and the Euler form nearest the last frame's.

use crate::retarget::fast::lanes::{LANES, Lanes, lanes, mask};
use crate::retarget::fast::quats::{Points, Quats};
use crate::retarget::plain::Setup;
use glam::{DQuat, DVec3};

/// The plain pass's turn of a bone onto a source chord (`near` to `far`): `arc(r · rest, chord) · r`
/// where the chord is longer than 1e-9, else `r`, glam's operations term for term. A lane whose
/// chord points against the bone (glam's other branch) takes the plain pass's code.
#[inline(always)]
pub(super) fn follow(
    setup: &Setup,
    rotation: &Quats,
    near: &Points,
    far: &Points,
    rest: DVec3,
) -> Quats {
    let apart = Points {
        x: lanes(|l| far.x[l] - near.x[l]),
        y: lanes(|l| far.y[l] - near.y[l]),
        z: lanes(|l| far.z[l] - near.z[l]),
    };
    let chord = turn(setup.ut_inv, &turn(setup.us, &apart));
    let from = rotation.rotate(&Points::splat(rest));
    let length =
        |v: &Points| lanes(|l| (v.x[l] * v.x[l] + v.y[l] * v.y[l] + v.z[l] * v.z[l]).sqrt());
    let (chord_length, from_length) = (length(&chord), length(&from));
    let unit = |v: &Points, length: &Lanes| {
        let recip = lanes(|l| 1.0 / length[l]);
        Points {
            x: lanes(|l| v.x[l] * recip[l]),
            y: lanes(|l| v.y[l] * recip[l]),
            z: lanes(|l| v.z[l] * recip[l]),
        }
    };
    let (a, b) = (unit(&from, &from_length), unit(&chord, &chord_length));
    let dot = lanes(|l| a.x[l] * b.x[l] + a.y[l] * b.y[l] + a.z[l] * b.z[l]);
    // glam's from_rotation_arc: (a × b, 1 + a·b), normalised.
    let (x, y, z, w) = (
        lanes(|l| a.y[l] * b.z[l] - b.y[l] * a.z[l]),
        lanes(|l| a.z[l] * b.x[l] - b.z[l] * a.x[l]),
        lanes(|l| a.x[l] * b.y[l] - b.x[l] * a.y[l]),
        lanes(|l| 1.0 + dot[l]),
    );
    let recip = lanes(|l| 1.0 / (x[l] * x[l] + y[l] * y[l] + z[l] * z[l] + w[l] * w[l]).sqrt());
    let arc = Quats {
        x: lanes(|l| x[l] * recip[l]),
        y: lanes(|l| y[l] * recip[l]),
        z: lanes(|l| z[l] * recip[l]),
        w: lanes(|l| w[l] * recip[l]),
    };
    let turned = arc.mul(rotation);
    // Where the chord is too short, or already along the bone (`arc` gives the identity, and
    // the identity times `r` is `r` but for the sign of a zero), `r` stays.
    let moves = mask(|l| chord_length[l] > 1e-9 && dot[l] <= 1.0 - 1e-15);
    let pick = |t: &Lanes, r: &Lanes| lanes(|l| if moves[l] { t[l] } else { r[l] });
    let mut out = Quats {
        x: pick(&turned.x, &rotation.x),
        y: pick(&turned.y, &rotation.y),
        z: pick(&turned.z, &rotation.z),
        w: pick(&turned.w, &rotation.w),
    };
    for l in 0..LANES {
        if moves[l] && dot[l] < -(1.0 - 2.0 * f64::EPSILON) {
            let r = rotation.get(l);
            out.set(l, crate::retarget::align::arc(r * rest, chord.get(l)) * r);
        }
    }
    out
}

/// `q · v` for every lane, or `v` itself when `q` is the identity (the same values but for the
/// sign of a zero).
#[inline(always)]
pub(super) fn turn(q: DQuat, v: &Points) -> Points {
    match q == DQuat::IDENTITY {
        true => *v,
        false => Quats::splat(q).rotate(v),
    }
}

/// The axes of an Euler order in file order, and their handedness, as [`crate::model::euler::split`]
/// reads them.
pub(super) fn axis_order(order: crate::model::skeleton::RotationOrder) -> ([usize; 3], f64) {
    let [i, j, k] = crate::model::euler::axes(order);
    ([i, j, k], crate::model::euler::handedness(i, j))
}

/// [`nearest_form`](crate::retarget::hinge::nearest_form) of every lane: its operations in its order, as one loop over the lanes that
/// the compiler vectorises.
#[inline(always)]
pub(super) fn nearest_forms(angles: &[Lanes; 3], reference: &[Lanes; 3]) -> [Lanes; 3] {
    let near = |angle: f64, to: f64| angle + 360.0 * ((to - angle) / 360.0).round();
    let mut best = [[0.0; LANES]; 3];
    for l in 0..LANES {
        let (a, r) = (
            [angles[0][l], angles[1][l], angles[2][l]],
            [reference[0][l], reference[1][l], reference[2][l]],
        );
        let first = [near(a[0], r[0]), near(a[1], r[1]), near(a[2], r[2])];
        let second = [
            near(a[0] + 180.0, r[0]),
            near(180.0 - a[1], r[1]),
            near(a[2] + 180.0, r[2]),
        ];
        let cost = |f: &[f64; 3]| (f[0] - r[0]).abs() + (f[1] - r[1]).abs() + (f[2] - r[2]).abs();
        let (first_cost, second_cost) = (cost(&first), cost(&second));
        // As `nearest_form`: the first form if its cost is below infinity, the second if below
        // that, else the angles as they are.
        let first_taken = first_cost < f64::INFINITY;
        let best_cost = if first_taken {
            first_cost
        } else {
            f64::INFINITY
        };
        let second_taken = second_cost < best_cost;
        for i in 0..3 {
            best[i][l] = if second_taken {
                second[i]
            } else if first_taken {
                first[i]
            } else {
                a[i]
            };
        }
    }
    best
}
