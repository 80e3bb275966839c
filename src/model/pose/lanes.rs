//! The fast forward kinematics: eight frames side by side in 32-bit lanes (`FkPlan`), held to
//! the plain [`super::world_matrices`] by its tests.

use super::mode::OffsetMode;
use crate::model::skeleton::{Channel, Skeleton};
use glam::Vec3;

/// `(sin, cos)` of an angle in degrees: reduced to a quadrant, then polynomials good to about
/// 1e-7 (a float's own precision), exact at multiples of 90°. Much faster than two libm calls.
#[inline]
pub fn sin_cos_degrees(degrees: f32) -> (f32, f32) {
    if degrees.abs() >= 1.0e6 {
        return degrees.to_radians().sin_cos();
    }
    sin_cos_lane(degrees)
}

/// The reduction and polynomials of `sin_cos_degrees`, without branches, so a loop over many
/// angles becomes SIMD code: rounding by the 1.5·2²³ trick and the quadrant picked with selects.
/// For |degrees| < 10⁶.
#[inline(always)]
pub(super) fn sin_cos_lane(degrees: f32) -> (f32, f32) {
    const ROUND: f32 = 12_582_912.0;
    let quadrant = (degrees * (1.0 / 90.0) + ROUND) - ROUND;
    let r = (degrees - quadrant * 90.0) * (std::f32::consts::PI / 180.0);
    let r2 = r * r;
    let sin = r
        * (1.0
            + r2 * (-1.0 / 6.0
                + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 * (1.0 / 362_880.0)))));
    let cos = 1.0
        + r2 * (-0.5
            + r2 * (1.0 / 24.0
                + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40_320.0 + r2 * (-1.0 / 3_628_800.0)))));
    let k = (quadrant as i32) & 3;
    let (s1, c1) = if k & 1 != 0 { (cos, -sin) } else { (sin, cos) };
    if k & 2 != 0 { (-s1, -c1) } else { (s1, c1) }
}

#[inline(always)]
pub(super) fn sin_cos_batch_impl(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    for ((&a, s), c) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
        (*s, *c) = sin_cos_lane(a);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) fn sin_cos_batch_avx2(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    sin_cos_batch_impl(angles, sin, cos)
}

/// `sin_cos_degrees` of every angle: eight at a time where the CPU has AVX2, four otherwise.
pub fn sin_cos_batch(angles: &[f32], sin: &mut [f32], cos: &mut [f32]) {
    if angles.iter().any(|a| a.abs() >= 1.0e6) {
        for ((&a, s), c) in angles.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
            (*s, *c) = sin_cos_degrees(a);
        }
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has just been found to support AVX2.
        unsafe { sin_cos_batch_avx2(angles, sin, cos) };
        return;
    }
    sin_cos_batch_impl(angles, sin, cos)
}

/// One joint, ready for fast FK: where its values are and what they do.
#[derive(Clone, Debug)]
pub(super) struct PlannedJoint {
    pub(super) parent: Option<usize>,
    pub(super) offset: Vec3,
    /// (axis, column) of each position channel: a range of the plan's flat position list.
    pub(super) positions: std::ops::Range<usize>,
    /// Its rotation channels: a range of the plan's flat rotation lists.
    pub(super) rotations: std::ops::Range<usize>,
    pub(super) axis: Option<glam::Quat>,
}

/// Forward kinematics compiled for one skeleton: the same products as
/// [`world_matrices`](super::world_matrices), kept as quaternion + translation, for exporting every
/// frame of long takes fast.
///
/// ```
/// use bvhview::{Take, model::pose::{FkPlan, FkScratch, OffsetMode, world_positions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let plan = FkPlan::new(&take.skeleton, OffsetMode::Replace);
/// let (mut points, mut scratch) = (Vec::new(), FkScratch::default());
/// plan.positions(take.motion.frame(10), &mut points, &mut scratch);
/// let slow = world_positions(&take.skeleton, take.motion.frame(10), OffsetMode::Replace);
/// assert!(points.iter().zip(&slow).all(|(a, b)| a.abs_diff_eq(*b, 1e-3)));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct FkPlan {
    pub(super) joints: Vec<PlannedJoint>,
    /// Every position channel, joint after joint: (axis, column).
    pub(super) position_channels: Vec<(usize, usize)>,
    /// Every rotation channel, joint after joint: its column and axis.
    pub(super) rotation_columns: Vec<usize>,
    pub(super) rotation_axes: Vec<usize>,
    pub(super) mode: OffsetMode,
}

