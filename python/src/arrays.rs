//! A take's numbers as numpy arrays: frames chosen, world positions and matrices, local
//! rotations, computed on the crate's FK and shared among the cores.

use crate::loaded::Motion;
use bvhview::Error;
use bvhview::model::pose::{self, FkPlan, FkScratch, LANES};
use glam::{Mat4, Vec3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PySlice;
use std::sync::{Mutex, PoisonError};

/// Joint transforms computed per piece of work (some 50 µs of it): small enough to share a
/// take of a thousand frames among the cores, large enough that taking a piece and waking a
/// helper cost little next to computing it.
pub(crate) const PIECE_TRANSFORMS: usize = 8192;

/// Frames per piece for a skeleton of `joints`: whole batches of [`LANES`] frames.
pub(crate) fn piece_frames(joints: usize) -> usize {
    (PIECE_TRANSFORMS / joints.max(1))
        .next_multiple_of(LANES)
        .clamp(LANES, 1024)
}

impl Motion {
    /// Frames `positions` and `world_matrices` can compute: every frame, or the rest pose as
    /// frame 0 of a take without frames (as the CLI's `positions` does).
    pub(crate) fn available_frames(&self) -> usize {
        self.loaded.motion.frame_count().max(1)
    }

    /// The frame numbers `frames` selects: None (all), an int (negative counts from the end),
    /// a slice, or a sequence of ints (a list, a range, a numpy array).
    pub(crate) fn selected_frames(
        &self,
        frames: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Vec<usize>> {
        let count = self.available_frames();
        let Some(frames) = frames else {
            return Ok((0..count).collect());
        };
        if let Ok(slice) = frames.cast::<PySlice>() {
            let indices = slice.indices(isize::try_from(count).unwrap_or(isize::MAX))?;
            let mut selected = Vec::with_capacity(indices.slicelength);
            let mut frame = indices.start;
            for _ in 0..indices.slicelength {
                selected.push(frame as usize);
                frame += indices.step;
            }
            return Ok(selected);
        }
        let numbers: Vec<isize> = match frames.extract::<isize>() {
            Ok(one) => vec![one],
            Err(_) => frames.extract().map_err(|_| {
                PyValueError::new_err(format!(
                    "frames={}: expected None, an int, a slice or a sequence of ints",
                    frames
                        .repr()
                        .map_or_else(|_| "?".to_string(), |r| r.to_string())
                ))
            })?,
        };
        numbers
            .into_iter()
            .map(|number| {
                let frame = if number < 0 {
                    number + count as isize
                } else {
                    number
                };
                usize::try_from(frame)
                    .ok()
                    .filter(|&frame| frame < count)
                    .ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "frame {number} is out of range: the take has frames 0 to {}",
                            count - 1
                        ))
                    })
            })
            .collect()
    }

    /// Whether `frames` is one int (a Python or numpy integer): the arrays then have no frame
    /// axis, as `array[i]` has none in numpy.
    pub(crate) fn one_frame(frames: Option<&Bound<'_, PyAny>>) -> bool {
        frames.is_some_and(|f| f.cast::<PySlice>().is_err() && f.extract::<isize>().is_ok())
    }

    /// `per_frame` floats of every frame in `frames` (of a skeleton of `joints`), computed by
    /// `compute(frames, out)` on every core, piece by piece, each piece straight into its place
    /// in the result.
    pub(crate) fn per_frame_floats(
        frames: &[usize],
        joints: usize,
        per_frame: usize,
        compute: impl Fn(&[usize], &mut [f32]) + Sync,
    ) -> Result<Vec<f32>, Error> {
        let mut result =
            bvhview::limits::zeroed_floats(frames.len().saturating_mul(per_frame), "the result")?;
        let piece = piece_frames(joints);
        let pieces = Mutex::new(
            frames
                .chunks(piece)
                .zip(result.chunks_mut((piece * per_frame).max(1))),
        );
        let threads = bvhview::plumbing::cores().clamp(1, frames.len().div_ceil(piece).max(1));
        bvhview::plumbing::on_threads(threads, || {
            loop {
                let next = pieces.lock().unwrap_or_else(PoisonError::into_inner).next();
                let Some((frames, out)) = next else {
                    return;
                };
                compute(frames, out);
            }
        });
        Ok(result)
    }

    /// World positions of every joint for `frames`: `frames × joints × 3` floats.
    pub(crate) fn positions_of(&self, frames: &[usize]) -> Result<Vec<f32>, Error> {
        let skeleton = &self.loaded.skeleton;
        let motion = &self.loaded.motion;
        let joints = skeleton.joints.len();
        if motion.frame_count() == 0 {
            // The rest pose: frame 0 is the only one there is.
            let rest = pose::world_positions(skeleton, &[], self.offset_mode);
            let rest: Vec<f32> = flatten(&rest).collect();
            let mut out = bvhview::limits::zeroed_floats(
                frames.len().saturating_mul(rest.len()),
                "the result",
            )?;
            for slot in out.chunks_exact_mut(rest.len().max(1)) {
                slot.copy_from_slice(&rest);
            }
            return Ok(out);
        }
        let plan = FkPlan::new(skeleton, self.offset_mode);
        Self::per_frame_floats(frames, joints, joints * 3, |frames, out| {
            let (mut points, mut scratch) = (Vec::new(), FkScratch::default());
            let mut rows: Vec<&[f32]> = Vec::with_capacity(LANES);
            for (batch, out) in frames
                .chunks(LANES)
                .zip(out.chunks_mut((LANES * joints * 3).max(1)))
            {
                rows.clear();
                rows.extend(batch.iter().map(|&frame| motion.frame(frame)));
                // Eight frames side by side, one per vector lane.
                plan.positions_of_frames(&rows, &mut points, &mut scratch);
                for (slot, point) in out.chunks_exact_mut(3).zip(&points) {
                    slot.copy_from_slice(&point.to_array());
                }
            }
        })
    }

    /// World matrices of every joint for `frames`, row-major: `frames × joints × 4 × 4`.
    /// `per_joint` floats for every joint of every frame selected, from the joint and its
    /// channel values (none for a take without frames: its rest pose), on every core.
    pub(crate) fn per_joint_of(
        &self,
        frames: &[usize],
        per_joint: usize,
        compute: impl Fn(&bvhview::Joint, &[f32], &mut [f32]) + Sync,
    ) -> Result<Vec<f32>, Error> {
        let skeleton = &self.loaded.skeleton;
        let motion = &self.loaded.motion;
        let joints = skeleton.joints.len();
        Self::per_frame_floats(frames, joints, joints * per_joint, |frames, out| {
            for (&frame, out) in frames
                .iter()
                .zip(out.chunks_mut((joints * per_joint).max(1)))
            {
                for (joint, slot) in skeleton.joints.iter().zip(out.chunks_exact_mut(per_joint)) {
                    let values = if motion.frame_count() == 0 {
                        &[][..]
                    } else {
                        joint.values(motion.frame(frame))
                    };
                    compute(joint, values, slot);
                }
            }
        })
    }

    pub(crate) fn matrices_of(&self, frames: &[usize]) -> Result<Vec<f32>, Error> {
        let skeleton = &self.loaded.skeleton;
        let motion = &self.loaded.motion;
        let joints = skeleton.joints.len();
        Self::per_frame_floats(frames, joints, joints * 16, |frames, out| {
            let mut matrices = Vec::with_capacity(joints);
            for (&frame, out) in frames.iter().zip(out.chunks_mut((joints * 16).max(1))) {
                let row = if motion.frame_count() == 0 {
                    &[][..]
                } else {
                    motion.frame(frame)
                };
                pose::world_matrices(skeleton, row, self.offset_mode, &mut matrices);
                for (slot, matrix) in out.chunks_exact_mut(16).zip(&matrices) {
                    slot.copy_from_slice(&row_major(matrix));
                }
            }
        })
    }
}

pub(crate) fn flatten(points: &[Vec3]) -> impl Iterator<Item = f32> + '_ {
    points.iter().flat_map(|p| p.to_array())
}

/// glam keeps columns; numpy users index `[row, column]`, translation in the last column.
pub(crate) fn row_major(matrix: &Mat4) -> [f32; 16] {
    matrix.transpose().to_cols_array()
}
