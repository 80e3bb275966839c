//! The plan of one retarget: each source and target joint's work, laid out once, then run on
//! pieces of eight frames.

use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use crate::retarget::fast::lanes::{LANES, Lanes, lanes};
use crate::retarget::fast::quats::{Points, Quats};
use crate::retarget::fast::trig::sin_cos;
use crate::retarget::fast::turns::{axis_order, follow, nearest_forms, turn};
use crate::retarget::hinge::{limited_angles, nearest_form};
use crate::retarget::map::Map;
use crate::retarget::plain::Setup;
use glam::{DQuat, DVec3};
use std::sync::{Mutex, PoisonError};

/// A source joint whose world transform the map reads (or a descendant's does).
pub(super) struct SourceJoint {
    pub(super) index: usize,
    pub(super) parent: Option<usize>,
    pub(super) offset: DVec3,
    /// (axis, input) of each position channel: where in [`Plan::inputs`] its values are.
    pub(super) positions: Vec<(usize, usize)>,
    /// Its rotation channels: a range of the plan's rotation list.
    pub(super) rotations: std::ops::Range<usize>,
    /// An ASF bone's axis C: its rotation is `C · R1 · R2 · R3 · C⁻¹`.
    pub(super) axis: Option<DQuat>,
    /// Whether its world position is read (or a descendant's is), not only its rotation.
    pub(super) placed: bool,
}

/// How a target joint's rotation channels are found.
pub(super) enum Turn {
    /// Three channels: the Euler angles, in file order (see [`axis_order`]), of
    /// `C⁻¹ · local · C` (`C` an ASF bone's axis).
    Euler {
        order: ([usize; 3], f64),
        axis: Option<DQuat>,
    },
    /// One or two: [`limited_angles`], a lane at a time.
    Limited,
    /// None: the joint turns by this fixed rotation (the identity, or `C · C⁻¹`).
    Fixed(DQuat),
}

/// Where a target channel's value comes from.
#[derive(Clone, Copy)]
pub(super) enum Column {
    /// The joint's rotation angle this many into its channels (0 past the third).
    Angle(usize),
    /// The OFFSET's component.
    Offset(f64),
    /// The carrier's translation along this axis, written last.
    Carried(usize),
    /// Its source joint's translation carried ([`Setup::translated`]), along this axis.
    Translated(usize),
}

pub(super) struct TargetJoint {
    pub(super) parent: Option<usize>,
    pub(super) offset: DVec3,
    pub(super) source: Option<usize>,
    pub(super) aligned: DQuat,
    /// [`Setup::held`]'s.
    pub(super) held: DQuat,
    pub(super) follow: Option<(usize, DVec3)>,
    pub(super) turn: Turn,
    pub(super) bone: Option<DVec3>,
    /// The source's rotation values that pick the Euler form: where in [`Plan::inputs`].
    pub(super) reference: Option<[usize; 3]>,
    /// Of the joints whose Euler form follows their own previous frame, its place.
    pub(super) chained: Option<usize>,
    pub(super) columns: Vec<(usize, Column)>,
    /// Whether its world position is read (the hips, the legs, their ancestors).
    pub(super) placed: bool,
    /// The source joint whose translation it carries ([`Setup::translated`]).
    pub(super) translated: Option<usize>,
}

/// The pass compiled for one pair of skeletons and one map.
pub(super) struct Plan<'a> {
    pub(super) setup: &'a Setup,
    pub(super) target: &'a Skeleton,
    pub(super) mode: OffsetMode,
    pub(super) source_joints: Vec<SourceJoint>,
    /// Per source joint, its place in `source_joints` (0 for one not read).
    pub(super) source_joints_by_index: Vec<usize>,
    pub(super) source_count: usize,
    /// Every rotation channel of the source joints read: (axis, input).
    pub(super) rotations: Vec<(usize, usize)>,
    /// The MOTION columns read (source rotations and positions, the references for the Euler
    /// form), gathered from the rows once per batch.
    pub(super) inputs: Vec<usize>,
    pub(super) target_joints: Vec<TargetJoint>,
    /// The joints whose Euler form follows their own previous frame.
    pub(super) chained: Vec<usize>,
    pub(super) channels: usize,
}