/// Frames computed side by side: lane `l` of every value belongs to the batch's frame `l`.
pub const LANES: usize = 8;
pub(super) type Lanes = [f32; LANES];

#[inline(always)]
pub(super) fn lanes(f: impl FnMut(usize) -> f32) -> Lanes {
    std::array::from_fn(f)
}

/// A quaternion per lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct QuatLanes {
    pub(super) x: Lanes,
    pub(super) y: Lanes,
    pub(super) z: Lanes,
    pub(super) w: Lanes,
}

/// A point per lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct PointLanes {
    pub(super) x: Lanes,
    pub(super) y: Lanes,
    pub(super) z: Lanes,
}

impl PointLanes {
    const ORIGIN: PointLanes = PointLanes {
        x: [0.0; LANES],
        y: [0.0; LANES],
        z: [0.0; LANES],
    };
}

impl QuatLanes {
    pub(super) fn splat(q: glam::Quat) -> QuatLanes {
        QuatLanes {
            x: [q.x; LANES],
            y: [q.y; LANES],
            z: [q.z; LANES],
            w: [q.w; LANES],
        }
    }

    /// The rotation of `(s, c)` (sine and cosine of half the angle) about one axis.
    #[inline(always)]
    pub(super) fn about_axis(axis: usize, s: &Lanes, c: &Lanes) -> QuatLanes {
        let zero = [0.0; LANES];
        match axis {
            0 => QuatLanes {
                x: *s,
                y: zero,
                z: zero,
                w: *c,
            },
            1 => QuatLanes {
                x: zero,
                y: *s,
                z: zero,
                w: *c,
            },
            _ => QuatLanes {
                x: zero,
                y: zero,
                z: *s,
                w: *c,
            },
        }
    }

