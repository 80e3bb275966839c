//! Where a take stands: its travel taken out (in place), its lowest point on the floor
//! (ground), and a quarter turn from one up axis to another (reorient).

use crate::edit::finite;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::euler;
use crate::model::motion::Motion;
use crate::model::pose::UpAxis;
use crate::model::skeleton::Skeleton;
use glam::Quat;

/// The ground plane's axes for an up axis: (the two across, the one up).
fn plane(up: crate::model::pose::Up) -> ([usize; 2], usize) {
    match up {
        crate::model::pose::Up::Y => ([0, 2], 1),
        crate::model::pose::Up::Z => ([0, 1], 2),
    }
}

/// The travel across the ground removed: the joint that carries it ([`travel_joint_of_take`],
/// the root in most files, `Hips` under a still root in others) keeps its first frame's place in
/// the ground plane, so the figure moves where it stands.
/// Only that joint's values change, to values the take already holds: nothing can overflow.
///
/// [`travel_joint_of_take`]: crate::model::body::travel_joint_of_take
pub fn in_place(skeleton: &Skeleton, motion: &Motion, up: crate::model::pose::Up) -> Motion {
    let (across, _) = plane(up);
    let mut data = motion.data.clone();
    if motion.frame_count() == 0 || motion.channels == 0 {
        return motion.clone();
    }
    let travel = crate::model::body::travel_joint_of_take(
        skeleton,
        motion,
        crate::model::pose::OffsetMode::Replace,
    );
    let joint = &skeleton.joints[travel];
    for (i, channel) in joint.channels.iter().enumerate() {
        if channel.is_position() && across.contains(&channel.axis()) {
            let column = joint.first_channel + i;
            let first = motion.frame(0)[column];
            for row in data.chunks_mut(motion.channels) {
                row[column] = first;
            }
        }
    }
    Motion::new(
        motion.frame_time,
        motion.channels,
        motion.frame_count(),
        data,
    )
}