/// Buffers one worker reuses from batch to batch.
#[derive(Default)]
pub(super) struct Scratch {
    /// The batch's values of [`Plan::inputs`].
    pub(super) inputs: Vec<Lanes>,
    pub(super) half_angles: Vec<Lanes>,
    pub(super) sin: Vec<Lanes>,
    pub(super) cos: Vec<Lanes>,
    pub(super) source_rotations: Vec<Quats>,
    pub(super) source_points: Vec<Points>,
    pub(super) target_rotations: Vec<Quats>,
    pub(super) target_points: Vec<Points>,
    pub(super) angles: Vec<[Lanes; 3]>,
    /// The translation of each target joint that carries one (OFFSET + the carried move).
    pub(super) translations: Vec<Points>,
    /// One batch's channel values, channel after channel.
    pub(super) values: Vec<Lanes>,
}

/// Each frame's move of the hips and the carrier's parent's rotation, for its translation.
#[derive(Clone, Copy)]
pub(super) struct Move {
    pub(super) moved: DVec3,
    pub(super) turned: DQuat,
}

impl Default for Move {
    fn default() -> Move {
        Move {
            moved: DVec3::ZERO,
            turned: DQuat::IDENTITY,
        }
    }
}

/// Per joint: whether it is one of `joints` or an ancestor of one.
pub(super) fn with_ancestors(
    skeleton: &Skeleton,
    joints: impl Iterator<Item = usize>,
) -> Vec<bool> {
    let mut marked = vec![false; skeleton.joints.len()];
    for joint in joints {
        let mut joint = Some(joint);
        while let Some(j) = joint.filter(|&j| !marked[j]) {
            marked[j] = true;
            joint = skeleton.joints[j].parent;
        }
    }
    marked
}

/// The MOTION columns a plan reads, each given its place once, in the order first asked.
#[derive(Default)]
struct Inputs {
    columns: Vec<usize>,
    place_of: std::collections::HashMap<usize, usize>,
}

impl Inputs {
    /// `column`'s place among the columns read, given it if it has none yet.
    fn place(&mut self, column: usize) -> usize {
        *self.place_of.entry(column).or_insert_with(|| {
            self.columns.push(column);
            self.columns.len() - 1
        })
    }
}

/// Per source joint, whether the plan reads it, and whether it reads its position (see
/// inside).
fn source_joints_read(
    setup: &Setup,
    source: &Skeleton,
    target: &Skeleton,
    map: &Map,
) -> (Vec<bool>, Vec<bool>) {
    // The source joints read: mapped ones, the far ends of followed chords, the hips, the
    // leg points, and their ancestors.
    // Of those, the ones whose positions are read: the ends of followed chords, the hips,
    // the leg points, and their ancestors.
    let placed_joints: Vec<usize> = (0..target.joints.len())
        .filter_map(|t| Some((map.source_of[t]?, setup.follow[t]?.0)))
        .flat_map(|(s, sd)| [s, sd])
        .chain(setup.hips.map(|(_, s)| s))
        .chain(setup.source_legs.iter().copied())
        .chain(setup.translated.iter().flatten().copied())
        .collect();
    let placed = with_ancestors(source, placed_joints.iter().copied());
    let needed = with_ancestors(
        source,
        map.source_of.iter().flatten().copied().chain(placed_joints),
    );
    (needed, placed)
}