    /// `self · (axis · s, c)`: half the work of a full product, the zeros of the axis left out.
    #[inline(always)]
    pub(super) fn times_axis(self, axis: usize, s: &Lanes, c: &Lanes) -> QuatLanes {
        let QuatLanes { x, y, z, w } = self;
        match axis {
            0 => QuatLanes {
                x: lanes(|l| w[l] * s[l] + x[l] * c[l]),
                y: lanes(|l| y[l] * c[l] + z[l] * s[l]),
                z: lanes(|l| z[l] * c[l] - y[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - x[l] * s[l]),
            },
            1 => QuatLanes {
                x: lanes(|l| x[l] * c[l] - z[l] * s[l]),
                y: lanes(|l| w[l] * s[l] + y[l] * c[l]),
                z: lanes(|l| z[l] * c[l] + x[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - y[l] * s[l]),
            },
            _ => QuatLanes {
                x: lanes(|l| x[l] * c[l] + y[l] * s[l]),
                y: lanes(|l| y[l] * c[l] - x[l] * s[l]),
                z: lanes(|l| w[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - z[l] * s[l]),
            },
        }
    }

    /// The Hamilton product `self · b`.
    #[inline(always)]
    pub(super) fn times(self, b: QuatLanes) -> QuatLanes {
        let a = self;
        QuatLanes {
            x: lanes(|l| a.w[l] * b.x[l] + a.x[l] * b.w[l] + a.y[l] * b.z[l] - a.z[l] * b.y[l]),
            y: lanes(|l| a.w[l] * b.y[l] - a.x[l] * b.z[l] + a.y[l] * b.w[l] + a.z[l] * b.x[l]),
            z: lanes(|l| a.w[l] * b.z[l] + a.x[l] * b.y[l] - a.y[l] * b.x[l] + a.z[l] * b.w[l]),
            w: lanes(|l| a.w[l] * b.w[l] - a.x[l] * b.x[l] - a.y[l] * b.y[l] - a.z[l] * b.z[l]),
        }
    }

    /// `v` turned by this (unit) quaternion: `v + w·t + q×t` with `t = 2·(q×v)`.
    #[inline(always)]
    pub(super) fn rotate(self, v: PointLanes) -> PointLanes {
        let QuatLanes { x, y, z, w } = self;
        let tx = lanes(|l| 2.0 * (y[l] * v.z[l] - z[l] * v.y[l]));
        let ty = lanes(|l| 2.0 * (z[l] * v.x[l] - x[l] * v.z[l]));
        let tz = lanes(|l| 2.0 * (x[l] * v.y[l] - y[l] * v.x[l]));
        PointLanes {
            x: lanes(|l| v.x[l] + w[l] * tx[l] + (y[l] * tz[l] - z[l] * ty[l])),
            y: lanes(|l| v.y[l] + w[l] * ty[l] + (z[l] * tx[l] - x[l] * tz[l])),
            z: lanes(|l| v.z[l] + w[l] * tz[l] + (x[l] * ty[l] - y[l] * tx[l])),
        }
    }
}

/// Buffers one thread reuses from batch to batch.
///
/// ```
/// use bvhview::{Take, model::pose::{FkPlan, FkScratch, LANES, OffsetMode}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let plan = FkPlan::new(&take.skeleton, OffsetMode::Replace);
/// // One scratch for the whole take: its buffers grow once and are reused.
/// let (mut scratch, mut points, mut count) = (FkScratch::default(), Vec::new(), 0);
/// let frames: Vec<&[f32]> = (0..take.frame_count()).map(|i| take.motion.frame(i)).collect();
/// for batch in frames.chunks(LANES) {
///     plan.positions_of_frames(batch, &mut points, &mut scratch);
///     count += points.len();
/// }
/// assert_eq!(count, take.frame_count() * take.skeleton.joints.len());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default)]
pub struct FkScratch {
    pub(super) half_angles: Vec<f32>,
    pub(super) sin: Vec<f32>,
    pub(super) cos: Vec<f32>,
    pub(super) rotations: Vec<QuatLanes>,
    pub(super) points: Vec<PointLanes>,
    pub(super) local_rotations: Vec<QuatLanes>,
    pub(super) local_points: Vec<PointLanes>,
}

impl FkPlan {
    /// The plan for `skeleton`, its position channels read in `mode`.
    pub fn new(skeleton: &Skeleton, mode: OffsetMode) -> FkPlan {
        let mut rotation_columns = Vec::new();
        let mut rotation_axes = Vec::new();
        let mut position_channels = Vec::new();
        let joints = skeleton
            .joints
            .iter()
            .map(|joint| {
                let columns: Vec<(Channel, usize)> = joint
                    .channels
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| (c, joint.first_channel + i))
                    .collect();
                let first = rotation_columns.len();
                for &(c, column) in columns.iter().filter(|(c, _)| c.is_rotation()) {
                    rotation_columns.push(column);
                    rotation_axes.push(c.axis());
                }
                let first_position = position_channels.len();
                position_channels.extend(
                    columns
                        .iter()
                        .filter(|(c, _)| c.is_position())
                        .map(|&(c, i)| (c.axis(), i)),
                );
                PlannedJoint {
                    parent: joint.parent,
                    offset: joint.offset,
                    positions: first_position..position_channels.len(),
                    rotations: first..rotation_columns.len(),
                    axis: joint.axis,
                }
            })
            .collect();
        FkPlan {
            joints,
            position_channels,
            rotation_columns,
            rotation_axes,
            mode,
        }
    }

    /// World position of every joint for one MOTION row, into `out` (one per joint).
    pub fn positions(&self, frame: &[f32], out: &mut Vec<Vec3>, scratch: &mut FkScratch) {
        self.positions_of_frames(&[frame], out, scratch);
    }

    /// World positions of every joint for up to [`LANES`] MOTION rows at once, into `out`
    /// (frame after frame, one point per joint). Each frame is a lane of the same vector
    /// operations, so a batch costs little more than one frame.
    pub fn positions_of_frames(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.lanes_avx2(frames, out, scratch) };
            return;
        }
        self.lanes_impl(frames, out, scratch)
    }

