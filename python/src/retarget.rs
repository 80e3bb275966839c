//! `Motion.retarget`: the take's motion on another skeleton (see the crate's `retarget`).

use crate::{Motion, to_python};
use bvhview::retarget::{Map, Target};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// The target skeleton: a Motion, a built-in skeleton's name (`"smpl22"`) or a file's path.
fn target_of(py: Python<'_>, target: &Bound<'_, PyAny>) -> PyResult<Target> {
    if let Ok(motion) = target.cast::<Motion>() {
        let motion = motion.get();
        let loaded = &motion.loaded;
        let name = motion.item.path.display().to_string();
        return Ok(Target::new(name, loaded.skeleton.clone(), &loaded.motion));
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

/// `source.retarget(target, names, any_body)`: the guessed map overridden by `names` (source
/// joint → target joint; "" leaves a source joint out), checked (a body that does not stand on
/// two legs is refused onto one that does unless `any_body`), then the motion carried over.
pub(crate) fn retarget(
    py: Python<'_>,
    source: &Motion,
    target: &Bound<'_, PyAny>,
    names: Option<HashMap<String, String>>,
    any_body: bool,
) -> PyResult<Motion> {
    let target = target_of(py, target)?;
    let loaded = &source.loaded;
    let mut pairs: Vec<(String, String)> = names.unwrap_or_default().into_iter().collect();
    pairs.sort();
    let name = source.item.path.display().to_string();
    let (skeleton, motion) = py
        .detach(|| {
            if !any_body {
                target.check_body(&name, &loaded.skeleton, &loaded.motion)?;
            }
            target.apply_any_body(
                &name,
                &loaded.skeleton,
                &loaded.motion,
                &pairs,
                bvhview::plumbing::cores(),
            )
        })
        .map_err(|e| to_python(py, e))?;
    Ok(source.edited(skeleton, motion, false))
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
