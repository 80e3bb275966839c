//! The native half of the Python package `bvhview`: a thin layer over the `bvhview` crate.
//!
//! Loading and forward kinematics are the crate's own (`input::load_checked`, `pose::FkPlan`,
//! `pose::world_matrices`, `bvh::writer::write_bvh`); this file only moves their results into
//! numpy arrays and their errors into Python exceptions. The GIL is released for every load and
//! every computation, so Python threads run meanwhile.

use bvhview::error::Error;
use bvhview::input::{self, Loaded};
use bvhview::output::AtomicFile;
use bvhview::pose::{self, FkPlan, FkScratch, LANES, OffsetMode};
use glam::{Mat4, Vec3};
use numpy::ndarray::ArrayView2;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyArray4, PyArrayMethods, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIndexError, PyIsADirectoryError, PyMemoryError, PyOSError,
    PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PySlice, PySliceMethods, PyTuple};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

mod datasets;
mod retarget;

create_exception!(
    bvhview,
    ParseError,
    PyValueError,
    "A malformed file. The message is `path:line:column: what was expected, what was found`; \
     the attributes `path`, `line`, `column` and `message` hold its parts."
);

/// Runs an entry point so that no Rust panic reaches Python as pyo3's `PanicException` (a
/// `BaseException`, which `except Exception` misses): a panic, which is a bug of bvhview's,
/// becomes a `RuntimeError` that says so. The environment variable `BVHVIEW_PLANT_PANIC`, set to
/// an entry point's name, plants a panic in it: the tests' switch to prove this.
fn guard<T>(entry: &str, work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    let run = || {
        if std::env::var_os("BVHVIEW_PLANT_PANIC").is_some_and(|name| name == entry) {
            panic!("a panic planted in {entry} by BVHVIEW_PLANT_PANIC");
        }
        work()
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".to_string());
        Err(PyRuntimeError::new_err(format!(
            "internal error in bvhview ({entry}): {what}; please report it"
        )))
    })
}

/// Every error of the crate as the Python exception a Python user expects: a malformed file is a
/// `ParseError` (a `ValueError`), a missing file a `FileNotFoundError`, other I/O an `OSError`,
/// a request that cannot be met a `ValueError`.
fn to_python(py: Python<'_>, error: Error) -> PyErr {
    let text = error.to_string();
    match error {
        Error::Parse {
            path,
            line,
            column,
            message,
        } => {
            let exception = ParseError::new_err(text);
            let value = exception.value(py);
            let set = || -> PyResult<()> {
                value.setattr("path", path)?;
                value.setattr("line", line)?;
                value.setattr("column", column)?;
                value.setattr("message", message)
            };
            if let Err(failure) = set() {
                return failure;
            }
            exception
        }
        Error::Io { path, source } | Error::Output { path, source } => {
            os_error(&path, &source, &text)
        }
        Error::Usage(_) => PyValueError::new_err(text),
        Error::Memory(_) => PyMemoryError::new_err(text),
        Error::Environment(_) => PyRuntimeError::new_err(text),
    }
}

/// An `OSError` of the subclass Python itself would raise, with `errno`, `strerror` and
/// `filename` set when the OS gave a number.
fn os_error(path: &Path, source: &io::Error, text: &str) -> PyErr {
    let filename = path.display().to_string();
    // The crate's text starts with the path; `filename` holds it already.
    let reason = text
        .strip_prefix(&format!("{filename}: "))
        .unwrap_or(text)
        .to_string();
    macro_rules! raise {
        ($class:ty) => {
            match source.raw_os_error() {
                Some(errno) => <$class>::new_err((errno, reason, filename)),
                None => <$class>::new_err(text.to_string()),
            }
        };
    }
    match source.kind() {
        io::ErrorKind::NotFound => raise!(PyFileNotFoundError),
        io::ErrorKind::PermissionDenied => raise!(PyPermissionError),
        io::ErrorKind::IsADirectory => raise!(PyIsADirectoryError),
        _ => raise!(PyOSError),
    }
}

fn parse_offset_mode(text: &str) -> PyResult<OffsetMode> {
    match text {
        "replace" => Ok(OffsetMode::Replace),
        "add" => Ok(OffsetMode::Add),
        other => Err(PyValueError::new_err(format!(
            "offset_mode={other:?}: expected \"replace\" (position channels replace the OFFSET, \
             as Blender and bvhio) or \"add\" (added to it, as three.js)"
        ))),
    }
}

fn offset_mode_name(mode: OffsetMode) -> &'static str {
    match mode {
        OffsetMode::Replace => "replace",
        OffsetMode::Add => "add",
    }
}

/// One thing to load: a BVH file, or an ASF skeleton with an optional AMC motion.
#[derive(Clone, Debug)]
struct Item {
    path: PathBuf,
    motion: Option<PathBuf>,
}

/// Loads one item with the crate's checks, on `threads` threads. A folder is refused as the OS
/// refuses to read one, so that Python sees an `IsADirectoryError`.
fn load_item(item: &Item, frame_time: Option<f64>, threads: usize) -> Result<Loaded, Error> {
    for path in std::iter::once(&item.path).chain(&item.motion) {
        if path.is_dir() {
            return Err(Error::io(path, io::ErrorKind::IsADirectory.into()));
        }
    }
    input::load_checked(
        &item.path,
        item.motion.as_deref(),
        frame_time,
        threads,
        input::DEFAULT_MAX_SIZE,
    )
}

/// A loaded take: the skeleton, the MOTION values, and forward kinematics on them.
///
/// Frozen: nothing changes after loading, so `values` can be a view of the loaded data (no
/// copy) and computations can read it without the GIL.
#[pyclass(frozen, module = "bvhview", name = "Motion")]
struct Motion {
    loaded: Loaded,
    item: Item,
    offset_mode: OffsetMode,
}

/// Joint transforms computed per piece of work (some 50 µs of it): small enough to share a
/// take of a thousand frames among the cores, large enough that taking a piece and waking a
/// helper cost little next to computing it.
const PIECE_TRANSFORMS: usize = 8192;

/// Frames per piece for a skeleton of `joints`: whole batches of [`LANES`] frames.
fn piece_frames(joints: usize) -> usize {
    (PIECE_TRANSFORMS / joints.max(1))
        .next_multiple_of(LANES)
        .clamp(LANES, 1024)
}

impl Motion {
    /// Frames `positions` and `world_matrices` can compute: every frame, or the rest pose as
    /// frame 0 of a take without frames (as the CLI's `positions` does).
    fn available_frames(&self) -> usize {
        self.loaded.motion.frame_count().max(1)
    }

