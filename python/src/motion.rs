//! The `Motion` class: a loaded take (`bvhview::take::Take`), its properties and the methods
//! Python calls, each a thin layer over `arrays`, `edits` and the crate.

use crate::*;

/// A loaded take: the skeleton, the MOTION values, and forward kinematics on them.
///
/// Frozen: nothing changes after loading, so `values` can be a view of the loaded data (no
/// copy) and computations can read it without the GIL.
#[pyclass(frozen, module = "bvhview", name = "Motion")]
pub(crate) struct Motion {
    pub(crate) loaded: Take,
    pub(crate) item: Item,
    pub(crate) offset_mode: OffsetMode,
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

    /// Writes the take as BVH (.bvh) or glTF (.glb binary, .gltf text), as `bvhview convert`
    /// does: for BVH, ASF bone axes are baked into ZYX rotation channels and names with
    /// whitespace or braces are written with `_`; glTF gets one node per joint and End Site and
    /// the take's offset mode. The file takes its name only when complete.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        guard("save", || {
            let extension = take::extension(&path);
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
        })
    }

    /// Frames `start` to `stop` (stop left out; negative counts from the end, as a slice
    /// does), as `bvhview convert --frames` keeps them: a new take.
    #[pyo3(signature = (start=None, stop=None))]
    fn trim(&self, start: Option<isize>, stop: Option<isize>) -> PyResult<Motion> {
        guard("trim", || {
            let count = self.loaded.motion.frame_count() as isize;
            let at = |bound: Option<isize>, default: isize| {
                let bound = bound.unwrap_or(default);
                (if bound < 0 { bound + count } else { bound }).clamp(0, count) as usize
            };
            let (start, stop) = (at(start, 0), at(stop, count));
            let motion = bvhview::edit::trim(&self.loaded.motion, start..stop.max(start));
            Ok(self.edited(self.loaded.skeleton.clone(), motion, true))
        })
    }

    /// The take at `fps` frames per second (any rate from 0.01 to 1000, whole or not; rotations
    /// slerped), as `convert --fps` makes it.
    fn resample(&self, py: Python<'_>, fps: f64) -> PyResult<Motion> {
        guard("resample", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let motion = py
                .detach(|| bvhview::edit::resample(skeleton, motion, fps))
                .map_err(|e| to_python(py, e))?;
            Ok(self.edited(skeleton.clone(), motion, true))
        })
    }

    /// Every length times `factor` (OFFSETs and position channels), as `convert --scale`.
    fn scale(&self, py: Python<'_>, factor: f32) -> PyResult<Motion> {
        guard("scale", || {
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
        })
    }

    /// The mirror image, as `convert --mirror`: left and right joints swap their motion
    /// (reflected across the body's middle) and every name and the skeleton's layout are kept,
    /// so the clip keeps its dataset group; the counterparts as `mirror_names` guesses them,
    /// `names` (joint → its counterpart, or a map file's path as `--mirror-names FILE` reads
    /// it, `[skeleton.FINGERPRINT]` sections too) over the guess for the joints it lists. With
    /// `rename=True`, as `convert --mirror-rename`: each joint reflected where it is and the
    /// names exchanged instead (`names` then gives the new names).
    #[pyo3(signature = (names=None, *, rename=false))]
    fn mirror(
        &self,
        py: Python<'_>,
        names: Option<Bound<'_, PyAny>>,
        rename: bool,
    ) -> PyResult<Motion> {
        guard("mirror", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let names = crate::retarget::map_pairs_of(py, names.as_ref())?;
            let options = bvhview::edit::MirrorOptions {
                rename,
                names: names.for_skeleton(skeleton).into_iter().collect(),
            };
            let (mirrored, motion) = py
                .detach(|| bvhview::edit::mirror(skeleton, motion, &options))
                .map_err(|e| to_python(py, e))?;
            Ok(self.edited(mirrored, motion, true))
        })
    }

    /// The take's motion on another skeleton, as `bvhview retarget` puts it: `target` a Motion,
    /// a built-in skeleton's name ("smpl22") or a file's path; `names` overrides the guessed
    /// map ({source joint: target joint}; "" leaves a source joint out), or is a map file's path
    /// (as `--map FILE` reads it, `[skeleton.FINGERPRINT]` sections too). Raises ValueError
    /// naming the joint when the map cannot stand, and for a body that does not stand on two
    /// legs onto one that does unless `any_body`.
    #[pyo3(signature = (target, names=None, *, any_body=false))]
    fn retarget(
        &self,
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
        names: Option<Bound<'_, PyAny>>,
        any_body: bool,
    ) -> PyResult<Motion> {
        guard("retarget", || {
            crate::retarget::retarget(py, self, target, names.as_ref(), any_body)
        })
    }

    /// The joint map `retarget(target)` would guess: {source joint: target joint}.
    fn retarget_map(
        &self,
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
    ) -> PyResult<std::collections::HashMap<String, String>> {
        guard("retarget_map", || {
            crate::retarget::retarget_map(py, self, target)
        })
    }

    /// The counterparts `mirror()` swaps: each joint whose name marks a side (`LeftArm`,
    /// `L_Arm`, `Arm.L`, CMU's `LHipJoint` and `lhumerus`, Daz's `lThigh`…) and whose
    /// counterpart is in the skeleton, with the counterpart's name.
    #[getter]
    fn mirror_names(&self, py: Python<'_>) -> PyResult<std::collections::HashMap<String, String>> {
        guard("mirror_names", || {
            let joints = &self.loaded.skeleton.joints;
            let partners =
                bvhview::edit::mirror_partners(&self.loaded.skeleton, &Default::default())
                    .map_err(|e| to_python(py, e))?;
            Ok(partners
                .iter()
                .enumerate()
                .filter(|&(j, &k)| k != j && !joints[j].end_site)
                .map(|(j, &k)| (joints[j].name.clone(), joints[k].name.clone()))
                .collect())
        })
    }

    /// The take turned to stand along `axis` ("y" or "z") from its `up_axis`, as `convert --up`.
    fn to_up(&self, py: Python<'_>, axis: &str) -> PyResult<Motion> {
        guard("to_up", || {
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
        })
    }

    /// The travel joint (the root in most files) kept over its first frame's place along the
    /// floor (across its `up_axis`), as `convert --in-place`.
    fn in_place(&self, py: Python<'_>) -> PyResult<Motion> {
        guard("in_place", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let motion = py.detach(|| {
                let up = self.loaded.stance(self.offset_mode).up;
                bvhview::edit::in_place(skeleton, motion, up)
            });
            Ok(self.edited(skeleton.clone(), motion, true))
        })
    }

    /// The take with each planted foot held where it landed, as `convert --lock-feet`: two-bone
    /// IK on thigh and shin during each contact, the foot's orientation and every bone's length
    /// kept.
    fn lock_feet(&self, py: Python<'_>) -> PyResult<Motion> {
        guard("lock_feet", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let motion = py
                .detach(|| {
                    let stance = self.loaded.stance(self.offset_mode);
                    bvhview::edit::lock_feet(
                        skeleton,
                        motion,
                        self.offset_mode,
                        stance.up,
                        f64::from(stance.units.metres),
                        &bvhview::edit::LockFeet::default(),
                    )
                })
                .map_err(|e| to_python(py, e))?
                .0;
            Ok(self.edited(skeleton.clone(), motion, true))
        })
    }

    /// The take with its jitter smoothed, as `convert --smooth HZ`: a zero-phase low-pass at
    /// `hz` (below half the frame rate) on every position channel and every joint's rotation
    /// (a sign-continuous quaternion path, renormalised). ValueError for a cutoff out of range.
    fn smooth(&self, py: Python<'_>, hz: f64) -> PyResult<Motion> {
        guard("smooth", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let motion = py
                .detach(|| bvhview::edit::smooth(skeleton, motion, hz))
                .map_err(|e| to_python(py, e))?;
            Ok(self.edited(skeleton.clone(), motion, true))
        })
    }

    /// The take moved along its `up_axis` so that the lowest point of its soles over the take
    /// (each leg's ankle and what is below it; every joint for a body without two feet), in its
    /// offset mode, is at 0, as `convert --ground`.
    fn ground(&self, py: Python<'_>) -> PyResult<Motion> {
        guard("ground", || {
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let (skeleton, motion) = py
                .detach(|| {
                    let up = self.loaded.stance(self.offset_mode).up;
                    bvhview::edit::ground(skeleton, motion, self.offset_mode, up)
                })
                .map_err(|e| to_python(py, e))?;
            Ok(self.edited(skeleton, motion, true))
        })
    }

    /// A take on `skeleton` (a Motion, a built-in skeleton's name such as "smpl22", or a file's
    /// path) whose joints stand where `positions` (frames × joints × 3: a motion model's or a
    /// pose estimator's output) puts them, as `bvhview solve` makes it: each bone laid along the
    /// data's, the skeleton's lengths kept, the path scaled by the legs. `joints`: the
    /// positions' joint names in order (a list, or a layout's name: "smpl22", the same as
    /// "humanml3d"); 22 joints without it are read in SMPL's order. `up`: the positions' up axis
    /// ("y" or "z") when it is not the skeleton's. `smooth`: a cutoff in Hz for jittery input,
    /// as `smooth()`.
    #[staticmethod]
    #[pyo3(signature = (positions, skeleton, *, joints=None, fps, up=None, smooth=None))]
    #[allow(clippy::too_many_arguments)]
    fn from_positions(
        py: Python<'_>,
        positions: numpy::PyArrayLike3<'_, f64, numpy::AllowTypeChange>,
        skeleton: &Bound<'_, PyAny>,
        joints: Option<Bound<'_, PyAny>>,
        fps: f64,
        up: Option<&str>,
        smooth: Option<f64>,
    ) -> PyResult<Motion> {
        guard("from_positions", || {
            let solved =
                crate::retarget::from_positions(py, positions, skeleton, joints.as_ref(), fps, up)?;
            match smooth {
                Some(hz) => solved.smooth(py, hz),
                None => Ok(solved),
            }
        })
    }

    /// A take on `skeleton` (default "smpl22") from HumanML3D's 263-value feature vectors
    /// (frames × 263, its `new_joint_vecs`), as `bvhview solve --from humanml3d`: the joint
    /// positions its own `recover_from_ric` gives, then `from_positions`. `fps`: 20, as
    /// HumanML3D's.
    #[staticmethod]
    #[pyo3(signature = (vectors, skeleton=None, *, fps=20.0))]
    fn from_humanml3d(
        py: Python<'_>,
        vectors: numpy::PyArrayLike2<'_, f32, numpy::AllowTypeChange>,
        skeleton: Option<Bound<'_, PyAny>>,
        fps: f64,
    ) -> PyResult<Motion> {
        guard("from_humanml3d", || {
            let smpl = pyo3::types::PyString::new(py, "smpl22").into_any();
            let skeleton = skeleton.unwrap_or(smpl);
            crate::retarget::from_humanml3d(py, vectors, &skeleton, fps)
        })
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
        guard("from_arrays", || {
            crate::edits::from_arrays(py, template, rotations, root_translations, fps, kind)
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
        let mut out = AtomicFile::create(path)?;
        out.write_all(text.as_bytes())
            .map_err(|e| Error::output(path, e))?;
        out.commit()
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
        let mut out = AtomicFile::create(path)?;
        out.write_all(&bytes).map_err(|e| Error::output(path, e))?;
        out.commit()
    }
}
