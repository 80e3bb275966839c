//! `Motion.retarget`: the take's motion on another skeleton (see the crate's `retarget`), and
//! takes solved from joint positions (`Motion.from_positions`, `Motion.from_humanml3d`).

use crate::common::{guard, to_python};
use crate::loaded::Motion;
use bvhview::retarget::{Map, MapPairs, Target};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// The target skeleton: a Motion, a built-in skeleton's name (`"smpl22"`) or a file's path.
pub(crate) fn target_of(py: Python<'_>, target: &Bound<'_, PyAny>) -> PyResult<Target> {
    if let Ok(motion) = target.cast::<Motion>() {
        let motion = motion.get();
        let loaded = &motion.loaded;
        let name = motion.item.path.display().to_string();
        // With the units and up axis its loader was given, over the guess.
        return Ok(Target::of_take(name, loaded));
    }
    let Ok(path) = target.extract::<PathBuf>() else {
        return Err(PyTypeError::new_err(
            "target: expected a Motion, a built-in skeleton's name (\"smpl22\") or a file's path",
        ));
    };
    let name = path.to_string_lossy().into_owned();
    py.detach(|| Target::load(&name, bvhview::take::DEFAULT_MAX_SIZE))
        .map_err(|e| to_python(py, e))
}

/// `names=` as pairs over a guessed map: a dict {source joint: target joint} ("" leaves a source
/// joint out), or a map file's path (TOML or JSON, as `bvhview retarget --map FILE` reads it,
/// with its `[skeleton.FINGERPRINT]` sections).
pub(crate) fn map_pairs_of(py: Python<'_>, names: Option<&Bound<'_, PyAny>>) -> PyResult<MapPairs> {
    let Some(names) = names else {
        return Ok(MapPairs::default());
    };
    if let Ok(dict) = names.extract::<HashMap<String, String>>() {
        let mut pairs: Vec<(String, String)> = dict.into_iter().collect();
        pairs.sort();
        return Ok(MapPairs::from_pairs(pairs));
    }
    let Ok(path) = names.extract::<PathBuf>() else {
        return Err(PyTypeError::new_err(
            "names: expected a dict {source joint: target joint} or a map file's path",
        ));
    };
    let shown = path.display().to_string();
    // A regular file of at most 16 MiB (a FIFO or a device is not a map), as the CLI reads one.
    let text = match std::fs::metadata(&path) {
        Ok(meta) if meta.is_file() && meta.len() <= 16 << 20 => std::fs::read(&path)
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("{shown}: {e}")))?,
        Ok(_) => {
            return Err(PyValueError::new_err(format!(
                "names={shown:?}: not a regular file of at most 16 MiB"
            )));
        }
        Err(e) => {
            return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!(
                "{shown}: {e}"
            )));
        }
    };
    let text = String::from_utf8(text).map_err(|_| {
        PyValueError::new_err(format!(
            "{shown}: not UTF-8 text: a map file is TOML or JSON"
        ))
    })?;
    bvhview::retarget::parse_map_pairs(&text, &shown).map_err(|e| to_python(py, e))
}

/// `source.retarget(target, names, any_body, force)`: the guessed map overridden by `names` (a
/// dict or a map file, [`map_pairs_of`]), checked (a body that does not stand on two legs is
/// refused onto one that does unless `any_body`), the motion carried over, and the result
/// checked against its source as `bvhview retarget` checks it (refused unless `force`).
pub(crate) fn retarget(
    py: Python<'_>,
    source: &Motion,
    target: &Bound<'_, PyAny>,
    names: Option<&Bound<'_, PyAny>>,
    any_body: bool,
    force: bool,
) -> PyResult<Motion> {
    let target = target_of(py, target)?;
    let loaded = &source.loaded;
    let pairs = map_pairs_of(py, names)?.for_skeleton(&loaded.skeleton);
    let name = source.item.path.display().to_string();
    let insist = bvhview::retarget::Insist { any_body, force };
    let put = py
        .detach(|| {
            target.apply_up(
                &name,
                &loaded.skeleton,
                &loaded.motion,
                loaded.stated_up,
                &pairs,
                insist,
                bvhview::plumbing::cores(),
            )
        })
        .map_err(|e| to_python(py, e))?;
    warn_put(py, &name, &target.name, &put.forced, &put.uncarried)?;
    let mut result = source.edited(put.skeleton, put.motion, false);
    // On the target it stands as the target does, in its units: as given for it, or guessed.
    target.state_on(&mut result.loaded);
    result.check = Some(put.check);
    Ok(result)
}