    /// The frame numbers `frames` selects: None (all), an int (negative counts from the end),
    /// a slice, or a sequence of ints (a list, a range, a numpy array).
    fn selected_frames(&self, frames: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
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
                            "frame {number} is out of range: the take has frames 0..{count}"
                        ))
                    })
            })
            .collect()
    }

    /// `per_frame` floats of every frame in `frames` (of a skeleton of `joints`), computed by
    /// `compute(frames, out)` on every core, piece by piece, each piece straight into its place
    /// in the result.
    fn per_frame_floats(
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
        let threads = bvhview::cores().clamp(1, frames.len().div_ceil(piece).max(1));
        bvhview::parallel::on_threads(threads, || {
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
    fn positions_of(&self, frames: &[usize]) -> Result<Vec<f32>, Error> {
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
    fn per_joint_of(
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

    fn matrices_of(&self, frames: &[usize]) -> Result<Vec<f32>, Error> {
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

fn flatten(points: &[Vec3]) -> impl Iterator<Item = f32> + '_ {
    points.iter().flat_map(|p| p.to_array())
}

/// glam keeps columns; numpy users index `[row, column]`, translation in the last column.
fn row_major(matrix: &Mat4) -> [f32; 16] {
    matrix.transpose().to_cols_array()
}

#[pymethods]
impl Motion {
    /// The file loaded (for ASF/AMC, the skeleton).
    #[getter]
    fn path(&self) -> String {
        self.item.path.display().to_string()
    }

    /// The AMC motion file, or None.
    #[getter]
    fn motion_path(&self) -> Option<String> {
        self.item.motion.as_ref().map(|p| p.display().to_string())
    }

    /// "replace" or "add": how position channels combine with OFFSETs in `positions` and
    /// `world_matrices`.
    #[getter]
    fn offset_mode(&self) -> &'static str {
        offset_mode_name(self.offset_mode)
    }

    /// Every joint's name in file order (pre-order), End Sites as the CLI names them,
    /// `<parent>_End` (a file calls them all "Site").
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        let skeleton = &self.loaded.skeleton;
        (0..skeleton.joints.len())
            .map(|index| bvhview::export::export_name(skeleton, index))
            .collect()
    }

    /// The index of the joint named `name` (an End Site as `<parent>_End`), as in
    /// `joint_names`; ValueError when there is none.
    fn index(&self, name: &str) -> PyResult<usize> {
        let skeleton = &self.loaded.skeleton;
        (0..skeleton.joints.len())
            .find(|&index| bvhview::export::export_name(skeleton, index) == name)
            .ok_or_else(|| PyValueError::new_err(format!("no joint named {name:?}")))
    }

    /// The indices of joint `index`'s children, in file order; IndexError past the last joint.
    fn children(&self, index: usize) -> PyResult<Vec<usize>> {
        let joints = &self.loaded.skeleton.joints;
        joints
            .get(index)
            .map(|joint| joint.children.clone())
            .ok_or_else(|| {
                PyIndexError::new_err(format!(
                    "joint {index}: the take has joints 0 to {}",
                    joints.len().saturating_sub(1)
                ))
            })
    }

    /// Frames per second (1 / `frame_time`), or None when the Frame Time is not above 0.
    #[getter]
    fn fps(&self) -> Option<f64> {
        let time = self.loaded.motion.frame_time;
        (time > 0.0).then(|| 1.0 / time)
    }

    /// Seconds the take lasts: frames × `frame_time`.
    #[getter]
    fn duration(&self) -> f64 {
        self.loaded.motion.duration()
    }

    /// The up axis guessed from the motion, "y" or "z", as `bvhview info` prints it.
    #[getter]
    fn up_axis(&self) -> &'static str {
        match self.loaded.stance(self.offset_mode).up {
            pose::Up::Y => "y",
            pose::Up::Z => "z",
        }
    }

    /// The units the lengths look written in ("centimetres", "inches", "CMU units (1/0.45
    /// inch)"…), guessed from the motion or stated by an ASF, as `bvhview info` prints them.
    #[getter]
    fn units(&self) -> &'static str {
        self.loaded.stance(self.offset_mode).units.name
    }

    /// Metres per unit of the file's lengths, by `units`: `positions() * metres_per_unit` is
    /// in metres.
    #[getter]
    fn metres_per_unit(&self) -> f32 {
        self.loaded.stance(self.offset_mode).units.metres
    }

    /// Parent index of every joint, -1 for a root (int32).
    #[getter]
    fn parents<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let parents: Vec<i32> = self
            .loaded
            .skeleton
            .joints
            .iter()
            .map(|j| j.parent.map_or(-1, |p| p as i32))
            .collect();
        parents.into_pyarray(py)
    }

    /// True for the End Sites (bool, one per joint).
    #[getter]
    fn end_sites<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let flags: Vec<bool> = self
            .loaded
            .skeleton
            .joints
            .iter()
            .map(|j| j.end_site)
            .collect();
        flags.into_pyarray(py)
    }

    /// Every joint's OFFSET (joints × 3, float32).
    #[getter]
    fn offsets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let joints = &self.loaded.skeleton.joints;
        let offsets: Vec<f32> = joints.iter().flat_map(|j| j.offset.to_array()).collect();
        offsets.into_pyarray(py).reshape([joints.len(), 3])
    }

    /// Every joint's channel names in file order ("Xposition", …, "Zrotation"); [] for End Sites.
    #[getter]
    fn channels(&self) -> Vec<Vec<&'static str>> {
        self.loaded
            .skeleton
            .joints
            .iter()
            .map(|j| j.channels.iter().map(|c| c.name()).collect())
            .collect()
    }

    /// Every joint's rotation order as its three axes in file order ("ZXY"), or None for a joint
    /// without exactly three rotation channels on distinct axes.
    #[getter]
    fn rotation_orders(&self) -> Vec<Option<String>> {
        self.loaded
            .skeleton
            .joints
            .iter()
            .map(|j| j.rotation_order.map(|o| o.letters().to_ascii_uppercase()))
            .collect()
    }

    /// Seconds per frame.
    #[getter]
    fn frame_time(&self) -> f64 {
        self.loaded.motion.frame_time
    }

    #[getter]
    fn frame_count(&self) -> usize {
        self.loaded.motion.frame_count()
    }

    /// Values per frame: the columns of `values`.
    #[getter]
    fn channel_count(&self) -> usize {
        self.loaded.motion.channels
    }

    /// What loaded but deserves a word (rows beyond the Frames count, a file that looks written
    /// for the other offset mode, …): what the CLI warns of.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        bvhview::info::warnings(&self.loaded, self.offset_mode)
    }

    /// The MOTION values, frames × channels (float32), read-only. A view of the loaded data, not
    /// a copy: it keeps this Motion alive.
    #[getter]
    fn values<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let motion = &slf.get().loaded.motion;
        let view = ArrayView2::from_shape((motion.frame_count(), motion.channels), &motion.data)
            .map_err(|e| PyRuntimeError::new_err(format!("values: {e}")))?;
        // SAFETY: the array's base is this Motion, which owns `data` for as long as the array
        // lives, and a frozen Motion never changes it. The array is made read-only below, so
        // numpy never writes into Rust's memory either.
        let array = unsafe { PyArray2::borrow_from_array(&view, slf.clone().into_any()) };
        array
            .try_readwrite()
            .map_err(|e| PyRuntimeError::new_err(format!("values: {e}")))?
            .make_nonwriteable();
        Ok(array)
    }

    /// The names the CLI's `positions` export gives its points: joints by name, End Sites as
    /// `<parent>_End`; for ASF, the root and each bone's end point named by the bone.
    #[getter]
    fn point_names(&self) -> Vec<String> {
        bvhview::export::export_points(&self.loaded.skeleton)
            .into_iter()
            .map(|(name, _)| name)
            .collect()
    }

    /// For each of `point_names`, the joint whose position it is (int32):
    /// `positions()[:, point_joints]` is the CLI's export.
    #[getter]
    fn point_joints<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let joints: Vec<i32> = bvhview::export::export_points(&self.loaded.skeleton)
            .into_iter()
            .map(|(_, joint)| joint as i32)
            .collect();
        joints.into_pyarray(py)
    }

    /// World position of every joint and End Site (see `end_sites`) for the frames selected:
    /// frames × joints × 3, float32. `frames`: None for all, an int, a slice or a sequence of
    /// ints. A take without frames has one: its rest pose.
    #[pyo3(signature = (frames=None))]
    fn positions<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let frames = self.selected_frames(frames)?;
        let values = py
            .detach(|| self.positions_of(&frames))
            .map_err(|e| to_python(py, e))?;
        let joints = self.loaded.skeleton.joints.len();
        values.into_pyarray(py).reshape([frames.len(), joints, 3])
    }

    /// Every joint's local transform for the frames selected, as FK multiplies them:
    /// `T(t) · R1 · R2 · R3` (ASF bones `T · C · R · C⁻¹`), frames × joints × 4 × 4, float32,
    /// `[row, column]`; `world_matrices` is their product down the tree.
    #[pyo3(signature = (frames=None))]
    fn local_matrices<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray4<f32>>> {
        let frames = self.selected_frames(frames)?;
        let mode = self.offset_mode;
        let values = py
            .detach(|| {
                self.per_joint_of(&frames, 16, |joint, values, out| {
                    let local = if values.is_empty() {
                        Mat4::from_translation(joint.offset)
                    } else {
                        pose::local_matrix(joint, values, mode)
                    };
                    out.copy_from_slice(&row_major(&local));
                })
            })
            .map_err(|e| to_python(py, e))?;
        let joints = self.loaded.skeleton.joints.len();
        values
            .into_pyarray(py)
            .reshape([frames.len(), joints, 4, 4])
    }

    /// Every joint's local rotation for the frames selected (the `R` of `local_matrices`):
    /// `kind="quat"` frames × joints × 4 as (w, x, y, z), w ≥ 0; `"matrix"` × 3 × 3
    /// `[row, column]`; `"6d"` × 6, the matrix's first two columns one after the other (Zhou
    /// et al. 2019);
    /// `"euler"` × 3, the joint's rotation channels in its file order, in degrees (0 where it has
    /// fewer than three). End Sites and joints without rotation channels: the identity.
    #[pyo3(signature = (frames=None, kind="quat"))]
    fn local_rotations<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
        kind: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let frames = self.selected_frames(frames)?;
        let Some(rotation_kind) = pose::RotationKind::parse(kind) else {
            return Err(PyValueError::new_err(format!(
                "kind={kind:?}: expected {}",
                pose::RotationKind::NAMES
            )));
        };
        let per_joint = rotation_kind.width();
        let values = py
            .detach(|| {
                self.per_joint_of(&frames, per_joint, |joint, values, out| {
                    pose::write_rotation(joint, values, rotation_kind, out)
                })
            })
            .map_err(|e| to_python(py, e))?;
        let joints = self.loaded.skeleton.joints.len();
        let array = values.into_pyarray(py);
        Ok(match rotation_kind {
            pose::RotationKind::Matrix => array.reshape([frames.len(), joints, 3, 3])?.into_any(),
            _ => array.reshape([frames.len(), joints, per_joint])?.into_any(),
        })
    }

    /// The first root's translation for the frames selected (its OFFSET with its position
    /// channels, in the offset mode), frames × 3, float32.
    #[pyo3(signature = (frames=None))]
    fn root_translations<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let frames = self.selected_frames(frames)?;
        let skeleton = &self.loaded.skeleton;
        let motion = &self.loaded.motion;
        let root = skeleton.roots().next();
        let mut out = Vec::with_capacity(frames.len() * 3);
        for &frame in &frames {
            let t = match root {
                None => Vec3::ZERO,
                Some(root) if motion.frame_count() == 0 => skeleton.joints[root].offset,
                Some(root) => {
                    let joint = &skeleton.joints[root];
                    pose::joint_translation(
                        joint,
                        joint.values(motion.frame(frame)),
                        self.offset_mode,
                    )
                }
            };
            out.extend(t.to_array());
        }
        out.into_pyarray(py).reshape([frames.len(), 3])
    }

    /// One name per column of `values`: the joint's name and the channel's, `Hips_Xposition`.
    #[getter]
    fn channel_names(&self) -> Vec<String> {
        self.loaded
            .skeleton
            .joints
            .iter()
            .flat_map(|j| {
                j.channels
                    .iter()
                    .map(move |c| format!("{}_{}", j.name, c.name()))
            })
            .collect()
    }

    /// Each joint's first column in `values` (int32; its channels follow in file order), -1 for
    /// a joint without channels: `values[:, first_channels[j]:first_channels[j] + len(channels[j])]`.
    #[getter]
    fn first_channels<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let columns: Vec<i32> = self
            .loaded
            .skeleton
            .joints
            .iter()
            .map(|j| {
                if j.channels.is_empty() {
                    -1
                } else {
                    j.first_channel as i32
                }
            })
            .collect();
        columns.into_pyarray(py)
    }

    /// World matrix of every joint for the frames selected: frames × joints × 4 × 4, float32,
    /// `[frame, joint, row, column]` with the translation in column 3. `frames` as in
    /// `positions`.
    #[pyo3(signature = (frames=None))]
    fn world_matrices<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray4<f32>>> {
        let frames = self.selected_frames(frames)?;
        let values = py
            .detach(|| self.matrices_of(&frames))
            .map_err(|e| to_python(py, e))?;
        let joints = self.loaded.skeleton.joints.len();
        values
            .into_pyarray(py)
            .reshape([frames.len(), joints, 4, 4])
    }

    /// Writes the take as BVH (.bvh) or glTF (.glb binary, .gltf text), as `bvhview convert`
    /// does: for BVH, ASF bone axes are baked into ZYX rotation channels and names with
    /// whitespace or braces are written with `_`; glTF gets one node per joint and End Site and
    /// the take's offset mode. The file takes its name only when complete.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let extension = input::extension(&path);
        let container = match extension.as_str() {
            "bvh" => None,
            "glb" => Some(bvhview::gltf::Container::Glb),
            "gltf" => Some(bvhview::gltf::Container::Gltf),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{}: save writes .bvh, .glb or .gltf files, not '{extension}'",
                    path.display()
                )));
            }
        };
        py.detach(|| match container {
            None => self.write_bvh(&path),
            Some(container) => self.write_gltf(&path, container),
        })
        .map_err(|e| to_python(py, e))
    }

    /// Frames `start` to `stop` (stop left out; negative counts from the end, as a slice
    /// does), as `bvhview convert --frames` keeps them: a new take.
    #[pyo3(signature = (start=None, stop=None))]
    fn trim(&self, start: Option<isize>, stop: Option<isize>) -> Motion {
        let count = self.loaded.motion.frame_count() as isize;
        let at = |bound: Option<isize>, default: isize| {
            let bound = bound.unwrap_or(default);
            (if bound < 0 { bound + count } else { bound }).clamp(0, count) as usize
        };
        let (start, stop) = (at(start, 0), at(stop, count));
        let motion = bvhview::edit::trim(&self.loaded.motion, start..stop.max(start));
        self.edited(self.loaded.skeleton.clone(), motion, true)
    }

    /// The take at `fps` frames per second (any rate from 0.01 to 1000, whole or not; rotations
    /// slerped), as `convert --fps` makes it.
    fn resample(&self, py: Python<'_>, fps: f64) -> PyResult<Motion> {
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let motion = py
            .detach(|| bvhview::edit::resample(skeleton, motion, fps))
            .map_err(|e| to_python(py, e))?;
        Ok(self.edited(skeleton.clone(), motion, true))
    }

    /// Every length times `factor` (OFFSETs and position channels), as `convert --scale`.
    fn scale(&self, py: Python<'_>, factor: f32) -> PyResult<Motion> {
        if !(factor.is_finite() && factor != 0.0) {
            return Err(PyValueError::new_err(format!(
                "scale {factor}: expected a finite number other than 0"
            )));
        }
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let (skeleton, motion) = py
            .detach(|| bvhview::edit::scale(skeleton, motion, factor))
            .map_err(|e| to_python(py, e))?;
        // The units an ASF stated hold no longer.
        Ok(self.edited(skeleton, motion, factor == 1.0))
    }

    /// Left and right swapped (names and motion), as `convert --mirror`, the names as
    /// `mirror_names` guesses them; `names` overrides the guess for the joints it lists.
    #[pyo3(signature = (names=None))]
    fn mirror(
        &self,
        py: Python<'_>,
        names: Option<std::collections::HashMap<String, String>>,
    ) -> PyResult<Motion> {
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let (mut mirrored, motion) = py.detach(|| bvhview::edit::mirror(skeleton, motion));
        if let Some(names) = names {
            for (joint, original) in mirrored.joints.iter_mut().zip(&skeleton.joints) {
                if let Some(name) = names.get(&original.name) {
                    joint.name = name.clone();
                }
            }
        }
        Ok(self.edited(mirrored, motion, true))
    }

    /// The take's motion on another skeleton, as `bvhview retarget` puts it: `target` a Motion,
    /// a built-in skeleton's name ("smpl22") or a file's path; `names` overrides the guessed
    /// map ({source joint: target joint}; "" leaves a source joint out). Raises ValueError
    /// naming the joint when the map cannot stand.
    #[pyo3(signature = (target, names=None))]
    fn retarget(
        &self,
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
        names: Option<std::collections::HashMap<String, String>>,
    ) -> PyResult<Motion> {
        guard("retarget", || retarget::retarget(py, self, target, names))
    }

    /// The joint map `retarget(target)` would guess: {source joint: target joint}.
    fn retarget_map(
        &self,
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
    ) -> PyResult<std::collections::HashMap<String, String>> {
        guard("retarget_map", || retarget::retarget_map(py, self, target))
    }

    /// The names `mirror()` gives: each joint whose name marks a side (`LeftArm`, `L_Arm`,
    /// `Arm.L`, CMU's `lhumerus`…), with the other side's name.
    #[getter]
    fn mirror_names(&self) -> std::collections::HashMap<String, String> {
        self.loaded
            .skeleton
            .joints
            .iter()
            .filter_map(|j| {
                bvhview::edit::mirrored_name(&j.name).map(|other| (j.name.clone(), other))
            })
            .collect()
    }

    /// The take turned to stand along `axis` ("y" or "z") from its `up_axis`, as `convert --up`.
    fn to_up(&self, py: Python<'_>, axis: &str) -> PyResult<Motion> {
        let target = match axis {
            "y" => pose::Up::Y,
            "z" => pose::Up::Z,
            other => {
                return Err(PyValueError::new_err(format!(
                    "axis={other:?}: expected \"y\" or \"z\""
                )));
            }
        };
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let (skeleton, motion) = py
            .detach(|| {
                let up = self.loaded.stance(self.offset_mode).up;
                bvhview::edit::reorient(skeleton, motion, up, target)
            })
            .map_err(|e| to_python(py, e))?;
        Ok(self.edited(skeleton, motion, true))
    }

    /// The root kept over its first frame's place along the floor (across its `up_axis`), as
    /// `convert --in-place`.
    fn in_place(&self, py: Python<'_>) -> Motion {
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let motion = py.detach(|| {
            let up = self.loaded.stance(self.offset_mode).up;
            bvhview::edit::in_place(skeleton, motion, up)
        });
        self.edited(skeleton.clone(), motion, true)
    }

    /// The take moved along its `up_axis` so that its lowest point, over every joint and frame
    /// in its offset mode, is at 0, as `convert --ground`.
    fn ground(&self, py: Python<'_>) -> PyResult<Motion> {
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        let (skeleton, motion) = py
            .detach(|| {
                let up = self.loaded.stance(self.offset_mode).up;
                bvhview::edit::ground(skeleton, motion, self.offset_mode, up)
            })
            .map_err(|e| to_python(py, e))?;
        Ok(self.edited(skeleton, motion, true))
    }

    /// A take built from arrays on `template`'s skeleton (a Motion), to save as BVH or glTF:
    /// `rotations`, every joint's local rotation per frame, as `local_rotations` gives them:
    /// frames × joints × 4 (quat, w x y z), × 3 × 3 (matrix), × 6 (6d) or × 3 (euler: each
    /// joint's rotation channels in file order, degrees), the kind told by the shape or `kind`;
    /// `root_translations` (frames × 3) for the first root; `fps` (default: the template's).
    /// Other position channels keep the template's values (its last frame's past its end). A
    /// joint with fewer than three rotation channels (an ASF bone with one or two degrees of
    /// freedom) takes the angles of the nearest rotation it can make.
    #[staticmethod]
    #[pyo3(signature = (template, rotations, root_translations=None, fps=None, kind=None))]
    fn from_arrays(
        py: Python<'_>,
        template: &Motion,
        rotations: numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>,
        root_translations: Option<numpy::PyArrayLike2<'_, f32, numpy::AllowTypeChange>>,
        fps: Option<f64>,
        kind: Option<&str>,
    ) -> PyResult<Motion> {
        let skeleton = &template.loaded.skeleton;
        let joints = skeleton.joints.len();
        let shape = rotations.shape().to_vec();
        let kind = match (kind, &shape[..]) {
            (Some(text), _) => pose::RotationKind::parse(text).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "kind={text:?}: expected {}",
                    pose::RotationKind::NAMES
                ))
            })?,
            (None, [_, _, 4]) => pose::RotationKind::Quat,
            (None, [_, _, 3, 3]) => pose::RotationKind::Matrix,
            (None, [_, _, 6]) => pose::RotationKind::SixD,
            (None, [_, _, 3]) => pose::RotationKind::Euler,
            (None, _) => {
                return Err(PyValueError::new_err(format!(
                    "rotations of shape {shape:?}: expected frames x joints x 4, 3x3, 6 or 3"
                )));
            }
        };
        let per_joint = kind.width();
        if shape.len() < 2
            || shape[1] != joints
            || shape[2..].iter().product::<usize>() != per_joint
        {
            return Err(PyValueError::new_err(format!(
                "rotations of shape {shape:?}: the template has {joints} joints, and {} takes {per_joint} numbers each",
                kind.name()
            )));
        }
        let frames = shape[0];
        let old = &template.loaded.motion;
        let channels = old.channels;
        let values = frames
            .checked_mul(channels.max(1))
            .filter(|&n| n as u64 <= bvhview::limits::MAX_GENERATED_VALUES)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "{frames} frames of {channels} values: more than a take holds ({} values at most)",
                    bvhview::limits::MAX_GENERATED_VALUES
                ))
            })?;
        // In C order whatever the strides (a slice or a transposed array is fine).
        let rotations: Vec<f32> = rotations.as_array().iter().copied().collect();
        if let Some(at) = rotations.iter().position(|v| !v.is_finite()) {
            let (frame, joint) = (at / per_joint / joints, at / per_joint % joints);
            return Err(PyValueError::new_err(format!(
                "rotations[{frame}, {joint}] is not a finite number"
            )));
        }
        let translations = match &root_translations {
            Some(t) if t.shape() != [frames, 3] => {
                return Err(PyValueError::new_err(format!(
                    "root_translations of shape {:?}: expected {frames} x 3",
                    t.shape()
                )));
            }
            Some(t) => Some(t.as_array().iter().copied().collect::<Vec<f32>>()),
            None => None,
        };
        if let Some(at) = translations
            .as_ref()
            .and_then(|t| t.iter().position(|v| !v.is_finite()))
        {
            return Err(PyValueError::new_err(format!(
                "root_translations[{}] is not a finite number",
                at / 3
            )));
        }
        // Numbers that stand for no rotation would become NaN angles, which `save` refuses
        // later: refused here, where the caller can see which.
        for frame in 0..frames {
            for (index, joint) in skeleton.joints.iter().enumerate() {
                if !joint.channels.iter().any(|c| c.is_rotation()) {
                    continue;
                }
                let numbers = &rotations[(frame * joints + index) * per_joint..][..per_joint];
                if let Some(problem) = pose::rotation_numbers_problem(kind, numbers) {
                    return Err(PyValueError::new_err(format!(
                        "rotations[{frame}, {index}] ({}): {problem}",
                        joint.name
                    )));
                }
            }
        }
        // The rates `convert --fps` takes: a Motion made at another could not be saved.
        let frame_time = match fps {
            Some(fps) if bvhview::limits::fps(fps, false).is_ok() => 1.0 / fps,
            Some(fps) => {
                return Err(PyValueError::new_err(format!(
                    "fps={}: expected frames per second from {} to {}",
                    bvhview::limits::show(fps),
                    bvhview::limits::show(bvhview::limits::MIN_FPS),
                    bvhview::limits::show(bvhview::limits::MAX_FPS)
                )));
            }
            None => template.loaded.motion.frame_time,
        };
        let root = skeleton.roots().next();
        let mode = template.offset_mode;
        let build =
            || -> Vec<f32> {
                let mut data = Vec::with_capacity(values);
                for frame in 0..frames {
                    let start = data.len();
                    // Position channels the arrays do not give: the template's.
                    if old.frame_count() > 0 {
                        data.extend_from_slice(old.frame(frame.min(old.frame_count() - 1)));
                    } else {
                        for joint in &skeleton.joints {
                            data.extend(joint.channels.iter().map(|c| {
                                match (c.is_position(), mode) {
                                    (true, OffsetMode::Replace) => joint.offset[c.axis()],
                                    _ => 0.0,
                                }
                            }));
                        }
                    }
                    let row = &mut data[start..];
                    for (index, joint) in skeleton.joints.iter().enumerate() {
                        let numbers =
                            &rotations[(frame * joints + index) * per_joint..][..per_joint];
                        let values = &mut row
                            [joint.first_channel..joint.first_channel + joint.channels.len()];
                        if Some(index) == root
                            && let Some(t) = &translations
                        {
                            for (channel, value) in joint.channels.iter().zip(values.iter_mut()) {
                                if channel.is_position() {
                                    let wanted = t[frame * 3 + channel.axis()];
                                    *value = match mode {
                                        OffsetMode::Replace => wanted,
                                        OffsetMode::Add => wanted - joint.offset[channel.axis()],
                                    };
                                }
                            }
                        }
                        let angles = bvhview::edit::channel_angles(joint, kind, numbers);
                        let mut angles = angles.into_iter();
                        for (channel, value) in joint.channels.iter().zip(values.iter_mut()) {
                            if channel.is_rotation()
                                && let Some(angle) = angles.next()
                            {
                                *value = angle;
                            }
                        }
                    }
                }
                data
            };
        let data = py.detach(build);
        let motion = bvhview::Motion::new(frame_time, channels, frames, data);
        let mut take = template.edited(skeleton.clone(), motion, true);
        take.loaded.warnings.clear();
        Ok(take)
    }

    /// The MOTION values as a pandas DataFrame: one row per frame (index "frame"), one column
    /// per channel (`channel_names`), float32; `frames` as in `positions`. Needs pandas.
    #[pyo3(signature = (frames=None))]
    fn to_dataframe<'py>(
        slf: &Bound<'py, Self>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let pandas = py.import("pandas").map_err(|_| {
            pyo3::exceptions::PyModuleNotFoundError::new_err(
                "to_dataframe needs pandas: pip install pandas",
            )
        })?;
        let take = slf.get();
        let motion = &take.loaded.motion;
        let selected = if motion.frame_count() == 0 {
            Vec::new()
        } else {
            take.selected_frames(frames)?
        };
        let mut values = Vec::with_capacity(selected.len() * motion.channels);
        for &frame in &selected {
            values.extend_from_slice(motion.frame(frame));
        }
        let array = values
            .into_pyarray(py)
            .reshape([selected.len(), motion.channels])?;
        let index = pandas.call_method(
            "Index",
            (selected,),
            Some(&[("name", "frame")].into_py_dict(py)?),
        )?;
        let options = [
            (
                "columns",
                take.channel_names().into_pyobject(py)?.into_any(),
            ),
            ("index", index),
        ]
        .into_py_dict(py)?;
        pandas.call_method("DataFrame", (array,), Some(&options))
    }

    /// Pickling (multiprocessing, Dask, Ray): the take itself travels, skeleton and values,
    /// not its path, so a worker on another machine needs no copy of the file.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (State,))> {
        let rebuild = py.import("bvhview._bvhview")?.getattr("_from_state")?;
        Ok((rebuild, (self.state(),)))
    }

    fn __len__(&self) -> usize {
        self.loaded.motion.frame_count()
    }

    fn __repr__(&self) -> String {
        let skeleton = &self.loaded.skeleton;
        let end_sites = skeleton.end_site_count();
        format!(
            "<bvhview.Motion {:?}: {} joints + {} End Sites, {} channels, {} frames at {} s>",
            self.path(),
            skeleton.joints.len() - end_sites,
            end_sites,
            self.loaded.motion.channels,
            self.loaded.motion.frame_count(),
            self.loaded.motion.frame_time
        )
    }
}

