//! The plain pass: one joint and one frame at a time, the reference the eight-lane pass
//! (`fast/`) is held to.

use crate::model::body::{Body, is_ancestor, path_between};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, world_transforms_f64};
use crate::model::skeleton::{Joint, Skeleton};
use crate::retarget::align::{
    Ups, alignments, arc, floor_points, hip_height, main_bones, reference_frame,
    source_offset_mode, to_y_up,
};
use crate::retarget::hinge::{limited_angles, nearest_form};
use crate::retarget::map::Map;
use glam::{DQuat, DVec3};

/// What the pass over the frames needs, worked out once from the skeletons and the map: the
/// same for the plain and the fast path.
pub(super) struct Setup {
    pub(super) source_mode: OffsetMode,
    /// The source's and the target's turn to Y up, and the target's back.
    pub(super) us: DQuat,
    pub(super) ut: DQuat,
    pub(super) ut_inv: DQuat,
    pub(super) aligned: Vec<DQuat>,
    /// The hips pair that carries the path: (target, source).
    pub(super) hips: Option<(usize, usize)>,
    /// The joint whose position channels move the hips there: the hips or an ancestor.
    pub(super) carrier: Option<usize>,
    pub(super) ratio: f64,
    /// Per target joint following a source chord: the chord's far source joint, and the bone at
    /// rest.
    pub(super) follow: Vec<Option<(usize, DVec3)>>,
    pub(super) source_legs: Vec<usize>,
    pub(super) target_legs: Vec<usize>,
    pub(super) under_carrier: Vec<bool>,
    pub(super) reference_columns: Vec<Option<[usize; 3]>>,
    pub(super) bone_of: Vec<Option<DVec3>>,
    /// Per target joint that carries its source joint's translation: that source joint. A
    /// mapped joint other than the carrier, with position channels, whose source joint has
    /// position channels and a parent: what they move it from its OFFSET, in the world, is
    /// scaled by the ratio and written into its own channels.
    pub(super) translated: Vec<Option<usize>>,
    /// Per target joint no source joint drives, the turn from its parent it keeps: none at
    /// rest, or its own in the pose of its take rest alignment read (a Blender FBX's pelvis
    /// bones, which would stack both thighs on one point in its rest along +y).
    pub(super) held: Vec<DQuat>,
}

impl Setup {
    pub(super) fn new(
        source: &Skeleton,
        motion: &Motion,
        target: &Skeleton,
        map: &Map,
        ups: Ups,
        target_poses: Option<&Motion>,
    ) -> Setup {
        let mode = OffsetMode::Replace;
        let source_mode = source_offset_mode(source, motion);
        let (us, ut) = (to_y_up(ups.source), to_y_up(ups.target));
        let ut_inv = ut.inverse();
        let mut source_rest = Vec::new();
        let mut target_rest = Vec::new();
        world_transforms_f64(source, &[], mode, &mut source_rest);
        world_transforms_f64(target, &[], mode, &mut target_rest);
        // The source's bones as a pose of its take shows them, where its rest pose cannot say
        // which way the body faces: the target's rest turned onto that pose, then that pose's
        // rotation taken back out, so that the frames' rotations carry over as from the rest.
        // The same of the target, from its own take's poses when it comes with them.
        let source_posed = posed(source, motion, source_mode, &map.source_body, &source_rest);
        let target_posed = target_poses
            .and_then(|poses| posed(target, poses, mode, &map.target_body, &target_rest));
        let aligned = alignments(
            source,
            target,
            map,
            ups,
            source_posed.as_deref().unwrap_or(&source_rest),
            target_posed.as_deref().unwrap_or(&target_rest),
        );
        let held = held_turns(target, map, target_posed.as_deref());
        let aligned = from_the_rests(
            &aligned,
            map,
            (us, ut),
            source_posed.as_deref(),
            target_posed.as_deref(),
        );
        let (hips, carrier) = path_carrier(target, map);
        let ratio = match hips {
            Some((t, s)) => {
                let ht = hip_height(target, &map.target_body, t, &target_rest);
                let hs = hip_height(source, &map.source_body, s, &source_rest);
                if ht > 1e-9 && hs > 1e-9 { ht / hs } else { 1.0 }
            }
            None => 1.0,
        };
        let follow = chords_followed(source, target, map, &target_rest);
        let source_legs = floor_points(source, &map.source_body);
        let target_legs = floor_points(target, &map.target_body);
        let joints = target.joints.len();
        let under_carrier: Vec<bool> = (0..joints)
            .map(|j| carrier.is_some_and(|c| is_ancestor(target, c, j)))
            .collect();
        let reference_columns = reference_columns(source, target, map);
        // Each target joint's main bone at rest, in its own frame (every rest rotation is the
        // identity): what a joint with fewer than three rotation channels lays where it can.
        let mut bone_of: Vec<Option<DVec3>> = vec![None; joints];
        for (t, d, _) in main_bones(source, target, map) {
            bone_of[t] = Some(target_rest[d].1 - target_rest[t].1);
        }
        let translated = translated(source, target, map, carrier);
        Setup {
            source_mode,
            us,
            ut,
            ut_inv,
            aligned,
            hips,
            carrier,
            ratio,
            follow,
            source_legs,
            target_legs,
            under_carrier,
            reference_columns,
            bone_of,
            translated,
            held,
        }
    }

