//! Where a joint's bones can reach: the twist about a bone that leaves the least of the joints
//! below it out of reach (ASF's thorax, its clavicles, its wrists turning about themselves), and
//! the search for the least-cost turn those choices share.

use crate::model::skeleton::Skeleton;
use glam::{DQuat, DVec3};

/// `wanted` (joint `j`'s world rotation, laying its bones along `to`) turned about `to` so that
/// the joints below it that turn about two axes (ASF's clavicles below the thorax) can lay
/// their bones where the data puts them: the twist that leaves the least out of their reach,
/// of those the nearest to `before` (the joint's rotation in the frame before). Two axes
/// `R1 · R2` reach a direction `w` only where `a1 · w` is within the reach of `a1 · R2(β) u`.
pub(super) fn reach_twist(
    skeleton: &Skeleton,
    targets: &[Vec<(usize, DVec3)>],
    j: usize,
    wanted: DQuat,
    to: DVec3,
    before: DQuat,
    data: impl Fn(usize) -> Option<DVec3>,
) -> DQuat {
    let Some(axis) = to.try_normalize() else {
        return wanted;
    };
    let out_of_reach = |twist: f64| {
        let world = DQuat::from_axis_angle(axis, twist) * wanted;
        out_of_reach_deep(skeleton, targets, j, world, &data)
    };
    let away = |twist: f64| (DQuat::from_axis_angle(axis, twist) * wanted).angle_between(before);
    let twist = least_cost_turn(out_of_reach, away, 0.0);
    DQuat::from_axis_angle(axis, twist) * wanted
}

/// A joint's one rotation axis (and its channels' frame) where its bone lies along it: the
/// joint turns its bone about itself only.
pub(super) fn twist_axis(
    joint: &crate::model::skeleton::Joint,
    bone: DVec3,
) -> Option<(DVec3, DQuat)> {
    let axes: Vec<usize> = joint.rotation_axes();
    let [a] = axes[..] else {
        return None;
    };
    let c = joint.axis_f64();
    let u = (c.inverse() * bone).try_normalize()?;
    (DVec3::AXES[a].dot(u).abs() > 1.0 - 1e-9).then_some((DVec3::AXES[a], c))
}

/// The angle (radians) `cost` of the rotation `turned(angle)` finds cheapest; where several
/// cost nothing (within rounding), the one nearest `before` (degrees), or 0.
pub(super) fn twist_search(
    cost: &impl Fn(DQuat) -> f64,
    before: Option<f64>,
    turned: impl Fn(f64) -> DQuat,
) -> f64 {
    let home = before.map_or(0.0, f64::to_radians);
    let away = |t: f64| {
        let d = (t - home).rem_euclid(std::f64::consts::TAU);
        d.min(std::f64::consts::TAU - d)
    };
    least_cost_turn(|t| cost(turned(t)), away, home)
}

/// The angle (radians, within half a turn of `start`) that `cost` finds cheapest: by steps of
/// a degree, then refined where nothing costs 0; among those that cost the same (within
/// rounding), the one `away` finds nearest. `start` itself when it costs nothing.
fn least_cost_turn(cost: impl Fn(f64) -> f64, away: impl Fn(f64) -> f64, start: f64) -> f64 {
    const STEPS: usize = 360;
    let step = std::f64::consts::TAU / STEPS as f64;
    let mut best = (start, cost(start));
    if best.1 <= 1e-12 {
        return start;
    }
    for k in 0..STEPS {
        let t = start + step * k as f64 - std::f64::consts::PI;
        let c = cost(t);
        let closer = (c - best.1).abs() <= 1e-12 && away(t) < away(best.0);
        if c < best.1 - 1e-12 || closer {
            best = (t, c);
        }
    }
    if best.1 > 1e-12 {
        // Out of reach everywhere: the least, between the steps beside the best.
        let (mut low, mut high) = (best.0 - step, best.0 + step);
        for _ in 0..60 {
            let (m1, m2) = (low + (high - low) / 3.0, high - (high - low) / 3.0);
            if cost(m1) <= cost(m2) {
                high = m2;
            } else {
                low = m1;
            }
        }
        best.0 = (low + high) / 2.0;
    }
    best.0
}

