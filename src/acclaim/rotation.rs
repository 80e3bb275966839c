//! A bone's fixed axis: the rotation C that an ASF `axis` (or the root's `orientation`) says,
//! and the joint that carries it. A file of its own, so that the ASF skeleton takes it from a
//! sibling rather than from the module above both.

use crate::model::skeleton::Joint;
use glam::Quat;

/// C for an `axis a b c ORDER` (or the root's `orientation` with its `axis ORDER`): the rotations
/// applied in the order the letters say, so `XYZ` gives Rz · Ry · Rx (as the ASF/AMC article does).
pub fn axis_rotation(degrees: [f64; 3], order: [usize; 3]) -> Quat {
    let mut rotation = Quat::IDENTITY;
    for &axis in &order {
        let angle = (degrees[axis] as f32).to_radians();
        let step = match axis {
            0 => Quat::from_rotation_x(angle),
            1 => Quat::from_rotation_y(angle),
            _ => Quat::from_rotation_z(angle),
        };
        // Each later rotation is applied after (outside) the earlier ones.
        rotation = step * rotation;
    }
    rotation
}

/// The joint a bone becomes (without its place in the tree).
pub(crate) fn bone_joint(name: &str, axis: Option<Quat>) -> Joint {
    let mut joint = Joint::new(name.to_string(), None);
    joint.axis = axis.filter(|q| !q.abs_diff_eq(Quat::IDENTITY, 1e-7));
    joint
}
