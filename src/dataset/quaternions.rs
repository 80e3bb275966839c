//! The dataset's fast posing: each kept frame's rotations go from the file's channels to
//! quaternions once (the first half of the FK plan), are scaled, turned and interpolated as
//! quaternions, and both the world positions (the second half of the FK plan) and every rotation
//! kind are made from them. No Euler angles on the way, and frames the dataset does not keep
//! are never touched. [`super::compile_take_plain`] makes the same clip step by step.

use super::{FeatureSet, Options, Posed, Prepared, Stages, topology_of};
use crate::edit::{Picks, QuarterTurn, resample_picks};
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::{self, FkPlan, FkScratch, LANES, RotationKind, Up};
use glam::Vec3;
use std::path::Path;

/// The posed frames of `take` at `options.fps`.
pub(crate) fn posed(
    take: &Prepared,
    path: &Path,
    options: &Options,
    stages: &mut Stages,
) -> Result<Posed, Error> {
    let mut clock = std::time::Instant::now();
    let mut lap = |stage: &mut std::time::Duration| {
        *stage += clock.elapsed();
        clock = std::time::Instant::now();
    };
    let (source, motion) = (&take.loaded.skeleton, &take.loaded.motion);
    let metres = take.stance.units.metres;
    let turned = take.stance.up != Up::Y;
    let quarter = QuarterTurn::between(take.stance.up, Up::Y);
    // The group's skeleton as the plain way makes it (the same edits, and so the same refusals),
    // with no frames to carry through them.
    let empty = Motion::new(motion.frame_time, motion.channels, 0, Vec::new());
    let (skeleton, empty) = crate::edit::scale(source, &empty, metres)?;
    let (skeleton, empty) = crate::edit::reorient(&skeleton, &empty, take.stance.up, Up::Y)?;
    let baked = skeleton.joints.iter().any(|j| j.axis.is_some());
    let skeleton = match baked {
        true => crate::edit::bake_axes(&skeleton, &empty)?.0,
        false => skeleton,
    };
    let picks = resample_picks(
        motion.frame_count(),
        motion.frame_time,
        options.fps,
        motion.channels,
    )?;
    let (topology, names) = topology_of(path, &skeleton, options, take.mode)?;

    // The frames each new frame is made from: itself, or the two it lies between.
    let made_of: Vec<(usize, usize, f32)> = match picks {
        Picks::Rows(rows) => rows.into_iter().map(|row| (row, row, 0.0)).collect(),
        Picks::Between(between) => between,
    };
    let frames = made_of.len();
    let joints = source.joints.len();
    let source_plan = FkPlan::new(source, take.mode);
    let plan = FkPlan::new(&skeleton, take.mode);
    let rotates: Vec<bool> = source
        .joints
        .iter()
        .map(|j| j.channels.iter().any(|c| c.is_rotation()))
        .collect();
    let kind = options.rotations;
    let width = kind.width();
    let rotated = &topology.rotated;
    // Euler angles are the file's own values where a frame is kept as it is.
    let as_is = !turned && !baked;
    let mut world: Vec<Vec3> = Vec::with_capacity(frames * joints);
    let mut rotations = Vec::with_capacity(frames * rotated.len() * width);
    let mut translations = Vec::with_capacity(frames * topology.translated.len() * 3);
    let mut scratch = FkScratch::default();
    let (mut qa, mut ta, mut qb, mut tb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut q, mut t, mut points) = (Vec::new(), Vec::new(), Vec::new());
    let mut rows: Vec<&[f32]> = Vec::with_capacity(LANES);
    let mut numbers = [0.0f32; 9];
    // Eight new frames at a time, every stage in turn, so that nothing but the arrays kept
    // grows with the take.
    for batch in made_of.chunks(LANES) {
        // The local rotation and translation of every joint, as the file gives them (its
        // units, its up axis, bone axes in the rotations).
        rows.clear();
        rows.extend(batch.iter().map(|&(a, _, _)| motion.frame(a)));
        source_plan.locals_of_frames(&rows, &mut qa, &mut ta, &mut scratch);
        if batch.iter().any(|&(a, b, _)| a != b) {
            rows.clear();
            rows.extend(batch.iter().map(|&(_, b, _)| motion.frame(b)));
            source_plan.locals_of_frames(&rows, &mut qb, &mut tb, &mut scratch);
        }
        lap(&mut stages.rotations);

        // Interpolated where a frame lies between two, then in metres and Y up.
        q.clear();
        t.clear();
        for (k, &(a, b, w)) in batch.iter().enumerate() {
            for (j, &rotates) in rotates.iter().enumerate() {
                let i = k * joints + j;
                let (mut rotation, mut translation) = (qa[i], ta[i]);
                if a != b {
                    if rotates {
                        rotation = rotation.slerp(qb[i], w);
                    }
                    // In f64, so that values near the f32 limit do not overflow (inf · 0).
                    let (w, from, to) = (f64::from(w), ta[i].as_dvec3(), tb[i].as_dvec3());
                    translation = (from * (1.0 - w) + to * w).as_vec3();
                }
                translation *= metres;
                if turned {
                    rotation = quarter.conjugate(rotation);
                    translation = quarter.apply(translation);
                }
                q.push(rotation);
                t.push(translation);
            }
        }
        lap(&mut stages.resample);

        plan.positions_of_locals(&q, &t, &mut points, &mut scratch);
        world.extend_from_slice(&points);
        lap(&mut stages.fk);

        // Rotations as asked; Euler angles in the joint's own order (its channels' order, or
        // Z Y X where a bone axis was baked in). HumanML3D's vectors are made of the positions
        // alone: its datasets write no rotations.
        let batch = match options.features {
            FeatureSet::Arrays => batch,
            FeatureSet::HumanMl3d => &[],
        };
        for (k, &(a, b, w)) in batch.iter().enumerate() {
            for &j in rotated {
                let j = j as usize;
                let slot = &mut numbers[..width];
                if kind != RotationKind::Euler {
                    pose::write_quat(q[k * joints + j], kind, slot);
                    rotations.extend_from_slice(slot);
                    continue;
                }
                let source_joint = &source.joints[j];
                let values_a = source_joint.values(motion.frame(a));
                match (skeleton.joints[j].rotation_order, as_is && a == b) {
                    (_, true) => pose::write_rotation(source_joint, values_a, kind, slot),
                    (Some(order), false) => {
                        let angles =
                            crate::model::euler::split_degrees(q[k * joints + j].as_dquat(), order);
                        slot[..3].copy_from_slice(&angles);
                    }
                    (None, false) => {
                        // Angles without a rotation order (one or two, or an axis twice) are
                        // interpolated one by one, as `edit::resample` does.
                        let values_b = source_joint.values(motion.frame(b));
                        let angles = |values: &[f32]| {
                            let mut out = [0.0f32; 3];
                            pose::write_rotation(source_joint, values, kind, &mut out);
                            out
                        };
                        let (from, to, w) = (angles(values_a), angles(values_b), f64::from(w));
                        for ((value, x), y) in slot.iter_mut().zip(from).zip(to) {
                            *value = (f64::from(x) * (1.0 - w) + f64::from(y) * w) as f32;
                        }
                    }
                }
                rotations.extend_from_slice(slot);
            }
            for &j in &topology.translated {
                translations.extend_from_slice(&t[k * joints + j as usize].to_array());
            }
        }
        lap(&mut stages.kinds);
    }
    Ok(Posed {
        skeleton,
        topology,
        names,
        frames,
        world,
        rotations,
        translations,
    })
}
