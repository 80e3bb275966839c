//! The `Motion` class: a loaded take (`bvhview::take::Take`), its properties and the arrays it
//! gives, each a thin layer over `arrays` and the crate. The methods that make a new take live
//! in `edits` (and `retarget`), in `#[pymethods]` blocks of their own.

use crate::arrays::row_major;
use crate::common::{Keywords, guard, offset_mode_name, to_python};
use crate::loaded::Motion;
use crate::pickle::State;
use bvhview::Error;
use bvhview::model::pose::{self};
use bvhview::plumbing::AtomicFile;
use glam::{Mat4, Vec3};
use numpy::ndarray::ArrayView2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::IntoPyDict;
use std::path::Path;

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

    /// What the retarget (`retarget`, `Character.dress`) that made this take measured it
    /// against its source, as a dict: `hips` and `shoulders` (each `source_width`, `width`,
    /// `rest_width`, `source_rest_width` in legs' lengths and `turn` in degrees, or None),
    /// `bones_median`, `bones_p99` (degrees), `path` (×, or None), `floor` (legs), `line`
    /// (what `bvhview retarget` prints) and `refusal` (why it would be refused, or None).
    /// None for a take no retarget made; an edit or a pickle drops it.
    #[getter]
    fn retarget_check<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(check) = &self.check else {
            return Ok(None);
        };
        let json = serde_json::to_string(check)
            .map_err(|e| PyValueError::new_err(format!("retarget_check: {e}")))?;
        let report = py.import("json")?.call_method1("loads", (json,))?;
        report.set_item("line", check.line())?;
        report.set_item("refusal", check.refusal())?;
        Ok(Some(report))
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
            .map(|index| bvhview::model::skeleton::export_name(skeleton, index))
            .collect()
    }

    /// The index of the joint named `name` (an End Site as `<parent>_End`), as in
    /// `joint_names`; ValueError when there is none.
    fn index(&self, name: &str) -> PyResult<usize> {
        guard("index", || {
            let skeleton = &self.loaded.skeleton;
            (0..skeleton.joints.len())
                .find(|&index| bvhview::model::skeleton::export_name(skeleton, index) == name)
                .ok_or_else(|| PyValueError::new_err(format!("no joint named {name:?}")))
        })
    }

    /// The indices of joint `index`'s children, in file order; IndexError past the last joint.
    fn children(&self, index: usize) -> PyResult<Vec<usize>> {
        guard("children", || {
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
        guard("offsets", || {
            let joints = &self.loaded.skeleton.joints;
            let offsets: Vec<f32> = joints.iter().flat_map(|j| j.offset.to_array()).collect();
            offsets.into_pyarray(py).reshape([joints.len(), 3])
        })
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
            .iter()
            .map(|warning| warning.spelled(&Keywords))
            .collect()
    }

    /// The MOTION values, frames × channels (float32), read-only. A view of the loaded data, not
    /// a copy: it keeps this Motion alive.
    #[getter]
    fn values<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        guard("values", || {
            let motion = &slf.get().loaded.motion;
            let view =
                ArrayView2::from_shape((motion.frame_count(), motion.channels), &motion.data)
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
        })
    }

    /// The names the CLI's `positions` export gives its points: joints by name, End Sites as
    /// `<parent>_End`; for ASF, the root and each bone's end point named by the bone.
    #[getter]
    fn point_names(&self) -> Vec<String> {
        bvhview::positions::export_points(&self.loaded.skeleton)
            .into_iter()
            .map(|(name, _)| name)
            .collect()
    }

    /// For each of `point_names`, the joint whose position it is (int32):
    /// `positions()[:, point_joints]` is the CLI's export.
    #[getter]
    fn point_joints<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let joints: Vec<i32> = bvhview::positions::export_points(&self.loaded.skeleton)
            .into_iter()
            .map(|(_, joint)| joint as i32)
            .collect();
        joints.into_pyarray(py)
    }

    /// World position of every joint and End Site (see `end_sites`) for the frames selected:
    /// frames × joints × 3, float32. `frames`: None for all, an int, a slice or a sequence of
    /// ints; one int gives joints × 3 (no frame axis, as numpy's `a[i]`). A take without
    /// frames has one: its rest pose.
    #[pyo3(signature = (frames=None))]
    fn positions<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("positions", || {
            let one = Self::one_frame(frames);
            let frames = self.selected_frames(frames)?;
            let values = py
                .detach(|| self.positions_of(&frames))
                .map_err(|e| to_python(py, e))?;
            let joints = self.loaded.skeleton.joints.len();
            let array = values.into_pyarray(py);
            Ok(if one {
                array.reshape([joints, 3])?.into_any()
            } else {
                array.reshape([frames.len(), joints, 3])?.into_any()
            })
        })
    }

    /// Every joint's local transform for the frames selected, as FK multiplies them:
    /// `T(t) · R1 · R2 · R3` (ASF bones `T · C · R · C⁻¹`), frames × joints × 4 × 4, float32,
    /// `[row, column]`; `world_matrices` is their product down the tree. One int for `frames`:
    /// no frame axis.
    #[pyo3(signature = (frames=None))]
    fn local_matrices<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("local_matrices", || {
            let one = Self::one_frame(frames);
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
            let array = values.into_pyarray(py);
            Ok(if one {
                array.reshape([joints, 4, 4])?.into_any()
            } else {
                array.reshape([frames.len(), joints, 4, 4])?.into_any()
            })
        })
    }

    /// Every joint's local rotation for the frames selected (the `R` of `local_matrices`):
    /// `kind="quat"` frames × joints × 4 as (w, x, y, z), w ≥ 0; `"matrix"` × 3 × 3
    /// `[row, column]`; `"6d"` × 6, the matrix's first two columns one after the other (Zhou
    /// et al. 2019);
    /// `"euler"` × 3, the joint's rotation channels in its file order, in degrees (0 where it has
    /// fewer than three). End Sites and joints without rotation channels: the identity. One
    /// int for `frames`: no frame axis.
    #[pyo3(signature = (frames=None, kind="quat"))]
    fn local_rotations<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
        kind: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("local_rotations", || {
            let one = Self::one_frame(frames);
            let frames = self.selected_frames(frames)?;
            let Some(rotation_kind) = pose::RotationKind::parse(kind) else {
                return Err(PyValueError::new_err(format!(
                    "kind={kind:?}: expected {}",
                    pose::RotationKind::NAMES
                )));
            };
            let per_joint = rotation_kind.width();
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let per_frame = skeleton.joints.len() * per_joint;
            let values = py
                .detach(|| {
                    Self::per_frame_floats(
                        &frames,
                        skeleton.joints.len(),
                        per_frame,
                        |frames, out| {
                            pose::write_local_rotations(
                                skeleton,
                                motion,
                                frames,
                                rotation_kind,
                                out,
                            )
                        },
                    )
                })
                .map_err(|e| to_python(py, e))?;
            let joints = self.loaded.skeleton.joints.len();
            let array = values.into_pyarray(py);
            Ok(match (rotation_kind, one) {
                (pose::RotationKind::Matrix, false) => {
                    array.reshape([frames.len(), joints, 3, 3])?.into_any()
                }
                (pose::RotationKind::Matrix, true) => array.reshape([joints, 3, 3])?.into_any(),
                (_, false) => array.reshape([frames.len(), joints, per_joint])?.into_any(),
                (_, true) => array.reshape([joints, per_joint])?.into_any(),
            })
        })
    }

    /// The first root's translation for the frames selected (its OFFSET with its position
    /// channels, in the offset mode), frames × 3, float32 (3 for one int).
    #[pyo3(signature = (frames=None))]
    fn root_translations<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("root_translations", || {
            let one = Self::one_frame(frames);
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
            let array = out.into_pyarray(py);
            Ok(if one {
                array.into_any()
            } else {
                array.reshape([frames.len(), 3])?.into_any()
            })
        })
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
    /// `positions` (one int: joints × 4 × 4).
    #[pyo3(signature = (frames=None))]
    fn world_matrices<'py>(
        &self,
        py: Python<'py>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("world_matrices", || {
            let one = Self::one_frame(frames);
            let frames = self.selected_frames(frames)?;
            let values = py
                .detach(|| self.matrices_of(&frames))
                .map_err(|e| to_python(py, e))?;
            let joints = self.loaded.skeleton.joints.len();
            let array = values.into_pyarray(py);
            Ok(if one {
                array.reshape([joints, 4, 4])?.into_any()
            } else {
                array.reshape([frames.len(), joints, 4, 4])?.into_any()
            })
        })
    }

    /// The MOTION values as a pandas DataFrame: one row per frame (index "frame"), one column
    /// per channel (`channel_names`), float32; `frames` as in `positions`. Needs pandas.
    #[pyo3(signature = (frames=None))]
    fn to_dataframe<'py>(
        slf: &Bound<'py, Self>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("to_dataframe", || {
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
        })
    }

    /// Pickling (multiprocessing, Dask, Ray): the take itself travels, skeleton and values,
    /// not its path, so a worker on another machine needs no copy of the file.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (State,))> {
        guard("__reduce__", || {
            let rebuild = py.import("bvhview._bvhview")?.getattr("_from_state")?;
            Ok((rebuild, (self.state(),)))
        })
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
    pub(crate) fn write_bvh(&self, path: &Path) -> Result<(), Error> {
        // Refused before the file is opened: nothing is written (a ValueError).
        let text = self.loaded.bvh_text()?;
        AtomicFile::write_whole(path, text.as_bytes())
    }

    /// FBX 7.4 binary in centimetres (or `units`), as `Take::save` writes it.
    pub(crate) fn write_fbx(
        &self,
        path: &Path,
        units: Option<bvhview::model::stance::Units>,
    ) -> Result<(), Error> {
        let mut take = self.loaded.clone();
        take.offset_mode = self.offset_mode;
        match units {
            Some(units) => AtomicFile::write_whole(path, &take.fbx_in(units)?.bytes),
            None => take.save(path),
        }
    }

    /// The take as AMASS's `.npz` at `path` ([`bvhview::Take::amass`]).
    pub(crate) fn write_amass(&self, path: &Path) -> Result<(), Error> {
        let mut take = self.loaded.clone();
        take.offset_mode = self.offset_mode;
        take.save(path)
    }

    /// The take scaled from its own units (as its stance reads them) into `units`, which it
    /// then states.
    pub(crate) fn in_units(&self, units: bvhview::model::stance::Units) -> Result<Motion, Error> {
        let own = self.loaded.stance(self.offset_mode).units;
        let factor = (f64::from(own.metres) / f64::from(units.metres)) as f32;
        let (skeleton, motion) =
            bvhview::edit::scale(&self.loaded.skeleton, &self.loaded.motion, factor)?;
        let mut scaled = self.edited(skeleton, motion, false);
        scaled.loaded.stated_units = Some(units);
        scaled.loaded.units_given = true;
        // The same body in other units: an AMASS file's betas and rest pelvis are metres.
        scaled.loaded.body = self.loaded.body.clone();
        Ok(scaled)
    }

    pub(crate) fn write_gltf(
        &self,
        path: &Path,
        container: bvhview::gltf::Container,
    ) -> Result<(), Error> {
        let bytes = bvhview::gltf::to_gltf(
            &self.loaded.skeleton,
            &self.loaded.motion,
            self.offset_mode,
            container,
            false,
        )?;
        AtomicFile::write_whole(path, &bytes)
    }
}