/// Python warnings (`UserWarning`) for what a retarget kept as insisted or could not carry.
pub(crate) fn warn_put(
    py: Python<'_>,
    source_name: &str,
    target_name: &str,
    forced: &Option<String>,
    uncarried: &[String],
) -> PyResult<()> {
    let warn = |text: String| crate::common::warn(py, &text);
    if let Some(why) = forced {
        warn(format!(
            "{source_name} onto {target_name}: kept as force=True asks though {why}"
        ))?;
    }
    for why in uncarried {
        warn(format!("{source_name}: {why}"))?;
    }
    Ok(())
}

/// `Motion.retarget_map(target)`: the guessed map as {source joint: target joint}.
pub(crate) fn retarget_map(
    py: Python<'_>,
    source: &Motion,
    target: &Bound<'_, PyAny>,
) -> PyResult<HashMap<String, String>> {
    let target = target_of(py, target)?;
    let skeleton = &source.loaded.skeleton;
    let map = Map::guess(skeleton, &target.skeleton);
    Ok(map
        .source_of
        .iter()
        .enumerate()
        .filter_map(|(t, s)| {
            let s = (*s)?;
            Some((
                skeleton.joints[s].name.clone(),
                target.skeleton.joints[t].name.clone(),
            ))
        })
        .collect())
}

/// `Motion.from_positions(..., layout=)`: a pose estimator's keypoints (frames × points × 3, or
/// × 4 with a confidence) in `layout`, as `bvhview solve --layout` reads them.
#[allow(clippy::too_many_arguments)]
fn from_keypoints(
    py: Python<'_>,
    positions: numpy::PyArrayLike3<'_, f64, numpy::AllowTypeChange>,
    skeleton: &Bound<'_, PyAny>,
    layout: &str,
    fps: f64,
    up: Option<bvhview::model::pose::UpAxis>,
    smooth: Option<f64>,
    min_confidence: f64,
) -> PyResult<Motion> {
    use bvhview::solve::layouts::{Keypoints, Layout, onto_skeleton, to_smpl};
    use pyo3::exceptions::PyValueError;
    let layout = Layout::parse(layout)
        .map_err(|why| PyValueError::new_err(format!("layout={layout:?}: {why}")))?;
    let shape = positions.as_array().shape().to_vec();
    let values: Vec<f64> = positions.as_array().iter().copied().collect();
    let keypoints = Keypoints::new(layout, &shape, &values, 1.0 / fps, "positions")
        .map_err(|e| to_python(py, e))?;
    let up_given = up.map(|up| up.vector().as_dvec3());
    let placed = to_smpl(&keypoints, min_confidence, up_given, "positions")
        .map_err(|e| to_python(py, e))?;
    let warnings = py.import("warnings")?;
    for line in &placed.said {
        warnings.call_method1("warn", (format!("from_positions: {line}"),))?;
    }
    let target = target_of(py, skeleton)?;
    let (positions, unused) =
        onto_skeleton(&placed.positions, &target.skeleton).map_err(|e| to_python(py, e))?;
    if !unused.is_empty() {
        let text = format!(
            "from_positions: {} has no joint of the role of {}: not used",
            target.name,
            unused.join(", ")
        );
        warnings.call_method1("warn", (text,))?;
    }
    let up = Some(bvhview::model::pose::UpAxis::Y);
    let (motion, _, _) = py
        .detach(|| {
            bvhview::solve::solve_smoothed(&target.skeleton, target.up, &positions, up, smooth)
        })
        .map_err(|e| to_python(py, e))?;
    let name = format!("{} keypoints on {}", layout.label(), target.name);
    Ok(solved_motion(target.skeleton, motion, name))
}

/// A solved take as a `Motion` named `name` (its position channels replace the OFFSETs).
fn solved_motion(skeleton: bvhview::Skeleton, motion: bvhview::Motion, name: String) -> Motion {
    Motion {
        loaded: bvhview::Take::new(skeleton, motion, name.clone()),
        item: crate::loaded::Item {
            path: PathBuf::from(name),
            motion: None,
        },
        offset_mode: bvhview::model::pose::OffsetMode::Replace,
        check: None,
    }
}