    /// How far a source joint's position channels move it from its OFFSET (`offset`), in the
    /// world where its parent is `parent` (world rotation and position) and it is `at`; scaled
    /// by the ratio and turned into the target's axes: the world move of the target joint that
    /// carries it.
    pub(super) fn carried_move(&self, offset: DVec3, parent: (DQuat, DVec3), at: DVec3) -> DVec3 {
        let rest_place = parent.1 + parent.0 * offset;
        self.ut_inv * (self.us * ((at - rest_place) * self.ratio))
    }

    /// Feet on the floor: the target's lowest foot point over the take where the source's is,
    /// scaled.
    pub(super) fn lift(&self, source_floor: f64, target_floor: f64) -> DVec3 {
        if source_floor.is_finite() && target_floor.is_finite() {
            self.ut_inv * DVec3::new(0.0, self.ratio * source_floor - target_floor, 0.0)
        } else {
            DVec3::ZERO
        }
    }
}

/// The world rotations and places of the frame of `motion` that [`reference_frame`] picks to
/// show which way the body faces; `None` where it picks none.
fn posed(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    body: &Body,
    rest: &[(DQuat, DVec3)],
) -> Option<Vec<(DQuat, DVec3)>> {
    let frame = reference_frame(skeleton, motion, mode, body, rest)?;
    let mut world = Vec::new();
    world_transforms_f64(skeleton, motion.frame(frame), mode, &mut world);
    Some(world)
}

/// Per target joint no source joint drives, the turn from its parent it keeps (see
/// [`Setup::held`]): its own in `target_posed`, else none.
fn held_turns(target: &Skeleton, map: &Map, target_posed: Option<&[(DQuat, DVec3)]>) -> Vec<DQuat> {
    (0..target.joints.len())
        .map(
            |t| match (target_posed, target.joints[t].parent, map.source_of[t]) {
                (Some(world), Some(p), None) => world[p].0.inverse() * world[t].0,
                _ => DQuat::IDENTITY,
            },
        )
        .collect()
}

/// The `aligned` turns with the poses they were read in taken out: the source's pose taken
/// back out, the target's put in (`us`, `ut`: each one's turn to Y up).
fn from_the_rests(
    aligned: &[DQuat],
    map: &Map,
    (us, ut): (DQuat, DQuat),
    source_posed: Option<&[(DQuat, DVec3)]>,
    target_posed: Option<&[(DQuat, DVec3)]>,
) -> Vec<DQuat> {
    aligned
        .iter()
        .enumerate()
        .map(|(t, &a)| {
            let Some(s) = map.source_of[t] else { return a };
            // The source's pose taken back out, the target's put in: each turn of the take
            // then carries over as from the rests.
            let from =
                source_posed.map_or(DQuat::IDENTITY, |w| (us * w[s].0 * us.inverse()).inverse());
            let to = target_posed.map_or(DQuat::IDENTITY, |w| ut * w[t].0 * ut.inverse());
            from * a * to
        })
        .collect()
}