    /// [`FkPlan::positions_of_frames`] without AVX2 even where the CPU has it: the path every
    /// other CPU takes, so that tests check it on any machine.
    pub fn positions_of_frames_portable(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        self.lanes_impl(frames, out, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn lanes_avx2(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        self.lanes_impl(frames, out, scratch)
    }

    #[inline(always)]
    pub(super) fn lanes_impl(
        &self,
        frames: &[&[f32]],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        self.local_lanes(frames, scratch);
        self.world_lanes(scratch, false);
        out.clear();
        let points = &scratch.points[..self.joints.len()];
        for l in 0..frames.len() {
            out.extend(points.iter().map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])));
        }
    }

    /// Each joint's local rotation and translation for up to [`LANES`] MOTION rows (the first
    /// half of [`FkPlan::positions_of_frames`]), into `rotations` and `translations`: frame after
    /// frame, one per joint, the identity where a joint has no rotation channel. A fixed axis C
    /// (ASF bones) is in the rotation already: `C · R1 · R2 · R3 · C⁻¹`.
    pub fn locals_of_frames(
        &self,
        frames: &[&[f32]],
        rotations: &mut Vec<glam::Quat>,
        translations: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        assert!(
            (1..=LANES).contains(&frames.len()),
            "1 to {LANES} frames at a time"
        );
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.locals_avx2(frames, scratch) };
        } else {
            self.local_lanes(frames, scratch);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.local_lanes(frames, scratch);
        rotations.clear();
        translations.clear();
        let count = self.joints.len();
        for l in 0..frames.len() {
            rotations.extend(
                scratch.local_rotations[..count]
                    .iter()
                    .map(|q| glam::Quat::from_xyzw(q.x[l], q.y[l], q.z[l], q.w[l])),
            );
            translations.extend(
                scratch.local_points[..count]
                    .iter()
                    .map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])),
            );
        }
    }

    /// World positions from local rotations and translations (the second half of
    /// [`FkPlan::positions_of_frames`]): `rotations` and `translations` hold up to [`LANES`]
    /// frames, one per joint of this plan's skeleton each; `out` gets one point per joint, frame
    /// after frame. Every rotation given is applied, the identity included.
    pub fn positions_of_locals(
        &self,
        rotations: &[glam::Quat],
        translations: &[Vec3],
        out: &mut Vec<Vec3>,
        scratch: &mut FkScratch,
    ) {
        let count = self.joints.len();
        let frames = rotations.len() / count.max(1);
        assert!(
            (1..=LANES).contains(&frames)
                && rotations.len() == frames * count
                && translations.len() == rotations.len(),
            "1 to {LANES} frames of every joint at a time"
        );
        // A short batch repeats its last frame in the spare lanes.
        let lane = |l: usize, j: usize| l.min(frames - 1) * count + j;
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.local_rotations.resize(count, identity);
        scratch.local_points.resize(count, PointLanes::ORIGIN);
        for j in 0..count {
            let q: [glam::Quat; LANES] = std::array::from_fn(|l| rotations[lane(l, j)]);
            scratch.local_rotations[j] = QuatLanes {
                x: q.map(|q| q.x),
                y: q.map(|q| q.y),
                z: q.map(|q| q.z),
                w: q.map(|q| q.w),
            };
            let t: [Vec3; LANES] = std::array::from_fn(|l| translations[lane(l, j)]);
            scratch.local_points[j] = PointLanes {
                x: t.map(|t| t.x),
                y: t.map(|t| t.y),
                z: t.map(|t| t.z),
            };
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has just been found to support AVX2.
            unsafe { self.world_avx2(scratch) };
        } else {
            self.world_lanes(scratch, true);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.world_lanes(scratch, true);
        out.clear();
        let points = &scratch.points[..count];
        for l in 0..frames {
            out.extend(points.iter().map(|p| Vec3::new(p.x[l], p.y[l], p.z[l])));
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn locals_avx2(&self, frames: &[&[f32]], scratch: &mut FkScratch) {
        self.local_lanes(frames, scratch)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) fn world_avx2(&self, scratch: &mut FkScratch) {
        self.world_lanes(scratch, true)
    }

    /// Every joint's local rotation and translation for the rows of one batch, into the
    /// scratch's `local_rotations` and `local_points`.
    #[inline(always)]
    pub(super) fn local_lanes(&self, frames: &[&[f32]], scratch: &mut FkScratch) {
        // A short batch repeats its last frame in the spare lanes.
        let rows: [&[f32]; LANES] = std::array::from_fn(|l| frames[l.min(frames.len() - 1)]);
        let frame = |l: usize| rows[l];
        // Every rotation's half angle, then all their sines and cosines in one vector loop. The
        // angles are gathered into a buffer of the right size by index: extending it value by
        // value cost as much as the sines and cosines.
        let n = self.rotation_columns.len() * LANES;
        scratch.half_angles.resize(n, 0.0);
        for (lanes, &column) in scratch
            .half_angles
            .chunks_exact_mut(LANES)
            .zip(&self.rotation_columns)
        {
            for (value, row) in lanes.iter_mut().zip(&rows) {
                *value = row[column] * 0.5;
            }
        }
        scratch.sin.resize(n, 0.0);
        scratch.cos.resize(n, 0.0);
        sin_cos_batch(&scratch.half_angles, &mut scratch.sin, &mut scratch.cos);
        let count = self.joints.len();
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.local_rotations.resize(count, identity);
        scratch.local_points.resize(count, PointLanes::ORIGIN);
        let sines: &[Lanes] = as_lanes(&scratch.sin);
        let cosines: &[Lanes] = as_lanes(&scratch.cos);
        for (index, joint) in self.joints.iter().enumerate() {
            let mut t = [joint.offset.x, joint.offset.y, joint.offset.z].map(|v| [v; LANES]);
            for &(axis, column) in &self.position_channels[joint.positions.clone()] {
                for (l, value) in t[axis].iter_mut().enumerate() {
                    match self.mode {
                        OffsetMode::Replace => *value = frame(l)[column],
                        OffsetMode::Add => *value += frame(l)[column],
                    }
                }
            }
            scratch.local_points[index] = PointLanes {
                x: t[0],
                y: t[1],
                z: t[2],
            };
            // A rotation of θ about an axis is the quaternion (axis · sin θ/2, cos θ/2); each
            // later channel multiplies on the right.
            let mut rotation: Option<QuatLanes> = None;
            for i in joint.rotations.clone() {
                let (s, c, axis) = (&sines[i], &cosines[i], self.rotation_axes[i]);
                rotation = Some(match rotation {
                    None => QuatLanes::about_axis(axis, s, c),
                    Some(q) => q.times_axis(axis, s, c),
                });
            }
            if let (Some(axis), Some(r)) = (joint.axis, rotation) {
                rotation = Some(
                    QuatLanes::splat(axis)
                        .times(r)
                        .times(QuatLanes::splat(axis.conjugate())),
                );
            }
            scratch.local_rotations[index] = rotation.unwrap_or(identity);
        }
    }

    /// World rotations and points of every joint from the scratch's local ones, into its
    /// `rotations` and `points`. A joint without rotation channels takes its parent's rotation
    /// as it is, unless `every_rotation` says its local one (given from outside) counts too.
    #[inline(always)]
    pub(super) fn world_lanes(&self, scratch: &mut FkScratch, every_rotation: bool) {
        let count = self.joints.len();
        let identity = QuatLanes::splat(glam::Quat::IDENTITY);
        scratch.rotations.resize(count, identity);
        scratch.points.resize(count, PointLanes::ORIGIN);
        let (points, rotations) = (
            &mut scratch.points[..count],
            &mut scratch.rotations[..count],
        );
        let (local_points, local_rotations) = (
            &scratch.local_points[..count],
            &scratch.local_rotations[..count],
        );
        for (index, joint) in self.joints.iter().enumerate() {
            let (t, rotation) = (local_points[index], local_rotations[index]);
            let rotates = every_rotation || !joint.rotations.is_empty();
            let (world_rotation, world_point) = match joint.parent {
                Some(parent) => {
                    let (parent_rotation, parent_point) = (rotations[parent], points[parent]);
                    let moved = parent_rotation.rotate(t);
                    let point = PointLanes {
                        x: lanes(|l| parent_point.x[l] + moved.x[l]),
                        y: lanes(|l| parent_point.y[l] + moved.y[l]),
                        z: lanes(|l| parent_point.z[l] + moved.z[l]),
                    };
                    let rotation = match rotates {
                        true => parent_rotation.times(rotation),
                        false => parent_rotation,
                    };
                    (rotation, point)
                }
                None => (rotation, t),
            };
            rotations[index] = world_rotation;
            points[index] = world_point;
        }
    }
}

/// A flat list of values as lanes (its length is a multiple of [`LANES`]).
pub(super) fn as_lanes(values: &[f32]) -> &[Lanes] {
    let (lanes, rest) = values.as_chunks::<LANES>();
    debug_assert!(rest.is_empty());
    lanes
}

/// Forward kinematics of every frame on every core; returns the sum of all coordinates (so the
/// work cannot be skipped, and as a checksum).
pub fn positions_all_frames(
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    mode: OffsetMode,
) -> f64 {
    let plan = FkPlan::new(skeleton, mode);
    let frames = motion.frame_count();
    // Pieces of a few thousand frames, taken in turn by every core.
    const PIECE: usize = 4096;
    let mut total = 0.0f64;
    crate::io::parallel::map_in_order(
        frames.div_ceil(PIECE),
        crate::io::parallel::cores(),
        2 * crate::io::parallel::cores(),
        |piece| {
            let (mut out, mut scratch) = (Vec::new(), FkScratch::default());
            let mut sum = 0.0f64;
            let mine = piece * PIECE..((piece + 1) * PIECE).min(frames);
            let mut batch: Vec<&[f32]> = Vec::with_capacity(LANES);
            for first in mine.clone().step_by(LANES) {
                batch.clear();
                batch.extend((first..(first + LANES).min(mine.end)).map(|f| motion.frame(f)));
                plan.positions_of_frames(&batch, &mut out, &mut scratch);
                for points in out.chunks(plan.joints.len()) {
                    let sum_of_points: Vec3 = points.iter().copied().sum();
                    sum += f64::from(sum_of_points.x + sum_of_points.y + sum_of_points.z);
                }
            }
            sum
        },
        |_, sum| {
            total += sum;
            true
        },
    );
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::pose::RotationKind;
    use crate::model::pose::rotation_of_numbers;
    use crate::model::pose::world_matrices;
    use crate::model::pose::write_local_rotations;
    use crate::model::pose::write_rotation;

    #[test]
    fn sin_cos_degrees_matches_libm() {
        let mut worst = 0.0f32;
        let mut degrees = -1000.0f32;
        while degrees < 1000.0 {
            let (s, c) = sin_cos_degrees(degrees);
            let (rs, rc) = (degrees as f64).to_radians().sin_cos();
            worst = worst
                .max((s as f64 - rs).abs() as f32)
                .max((c as f64 - rc).abs() as f32);
            degrees += 0.0137;
        }
        assert!(worst < 3e-7, "worst error {worst}");
        assert_eq!(sin_cos_degrees(90.0), (1.0, 0.0));
        let angles: Vec<f32> = (0..1000).map(|i| i as f32 * 0.731 - 365.0).collect();
        let (mut s, mut c) = (vec![0.0; 1000], vec![0.0; 1000]);
        sin_cos_batch(&angles, &mut s, &mut c);
        for (i, &a) in angles.iter().enumerate() {
            let (rs, rc) = (a as f64).to_radians().sin_cos();
            assert!(
                (s[i] as f64 - rs).abs() < 3e-7 && (c[i] as f64 - rc).abs() < 3e-7,
                "{a}"
            );
        }
        assert_eq!(sin_cos_degrees(-180.0), (0.0, -1.0));
    }

    #[test]
    fn local_rotations_by_the_plan_match_joint_by_joint_on_real_files() {
        let mut worst: f32 = 0.0;
        for entry in std::fs::read_dir("tests/data/bvh").unwrap() {
            let path = entry.unwrap().path();
            let Ok(bvh) = crate::bvh::load_file(&path, Default::default()) else {
                continue;
            };
            let (skeleton, motion) = (&bvh.skeleton, &bvh.motion);
            let frames: Vec<usize> = (0..motion.frame_count()).step_by(7).collect();
            for kind in [
                RotationKind::Quat,
                RotationKind::Matrix,
                RotationKind::SixD,
                RotationKind::AxisAngle,
                RotationKind::Euler,
            ] {
                let (joints, width) = (skeleton.joints.len(), kind.width());
                let mut fast = vec![0.0; frames.len() * joints * width];
                write_local_rotations(skeleton, motion, &frames, kind, &mut fast);
                let mut slot = vec![0.0; width];
                for (k, &frame) in frames.iter().enumerate() {
                    for (j, joint) in skeleton.joints.iter().enumerate() {
                        write_rotation(joint, joint.values(motion.frame(frame)), kind, &mut slot);
                        let got = &fast[(k * joints + j) * width..][..width];
                        if kind == RotationKind::Euler {
                            assert_eq!(got, &slot[..], "{}", path.display());
                            continue;
                        }
                        let (a, b) = (
                            rotation_of_numbers(kind, got).unwrap(),
                            rotation_of_numbers(kind, &slot).unwrap(),
                        );
                        for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
                            worst = worst.max((x - y).abs());
                        }
                    }
                }
            }
        }
        assert!(worst < 1e-5, "worst matrix element apart: {worst}");
    }

    #[test]
    fn plan_matches_world_matrices_on_real_files_on_both_paths() {
        // The repository's own corpus: mixed orders, position channels on 143 joints, CR endings,
        // and a CMU ASF/AMC pair whose bones turn about their own axes (the C·R·C⁻¹ step).
        let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let mut inputs: Vec<(String, Skeleton, crate::model::motion::Motion)> = [
            "bvh11_131_01.bvh",
            "makehuman_tpose.bvh",
            "opencollar_run.bvh",
        ]
        .iter()
        .map(|name| {
            let bvh =
                crate::bvh::load_file(&data.join("bvh").join(name), Default::default()).unwrap();
            (name.to_string(), bvh.skeleton, bvh.motion)
        })
        .collect();
        let asf = data.join("asf_amc/heiden_12.asf");
        let amc = data.join("asf_amc/heiden_12_02_01.amc");
        let cmu = crate::take::load(&asf, Some(&amc), None).unwrap();
        let turned = cmu.skeleton.joints.iter().filter(|j| {
            j.axis
                .is_some_and(|a| a.angle_between(glam::Quat::IDENTITY) > 0.1)
        });
        assert!(turned.count() >= 10, "bones with an axis of their own");
        inputs.push(("heiden_12_02_01.amc".to_string(), cmu.skeleton, cmu.motion));

        for (name, skeleton, motion) in &inputs {
            for mode in [OffsetMode::Replace, OffsetMode::Add] {
                let plan = FkPlan::new(skeleton, mode);
                let (mut out, mut scratch, mut matrices) =
                    (Vec::new(), FkScratch::default(), Vec::new());
                let last = motion.frame_count() - 1;
                // One frame, and a batch of eight (a lane each), on the dispatching and the
                // portable path.
                let batch: Vec<usize> = (0..LANES).map(|i| i * last / (LANES - 1)).collect();
                for (path, frames) in [("one", vec![last / 2]), ("eight", batch)] {
                    let rows: Vec<&[f32]> = frames.iter().map(|&f| motion.frame(f)).collect();
                    for portable in [false, true] {
                        if portable {
                            plan.positions_of_frames_portable(&rows, &mut out, &mut scratch);
                        } else {
                            plan.positions_of_frames(&rows, &mut out, &mut scratch);
                        }
                        for (lane, row) in rows.iter().enumerate() {
                            world_matrices(skeleton, row, mode, &mut matrices);
                            let points = &out[lane * matrices.len()..][..matrices.len()];
                            for (p, m) in points.iter().zip(&matrices) {
                                let q = m.w_axis.truncate();
                                assert!(
                                    p.distance(q) <= 1e-5 * q.length().max(10.0),
                                    "{name} {path} portable {portable} lane {lane}: {p} vs {q}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