impl Motion {
    fn write_bvh(&self, path: &Path) -> Result<(), Error> {
        let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
        // BVH has no fixed bone axis.
        let baked = skeleton
            .joints
            .iter()
            .any(|j| j.axis.is_some())
            .then(|| bvhview::edit::bake_axes(skeleton, motion))
            .transpose()?;
        let (skeleton, motion) = baked.as_ref().map_or((skeleton, motion), |(s, m)| (s, m));
        // Refused before the file is opened: nothing is written (a ValueError).
        bvhview::bvh::writer::check(skeleton, motion)?;
        let mut out = AtomicFile::create(path)?;
        bvhview::bvh::writer::write_bvh(&mut out, skeleton, motion)
            .map_err(|e| Error::output(path, e))?;
        out.commit()
    }

    fn write_gltf(&self, path: &Path, container: bvhview::gltf::Container) -> Result<(), Error> {
        let bytes = bvhview::gltf::to_gltf(
            &self.loaded.skeleton,
            &self.loaded.motion,
            self.offset_mode,
            container,
            false,
        )?;
        let mut out = AtomicFile::create(path)?;
        out.write_all(&bytes).map_err(|e| Error::output(path, e))?;
        out.commit()
    }
}

/// Loads a .bvh file, or an .asf skeleton with `motion` its .amc take (an .asf alone gives the
/// rest pose). `offset_mode`: "replace" (default) or "add"; `frame_time` overrides the file's
/// (AMC files have none: 1/120 s is the default).
#[pyfunction]
#[pyo3(signature = (path, motion=None, offset_mode="replace", frame_time=None))]
fn load(
    py: Python<'_>,
    path: PathBuf,
    motion: Option<PathBuf>,
    offset_mode: &str,
    frame_time: Option<f64>,
) -> PyResult<Motion> {
    let offset_mode = parse_offset_mode(offset_mode)?;
    let item = Item { path, motion };
    let loaded = py
        .detach(|| load_item(&item, frame_time, bvhview::cores()))
        .map_err(|e| to_python(py, e))?;
    Ok(Motion {
        loaded,
        item,
        offset_mode,
    })
}

