//! The dataset's fast posing: each kept frame's rotations go from the file's channels to
//! quaternions once (the first half of the FK plan), are scaled, turned and interpolated as
//! quaternions, and both the world positions (the second half of the FK plan) and every rotation
//! kind are made from them. No Euler angles on the way, and frames the dataset does not keep
//! are never touched. [`super::compile_take_plain`] makes the same clip step by step.

use super::{Options, Posed, Prepared, Stages, topology_of};
use crate::edit::{Picks, QuarterTurn, euler_order, resample_picks};
use crate::error::Error;
use crate::motion::Motion;
use crate::pose::{self, FkPlan, FkScratch, LANES, RotationKind, Up};
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

    // Every source frame a new frame is made from, in order, once.
    let (needed, made_of): (Vec<usize>, Vec<(usize, usize, f32)>) = match &picks {
        Picks::Rows(rows) => (rows.clone(), (0..rows.len()).map(|k| (k, k, 0.0)).collect()),
        Picks::Between(between) => {
            // Rows come in order (b is a or a + 1, and a never goes back), so `needed` stays
            // sorted and each row is found by a binary search.
            let mut needed: Vec<usize> = Vec::with_capacity(between.len() + 1);
            let index = |row: usize, needed: &mut Vec<usize>| {
                if needed.last().is_none_or(|&last| last < row) {
                    needed.push(row);
                }
                needed.partition_point(|&r| r < row)
            };
            let made_of = between
                .iter()
                .map(|&(a, b, w)| {
                    let a = index(a, &mut needed);
                    (a, index(b, &mut needed), w)
                })
                .collect();
            (needed, made_of)
        }
    };

    // The local rotation and translation of every joint in every needed frame, as the file
    // gives them (its units, its up axis, bone axes in the rotations).
    let joints = source.joints.len();
    let source_plan = FkPlan::new(source, take.mode);
    let mut scratch = FkScratch::default();
    let (mut local_q, mut local_t) = (
        Vec::with_capacity(needed.len() * joints),
        Vec::with_capacity(needed.len() * joints),
    );
    let (mut batch_q, mut batch_t) = (Vec::new(), Vec::new());
    let mut rows: Vec<&[f32]> = Vec::with_capacity(LANES);
    for batch in needed.chunks(LANES) {
        rows.clear();
        rows.extend(batch.iter().map(|&f| motion.frame(f)));
        source_plan.locals_of_frames(&rows, &mut batch_q, &mut batch_t, &mut scratch);
        local_q.extend_from_slice(&batch_q);
        local_t.extend_from_slice(&batch_t);
    }

    lap(&mut stages.rotations);

    // Each new frame: interpolated where it lies between two, then in metres and Y up.
    let frames = made_of.len();
    let rotates: Vec<bool> = source
        .joints
        .iter()
        .map(|j| j.channels.iter().any(|c| c.is_rotation()))
        .collect();
    let mut out_q = Vec::with_capacity(frames * joints);
    let mut out_t = Vec::with_capacity(frames * joints);
    for &(a, b, w) in &made_of {
        let (qa, ta) = (
            &local_q[a * joints..][..joints],
            &local_t[a * joints..][..joints],
        );
        let (qb, tb) = (
            &local_q[b * joints..][..joints],
            &local_t[b * joints..][..joints],
        );
        for j in 0..joints {
            let mut q = qa[j];
            let mut t = ta[j];
            if a != b {
                if rotates[j] {
                    q = q.slerp(qb[j], w);
                }
                // In f64, so that values near the f32 limit do not overflow on the way (inf · 0).
                let (w64, from, to) = (f64::from(w), ta[j].as_dvec3(), tb[j].as_dvec3());
                t = (from * (1.0 - w64) + to * w64).as_vec3();
            }
            t *= metres;
            if turned {
                q = quarter.conjugate(q);
                t = quarter.apply(t);
            }
            out_q.push(q);
            out_t.push(t);
        }
    }

    lap(&mut stages.resample);

    // World positions, eight frames side by side.
    let plan = FkPlan::new(&skeleton, take.mode);
    let mut world: Vec<Vec3> = Vec::with_capacity(frames * joints);
    let mut points = Vec::new();
    for (q, t) in out_q
        .chunks(LANES * joints)
        .zip(out_t.chunks(LANES * joints))
    {
        plan.positions_of_locals(q, t, &mut points, &mut scratch);
        world.extend_from_slice(&points);
    }

    lap(&mut stages.fk);

    // Rotations as asked. Euler angles are the file's own values where a frame is kept as it
    // is; otherwise they are the quaternion's in the joint's own order (its channels' order, or
    // Z Y X where a bone axis was baked in).
    let kind = options.rotations;
    let width = kind.width();
    let rotated = &topology.rotated;
    let mut rotations = vec![0.0f32; frames * rotated.len() * width];
    let as_is = !turned && !baked;
    for (f, out) in rotations
        .chunks_mut(rotated.len().max(1) * width)
        .enumerate()
        .take(frames)
    {
        let (a, b, w) = made_of[f];
        for (&j, slot) in rotated.iter().zip(out.chunks_mut(width)) {
            let j = j as usize;
            let q = out_q[f * joints + j];
            if kind != RotationKind::Euler {
                pose::write_quat(q, kind, slot);
                continue;
            }
            let joint = &skeleton.joints[j];
            let source_joint = &source.joints[j];
            let values_a = source_joint.values(motion.frame(needed[a]));
            match (joint.rotation_order, as_is && a == b) {
                (_, true) => pose::write_rotation(source_joint, values_a, kind, slot),
                (Some(order), false) => {
                    let (x, y, z) = q.to_euler(euler_order(order));
                    for (value, angle) in slot.iter_mut().zip([x, y, z]) {
                        *value = angle.to_degrees();
                    }
                }
                (None, false) => {
                    // Angles without a rotation order (one or two, or an axis twice) are
                    // interpolated one by one, as `edit::resample` does.
                    let values_b = source_joint.values(motion.frame(needed[b]));
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
        }
    }
    let mut translations = Vec::with_capacity(frames * topology.translated.len() * 3);
    for f in 0..frames {
        for &j in &topology.translated {
            translations.extend_from_slice(&out_t[f * joints + j as usize].to_array());
        }
    }
    lap(&mut stages.kinds);
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