/// The hips pair that carries the path, (target, source), and the target joint whose
/// position channels move the hips there: the hips or an ancestor.
fn path_carrier(target: &Skeleton, map: &Map) -> (Option<(usize, usize)>, Option<usize>) {
    // The hips pair that carries the path: the target's hips if mapped, else its first
    // mapped joint.
    let hips_t = map
        .target_body
        .hips
        .filter(|&h| map.source_of[h].is_some())
        .or_else(|| map.source_of.iter().position(Option::is_some));
    let hips = hips_t.and_then(|t| Some((t, map.source_of[t]?)));
    // The joint whose position channels move the hips there: the hips or an ancestor.
    let carrier = hips_t.and_then(|t| {
        let mut joint = t;
        loop {
            if target.joints[joint]
                .channels
                .iter()
                .any(|c| c.is_position())
            {
                return Some(joint);
            }
            joint = target.joints[joint].parent?;
        }
    });
    (hips, carrier)
}

/// Per target joint following a source chord (see [`Setup::follow`]): the chord's far source
/// joint, and the bone at rest.
fn chords_followed(
    source: &Skeleton,
    target: &Skeleton,
    map: &Map,
    target_rest: &[(DQuat, DVec3)],
) -> Vec<Option<(usize, DVec3)>> {
    // Bones whose source chord spans joints the target lacks (CMU's Neck1 between Neck and
    // Head): the target bone follows the chord each frame, by the smallest turn.
    let mut follow: Vec<Option<(usize, DVec3)>> = vec![None; target.joints.len()];
    for (t, d, _) in main_bones(source, target, map) {
        let (Some(s), Some(sd)) = (map.source_of[t], map.source_of[d]) else {
            continue;
        };
        let mut used = vec![false; source.joints.len()];
        for u in map.source_of.iter().flatten() {
            used[*u] = true;
        }
        if path_between(source, s, sd).iter().any(|&j| !used[j]) {
            follow[t] = Some((sd, target_rest[d].1 - target_rest[t].1));
        }
    }
    follow
}

/// Of each target joint turning in the same order as its source joint, the source's
/// rotation columns: its values are the reference for the Euler form written.
fn reference_columns(source: &Skeleton, target: &Skeleton, map: &Map) -> Vec<Option<[usize; 3]>> {
    (0..target.joints.len())
        .map(|t| {
            let joint = &target.joints[t];
            let s = &source.joints[map.source_of[t]?];
            if joint.rotation_order.is_none()
                || s.rotation_order != joint.rotation_order
                || s.axis != joint.axis
            {
                return None;
            }
            let columns: Vec<usize> = s
                .channels
                .iter()
                .enumerate()
                .filter(|(_, c)| c.is_rotation())
                .map(|(i, _)| s.first_channel + i)
                .collect();
            Some([columns[0], columns[1], columns[2]])
        })
        .collect()
}

/// Per target joint that carries its source joint's translation, that source joint (see
/// [`Setup::translated`]).
fn translated(
    source: &Skeleton,
    target: &Skeleton,
    map: &Map,
    carrier: Option<usize>,
) -> Vec<Option<usize>> {
    let moves = |joint: &Joint| joint.channels.iter().any(|c| c.is_position());
    (0..target.joints.len())
        .map(|t| {
            let s = map.source_of[t]?;
            let carries = Some(t) != carrier
                && target.joints[t].parent.is_some()
                && moves(&target.joints[t])
                && moves(&source.joints[s])
                && source.joints[s].parent.is_some();
            carries.then_some(s)
        })
        .collect()
}

/// One piece of frames, posed on one core: each target joint's rotation channels in one Euler
/// form (radians turned to degrees), where the carrier moves the hips, and the lowest leg
/// points of source and target.
struct Piece {
    angles: Vec<[f64; 3]>,
    /// Per frame, the translation of each target joint in `translated` order.
    translations: Vec<DVec3>,
    moves: Vec<DVec3>,
    carrier_parent: Vec<DQuat>,
    source_floor: f64,
    target_floor: f64,
}

/// One frame's world rotations and places, per joint.
type World = [(DQuat, DVec3)];

/// The frames of one [`Piece`].
const PIECE: usize = 512;