/// A joint as pickled: name, parent (-1 for a root), OFFSET, channel names, End Site or not,
/// its fixed axis (an ASF bone's, as x, y, z, w) if any.
type JointState = (String, i64, [f32; 3], Vec<String>, bool, Option<[f32; 4]>);

/// A take as pickled: a format number, path, AMC path, offset mode, warnings, whether the
/// skeleton is an ASF's, whether it stated CMU's units, the joints, the Frame Time, the values
/// per frame and the values (float32, little-endian bytes).
type State = (
    u32,
    String,
    Option<String>,
    String,
    Vec<String>,
    bool,
    bool,
    Vec<JointState>,
    f64,
    usize,
    Vec<u8>,
);

/// The version of `State` this module writes and reads.
const STATE_FORMAT: u32 = 1;

impl Motion {
    /// A new take from this one's edit: the same path, offset mode and loader warnings;
    /// `same_lengths`: whether units an ASF stated still hold.
    fn edited(
        &self,
        skeleton: bvhview::Skeleton,
        motion: bvhview::Motion,
        same_lengths: bool,
    ) -> Motion {
        Motion {
            loaded: Loaded {
                skeleton,
                motion,
                warnings: self.loaded.warnings.clone(),
                stated_units: self.loaded.stated_units.filter(|_| same_lengths),
            },
            item: Item {
                path: self.item.path.clone(),
                motion: self.item.motion.clone(),
            },
            offset_mode: self.offset_mode,
        }
    }