/// Source joint `index` as the plan reads it: its rotation channels pushed onto `rotations`,
/// its position channels read where `placed`, each column given its place in `inputs`.
fn source_joint(
    source: &Skeleton,
    index: usize,
    placed: bool,
    inputs: &mut Inputs,
    rotations: &mut Vec<(usize, usize)>,
) -> SourceJoint {
    let joint = &source.joints[index];
    let first = rotations.len();
    let mut positions = Vec::new();
    for (i, channel) in joint.channels.iter().enumerate() {
        let column = joint.first_channel + i;
        if channel.is_rotation() {
            rotations.push((channel.axis(), inputs.place(column)));
        } else if channel.is_position() && placed {
            positions.push((channel.axis(), inputs.place(column)));
        }
    }
    SourceJoint {
        index,
        parent: joint.parent,
        offset: joint.offset.as_dvec3(),
        positions,
        rotations: first..rotations.len(),
        axis: joint.axis.map(|c| c.as_dquat().normalize()),
        placed,
    }
}

/// How a target joint's rotation channels are found, by how many it has.
fn turn_of(joint: &crate::model::skeleton::Joint) -> Turn {
    let rotation_channels = joint.channels.iter().filter(|c| c.is_rotation()).count();
    match joint.rotation_order {
        Some(order) => Turn::Euler {
            order: axis_order(order),
            axis: joint.axis.map(|c| c.as_dquat().normalize()),
        },
        None if rotation_channels > 0 => Turn::Limited,
        None => Turn::Fixed(crate::model::pose::local_rotation_f64(
            joint,
            &vec![0.0; joint.channels.len()],
        )),
    }
}

/// Where each of target joint `t`'s channels takes its value from, with its MOTION column.
fn columns_of(setup: &Setup, target: &Skeleton, t: usize) -> Vec<(usize, Column)> {
    let joint = &target.joints[t];
    let mut rotation = 0;
    joint
        .channels
        .iter()
        .enumerate()
        .map(|(i, channel)| {
            let column = joint.first_channel + i;
            if channel.is_position() {
                if Some(t) == setup.carrier {
                    (column, Column::Carried(channel.axis()))
                } else if setup.translated[t].is_some() {
                    (column, Column::Translated(channel.axis()))
                } else {
                    let offset = joint.offset.as_dvec3();
                    (column, Column::Offset(offset[channel.axis()]))
                }
            } else {
                rotation += 1;
                (column, Column::Angle(rotation - 1))
            }
        })
        .collect()
}