/// [`out_of_reach_below`], and one step deeper: for each joint below that turns about two axes,
/// what is out of reach below it when it takes the one of its two solutions that reaches best.
pub(super) fn out_of_reach_deep(
    skeleton: &Skeleton,
    targets: &[Vec<(usize, DVec3)>],
    j: usize,
    world: DQuat,
    data: impl Fn(usize) -> Option<DVec3>,
) -> f64 {
    let mut total = out_of_reach_below(skeleton, targets, j, world, &data);
    for &(d, _) in &targets[j] {
        let joint = &skeleton.joints[d];
        let turns = joint.rotation_axes().len();
        if joint.rotation_order.is_some() || turns != 2 {
            continue;
        }
        let Some(&(below, bone)) = targets[d].first() else {
            continue;
        };
        let (Some(from), Some(to)) = (data(d), data(below)) else {
            continue;
        };
        let (Some(rest), Some(goal)) =
            ((world * bone).try_normalize(), (to - from).try_normalize())
        else {
            continue;
        };
        let local = world.inverse() * DQuat::from_rotation_arc(rest, goal) * world;
        let (_, realized) = crate::retarget::limited_angles_by(joint, local, Some(bone), |t| {
            out_of_reach_below(skeleton, targets, d, world * t, &data)
        });
        total += out_of_reach_below(skeleton, targets, d, world * realized, &data);
    }
    total
}

/// How far the data lies out of reach of the joints below `j` that turn about fewer than three
/// axes, with `j` turned to `world`: for a hinge, how far its bone's direction leaves the
/// plane the hinge turns it in; for two axes `R1 · R2`, how far `a1 · w` passes the reach of
/// `a1 · R2(β) u`. 0 where every one of them can lay its bone where the data puts it.
fn out_of_reach_below(
    skeleton: &Skeleton,
    targets: &[Vec<(usize, DVec3)>],
    j: usize,
    world: DQuat,
    data: impl Fn(usize) -> Option<DVec3>,
) -> f64 {
    let mut total = 0.0;
    for &(d, _) in &targets[j] {
        let joint = &skeleton.joints[d];
        if joint.rotation_order.is_some() {
            continue;
        }
        let axes: Vec<DVec3> = joint
            .rotation_axes()
            .into_iter()
            .map(|a| DVec3::AXES[a])
            .collect();
        let Some(&(below, bone)) = targets[d].first() else {
            continue;
        };
        let (Some(from), Some(to)) = (data(d), data(below)) else {
            continue;
        };
        let c = joint.axis_f64();
        let (Some(u), Some(w)) = (
            (c.inverse() * bone).try_normalize(),
            (c.inverse() * (world.inverse() * (to - from))).try_normalize(),
        ) else {
            continue;
        };
        total += match axes[..] {
            [a] => (a.dot(w) - a.dot(u)).abs(),
            [a1, a2] => (a1.dot(w).abs() - a1.dot(u).hypot(a1.dot(a2.cross(u)))).max(0.0),
            _ => 0.0,
        };
    }
    total
}

/// `wanted` (joint `j`'s world rotation, laying its one bone along `to`) turned about that
/// bone so that, where the joint it turns towards is a hinge (one rotation channel: an ASF knee
/// or elbow), the hinge's axis is across the plane the data bends in there: a hinge cannot
/// leave its plane, so only the twist of the bone above it lets it reach the data. Of the two
/// twists that do, the smaller.
pub(super) fn hinge_twist(
    skeleton: &Skeleton,
    targets: &[Vec<(usize, DVec3)>],
    j: usize,
    wanted: DQuat,
    to: DVec3,
    data: impl Fn(usize) -> Option<DVec3>,
) -> DQuat {
    let Some(&(d, _)) = targets[j].first() else {
        return wanted;
    };
    let hinge = &skeleton.joints[d];
    let axes: Vec<usize> = hinge.rotation_axes();
    let ([axis], Some(&(below, _))) = (&axes[..], targets[d].first()) else {
        return wanted;
    };
    let (Some(at), Some(next)) = (data(d), data(below)) else {
        return wanted;
    };
    let bone = to.normalize();
    let Some(across) = bone.cross(next - at).try_normalize() else {
        // The limb straight: any plane holds it.
        return wanted;
    };
    let local_axis = hinge.axis_f64() * DVec3::AXES[*axis];
    let now = wanted * local_axis;
    let now = now - bone * now.dot(bone);
    let Some(now) = now.try_normalize() else {
        return wanted;
    };
    let turn = |goal: DVec3| bone.dot(now.cross(goal)).atan2(now.dot(goal));
    let (a, b) = (turn(across), turn(-across));
    let angle = if a.abs() <= b.abs() { a } else { b };
    DQuat::from_axis_angle(bone, angle) * wanted
}