    fn state(&self) -> State {
        let skeleton = &self.loaded.skeleton;
        let joints = skeleton
            .joints
            .iter()
            .map(|j| {
                (
                    j.name.clone(),
                    j.parent.map_or(-1, |p| p as i64),
                    j.offset.to_array(),
                    j.channels.iter().map(|c| c.name().to_string()).collect(),
                    j.end_site,
                    j.axis.map(|q| q.to_array()),
                )
            })
            .collect();
        let motion = &self.loaded.motion;
        (
            STATE_FORMAT,
            self.item.path.display().to_string(),
            self.item.motion.as_ref().map(|p| p.display().to_string()),
            offset_mode_name(self.offset_mode).to_string(),
            self.loaded.warnings.clone(),
            skeleton.source == bvhview::skeleton::Source::Acclaim,
            self.loaded.stated_units.is_some(),
            joints,
            motion.frame_time,
            motion.channels,
            motion.data.iter().flat_map(|v| v.to_le_bytes()).collect(),
        )
    }
}

/// A take from its pickled state (see `Motion.__reduce__`).
#[pyfunction]
fn _from_state(state: State) -> PyResult<Motion> {
    let (
        format,
        path,
        motion_path,
        mode,
        warnings,
        acclaim,
        cmu_units,
        joints,
        frame_time,
        channels,
        data,
    ) = state;
    let bad = |what: &str| PyValueError::new_err(format!("not a pickled bvhview.Motion: {what}"));
    if format != STATE_FORMAT {
        return Err(bad(&format!(
            "format {format}, this bvhview reads {STATE_FORMAT}"
        )));
    }
    let mut skeleton = bvhview::Skeleton {
        joints: Vec::with_capacity(joints.len()),
        source: if acclaim {
            bvhview::skeleton::Source::Acclaim
        } else {
            bvhview::skeleton::Source::Bvh
        },
    };
    if !bvhview::limits::frame_time_in_file(frame_time) {
        return Err(bad(&format!("a frame time of {frame_time} s")));
    }
    let mut first_channel = 0;
    for (index, (name, parent, offset, names, end_site, axis)) in joints.into_iter().enumerate() {
        // Pre-order: a joint's parent is the joint before it or one of that joint's ancestors.
        let parent = match parent {
            -1 => None,
            p if p >= 0 && (p as usize) < index => {
                let p = p as usize;
                let mut line = Some(index - 1);
                while let Some(at) = line.filter(|&at| at != p) {
                    line = skeleton.joints[at].parent;
                }
                if line.is_none() {
                    return Err(bad("joints out of pre-order"));
                }
                Some(p)
            }
            _ => return Err(bad("a parent after its child")),
        };
        if let Some(parent) = parent
            && skeleton.joints[parent].end_site
        {
            return Err(bad("an End Site with children"));
        }
        if end_site && !names.is_empty() {
            return Err(bad("an End Site with channels"));
        }
        // Written so that NaN fails: a NaN length is not within 1e-3 of 1.
        let unit = |q: [f32; 4]| {
            q.iter().all(|v| v.is_finite())
                && (glam::Quat::from_array(q).length() - 1.0).abs() <= 1e-3
        };
        if !offset.iter().all(|v| v.is_finite()) || axis.is_some_and(|q| !unit(q)) {
            return Err(bad("an OFFSET or an axis that is not a finite rotation"));
        }
        let mut joint = bvhview::Joint::new(name, parent);
        joint.offset = Vec3::from_array(offset);
        joint.channels = names
            .iter()
            .map(|n| bvhview::Channel::parse(n).ok_or_else(|| bad("a channel name")))
            .collect::<PyResult<_>>()?;
        joint.rotation_order = bvhview::RotationOrder::get_flags(&joint.channels);
        joint.first_channel = first_channel;
        first_channel += joint.channels.len();
        joint.end_site = end_site;
        joint.axis = axis.map(glam::Quat::from_array);
        if let Some(parent) = parent {
            skeleton.joints[parent].children.push(index);
        }
        skeleton.joints.push(joint);
    }
    if first_channel != channels
        || data.len() % 4 != 0
        || (channels == 0 && !data.is_empty())
        || (channels > 0 && data.len() / 4 % channels != 0)
    {
        return Err(bad("values that do not fit the channels"));
    }
    let values: Vec<f32> = data
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if values.iter().any(|v| !v.is_finite()) {
        return Err(bad("a value that is not a finite number"));
    }
    let frames = values.len().checked_div(channels).unwrap_or(0);
    let loaded = Loaded {
        skeleton,
        motion: bvhview::Motion::new(frame_time, channels, frames, values),
        warnings,
        stated_units: cmu_units.then_some(bvhview::stance::CMU_UNITS),
    };
    Ok(Motion {
        loaded,
        item: Item {
            path: PathBuf::from(path),
            motion: motion_path.map(PathBuf::from),
        },
        offset_mode: parse_offset_mode(&mode)?,
    })
}

