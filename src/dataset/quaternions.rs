//! The dataset's fast posing: each kept frame's rotations go from the file's channels to
//! quaternions once (the first half of the FK plan), are scaled, turned and interpolated as
//! quaternions, and both the world positions (the second half of the FK plan) and every rotation
//! kind are made from them. No Euler angles on the way, and frames the dataset does not keep
//! are never touched. [`super::compile_take_plain`] makes the same clip step by step.

use super::clip::Topology;
use super::options::{FeatureSet, Options};
use super::steps::{Posed, Prepared, Stages, topology_of};
use crate::edit::{Picks, QuarterTurn, resample_picks};
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::{self, FkPlan, FkScratch, LANES, RotationKind, Up};
use crate::model::skeleton::Skeleton;
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
    let motion = &take.loaded.motion;
    let (skeleton, baked) = group_skeleton(take)?;
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
    let joints = take.loaded.skeleton.joints.len();
    let mut posing = Posing::new(take, &skeleton, options, baked);
    let mut world: Vec<Vec3> = Vec::with_capacity(frames * joints);
    let mut rotations = Vec::with_capacity(frames * topology.rotated.len() * posing.width);
    let mut translations = Vec::with_capacity(frames * topology.translated.len() * 3);
    // Eight new frames at a time, every stage in turn, so that nothing but the arrays kept
    // grows with the take.
    for batch in made_of.chunks(LANES) {
        posing.read(batch);
        lap(&mut stages.rotations);

        posing.interpolate(batch);
        lap(&mut stages.resample);

        posing.positions(&mut world);
        lap(&mut stages.fk);

        // HumanML3D's vectors are made of the positions alone: its datasets write no
        // rotations.
        let batch = match options.features {
            FeatureSet::Arrays => batch,
            FeatureSet::HumanMl3d => &[],
        };
        posing.write_kinds(batch, &topology, &mut rotations, &mut translations);
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

/// The group's skeleton as the plain way makes it (the same edits, and so the same refusals),
/// with no frames to carry through them, and whether a bone axis was baked into it.
fn group_skeleton(take: &Prepared) -> Result<(Skeleton, bool), Error> {
    let (source, motion) = (&take.loaded.skeleton, &take.loaded.motion);
    let metres = take.stance.units.metres;
    let empty = Motion::new(motion.frame_time, motion.channels, 0, Vec::new());
    let (skeleton, empty) = crate::edit::scale(source, &empty, metres)?;
    let (skeleton, empty) = crate::edit::reorient(&skeleton, &empty, take.stance.up, Up::Y)?;
    let baked = skeleton.joints.iter().any(|j| j.axis.is_some());
    let skeleton = match baked {
        true => crate::edit::bake_axes(&skeleton, &empty)?.0,
        false => skeleton,
    };
    Ok((skeleton, baked))
}

/// One take posed a batch of eight new frames at a time: what every batch needs, and the
/// buffers each stage fills and the next reads.
struct Posing<'a> {
    source: &'a Skeleton,
    motion: &'a Motion,
    /// The group's skeleton.
    skeleton: &'a Skeleton,
    source_plan: FkPlan,
    plan: FkPlan,
    /// Per source joint: whether it has rotation channels.
    rotates: Vec<bool>,
    metres: f32,
    turned: bool,
    quarter: QuarterTurn,
    /// Euler angles are the file's own values where a frame is kept as it is.
    as_is: bool,
    kind: RotationKind,
    width: usize,
    scratch: FkScratch,
    /// The batch's local rotations and translations as the file gives them, of the frames
    /// each new frame is made from (`a`, and `b` where it lies between two).
    qa: Vec<glam::Quat>,
    ta: Vec<Vec3>,
    qb: Vec<glam::Quat>,
    tb: Vec<Vec3>,
    /// The new frames' local rotations and translations, in metres and Y up.
    q: Vec<glam::Quat>,
    t: Vec<Vec3>,
    points: Vec<Vec3>,
    rows: Vec<&'a [f32]>,
}

impl<'a> Posing<'a> {
    fn new(take: &'a Prepared, skeleton: &'a Skeleton, options: &Options, baked: bool) -> Self {
        let (source, motion) = (&take.loaded.skeleton, &take.loaded.motion);
        let turned = take.stance.up != Up::Y;
        Posing {
            source,
            motion,
            skeleton,
            source_plan: FkPlan::new(source, take.mode),
            plan: FkPlan::new(skeleton, take.mode),
            rotates: source
                .joints
                .iter()
                .map(|j| j.channels.iter().any(|c| c.is_rotation()))
                .collect(),
            metres: take.stance.units.metres,
            turned,
            quarter: QuarterTurn::between(take.stance.up, Up::Y),
            as_is: !turned && !baked,
            kind: options.rotations,
            width: options.rotations.width(),
            scratch: FkScratch::default(),
            qa: Vec::new(),
            ta: Vec::new(),
            qb: Vec::new(),
            tb: Vec::new(),
            q: Vec::new(),
            t: Vec::new(),
            points: Vec::new(),
            rows: Vec::with_capacity(LANES),
        }
    }