/// The plain pass over the frames: every frame's channel values, frame after frame.
pub(super) fn plain_frames(
    setup: &Setup,
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    threads: usize,
) -> Vec<f64> {
    let frames = motion.frame_count();
    // First, on the cores, a piece of frames at a time.
    let compute = |piece: usize| -> Piece {
        let range = piece * PIECE..((piece + 1) * PIECE).min(frames);
        setup.piece(source, motion, target, map, range)
    };
    let mut pieces: Vec<Piece> = Vec::with_capacity(frames.div_ceil(PIECE));
    crate::io::parallel::map_in_order(
        frames.div_ceil(PIECE),
        threads.max(1),
        threads.max(1) * 4,
        compute,
        |_, piece| {
            pieces.push(piece);
            true
        },
    );
    let source_floor = pieces
        .iter()
        .map(|p| p.source_floor)
        .fold(f64::INFINITY, f64::min);
    let target_floor = pieces
        .iter()
        .map(|p| p.target_floor)
        .fold(f64::INFINITY, f64::min);
    let lift = setup.lift(source_floor, target_floor);
    setup.written(motion, target, &pieces, lift)
}

impl Setup {
    /// The frames `range` of the plain pass, posed (see [`Piece`]).
    fn piece(
        &self,
        source: &Skeleton,
        motion: &Motion,
        target: &Skeleton,
        map: &Map,
        range: std::ops::Range<usize>,
    ) -> Piece {
        let joints = target.joints.len();
        let mut out = Piece {
            angles: Vec::with_capacity(range.len() * joints),
            translations: Vec::new(),
            moves: Vec::with_capacity(range.len()),
            carrier_parent: Vec::with_capacity(range.len()),
            source_floor: f64::INFINITY,
            target_floor: f64::INFINITY,
        };
        let mut world_s = Vec::new();
        let mut world_t: Vec<(DQuat, DVec3)> = vec![(DQuat::IDENTITY, DVec3::ZERO); joints];
        for frame in range {
            world_transforms_f64(source, motion.frame(frame), self.source_mode, &mut world_s);
            for t in 0..joints {
                let posed = self.pose_joint(source, target, map, t, (&world_s, &world_t), &mut out);
                world_t[t] = posed;
            }
            self.carry_path(target, &world_s, &mut world_t, &mut out);
            for &j in &self.source_legs {
                out.source_floor = out.source_floor.min((self.us * world_s[j].1).y);
            }
            for &j in &self.target_legs {
                out.target_floor = out.target_floor.min((self.ut * world_t[j].1).y);
            }
        }
        out
    }

    /// Target joint `t`'s world rotation and place in a frame whose source pose is `world_s`
    /// (its parents' already in `world_t`); its angles, and its translation where it carries
    /// one, pushed onto `out`.
    fn pose_joint(
        &self,
        source: &Skeleton,
        target: &Skeleton,
        map: &Map,
        t: usize,
        (world_s, world_t): (&World, &World),
        out: &mut Piece,
    ) -> (DQuat, DVec3) {
        let joint = &target.joints[t];
        let parent = joint.parent.map(|p| world_t[p]);
        let parent_rotation = parent.map_or(DQuat::IDENTITY, |(r, _)| r);
        let rotation = match map.source_of[t] {
            Some(s) => self.carried_rotation(t, s, world_s),
            None => parent_rotation * self.held[t],
        };
        let mut rotation = rotation;
        let local = parent_rotation.inverse() * rotation;
        out.angles.push(match joint.rotation_order {
            Some(order) => {
                let channel_rotation = match joint.axis {
                    Some(c) => {
                        let c = c.as_dquat().normalize();
                        c.inverse() * local * c
                    }
                    None => local,
                };
                crate::model::euler::split(channel_rotation, order, None).map(f64::to_degrees)
            }
            None => {
                // Fewer than three rotation channels: the rotation the joint can take,
                // and its children go on from that one, not from the one asked for.
                let (angles, realized) = limited_angles(joint, local, self.bone_of[t]);
                rotation = parent_rotation * realized;
                angles
            }
        });
        let position = match (parent, self.translated[t]) {
            (Some((r, p)), Some(s)) => {
                let from = &source.joints[s];
                let parent = world_s[from.parent.unwrap_or(s)];
                let moved = self.carried_move(from.offset.as_dvec3(), parent, world_s[s].1);
                out.translations
                    .push(joint.offset.as_dvec3() + r.inverse() * moved);
                p + r * joint.offset.as_dvec3() + moved
            }
            (Some((r, p)), None) => p + r * joint.offset.as_dvec3(),
            (None, _) => joint.offset.as_dvec3(),
        };
        (rotation, position)
    }

