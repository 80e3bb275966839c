//! AMC files whose rotations are each bone's own orientation in the world, not its turn from its
//! parent's (PyAsfAmc's test take: `Head`, `Neck`, `LeftCollar` and `Torso` give the same three
//! values on every frame, as do `LeftWrist` and `LeftHand`). Read as the ASF specification says,
//! each bone turns its parent's turn again: a chain of four bones leaning 11° leans 44°, and
//! arms fold into the chest. A captured motion never repeats a parent's three values on every
//! frame, so such repeats are the evidence; the rotations are then made relative to the parent.

use crate::model::euler::split;
use crate::model::motion::Motion;
use crate::model::pose::local_rotation_f64;
use crate::model::skeleton::Skeleton;

/// Bones repeating their parent's values on every frame, at least this many, say the file's
/// rotations are the bones' own in the world.
const REPEATS: usize = 2;

/// The rotation channels' columns of joint `j`, when it has three.
fn rotation_columns(skeleton: &Skeleton, j: usize) -> Option<Vec<usize>> {
    let joint = &skeleton.joints[j];
    joint.rotation_order?;
    let columns: Vec<usize> = joint
        .channels
        .iter()
        .enumerate()
        .filter(|(_, c)| c.is_rotation())
        .map(|(i, _)| joint.first_channel + i)
        .collect();
    (columns.len() == 3).then_some(columns)
}

/// `motion` with each bone's rotation made relative to its parent's, when the file gives every
/// bone's own orientation in the world; with the word to say once. `None` when its rotations
/// read as the specification says (each relative to its parent).
pub fn made_relative(skeleton: &Skeleton, motion: &Motion) -> Option<(Motion, String)> {
    let frames = motion.frame_count();
    if frames == 0 {
        return None;
    }
    let joints = skeleton.joints.len();
    let columns: Vec<Option<Vec<usize>>> =
        (0..joints).map(|j| rotation_columns(skeleton, j)).collect();
    let mut repeats = Vec::new();
    for j in 0..joints {
        let (Some(p), Some(own)) = (skeleton.joints[j].parent, &columns[j]) else {
            continue;
        };
        let Some(parent) = &columns[p] else { continue };
        let mut moved = false;
        let same = (0..frames).all(|f| {
            let row = motion.frame(f);
            own.iter().zip(parent).all(|(&a, &b)| {
                moved |= row[a].abs() > 1.0;
                (row[a] - row[b]).abs() <= 1e-3
            })
        });
        if same && moved {
            repeats.push((j, p));
        }
    }
    if repeats.len() < REPEATS {
        return None;
    }
    // Every turning joint must take three rotations for the orientation to be its own.
    if (0..joints).any(|j| {
        let joint = &skeleton.joints[j];
        joint.channels.iter().any(|c| c.is_rotation()) && columns[j].is_none()
    }) {
        return None;
    }
    let mut data = motion.data.clone();
    let mut world = vec![glam::DQuat::IDENTITY; joints];
    let mut previous: Vec<Option<[f64; 3]>> = vec![None; joints];
    for f in 0..frames {
        let row = motion.frame(f).to_vec();
        let out = &mut data[f * motion.channels..(f + 1) * motion.channels];
        for j in 0..joints {
            let joint = &skeleton.joints[j];
            let values = joint.values(&row);
            let parent = joint.parent.map_or(glam::DQuat::IDENTITY, |p| world[p]);
            let (Some(own), Some(order), Some(_)) =
                (&columns[j], joint.rotation_order, joint.parent)
            else {
                world[j] = parent * local_rotation_f64(joint, values);
                continue;
            };
            // Its values as its orientation in the world; its turn from its parent's written.
            world[j] = local_rotation_f64(joint, values);
            let local = parent.inverse() * world[j];
            let turn = match joint.axis {
                Some(axis) => {
                    let axis = axis.as_dquat().normalize();
                    axis.inverse() * local * axis
                }
                None => local,
            };
            let angles = split(turn, order, previous[j]);
            previous[j] = Some(angles);
            for (&column, angle) in own.iter().zip(angles) {
                out[column] = angle.to_degrees() as f32;
            }
        }
    }
    let (j, p) = repeats[0];
    let word = format!(
        "rotations read as each bone's own orientation, not its turn from its parent's: {} bones \
         repeat their parent's values on every frame ('{}' repeats '{}'), which no captured \
         motion does",
        repeats.len(),
        crate::limits::quoted(&skeleton.joints[j].name),
        crate::limits::quoted(&skeleton.joints[p].name)
    );
    Some((
        Motion::new(motion.frame_time, motion.channels, frames, data),
        word,
    ))
}