/// One entry of `load_many`: a path, or an (asf, amc) pair.
fn item_of(entry: &Bound<'_, PyAny>) -> PyResult<Item> {
    if let Ok(pair) = entry.cast::<PyTuple>() {
        let (path, motion): (PathBuf, PathBuf) = pair.extract()?;
        return Ok(Item {
            path,
            motion: Some(motion),
        });
    }
    Ok(Item {
        path: entry.extract()?,
        motion: None,
    })
}

/// The entries `load_many` was given: a folder's takes (every BVH file and ASF/AMC pair under it,
/// in path order, as `bvhview info DIR` finds them; an AMC without a skeleton is left out), a
/// single file, or a list of paths and (asf, amc) pairs.
fn items_of(paths: &Bound<'_, PyAny>) -> PyResult<Vec<Item>> {
    // A str or os.PathLike is one path: not a sequence of one-letter paths.
    if let Ok(path) = paths.extract::<PathBuf>() {
        if path.is_dir() {
            let found =
                bvhview::batch::collect(&path).map_err(|e| PyOSError::new_err(e.to_string()))?;
            warn_skipped(paths.py(), &found, 1)?;
            return Ok(found
                .items
                .into_iter()
                .filter(|item| !item.is_unpaired_motion())
                .map(|item| Item {
                    path: item.path,
                    motion: item.motion,
                })
                .collect());
        }
        return Ok(vec![Item { path, motion: None }]);
    }
    paths.try_iter()?.map(|entry| item_of(&entry?)).collect()
}

