//! `Motion`'s methods that make a new take: `save`, the edits (the crate's `edit` results
//! wrapped as a `Motion`), and `Motion.from_arrays` (a take built from arrays on a template's
//! skeleton).

use crate::common::{guard, to_python};
use crate::loaded::Item;
use crate::loaded::Motion;
use bvhview::model::pose::{self, OffsetMode};
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

impl Motion {
    /// A new take from this one's edit: the same path, offset mode and loader warnings;
    /// `same_lengths`: whether units an ASF stated still hold.
    pub(crate) fn edited(
        &self,
        skeleton: bvhview::Skeleton,
        motion: bvhview::Motion,
        same_lengths: bool,
    ) -> Motion {
        Motion {
            loaded: self.loaded.edited(skeleton, motion, same_lengths),
            item: Item {
                path: self.item.path.clone(),
                motion: self.item.motion.clone(),
            },
            offset_mode: self.offset_mode,
            check: None,
        }
    }
}

/// Whether keyword `name` asks for its one value `only` (`None`: not asked); any other value
/// is refused by name.
fn the_one(name: &str, value: Option<&str>, only: &str) -> PyResult<bool> {
    match value {
        None => Ok(false),
        Some(value) if value == only => Ok(true),
        Some(other) => Err(PyValueError::new_err(format!(
            "{name}={other:?}: expected {only:?}"
        ))),
    }
}