impl<'a> Plan<'a> {
    pub(super) fn new(
        setup: &'a Setup,
        source: &Skeleton,
        target: &'a Skeleton,
        map: &Map,
    ) -> Plan<'a> {
        let (needed, placed) = source_joints_read(setup, source, target, map);
        // The MOTION columns read, each gathered once per batch.
        let mut inputs = Inputs::default();
        let mut rotations = Vec::new();
        let source_joints: Vec<SourceJoint> = source
            .joints
            .iter()
            .enumerate()
            .filter(|&(j, _)| needed[j])
            .map(|(index, _)| {
                source_joint(source, index, placed[index], &mut inputs, &mut rotations)
            })
            .collect();
        let target_placed = with_ancestors(
            target,
            setup
                .hips
                .map(|(t, _)| t)
                .into_iter()
                .chain(setup.target_legs.iter().copied()),
        );
        let mut chained = Vec::new();
        let target_joints = (0..target.joints.len())
            .map(|t| {
                let reference = setup.reference_columns[t].map(|c| c.map(|c| inputs.place(c)));
                let joint = &target.joints[t];
                let follows_itself = joint.rotation_order.is_some() && reference.is_none();
                if follows_itself {
                    chained.push(t);
                }
                TargetJoint {
                    parent: joint.parent,
                    offset: joint.offset.as_dvec3(),
                    source: map.source_of[t],
                    aligned: setup.aligned[t],
                    held: setup.held[t],
                    follow: setup.follow[t],
                    turn: turn_of(joint),
                    bone: setup.bone_of[t],
                    reference,
                    chained: follows_itself.then(|| chained.len() - 1),
                    columns: columns_of(setup, target, t),
                    placed: target_placed[t],
                    translated: setup.translated[t],
                }
            })
            .collect();
        let mut source_joints_by_index = vec![0; source.joints.len()];
        for (k, joint) in source_joints.iter().enumerate() {
            source_joints_by_index[joint.index] = k;
        }
        Plan {
            setup,
            target,
            mode: setup.source_mode,
            source_joints,
            source_joints_by_index,
            source_count: source.joints.len(),
            rotations,
            inputs: inputs.columns,
            target_joints,
            chained,
            channels: target.channel_count(),
        }
    }

    /// World rotation and position of every source joint read, for one batch of rows.
    #[inline(always)]
    pub(super) fn source_fk(&self, rows: &[&[f32]; LANES], scratch: &mut Scratch) {
        scratch.inputs.resize(self.inputs.len(), [0.0; LANES]);
        for (l, row) in rows.iter().enumerate() {
            for (input, &column) in scratch.inputs.iter_mut().zip(&self.inputs) {
                input[l] = f64::from(row[column]);
            }
        }
        let n = self.rotations.len();
        scratch.half_angles.resize(n, [0.0; LANES]);
        scratch.sin.resize(n, [0.0; LANES]);
        scratch.cos.resize(n, [0.0; LANES]);
        for (half, &(_, input)) in scratch.half_angles.iter_mut().zip(&self.rotations) {
            // glam's from_rotation_x(θ) takes sin and cos of θ · 0.5.
            let degrees = &scratch.inputs[input];
            *half = lanes(|l| degrees[l].to_radians() * 0.5);
        }
        for ((half, sin), cos) in scratch
            .half_angles
            .iter()
            .zip(scratch.sin.iter_mut())
            .zip(scratch.cos.iter_mut())
        {
            sin_cos(half, sin, cos);
        }
        let origin = Points::splat(DVec3::ZERO);
        scratch
            .source_rotations
            .resize(self.source_count, Quats::IDENTITY);
        scratch.source_points.resize(self.source_count, origin);
        for joint in &self.source_joints {
            let mut t = [joint.offset.x, joint.offset.y, joint.offset.z].map(|v| [v; LANES]);
            for &(axis, input) in &joint.positions {
                let written = &scratch.inputs[input];
                for (value, &written) in t[axis].iter_mut().zip(written) {
                    match self.mode {
                        OffsetMode::Replace => *value = written,
                        OffsetMode::Add => *value += written,
                    }
                }
            }
            let t = Points {
                x: t[0],
                y: t[1],
                z: t[2],
            };
            let mut rotation = Quats::IDENTITY;
            for i in joint.rotations.clone() {
                rotation =
                    rotation.times_axis(self.rotations[i].0, &scratch.sin[i], &scratch.cos[i]);
            }
            if let Some(c) = joint.axis {
                rotation = Quats::splat(c)
                    .mul(&rotation)
                    .mul(&Quats::splat(c.inverse()));
            }
            // The plain pass multiplies by a joint's identity rotation too: the same values
            // (but for the sign of a zero).
            let turns = !joint.rotations.is_empty() || joint.axis.is_some();
            let (rotation, point) = match joint.parent {
                Some(p) => {
                    let (r, at) = (&scratch.source_rotations[p], &scratch.source_points[p]);
                    let rotation = if turns { r.mul(&rotation) } else { *r };
                    let point = if joint.placed {
                        at.add(&r.rotate(&t))
                    } else {
                        *at
                    };
                    (rotation, point)
                }
                None => (rotation, t),
            };
            scratch.source_rotations[joint.index] = rotation;
            scratch.source_points[joint.index] = point;
        }
    }

    /// Every target joint's world rotation and position and its rotation channels' angles (one
    /// Euler form, degrees), for one batch.
    // Whole: the hot loop over the joints, inlined into each lane width's piece.
    #[inline(always)]
    pub(super) fn target_pass(&self, scratch: &mut Scratch) {
        let setup = self.setup;
        let (us, us_inv) = (Quats::splat(setup.us), Quats::splat(setup.us.inverse()));
        let (ut, ut_inv) = (Quats::splat(setup.ut), Quats::splat(setup.ut_inv));
        let count = self.target_joints.len();
        let origin = Points::splat(DVec3::ZERO);
        scratch.target_rotations.resize(count, Quats::IDENTITY);
        scratch.target_points.resize(count, origin);
        scratch.angles.resize(count, [[0.0; LANES]; 3]);
        scratch.translations.resize(count, origin);
        for (t, joint) in self.target_joints.iter().enumerate() {
            let parent_rotation = joint
                .parent
                .map_or(Quats::IDENTITY, |p| scratch.target_rotations[p]);
            // The plain pass's products, those by the identity (a Y-up skeleton's turn, a bone
            // aligned at rest) left out: the same values but for the sign of a zero.
            let mut rotation = match joint.source {
                Some(s) => {
                    let world = &scratch.source_rotations[s];
                    let carried = match setup.us == DQuat::IDENTITY {
                        true => *world,
                        false => us.mul(world).mul(&us_inv),
                    };
                    let mut rotation = match setup.ut == DQuat::IDENTITY {
                        true => carried,
                        false => ut_inv.mul(&carried),
                    };
                    if joint.aligned != DQuat::IDENTITY {
                        rotation = rotation.mul(&Quats::splat(joint.aligned));
                    }
                    if setup.ut != DQuat::IDENTITY {
                        rotation = rotation.mul(&ut);
                    }
                    if let Some((sd, rest)) = joint.follow {
                        let (near, far) = (&scratch.source_points[s], &scratch.source_points[sd]);
                        rotation = follow(setup, &rotation, near, far, rest);
                    }
                    rotation
                }
                None if joint.held != DQuat::IDENTITY => {
                    parent_rotation.mul(&Quats::splat(joint.held))
                }
                None => parent_rotation,
            };
            let local = || parent_rotation.conjugate().mul(&rotation);
            match joint.turn {
                Turn::Euler { order, axis } => {
                    let local = local();
                    let channel_rotation = match axis {
                        Some(c) => Quats::splat(c.inverse()).mul(&local).mul(&Quats::splat(c)),
                        None => local,
                    };
                    scratch.angles[t] = channel_rotation.euler_degrees(order);
                }
                Turn::Limited => {
                    // Fewer than three rotation channels: the rotation the joint can take, and
                    // its children go on from that one, not from the one asked for.
                    let local = local();
                    for l in 0..LANES {
                        let (angles, realized) =
                            limited_angles(&self.target.joints[t], local.get(l), joint.bone);
                        for (a, angle) in angles.into_iter().enumerate() {
                            scratch.angles[t][a][l] = angle;
                        }
                        rotation.set(l, parent_rotation.get(l) * realized);
                    }
                }
                Turn::Fixed(realized) if realized != DQuat::IDENTITY => {
                    rotation = parent_rotation.mul(&Quats::splat(realized));
                }
                Turn::Fixed(_) => rotation = parent_rotation,
            }
            let mut position = match joint.parent {
                Some(p) if joint.placed => scratch.target_points[p]
                    .add(&scratch.target_rotations[p].rotate(&Points::splat(joint.offset))),
                Some(p) => scratch.target_points[p],
                None => Points::splat(joint.offset),
            };
            if let (Some(s), Some(p)) = (joint.translated, joint.parent) {
                // The plain pass's arithmetic, a lane at a time (few joints carry any).
                let from = self.source_joints_by_index[s];
                let parent_s = self.source_joints[from].parent.unwrap_or(s);
                let offset_s = self.source_joints[from].offset;
                let mut translation = Points::splat(joint.offset);
                for l in 0..LANES {
                    let moved = setup.carried_move(
                        offset_s,
                        (
                            scratch.source_rotations[parent_s].get(l),
                            scratch.source_points[parent_s].get(l),
                        ),
                        scratch.source_points[s].get(l),
                    );
                    let r = scratch.target_rotations[p].get(l);
                    translation.set(l, joint.offset + r.inverse() * moved);
                    if joint.placed {
                        let at = scratch.target_points[p].get(l) + r * joint.offset + moved;
                        position.set(l, at);
                    }
                }
                scratch.translations[t] = translation;
            }
            scratch.target_rotations[t] = rotation;
            scratch.target_points[t] = position;
        }
    }

    /// One piece of frames starting at `first`: their channel values into `rows` (all but the
    /// chained joints' and the carrier's translation), the chained joints' Euler angles into
    /// `chained`, the moves into `moves`; returns the lowest leg points of source and target.
    #[inline(always)]
    pub(super) fn piece<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        let setup = self.setup;
        let frames = moves.len();
        let (mut source_floor, mut target_floor) = (f64::INFINITY, f64::INFINITY);
        for batch in (0..frames).step_by(LANES) {
            let used = (frames - batch).min(LANES);
            // A short batch repeats its last frame in the spare lanes.
            let source_rows: [&[f32]; LANES] =
                std::array::from_fn(|l| motion.frame(first + batch + l.min(used - 1)));
            self.source_fk(&source_rows, scratch);
            self.target_pass(scratch);
            // Where the carrier moves the hips, and the legs' lowest points.
            let mut moved = Points::splat(DVec3::ZERO);
            if let (Some((t, s)), Some(carrier)) = (setup.hips, setup.carrier) {
                let scaled = turn(setup.us, &scratch.source_points[s]);
                let scaled = Points {
                    x: lanes(|l| setup.ratio * scaled.x[l]),
                    y: lanes(|l| setup.ratio * scaled.y[l]),
                    z: lanes(|l| setup.ratio * scaled.z[l]),
                };
                let wanted = turn(setup.ut_inv, &scaled);
                let at = &scratch.target_points[t];
                moved = Points {
                    x: lanes(|l| wanted.x[l] - at.x[l]),
                    y: lanes(|l| wanted.y[l] - at.y[l]),
                    z: lanes(|l| wanted.z[l] - at.z[l]),
                };
                let parent = self.target.joints[carrier].parent;
                for (l, slot) in moves[batch..batch + used].iter_mut().enumerate() {
                    *slot = Move {
                        moved: moved.get(l),
                        turned: parent
                            .map_or(DQuat::IDENTITY, |p| scratch.target_rotations[p].get(l)),
                    };
                }
            }
            for &j in &setup.source_legs {
                let y = turn(setup.us, &scratch.source_points[j]).y;
                source_floor = y.iter().fold(source_floor, |a, &b| a.min(b));
            }
            for &j in &setup.target_legs {
                let mut point = scratch.target_points[j];
                if setup.under_carrier[j] {
                    point = point.add(&moved);
                }
                let y = turn(setup.ut, &point).y;
                target_floor = y.iter().fold(target_floor, |a, &b| a.min(b));
            }
            // The channel values, a channel at a time across the lanes, then row by row.
            scratch.values.resize(self.channels, [0.0; LANES]);
            let width = self.chained.len();
            for (t, joint) in self.target_joints.iter().enumerate() {
                let raw = &scratch.angles[t];
                let angles = match (&joint.turn, joint.reference, joint.chained) {
                    // A chained joint's angles wait for the pass in frame order.
                    (_, _, Some(slot)) => {
                        for l in 0..used {
                            chained[(batch + l) * width + slot] = raw.map(|a| a[l]);
                        }
                        None
                    }
                    (Turn::Euler { .. }, Some(inputs), _) => {
                        let reference = inputs.map(|i| scratch.inputs[i]);
                        Some(nearest_forms(raw, &reference))
                    }
                    _ => Some(*raw),
                };
                for &(column, what) in &joint.columns {
                    match (what, angles) {
                        (Column::Angle(a), Some(angles)) => {
                            scratch.values[column] = angles.get(a).copied().unwrap_or_default();
                        }
                        (Column::Offset(value), _) => scratch.values[column] = [value; LANES],
                        (Column::Translated(axis), _) => {
                            let at = &scratch.translations[t];
                            scratch.values[column] = [at.x, at.y, at.z][axis];
                        }
                        // Written in frame order after all pieces.
                        _ => {}
                    }
                }
            }
            for l in 0..used {
                let frame = batch + l;
                let row = &mut rows[frame * self.channels..(frame + 1) * self.channels];
                for (value, lanes) in row.iter_mut().zip(&scratch.values) {
                    *value = T::of(lanes[l]);
                }
            }
        }
        (source_floor, target_floor)
    }

    /// A piece's values that waited for the take's floor or for the frames before it: the
    /// chained joints' Euler forms (nearest `previous`, which it carries on) and the carrier's
    /// translation. Whether they are finite.
    pub(super) fn rest_of_piece<T: Value>(
        &self,
        rows: &mut [T],
        angles: &[[f64; 3]],
        moves: &[Move],
        lift: DVec3,
        previous: &mut [[f64; 3]],
    ) -> bool {
        let (channels, width) = (self.channels, self.chained.len());
        let mut finite = true;
        for (frame, &Move { moved, turned }) in moves.iter().enumerate() {
            let row = &mut rows[frame * channels..(frame + 1) * channels];
            for (slot, &t) in self.chained.iter().enumerate() {
                let chosen = nearest_form(angles[frame * width + slot], previous[slot]);
                previous[slot] = chosen;
                for &(column, what) in &self.target_joints[t].columns {
                    if let Column::Angle(a) = what {
                        row[column] = T::of(chosen.get(a).copied().unwrap_or(0.0));
                        finite &= row[column].is_finite();
                    }
                }
            }
            if let Some(carrier) = self.setup.carrier {
                let joint = &self.target_joints[carrier];
                let translation = joint.offset + turned.inverse() * (moved + lift);
                for &(column, what) in &joint.columns {
                    if let Column::Carried(axis) = what {
                        row[column] = T::of(translation[axis]);
                        finite &= row[column].is_finite();
                    }
                }
            }
        }
        finite
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    pub(super) fn piece_avx512<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        self.piece(motion, first, rows, chained, moves, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn piece_avx2<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        self.piece(motion, first, rows, chained, moves, scratch)
    }

    /// [`Plan::piece`] compiled for the widest vectors the CPU has: the same operations, so the
    /// same values, on any.
    pub(super) fn piece_here<T: Value>(
        &self,
        motion: &Motion,
        first: usize,
        rows: &mut [T],
        chained: &mut [[f64; 3]],
        moves: &mut [Move],
        scratch: &mut Scratch,
    ) -> (f64, f64) {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has just been found to support AVX-512F.
                return unsafe { self.piece_avx512(motion, first, rows, chained, moves, scratch) };
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has just been found to support AVX2.
                return unsafe { self.piece_avx2(motion, first, rows, chained, moves, scratch) };
            }
        }
        self.piece(motion, first, rows, chained, moves, scratch)
    }
}

