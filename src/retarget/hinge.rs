//! Hinge limits: a joint with fewer than three rotation channels (an ASF knee) keeps the part
//! of a rotation its channels can hold, in the form nearest the last frame's.

use crate::edit::channel_angles;
use crate::model::pose::RotationKind;
use crate::model::skeleton::Joint;
use glam::{DQuat, DVec3};

/// Of the two Euler forms of a rotation, and their turns by whole circles, the one nearest
/// `reference` (degrees).
pub(super) fn nearest_form(angles: [f64; 3], reference: [f64; 3]) -> [f64; 3] {
    let near = |angle: f64, to: f64| angle + 360.0 * ((to - angle) / 360.0).round();
    let forms = [
        angles,
        [angles[0] + 180.0, 180.0 - angles[1], angles[2] + 180.0],
    ];
    let mut best = angles;
    let mut best_cost = f64::INFINITY;
    for form in forms {
        let fitted = [
            near(form[0], reference[0]),
            near(form[1], reference[1]),
            near(form[2], reference[2]),
        ];
        let cost: f64 = (0..3).map(|i| (fitted[i] - reference[i]).abs()).sum();
        if cost < best_cost {
            best_cost = cost;
            best = fitted;
        }
    }
    best
}

/// The turn about unit `axis` that best lays `from` on `to` (the angle between them projected on
/// the plane across the axis); `None` when either lies along the axis.
pub(super) fn hinge_angle(axis: DVec3, from: DVec3, to: DVec3) -> Option<f64> {
    let from = from - axis * from.dot(axis);
    let to = to - axis * to.dot(axis);
    (from.length() > 1e-9 && to.length() > 1e-9)
        .then(|| axis.dot(from.cross(to)).atan2(from.dot(to)))
}

/// The channel values of a joint with fewer than three rotation channels (an ASF knee `dof rx`,
/// a foot `dof rx rz`, a bone without dof) for the local rotation `local` it cannot always take,
/// and the local rotation those values give. A hinge turns so that its bone (`bone`: at rest,
/// in the joint's frame) lies as near as it can to where `local` puts it: the bone's direction
/// projected on the plane the hinge turns in, which is the best a hinge can do. Two channels
/// `R1 · R2` lay the bone exactly where the direction is within their reach (the second angle
/// keeps the bone's component along the first axis, the first turns it into place), of the two
/// solutions the one nearer the Euler decomposition. Without a bone, or where the bone lies
/// along an axis, the Euler decomposition's angles ([`channel_angles`]).
pub(crate) fn limited_angles(
    joint: &Joint,
    local: DQuat,
    bone: Option<DVec3>,
) -> ([f64; 3], DQuat) {
    limited_angles_by(joint, local, bone, |_| 0.0)
}

/// [`limited_angles`], where of two channels' two solutions the one `cost` (of the local
/// rotation each gives) finds cheaper is taken, the nearer one where they cost the same: `solve`
/// takes the one whose joints below can reach the data.
pub(crate) fn limited_angles_by(
    joint: &Joint,
    local: DQuat,
    bone: Option<DVec3>,
    cost: impl Fn(DQuat) -> f64,
) -> ([f64; 3], DQuat) {
    let axes: Vec<usize> = joint.rotation_axes();
    let mut angles = [0.0; 3];
    let q = local.as_quat();
    for (angle, value) in angles.iter_mut().zip(channel_angles(
        joint,
        RotationKind::Quat,
        &[q.w, q.x, q.y, q.z],
    )) {
        *angle = f64::from(value);
    }
    let c = joint.axis_f64();
    if let Some(bone) = bone.filter(|b| b.length() > 1e-9) {
        // In the channels' frame: the bone at rest and where `local` puts it.
        let u = c.inverse() * bone;
        let w = c.inverse() * (local * bone);
        let unit = |axis: usize| DVec3::AXES[axis];
        let about =
            |axis: usize, degrees: f64| DQuat::from_axis_angle(unit(axis), degrees.to_radians());
        match axes[..] {
            [a] => {
                if let Some(theta) = hinge_angle(unit(a), u, w) {
                    angles[0] = theta.to_degrees();
                }
            }
            [a1, a2] if a1 != a2 => {
                let (x1, x2) = (unit(a1), unit(a2));
                // a1 · R2(β) u = A cos β + B sin β must equal a1 · w.
                let (along, across) = (x1.dot(u), x1.dot(x2.cross(u)));
                let reach = along.hypot(across);
                if reach > 1e-9 {
                    let phase = across.atan2(along);
                    let spread = (x1.dot(w) / reach).clamp(-1.0, 1.0).acos();
                    let near = |b: f64| {
                        let d = (b.to_degrees() - angles[1]).rem_euclid(360.0);
                        d.min(360.0 - d)
                    };
                    // Each solution: its angles, what `cost` says of it, how far it is.
                    let solutions = [phase + spread, phase - spread].map(|beta| {
                        let mut beta = beta.to_degrees();
                        beta -= 360.0 * ((beta - angles[1]) / 360.0).round();
                        let alpha = hinge_angle(x1, about(a2, beta) * u, w)?.to_degrees();
                        let turned = c * about(a1, alpha) * about(a2, beta) * c.inverse();
                        Some((alpha, beta, cost(turned), near(beta.to_radians())))
                    });
                    let chosen = solutions.into_iter().flatten().min_by(|a, b| {
                        match (a.2 - b.2).abs() > 1e-9 {
                            true => a.2.total_cmp(&b.2),
                            false => a.3.total_cmp(&b.3),
                        }
                    });
                    if let Some((alpha, beta, _, _)) = chosen {
                        angles[0] = alpha;
                        angles[1] = beta;
                    }
                }
            }
            _ => {}
        }
    }
    // The rotation the values give, as they are written (32-bit).
    let mut values = Vec::with_capacity(joint.channels.len());
    let mut rotations = angles.iter();
    for channel in &joint.channels {
        values.push(if channel.is_rotation() {
            rotations.next().copied().unwrap_or(0.0) as f32
        } else {
            0.0
        });
    }
    (
        angles,
        crate::model::pose::local_rotation_f64(joint, &values),
    )
}