#[pymethods]
impl Motion {
    /// Writes the take as BVH (.bvh), glTF (.glb binary, .gltf text), FBX (.fbx) or AMASS's
    /// .npz (a take on a SMPL-family skeleton: SMPL, SMPL-H or SMPL-X parameters, in metres,
    /// Z up), as `bvhview convert` does: for BVH, ASF bone axes are baked into ZYX rotation channels and
    /// names with whitespace or braces are written with `_`; glTF and FBX get one node per
    /// joint and End Site and the take's offset mode. `units` ("mm", "cm", "m", "in", "ft" or
    /// metres per unit) writes the take in those units, scaled from its own (`units`); an FBX
    /// states them (centimetres without). The file takes its name only when complete.
    #[pyo3(signature = (path, *, units=None))]
    fn save(&self, py: Python<'_>, path: PathBuf, units: Option<Bound<'_, PyAny>>) -> PyResult<()> {
        guard("save", || {
            let units = units.as_ref().map(crate::common::parse_units).transpose()?;
            let extension = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            let container = match extension.as_str() {
                "bvh" | "fbx" | "npz" => None,
                "glb" => Some(bvhview::gltf::Container::Glb),
                "gltf" => Some(bvhview::gltf::Container::Gltf),
                _ => {
                    return Err(PyValueError::new_err(format!(
                        "{}: save writes .bvh, .glb, .gltf, .fbx or .npz files, not '{extension}'",
                        path.display()
                    )));
                }
            };
            py.detach(|| {
                let scaled;
                let take = match units {
                    Some(units) => {
                        scaled = self.in_units(units)?;
                        &scaled
                    }
                    None => self,
                };
                match container {
                    None if extension == "fbx" => take.write_fbx(&path, units),
                    None if extension == "npz" => take.write_amass(&path),
                    None => take.write_bvh(&path),
                    Some(container) => take.write_gltf(&path, container),
                }
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

    /// The take in a canonical layout, as `convert --channels root6,rot3 --order ORDER
    /// --strip-prefix`: `channels="root6,rot3"` gives every root three positions then three
    /// rotations and every other joint three rotations (a still position channel below the
    /// root goes into the OFFSET; a moving one is refused by name); `order` ("ZYX", "XYZ", any
    /// of the six) splits every joint's rotation once into that order; `strip_prefix=True`
    /// drops a namespace (`mixamorig:`) and a prefix every joint shares; `names` (a built-in
    /// skeleton such as "smpl22", or a file) gives each joint the reading of the body maps onto
    /// that skeleton its joint's name; `rest="tpose"` first resets the rest pose to a T-pose
    /// by the reading of the body (`convert --rest tpose`). World positions are kept; what
    /// changed is said as warnings.
    #[pyo3(signature = (*, channels=None, order=None, strip_prefix=false, names=None, rest=None))]
    #[allow(clippy::too_many_arguments)]
    fn canonical(
        &self,
        py: Python<'_>,
        channels: Option<&str>,
        order: Option<&str>,
        strip_prefix: bool,
        names: Option<String>,
        rest: Option<&str>,
    ) -> PyResult<Motion> {
        guard("canonical", || {
            let tpose = the_one("rest", rest, "tpose")?;
            let root6_rot3 = the_one("channels", channels, "root6,rot3")?;
            let order = match order {
                None => None,
                Some(letters) => {
                    let axes: Vec<usize> = letters
                        .to_ascii_lowercase()
                        .bytes()
                        .filter_map(|c| match c {
                            b'x' => Some(0),
                            b'y' => Some(1),
                            b'z' => Some(2),
                            _ => None,
                        })
                        .collect();
                    let order = (axes.len() == 3 && letters.len() == 3)
                        .then(|| {
                            bvhview::model::skeleton::RotationOrder::from_axes([
                                axes[0], axes[1], axes[2],
                            ])
                        })
                        .flatten();
                    Some(order.ok_or_else(|| {
                        PyValueError::new_err(format!(
                            "order={letters:?}: expected one of ZYX, YZX, ZXY, XZY, YXZ, XYZ"
                        ))
                    })?)
                }
            };
            let wanted = bvhview::edit::Canonical {
                root6_rot3,
                order,
                strip_prefix,
            };
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let (skeleton, motion, said) = py
                .detach(|| {
                    let (mut mode, mut said) = (self.offset_mode, Vec::new());
                    let rested;
                    let (skeleton, motion) = if tpose {
                        let up = self.loaded.stance(mode).up;
                        let (s, m, words) =
                            bvhview::edit::rest_tpose(skeleton, motion, mode, up)?;
                        said.extend(words);
                        mode = bvhview::model::pose::OffsetMode::Replace;
                        rested = (s, m);
                        (&rested.0, &rested.1)
                    } else {
                        (skeleton, motion)
                    };
                    let (skeleton, motion, more) =
                        bvhview::edit::canonical(skeleton, motion, mode, &wanted)?;
                    said.extend(more);
                    let Some(family) = &names else {
                        return Ok((skeleton, motion, said));
                    };
                    let family =
                        bvhview::retarget::Target::load(family, bvhview::take::DEFAULT_MAX_SIZE)?;
                    let (named, more) =
                        bvhview::retarget::names_of_family(&skeleton, &family.skeleton)?;
                    said.extend(more);
                    Ok::<_, bvhview::Error>((named, motion, said))
                })
                .map_err(|e| to_python(py, e))?;
            for line in said {
                crate::common::warn(py, &format!("{}: {line}", self.item.path.display()))?;
            }
            let mut edited = self.edited(skeleton, motion, true);
            if root6_rot3 || tpose {
                edited.offset_mode = bvhview::model::pose::OffsetMode::Replace;
            }
            Ok(edited)
        })
    }

    /// The take turned to stand along `axis` ("y", "z", "x", "-y", "-z" or "-x") from its
    /// `up_axis`, as `convert --out-up`.
    fn to_up(&self, py: Python<'_>, axis: &str) -> PyResult<Motion> {
        guard("to_up", || {
            let target: pose::UpAxis = axis.parse().map_err(|_| {
                PyValueError::new_err(format!(
                    "axis={axis:?}: expected \"y\", \"z\", \"x\", \"-y\", \"-z\" or \"-x\""
                ))
            })?;
            let (skeleton, motion) = (&self.loaded.skeleton, &self.loaded.motion);
            let (skeleton, motion) = py
                .detach(|| {
                    let up = self.loaded.stance(self.offset_mode).up;
                    bvhview::edit::reorient(skeleton, motion, up, target)
                })
                .map_err(|e| to_python(py, e))?;
            let mut turned = self.edited(skeleton, motion, true);
            // Turned, it stands along the axis asked for (an up axis given before is no longer;
            // one the stances do not stand along is guessed again).
            turned.loaded.stated_up = turned
                .loaded
                .stated_up
                .and_then(|_| target.standing());
            Ok(turned)
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
    pub(crate) fn smooth(&self, py: Python<'_>, hz: f64) -> PyResult<Motion> {
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

    /// The take in other units, `units` ("mm", "cm", "m", "in", "ft" or metres per unit): every
    /// length scaled from its own (`units`, as guessed or given), as `convert --out-units`; its
    /// `positions()` then come out in them.
    #[pyo3(name = "in_units")]
    fn to_units(&self, py: Python<'_>, units: Bound<'_, PyAny>) -> PyResult<Motion> {
        guard("in_units", || {
            let units = crate::common::parse_units(&units)?;
            py.detach(|| self.in_units(units))
                .map_err(|e| to_python(py, e))
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
            let build = || -> Vec<f32> {
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
        })
    }
}