/// Every frame's channel values of the retargeted take, on up to `threads` threads (the same
/// values on any number), and whether they are all finite (checked on the cores as they are
/// written).
pub(in crate::retarget) fn frames<T: Value>(
    setup: &Setup,
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    threads: usize,
) -> (Vec<T>, bool) {
    let plan = Plan::new(setup, source, target, map);
    let frames = motion.frame_count();
    let (channels, width) = (plan.channels, plan.chained.len());
    let mut data = vec![T::default(); frames * channels];
    let mut chained = vec![[0.0; 3]; frames * width];
    // Each piece's moves, filled by the worker that computes it.
    let mut moves: Vec<Vec<Move>> = vec![Vec::new(); frames.div_ceil(PIECE)];
    let floors = Mutex::new((f64::INFINITY, f64::INFINITY, true));
    let work = Mutex::new(pieces(
        frames,
        (&mut data, channels),
        (&mut chained, width),
        &mut moves,
    ));
    crate::io::parallel::on_threads(threads.max(1), || {
        let mut scratch = Scratch::default();
        let (mut source_floor, mut target_floor, mut finite) = (f64::INFINITY, f64::INFINITY, true);
        loop {
            let next = work.lock().unwrap_or_else(PoisonError::into_inner).next();
            let Some((first, count, rows, angles, moves)) = next else {
                break;
            };
            moves.resize(count, Move::default());
            let (s, t) = plan.piece_here(motion, first, rows, angles, moves, &mut scratch);
            source_floor = source_floor.min(s);
            target_floor = target_floor.min(t);
            finite &= all_finite(rows);
        }
        let mut floors = floors.lock().unwrap_or_else(PoisonError::into_inner);
        floors.0 = floors.0.min(source_floor);
        floors.1 = floors.1.min(target_floor);
        floors.2 &= finite;
    });
    // The pieces' borrows of the outputs end here.
    drop(work);
    let (source_floor, target_floor, finite) =
        *floors.lock().unwrap_or_else(PoisonError::into_inner);
    let lift = setup.lift(source_floor, target_floor);
    // Then the values that waited: the chained joints' Euler form nearest their previous frame's
    // (in frame order, so on one thread), and the carrier's translation (on the cores when there
    // is no chained joint).
    let work = pieces(
        frames,
        (&mut data, channels),
        (&mut chained, width),
        &mut moves,
    );
    let finite = if width > 0 {
        let mut previous = vec![[0.0; 3]; width];
        work.fold(finite, |finite, (_, _, rows, angles, moves)| {
            finite & plan.rest_of_piece(rows, angles, moves, lift, &mut previous)
        })
    } else {
        let (work, all) = (Mutex::new(work), Mutex::new(finite));
        crate::io::parallel::on_threads(threads.max(1), || {
            let mut finite = true;
            loop {
                let next = work.lock().unwrap_or_else(PoisonError::into_inner).next();
                let Some((_, _, rows, angles, moves)) = next else {
                    break;
                };
                finite &= plan.rest_of_piece(rows, angles, moves, lift, &mut []);
            }
            *all.lock().unwrap_or_else(PoisonError::into_inner) &= finite;
        });
        all.into_inner().unwrap_or_else(PoisonError::into_inner)
    };
    (data, finite)
}