#[cfg(test)]
mod limited {
    use super::*;
    use crate::model::skeleton::Channel;

    /// A joint turning about `axes` inside a fixed axis C (an ASF bone).
    fn joint(channels: Vec<Channel>, c: DQuat) -> Joint {
        let mut joint = Joint::new("j".into(), None);
        joint.channels = channels;
        joint.axis = Some(c.as_quat());
        joint
    }

    /// Rotations spread over the sphere, from a fixed sequence (no randomness in tests).
    fn rotations() -> impl Iterator<Item = DQuat> {
        (0..200).map(|k| {
            let k = f64::from(k);
            DQuat::from_euler(glam::EulerRot::ZXY, 0.37 * k, 0.61 * k, 0.23 * k)
        })
    }

    #[test]
    fn a_hinge_lays_its_bone_in_its_plane_as_near_as_it_can() {
        let c = DQuat::from_rotation_z(20f64.to_radians());
        let knee = joint(vec![Channel::Xrotation], c);
        let bone = c * DVec3::new(0.0, -1.0, 0.0);
        let hinge = c * DVec3::X;
        for local in rotations() {
            let (angles, realized) = limited_angles(&knee, local, Some(bone));
            assert_eq!(angles[1..], [0.0, 0.0]);
            let (got, want) = (realized * bone, local * bone);
            // In the hinge's plane, the bone points where it is asked to (within the 32-bit
            // rounding of the written angle).
            let across = |v: DVec3| (v - hinge * v.dot(hinge)).normalize();
            assert!(across(got).angle_between(across(want)).to_degrees() < 1e-4);
            // And no angle of the hinge lays it nearer.
            for step in 0..360 {
                let other = c * DQuat::from_rotation_x(f64::from(step).to_radians()) * c.inverse();
                assert!(
                    (other * bone).angle_between(want) >= got.angle_between(want) - 1e-6,
                    "{local:?}: {step}° is nearer"
                );
            }
        }
    }

    #[test]
    fn two_channels_lay_their_bone_exactly_where_it_is_within_reach() {
        // A clavicle: `dof ry rz` about its axis, the bone along the axis frame's x.
        let c = DQuat::from_rotation_z(-15f64.to_radians());
        let clavicle = joint(vec![Channel::Yrotation, Channel::Zrotation], c);
        let bone = c * DVec3::new(2.0, 0.0, 0.0);
        for local in rotations() {
            let (angles, realized) = limited_angles(&clavicle, local, Some(bone));
            assert_eq!(angles[2], 0.0);
            let error = (realized * bone).angle_between(local * bone).to_degrees();
            assert!(error < 1e-4, "{local:?}: {error}° off");
        }
    }

    #[test]
    fn a_bone_without_rotation_channels_keeps_its_rest() {
        let hip = joint(Vec::new(), DQuat::IDENTITY);
        let (angles, realized) = limited_angles(&hip, DQuat::from_rotation_y(1.0), Some(DVec3::X));
        assert_eq!(angles, [0.0; 3]);
        assert_eq!(realized, DQuat::IDENTITY);
    }
}