    /// The local rotation and translation of every joint, as the file gives them (its units,
    /// its up axis, bone axes in the rotations).
    fn read(&mut self, batch: &[(usize, usize, f32)]) {
        let motion = self.motion;
        self.rows.clear();
        self.rows
            .extend(batch.iter().map(|&(a, _, _)| motion.frame(a)));
        self.source_plan.locals_of_frames(
            &self.rows,
            &mut self.qa,
            &mut self.ta,
            &mut self.scratch,
        );
        if batch.iter().any(|&(a, b, _)| a != b) {
            self.rows.clear();
            self.rows
                .extend(batch.iter().map(|&(_, b, _)| motion.frame(b)));
            self.source_plan.locals_of_frames(
                &self.rows,
                &mut self.qb,
                &mut self.tb,
                &mut self.scratch,
            );
        }
    }

    /// Interpolated where a frame lies between two, then in metres and Y up.
    fn interpolate(&mut self, batch: &[(usize, usize, f32)]) {
        let joints = self.source.joints.len();
        self.q.clear();
        self.t.clear();
        for (k, &(a, b, w)) in batch.iter().enumerate() {
            for (j, &rotates) in self.rotates.iter().enumerate() {
                let i = k * joints + j;
                let (mut rotation, mut translation) = (self.qa[i], self.ta[i]);
                if a != b {
                    if rotates {
                        rotation = rotation.slerp(self.qb[i], w);
                    }
                    // In f64, so that values near the f32 limit do not overflow (inf · 0).
                    let (w, from, to) =
                        (f64::from(w), self.ta[i].as_dvec3(), self.tb[i].as_dvec3());
                    translation = (from * (1.0 - w) + to * w).as_vec3();
                }
                translation *= self.metres;
                if self.turned {
                    rotation = self.quarter.conjugate(rotation);
                    translation = self.quarter.apply(translation);
                }
                self.q.push(rotation);
                self.t.push(translation);
            }
        }
    }

    /// The batch's world positions, added to `world`.
    fn positions(&mut self, world: &mut Vec<Vec3>) {
        self.plan
            .positions_of_locals(&self.q, &self.t, &mut self.points, &mut self.scratch);
        world.extend_from_slice(&self.points);
    }

    /// The batch's rotations as asked and its translations, added to `rotations` and
    /// `translations`.
    fn write_kinds(
        &mut self,
        batch: &[(usize, usize, f32)],
        topology: &Topology,
        rotations: &mut Vec<f32>,
        translations: &mut Vec<f32>,
    ) {
        let joints = self.source.joints.len();
        let mut numbers = [0.0f32; 9];
        for (k, &(a, b, w)) in batch.iter().enumerate() {
            for &j in &topology.rotated {
                let j = j as usize;
                let slot = &mut numbers[..self.width];
                self.write_rotation(k * joints + j, j, (a, b, w), slot);
                rotations.extend_from_slice(slot);
            }
            for &j in &topology.translated {
                translations.extend_from_slice(&self.t[k * joints + j as usize].to_array());
            }
        }
    }

    /// Joint `j`'s rotation in the new frame made of `(a, b, w)` (`at` in the batch's
    /// rotations) as asked; Euler angles in the joint's own order (its channels' order, or
    /// Z Y X where a bone axis was baked in).
    fn write_rotation(
        &self,
        at: usize,
        j: usize,
        (a, b, w): (usize, usize, f32),
        slot: &mut [f32],
    ) {
        let kind = self.kind;
        if kind != RotationKind::Euler {
            pose::write_quat(self.q[at], kind, slot);
            return;
        }
        let motion = self.motion;
        let source_joint = &self.source.joints[j];
        let values_a = source_joint.values(motion.frame(a));
        match (self.skeleton.joints[j].rotation_order, self.as_is && a == b) {
            (_, true) => pose::write_rotation(source_joint, values_a, kind, slot),
            (Some(order), false) => {
                let angles = crate::model::euler::split_degrees(self.q[at].as_dquat(), order);
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
    }
}