/// A piece of frames: its first frame, how many, and its part of the rows, of the chained
/// joints' angles and of the moves.
pub(super) type Piece<'a, T> = (
    usize,
    usize,
    &'a mut [T],
    &'a mut [[f64; 3]],
    &'a mut Vec<Move>,
);

/// Frames a worker takes at a time (a multiple of [`LANES`]).
pub(super) const PIECE: usize = 512;

/// A channel value as written: 32-bit in a take, 64-bit for the test against the plain pass.
pub(in crate::retarget) trait Value: Copy + Default + Send {
    fn of(value: f64) -> Self;
    fn is_finite(self) -> bool;
}

impl Value for f32 {
    fn of(value: f64) -> f32 {
        value as f32
    }
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
}

impl Value for f64 {
    fn of(value: f64) -> f64 {
        value
    }
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

/// Whether every value is finite, by a loop without an early exit (which the compiler
/// vectorises).
fn all_finite<T: Value>(values: &[T]) -> bool {
    values.iter().fold(true, |all, v| all & v.is_finite())
}

/// The pieces of the outputs, in frame order.
fn pieces<'a, T>(
    frames: usize,
    (mut rows, channels): (&'a mut [T], usize),
    (mut angles, width): (&'a mut [[f64; 3]], usize),
    moves: &'a mut [Vec<Move>],
) -> impl Iterator<Item = Piece<'a, T>> {
    moves.iter_mut().enumerate().map(move |(piece, moves)| {
        let first = piece * PIECE;
        let count = (frames - first).min(PIECE);
        let (piece_rows, rest) = std::mem::take(&mut rows).split_at_mut(count * channels);
        rows = rest;
        let (piece_angles, rest) = std::mem::take(&mut angles).split_at_mut(count * width);
        angles = rest;
        (first, count, piece_rows, piece_angles, moves)
    })
}