/// The take moved up or down so that the lowest point of its soles over the take (each leg's
/// ankle and everything below it, toe tips too, as the reading of the body finds them:
/// [`crate::model::body::Body::sole_points`]) is at 0: the feet on the floor, as `dataset
/// --ground` stands them. A body without two feet: its lowest point, over every joint and frame. The roots' up position
/// channel carries the move (their OFFSET when they have none).
pub fn ground(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: crate::model::pose::OffsetMode,
    up: crate::model::pose::Up,
) -> Result<(Skeleton, Motion), Error> {
    let (_, axis) = plane(up);
    let feet = crate::model::body::Body::of(skeleton).sole_points(skeleton);
    let mut lowest = f32::INFINITY;
    let frames = motion.frame_count();
    for frame in 0..frames.max(1) {
        let row = if frames == 0 {
            &[][..]
        } else {
            motion.frame(frame)
        };
        let points = crate::model::pose::world_positions(skeleton, row, mode);
        for (j, p) in points.iter().enumerate() {
            if feet.is_empty() || feet.binary_search(&j).is_ok() {
                lowest = lowest.min(p[axis]);
            }
        }
    }
    let mut grounded = skeleton.clone();
    let mut data = motion.data.clone();
    if !lowest.is_finite() {
        return finite(
            Message::of_argument("ground", None),
            grounded,
            motion.clone(),
        );
    }
    for root in skeleton.roots() {
        let joint = &skeleton.joints[root];
        let channel = joint
            .channels
            .iter()
            .position(|c| c.is_position() && c.axis() == axis);
        match (channel, frames) {
            (Some(i), 1..) => {
                for row in data.chunks_mut(motion.channels) {
                    row[joint.first_channel + i] -= lowest;
                }
            }
            _ => grounded.joints[root].offset[axis] -= lowest,
        }
    }
    finite(
        Message::of_argument("ground", None),
        grounded,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

/// The turn from one up axis to another, `turn`, which moves each axis onto another (maybe
/// negated): [`QuarterTurn::apply`] turns a vector exactly, with no rounding and no overflow on
/// the way (a product with the quaternion does both).
///
/// ```
/// use bvhview::{edit::QuarterTurn, model::pose::Up};
/// use glam::Vec3;
///
/// let turn = QuarterTurn::between(Up::Z, Up::Y);
/// assert_eq!(turn.apply(Vec3::Z), Vec3::Y); // up stays up
/// assert_eq!(turn.apply(Vec3::new(1.0, 2.0, 3.0)), Vec3::new(1.0, 3.0, -2.0));
/// assert!((turn.turn * Vec3::Z).abs_diff_eq(Vec3::Y, 1e-6)); // the quaternion, rounded
/// ```
#[derive(Clone, Copy, Debug)]
pub struct QuarterTurn {
    /// The turn as a quaternion (for rotations; [`QuarterTurn::apply`] turns vectors exactly).
    pub turn: Quat,
    /// Column k: where axis k goes, as signs of 0, 1 or −1.
    axes: [[f32; 3]; 3],
}

impl QuarterTurn {
    /// The turn that takes a take standing along `from` to one standing along `to` (either
    /// an [`Up`](crate::model::pose::Up) or any signed [`UpAxis`]).
    pub fn between(from: impl Into<UpAxis>, to: impl Into<UpAxis>) -> QuarterTurn {
        // Into Y-up from `from`, then out of Y-up into `to`.
        let turn = to.into().to_y_up().inverse() * from.into().to_y_up();
        let axes = glam::Mat3::from_quat(turn)
            .to_cols_array_2d()
            .map(|c| c.map(f32::round));
        QuarterTurn { turn, axes }
    }

    /// `v` turned.
    pub fn apply(&self, v: glam::Vec3) -> glam::Vec3 {
        let mut out = glam::Vec3::ZERO;
        for (column, &value) in self.axes.iter().zip(&v.to_array()) {
            for (row, &sign) in column.iter().enumerate() {
                if sign != 0.0 {
                    out[row] = sign * value;
                }
            }
        }
        out
    }

    /// `turn · q · turn⁻¹`: the rotation q as seen once everything is turned (its axis turned,
    /// its angle kept), exactly.
    pub fn conjugate(&self, q: Quat) -> Quat {
        let axis = self.apply(glam::Vec3::new(q.x, q.y, q.z));
        Quat::from_xyzw(axis.x, axis.y, axis.z, q.w)
    }
}

/// Whether a joint's rotation turns as Q·R·Q⁻¹ split again into its own three channels (a BVH
/// joint's), rather than by its axis (an ASF bone's, or a hinge's given one).
fn by_channels(joint: &crate::model::skeleton::Joint) -> bool {
    joint.rotation_order.is_some() && joint.axis.is_none()
}

/// The take turned from one up axis to another, so that it loads the same way in the other
/// convention: every OFFSET and position turned by the rotation Q between them, every joint's
/// rotation R replaced by Q·R·Q⁻¹ in the joint's own channel order. An ASF bone, whose local
/// rotation is C·R·C⁻¹ about its axis C, gets the axis Q·C instead and keeps its channels as
/// they are, and a joint of one or two rotations (a hinge) the axis Q: their degrees of freedom
/// turn with them (a BVH writer bakes such axes into three channels). The world positions come
/// out turned by Q.
pub fn reorient(
    skeleton: &Skeleton,
    motion: &Motion,
    from: impl Into<UpAxis>,
    to: impl Into<UpAxis>,
) -> Result<(Skeleton, Motion), Error> {
    let (from, to) = (from.into(), to.into());
    if from == to {
        return Ok((skeleton.clone(), motion.clone()));
    }
    let quarter = QuarterTurn::between(from, to);
    let (turn, exactly) = (quarter.turn, |v| quarter.apply(v));
    let mut turned = skeleton.clone();
    // Turned, it no longer stands the way its file stated.
    turned.y_up_stated = skeleton.y_up_stated && to == UpAxis::Y;
    for joint in &mut turned.joints {
        joint.offset = exactly(joint.offset);
        // Q·(C·R·C⁻¹)·Q⁻¹ = (Q·C)·R·(Q·C)⁻¹: the channels stay, the axis turns. A joint with
        // one or two rotations (a hinge) has no three channels to turn R in: it gets the axis Q.
        let rotations = joint.channels.iter().filter(|c| c.is_rotation()).count();
        if rotations != 0 && !by_channels(joint) {
            let c = joint.axis.unwrap_or(Quat::IDENTITY);
            joint.axis = Some((turn * c).normalize());
        }
        let positions = joint.channels.iter().filter(|c| c.is_position()).count();
        if positions != 0 && positions != 3 {
            return Err(Error::invalid(
                "up",
                format!("{from} to {to}"),
                format!(
                    "'{}' has position channels that cannot be turned to another axis (it \
                     needs three or none)",
                    joint.name
                ),
            ));
        }
    }
    let mut data = motion.data.clone();
    if motion.channels > 0 {
        for row in data.chunks_mut(motion.channels) {
            let original = row.to_vec();
            for joint in &skeleton.joints {
                let values = joint.values(&original);
                let columns = |position: bool| {
                    joint
                        .channels
                        .iter()
                        .enumerate()
                        .filter(move |(_, c)| c.is_position() == position)
                        .map(|(i, &c)| (joint.first_channel + i, c.axis()))
                        .collect::<Vec<_>>()
                };
                let positions = columns(true);
                if !positions.is_empty() {
                    let mut p = glam::Vec3::ZERO;
                    for &(column, axis) in &positions {
                        p[axis] = original[column];
                    }
                    let p = exactly(p);
                    for &(column, axis) in &positions {
                        row[column] = p[axis];
                    }
                }
                if let Some(order) = joint.rotation_order.filter(|_| by_channels(joint)) {
                    let r = crate::model::pose::channel_rotations_f64(joint, values);
                    let turn = turn.as_dquat();
                    let angles = euler::split_degrees(turn * r * turn.inverse(), order);
                    for (&(column, _), angle) in columns(false).iter().zip(angles) {
                        row[column] = angle;
                    }
                }
            }
        }
    }
    let frames = motion.frame_count();
    finite(
        Message::of_argument("up", None),
        turned,
        Motion::new(motion.frame_time, motion.channels, frames, data),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::testing::*;

    #[test]
    fn in_place_and_ground_by_hand_worked_values() {
        let bvh = take(TWO_FRAMES);
        let still = in_place(&bvh.skeleton, &bvh.motion, crate::model::pose::Up::Y);
        // x and z stay at frame 0's (0, 0); y keeps moving.
        assert_eq!(&still.frame(2)[..3], [0.0, 4.0, 0.0]);
        // The lowest point is the root at frame 0 (y 0) once the chest bends down: lift the
        // chain so that its lowest joint sits at 0.
        let bent = take(&TWO_FRAMES.replace("8 4 -4 0 0 0 80 0 0", "8 4 -4 0 0 0 180 0 0"));
        let mode = crate::model::pose::OffsetMode::Replace;
        let (skeleton, motion) = ground(
            &bent.skeleton,
            &bent.motion,
            mode,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        // Frame 2: root at y 4, chest at 14, the site 5 below the chest (turned 180°): 9. Frame
        // 0: root at 0, the lowest anywhere. So nothing moves.
        assert_eq!(motion.frame(2)[1], 4.0);
        let lifted = take(&TWO_FRAMES.replace("0 0 0 0 0 0 0 0 0\n4", "0 -7 0 0 0 0 0 0 0\n4"));
        let (_, motion) = ground(
            &lifted.skeleton,
            &lifted.motion,
            mode,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        // The root at -7 on frame 0 is the lowest point: every frame's y rises by 7.
        assert_eq!([motion.frame(0)[1], motion.frame(1)[1]], [0.0, 9.0]);
        assert_eq!(skeleton.joints[0].offset, glam::Vec3::ZERO);
    }

    #[test]
    fn reorienting_turns_every_world_position() {
        let bvh = take(TWO_FRAMES);
        let (skeleton, motion) = reorient(
            &bvh.skeleton,
            &bvh.motion,
            crate::model::pose::Up::Y,
            crate::model::pose::Up::Z,
        )
        .unwrap();
        // Y-up to Z-up: (x, y, z) becomes (x, -z, y).
        assert_eq!(skeleton.joints[1].offset, glam::Vec3::new(0.0, 0.0, 10.0));
        let mode = crate::model::pose::OffsetMode::Replace;
        for frame in 0..3 {
            let before =
                crate::model::pose::world_positions(&bvh.skeleton, bvh.motion.frame(frame), mode);
            let after = crate::model::pose::world_positions(&skeleton, motion.frame(frame), mode);
            for (b, a) in before.iter().zip(&after) {
                assert!(
                    glam::Vec3::new(b.x, -b.z, b.y).abs_diff_eq(*a, 1e-4),
                    "{b} {a}"
                );
            }
        }
        let (back, motion_back) = reorient(
            &skeleton,
            &motion,
            crate::model::pose::Up::Z,
            crate::model::pose::Up::Y,
        )
        .unwrap();
        let again = crate::model::pose::world_positions(&back, motion_back.frame(2), mode);
        let original =
            crate::model::pose::world_positions(&bvh.skeleton, bvh.motion.frame(2), mode);
        for (a, o) in again.iter().zip(&original) {
            assert!(a.abs_diff_eq(*o, 1e-4));
        }
    }
}