    /// Target joint `t`'s world rotation, driven by source joint `s` in the source pose
    /// `world_s`: the source's turned into the target's axes, then along its chord where it
    /// follows one.
    fn carried_rotation(&self, t: usize, s: usize, world_s: &[(DQuat, DVec3)]) -> DQuat {
        let (us, ut, ut_inv) = (self.us, self.ut, self.ut_inv);
        let carried = us * world_s[s].0 * us.inverse();
        let rotation = ut_inv * carried * self.aligned[t] * ut;
        match self.follow[t] {
            Some((sd, rest)) => {
                let chord = ut_inv * (us * (world_s[sd].1 - world_s[s].1));
                if chord.length() > 1e-9 {
                    arc(rotation * rest, chord) * rotation
                } else {
                    rotation
                }
            }
            None => rotation,
        }
    }

    /// The hips moved to where the source's are, scaled: every joint under the carrier moved
    /// with them in `world_t`, and the move and the carrier's parent's rotation pushed onto
    /// `out` (none without hips and carrier).
    fn carry_path(
        &self,
        target: &Skeleton,
        world_s: &[(DQuat, DVec3)],
        world_t: &mut [(DQuat, DVec3)],
        out: &mut Piece,
    ) {
        let (mut moved, mut turned) = (DVec3::ZERO, DQuat::IDENTITY);
        if let (Some((t, s)), Some(carrier)) = (self.hips, self.carrier) {
            let wanted = self.ut_inv * (self.ratio * (self.us * world_s[s].1));
            moved = wanted - world_t[t].1;
            turned = target.joints[carrier]
                .parent
                .map_or(DQuat::IDENTITY, |p| world_t[p].0);
            for (joint, &under) in world_t.iter_mut().zip(&self.under_carrier) {
                if under {
                    joint.1 += moved;
                }
            }
        }
        out.moves.push(moved);
        out.carrier_parent.push(turned);
    }

    /// Then, in frame order, every frame's channel values from the `pieces`, the carrier's
    /// translation lifted by `lift`: of the two Euler forms of each rotation and their turns by
    /// whole circles, the one nearest the source joint's own values when it turns in the same
    /// order, else nearest this joint's previous frame.
    fn written(
        &self,
        motion: &Motion,
        target: &Skeleton,
        pieces: &[Piece],
        lift: DVec3,
    ) -> Vec<f64> {
        let frames = motion.frame_count();
        let joints = target.joints.len();
        let channels = target.channel_count();
        let mut data = vec![0.0f64; frames * channels];
        let mut previous: Vec<[f64; 3]> = vec![[0.0; 3]; joints];
        let carrying = self.translated.iter().flatten().count();
        let rows = pieces.iter().flat_map(|p| {
            p.angles
                .chunks(joints.max(1))
                .zip(p.moves.iter().zip(&p.carrier_parent))
                .enumerate()
                .map(|(f, row)| (row, &p.translations[f * carrying..(f + 1) * carrying]))
        });
        for (frame, ((angles, (moved, turned)), carried)) in rows.enumerate() {
            let row = &mut data[frame * channels..(frame + 1) * channels];
            let source_row = motion.frame(frame);
            let mut carried = carried.iter();
            for (t, joint) in target.joints.iter().enumerate() {
                let mut translation = joint.offset.as_dvec3();
                if Some(t) == self.carrier {
                    translation += turned.inverse() * (*moved + lift);
                }
                if self.translated[t].is_some() {
                    translation = carried.next().copied().unwrap_or(translation);
                }
                let angles = match joint.rotation_order {
                    Some(_) => {
                        let reference = self.reference_columns[t]
                            .map(|c| c.map(|column| f64::from(source_row[column])))
                            .unwrap_or(previous[t]);
                        let chosen = nearest_form(angles[t], reference);
                        previous[t] = chosen;
                        chosen
                    }
                    None => angles[t],
                };
                let mut rotations = angles.into_iter();
                for (i, channel) in joint.channels.iter().enumerate() {
                    row[joint.first_channel + i] = if channel.is_position() {
                        translation[channel.axis()]
                    } else {
                        rotations.next().unwrap_or(0.0)
                    };
                }
            }
        }
        data
    }
}