/// `Motion.from_positions`: joint positions (frames × joints × 3) as a take on a skeleton.
#[allow(clippy::too_many_arguments)]
pub(crate) fn from_positions(
    py: Python<'_>,
    positions: numpy::PyArrayLike3<'_, f64, numpy::AllowTypeChange>,
    skeleton: &Bound<'_, PyAny>,
    joints: Option<&Bound<'_, PyAny>>,
    fps: f64,
    up: Option<&str>,
    smooth: Option<f64>,
    layout: Option<&str>,
    min_confidence: f64,
) -> PyResult<Motion> {
    use pyo3::exceptions::PyValueError;
    if !(fps > 0.0 && fps.is_finite() && fps <= 1000.0) {
        return Err(PyValueError::new_err(format!(
            "fps={fps}: expected frames per second from above 0 to 1000"
        )));
    }
    let up = up.map(crate::common::parse_up).transpose()?;
    if let Some(name) = layout {
        return from_keypoints(py, positions, skeleton, name, fps, up, smooth, min_confidence);
    }
    let shape = positions.as_array().shape().to_vec();
    if shape.len() != 3 || shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyValueError::new_err(format!(
            "positions of shape {shape:?}: expected frames × joints × 3"
        )));
    }
    let names: Vec<String> = match joints {
        None if shape[1] == 22 => bvhview::solve::joint_names("smpl22"),
        None => {
            return Err(PyValueError::new_err(format!(
                "{} joints a frame: name them with joints= (a list of names, or \"smpl22\")",
                shape[1]
            )));
        }
        Some(given) => match given.extract::<String>() {
            Ok(spec) => bvhview::solve::joint_names(&spec),
            Err(_) => given.extract::<Vec<String>>().map_err(|_| {
                PyTypeError::new_err("joints: expected a list of names or a layout's name")
            })?,
        },
    };
    if names.len() != shape[1] {
        return Err(PyValueError::new_err(format!(
            "positions have {} joints a frame, and joints= names {}",
            shape[1],
            names.len()
        )));
    }
    let values = positions.as_array();
    let points: Vec<glam::DVec3> = values
        .outer_iter()
        .flat_map(|frame| {
            frame
                .outer_iter()
                .map(|p| glam::DVec3::new(p[0], p[1], p[2]))
                .collect::<Vec<_>>()
        })
        .collect();
    let target = target_of(py, skeleton)?;
    let positions =
        bvhview::solve::Positions::new(names, points, 1.0 / fps).map_err(|e| to_python(py, e))?;
    // Measured on what is given back: after `smooth`, as `bvhview solve --smooth` measures.
    let (motion, solved, worse) = py
        .detach(|| {
            bvhview::solve::solve_smoothed(&target.skeleton, target.up, &positions, up, smooth)
        })
        .map_err(|e| to_python(py, e))?;
    // What was not used is said, as the CLI says it: a misspelt name leaves a joint at rest.
    let warnings = py.import("warnings")?;
    if !solved.unmatched.is_empty() {
        let text = format!(
            "from_positions: not joints of {}, left out: {}",
            target.name,
            solved.unmatched.join(", ")
        );
        warnings.call_method1("warn", (text,))?;
    }
    for note in &solved.notes {
        warnings.call_method1("warn", (format!("from_positions: {note}"),))?;
    }
    if let Some(off) = solved.off_the_data_line(&target.skeleton) {
        let why = match smooth {
            Some(_) => "the skeleton's bones are not the data's, or smooth= moved them",
            None => "the skeleton's bones are not the data's",
        };
        let text = format!("from_positions: {why}; off the data (skeleton units): {off}");
        warnings.call_method1("warn", (text,))?;
    }
    if let Some(worse) = worse {
        warnings.call_method1(
            "warn",
            (format!("from_positions: smooth= made worse: {worse}"),),
        )?;
    }
    let name = format!("positions on {}", target.name);
    Ok(solved_motion(target.skeleton, motion, name))
}

/// `Motion.from_humanml3d`: HumanML3D's feature vectors (frames × 263) recovered to joint
/// positions as its `recover_from_ric` does, then solved onto a skeleton.
pub(crate) fn from_humanml3d(
    py: Python<'_>,
    vectors: numpy::PyArrayLike2<'_, f32, numpy::AllowTypeChange>,
    skeleton: &Bound<'_, PyAny>,
    fps: f64,
) -> PyResult<Motion> {
    let array = vectors.as_array();
    let shape = array.shape().to_vec();
    if shape[1] != bvhview::humanml3d::WIDTH || shape[0] == 0 {
        return Err(PyValueError::new_err(format!(
            "vectors of shape {shape:?}: expected frames × {}",
            bvhview::humanml3d::WIDTH
        )));
    }
    let values: Vec<f32> = array.iter().copied().collect();
    let points = bvhview::humanml3d::recover_from_ric(&values).map_err(|e| to_python(py, e))?;
    let positions: Vec<f64> = points.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let frames = shape[0];
    let array = numpy::ndarray::Array3::from_shape_vec((frames, 22, 3), positions)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let array = numpy::PyArray3::from_owned_array(py, array);
    let like: numpy::PyArrayLike3<'_, f64, numpy::AllowTypeChange> = array.extract()?;
    from_positions(py, like, skeleton, None, fps, None, None, None, 0.3)
}

/// HumanML3D's vectors and the positions they stand for, as numpy arrays.
type VectorsAndJoints<'py> = (
    Bound<'py, numpy::PyArray2<f32>>,
    Bound<'py, numpy::PyArray3<f32>>,
);