/// Loads every entry (a path, or an (asf, amc) pair) on all cores, in list order; given a
/// folder, every take under it in path order. `errors="raise"` raises the first failure in
/// list order; `errors="return"` puts the exception in the failed entry's place instead.
#[pyfunction]
#[pyo3(signature = (paths, offset_mode="replace", frame_time=None, errors="raise"))]
fn load_many(
    py: Python<'_>,
    paths: &Bound<'_, PyAny>,
    offset_mode: &str,
    frame_time: Option<f64>,
    errors: &str,
) -> PyResult<Vec<Py<PyAny>>> {
    let offset_mode = parse_offset_mode(offset_mode)?;
    let return_errors = match errors {
        "raise" => false,
        "return" => true,
        other => {
            return Err(PyValueError::new_err(format!(
                "errors={other:?}: expected \"raise\" or \"return\""
            )));
        }
    };
    let items = items_of(paths)?;
    let results = py.detach(|| {
        let cores = bvhview::cores();
        // Many files: one core each. Fewer files than cores: each parses on a share of them.
        let threads_per_file = (cores / items.len().max(1)).max(1);
        // Largest first, so that no core is left with a big file at the end while the others
        // wait; the results go back in the order given.
        let size = |item: &Item| {
            std::iter::once(&item.path)
                .chain(&item.motion)
                .map(|p| std::fs::metadata(p).map_or(0, |m| m.len()))
                .sum::<u64>()
        };
        let mut order: Vec<usize> = (0..items.len()).collect();
        order.sort_by_key(|&index| std::cmp::Reverse(size(&items[index])));
        let mut slots: Vec<Option<Result<Loaded, Error>>> =
            (0..items.len()).map(|_| None).collect();
        bvhview::parallel::map_in_order(
            items.len(),
            cores,
            2 * cores,
            |turn| load_item(&items[order[turn]], frame_time, threads_per_file),
            |turn, result| {
                slots[order[turn]] = Some(result);
                true
            },
        );
        slots
            .into_iter()
            .map(|slot| slot.expect("every file was loaded or failed"))
            .collect::<Vec<_>>()
    });
    let mut loaded = Vec::with_capacity(items.len());
    for (item, result) in items.into_iter().zip(results) {
        match result {
            Ok(take) => loaded.push(
                Motion {
                    loaded: take,
                    item,
                    offset_mode,
                }
                .into_pyobject(py)?
                .into_any()
                .unbind(),
            ),
            Err(error) if return_errors => {
                loaded.push(to_python(py, error).into_value(py).into_any())
            }
            Err(error) => return Err(to_python(py, error)),
        }
    }
    Ok(loaded)
}

/// A `UserWarning` for each thing a folder walk skipped (a loop, a folder or file reached again,
/// a link out of the folder, what is not a regular file or cannot be read), the first
/// `SKIPS_SAID` one each, then one with how many more; `stacklevel` as `warnings.warn` takes it.
fn warn_skipped(py: Python<'_>, walk: &bvhview::batch::Walk, stacklevel: u32) -> PyResult<()> {
    if walk.skipped.is_empty() {
        return Ok(());
    }
    let warnings = py.import("warnings")?;
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    for line in walk.skipped_lines() {
        warnings.call_method1("warn", (line, &category, stacklevel))?;
    }
    Ok(())
}

/// A take as `list_takes` gives it: its path and its AMC's (or None), relative to the folder.
type TakePaths = (PathBuf, Option<PathBuf>);