/// `bvhview.humanml3d_features`: joint positions (frames × 22 × 3, SMPL's order, metres, y up,
/// 20 fps) as HumanML3D's pipeline turns them into its vectors: (vectors (frames − 1) × 263,
/// the positions they stand for (frames − 1) × 22 × 3), float32.
#[pyfunction]
pub(crate) fn humanml3d_features<'py>(
    py: Python<'py>,
    positions: numpy::PyArrayLike3<'py, f64, numpy::AllowTypeChange>,
) -> PyResult<VectorsAndJoints<'py>> {
    guard("humanml3d_features", || {
        let array = positions.as_array();
        let shape = array.shape().to_vec();
        if shape[1] != bvhview::humanml3d::JOINTS || shape[2] != 3 {
            return Err(PyValueError::new_err(format!(
                "positions of shape {shape:?}: expected frames × 22 × 3 (SMPL's joints)"
            )));
        }
        let points: Vec<glam::DVec3> = array
            .as_standard_layout()
            .as_slice()
            .expect("a standard layout")
            .chunks_exact(3)
            .map(|p| glam::DVec3::new(p[0], p[1], p[2]))
            .collect();
        let features = py
            .detach(|| bvhview::humanml3d::features(&points))
            .map_err(|e| to_python(py, e))?;
        let rows = features.frames();
        let vectors = numpy::ndarray::Array2::from_shape_vec(
            (rows, bvhview::humanml3d::WIDTH),
            features.vectors,
        )
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let joints = numpy::ndarray::Array3::from_shape_vec(
            (rows, bvhview::humanml3d::JOINTS, 3),
            features.joints,
        )
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok((
            numpy::PyArray2::from_owned_array(py, vectors),
            numpy::PyArray3::from_owned_array(py, joints),
        ))
    })
}

#[pymethods]
impl Motion {
    /// The take's motion on another skeleton, as `bvhview retarget` puts it: `target` a Motion,
    /// a built-in skeleton's name ("smpl22") or a file's path; `names` overrides the guessed
    /// map ({source joint: target joint}; "" leaves a source joint out), or is a map file's path
    /// (as `--map FILE` reads it, `[skeleton.FINGERPRINT]` sections too). Raises ValueError
    /// naming the joint when the map cannot stand, for a body that does not stand on two
    /// legs onto one that does unless `any_body`, and for a result whose check against its
    /// source finds a side crossed or a width collapsed unless `force`.
    #[pyo3(signature = (target, names=None, *, any_body=false, force=false))]
    fn retarget(
        &self,
        py: Python<'_>,
        target: &Bound<'_, PyAny>,
        names: Option<Bound<'_, PyAny>>,
        any_body: bool,
        force: bool,
    ) -> PyResult<Motion> {
        guard("retarget", || {
            crate::retarget::retarget(py, self, target, names.as_ref(), any_body, force)
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

    /// A take on `skeleton` (a Motion, a built-in skeleton's name such as "smpl22", or a file's
    /// path) whose joints stand where `positions` (frames × joints × 3: a motion model's or a
    /// pose estimator's output) puts them, as `bvhview solve` makes it: each bone laid along the
    /// data's, the skeleton's lengths kept, the path scaled by the legs. `joints`: the
    /// positions' joint names in order (a list, or a layout's name: "smpl22", the same as
    /// "humanml3d"); 22 joints without it are read in SMPL's order. `up`: the positions' up axis
    /// ("y" or "z") when it is not the skeleton's. `smooth`: a cutoff in Hz for jittery input,
    /// as `smooth()`. `layout`: the positions are a pose estimator's keypoints in this layout
    /// ("h36m17", "coco17", "mediapipe33", "body25", "smpl24"; frames × points × 3, or × 4 with
    /// a confidence), as `bvhview solve --layout` reads them; points under `min_confidence`
    /// count as missing and are filled from the frames around.
    #[staticmethod]
    #[pyo3(signature = (positions, skeleton, *, joints=None, fps, up=None, smooth=None, layout=None, min_confidence=0.3))]
    #[allow(clippy::too_many_arguments)]
    fn from_positions(
        py: Python<'_>,
        positions: numpy::PyArrayLike3<'_, f64, numpy::AllowTypeChange>,
        skeleton: &Bound<'_, PyAny>,
        joints: Option<Bound<'_, PyAny>>,
        fps: f64,
        up: Option<&str>,
        smooth: Option<f64>,
        layout: Option<&str>,
        min_confidence: f64,
    ) -> PyResult<Motion> {
        guard("from_positions", || {
            crate::retarget::from_positions(
                py,
                positions,
                skeleton,
                joints.as_ref(),
                fps,
                up,
                smooth,
                layout,
                min_confidence,
            )
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
}