/// Every take under `folder` in path order, as `(path, motion)` relative to it: BVH files and
/// ASF/AMC pairs (`motion` the AMC), an AMC without a skeleton and an ASF without motion too (a
/// compile skips and lists them). The list `compile_dataset(takes=…)` takes pieces of.
#[pyfunction]
fn list_takes(py: Python<'_>, folder: PathBuf) -> PyResult<Vec<TakePaths>> {
    let walk = py
        .detach(|| bvhview::dataset::walk(&folder))
        .map_err(|e| to_python(py, e))?;
    warn_skipped(py, &walk, 1)?;
    let items = walk.items;
    // Paths, not text: a name that is not UTF-8 comes back as Python's os.fsdecode gives it.
    let relative = |p: &Path| p.strip_prefix(&folder).unwrap_or(p).to_path_buf();
    Ok(items
        .iter()
        .map(|item| (relative(&item.path), item.motion.as_deref().map(relative)))
        .collect())
}

/// The native half of `bvhview.compile_dataset` (which adds Parquet): returns (clips, frames,
/// groups, skipped as (path, motion, reason) triples). `takes`: a list of its own (relative
/// paths); `piece`: (index, pieces), the run of the folder's list a Dask worker compiles.
#[pyfunction]
#[pyo3(signature = (folder, out, fps=30.0, rotations="6d", root_relative=false, feet=None,
    contact_height=0.05, contact_speed=0.5, takes=None, piece=None, threads=None, onto=None))]
#[allow(clippy::too_many_arguments)]
fn _compile_dataset(
    py: Python<'_>,
    folder: PathBuf,
    out: PathBuf,
    fps: f64,
    rotations: &str,
    root_relative: bool,
    feet: Option<Vec<String>>,
    contact_height: f32,
    contact_speed: f32,
    takes: Option<Vec<(PathBuf, Option<PathBuf>)>>,
    piece: Option<(usize, usize)>,
    threads: Option<usize>,
    onto: Option<String>,
) -> PyResult<(usize, usize, usize, Vec<(String, Option<String>, String)>)> {
    guard("_compile_dataset", || {
        let rotations = pose::RotationKind::parse(rotations).ok_or_else(|| {
            PyValueError::new_err(format!(
                "rotations={rotations:?}: expected {}",
                pose::RotationKind::NAMES
            ))
        })?;
        let options = bvhview::dataset::Options {
            fps,
            rotations,
            root_relative,
            feet,
            contact_height,
            contact_speed,
            onto: onto
                .map(|onto| {
                    bvhview::retarget::Target::load(&onto, bvhview::input::DEFAULT_MAX_SIZE)
                })
                .transpose()
                .map_err(|e| to_python(py, e))?,
            ..Default::default()
        };
        let threads = threads.unwrap_or_else(bvhview::cores).max(1);
        // A compile of a folder must compile something; a piece may hold only takes that fail.
        let require_clips = takes.is_none() && piece.is_none();
        let interrupt: Mutex<Option<PyErr>> = Mutex::new(None);
        let mut walk = bvhview::batch::Walk::default();
        let result = py.detach(|| {
            let (items, list) = match (&takes, piece) {
                (Some(_), Some(_)) => {
                    return Err(Error::Usage(
                        "takes= and piece= cannot be given together".to_string(),
                    ));
                }
                (Some(pairs), None) => {
                    let items = bvhview::dataset::items_in(&folder, pairs);
                    let list = bvhview::dataset::whole_list(&folder, &items);
                    (items, list)
                }
                (None, Some((index, pieces))) => {
                    let all = bvhview::dataset::takes(&folder)?;
                    bvhview::dataset::piece(&folder, all, index, pieces)?
                }
                (None, None) => {
                    walk = bvhview::dataset::walk(&folder)?;
                    let items = std::mem::take(&mut walk.items);
                    let list = bvhview::dataset::whole_list(&folder, &items);
                    (items, list)
                }
            };
            // Ctrl-C (or SIGTERM, which the package turns into an exception for the call)
            // stops the compile between takes; the exception is raised after.
            let interrupted = |_: &_, _: Option<&str>, _: usize, _: usize| {
                Python::attach(|py| match py.check_signals() {
                    Ok(()) => true,
                    Err(raised) => {
                        *interrupt.lock().unwrap_or_else(PoisonError::into_inner) = Some(raised);
                        false
                    }
                })
            };
            bvhview::dataset::compile(
                &folder,
                items,
                &options,
                threads,
                &out,
                require_clips,
                list,
                interrupted,
            )
        });
        if let Some(raised) = interrupt
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
        {
            return Err(raised);
        }
        // Said from the caller of `bvhview.compile_dataset`.
        warn_skipped(py, &walk, 2)?;
        let summary = result.map_err(|e| to_python(py, e))?;
        let skipped = summary
            .skipped
            .into_iter()
            .map(|s| (s.source.path, s.source.motion, s.error))
            .collect();
        Ok((summary.clips, summary.frames, summary.groups, skipped))
    })
}

/// The native half of `bvhview.merge_datasets`: returns (clips, frames, groups, skipped).
/// `join`: "pieces" (of one compile, byte for byte) or "folders" (any, grouped by topology).
#[pyfunction]
#[pyo3(signature = (pieces, out, join="pieces"))]
fn _merge_datasets(
    py: Python<'_>,
    pieces: Vec<PathBuf>,
    out: PathBuf,
    join: &str,
) -> PyResult<(usize, usize, usize, usize)> {
    guard("_merge_datasets", || {
        let join = match join {
            "pieces" => bvhview::dataset::store::Join::Pieces,
            "folders" => bvhview::dataset::store::Join::Folders,
            other => {
                return Err(PyValueError::new_err(format!(
                    "join={other:?}: expected \"pieces\" or \"folders\""
                )));
            }
        };
        py.detach(|| bvhview::dataset::store::merge(&pieces, &out, join))
            .map(|s| (s.clips, s.frames, s.groups, s.skipped.len()))
            .map_err(|e| to_python(py, e))
    })
}

/// Load BVH and ASF/AMC motion capture into numpy arrays (bvhview's Rust loader and FK).
#[pymodule]
fn _bvhview(module: &Bound<'_, PyModule>) -> PyResult<()> {
    // One-time setup done at import, as a C extension's `import_array()` in its module init:
    // numpy's C API, the numpy crate's shared borrow flags and the owner type of arrays made
    // from Rust vectors (each fetched on first use otherwise), and the core count (which reads
    // the cgroup's CPU limits): some 0.6 ms the first load and arrays would pay otherwise.
    let empty = numpy::PyArray1::<f32>::zeros(module.py(), 0, false);
    drop(empty.try_readwrite());
    Vec::<f32>::new().into_pyarray(module.py());
    bvhview::cores();
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_function(wrap_pyfunction!(load, module)?)?;
    module.add_function(wrap_pyfunction!(load_many, module)?)?;
    module.add_function(wrap_pyfunction!(_from_state, module)?)?;
    module.add_function(wrap_pyfunction!(list_takes, module)?)?;
    module.add_function(wrap_pyfunction!(_compile_dataset, module)?)?;
    module.add_function(wrap_pyfunction!(_merge_datasets, module)?)?;
    module.add_function(wrap_pyfunction!(datasets::_open_dataset, module)?)?;
    module.add_function(wrap_pyfunction!(datasets::_dataset_motion, module)?)?;
    module.add_class::<Motion>()?;
    module.add("ParseError", module.py().get_type::<ParseError>())?;
    Ok(())
}
