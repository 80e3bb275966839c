//! `Motion.retarget`: the take's motion on another skeleton (see the crate's `retarget`).

use crate::{Item, Motion, load_item, to_python};
use bvhview::error::Error;
use bvhview::input::Loaded;
use bvhview::pose::{OffsetMode, Up};
use bvhview::retarget::{self, Map, Ups};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;

/// The target skeleton: a Motion, a built-in skeleton's name (`"smpl22"`) or a file's path.
fn target_of(py: Python<'_>, target: &Bound<'_, PyAny>) -> PyResult<Loaded> {
    if let Ok(motion) = target.cast::<Motion>() {
        return Ok(motion.get().loaded.clone());
    }
    let Ok(path) = target.extract::<PathBuf>() else {
        return Err(PyTypeError::new_err(
            "target: expected a Motion, a built-in skeleton's name (\"smpl22\") or a file's path",
        ));
    };
    if !path.exists()
        && let Some((skeleton, motion)) = retarget::built_in(&path.to_string_lossy())
    {
        return Ok(Loaded {
            skeleton,
            motion,
            warnings: Vec::new(),
            stated_units: None,
        });
    }
    let item = Item { path, motion: None };
    py.detach(|| load_item(&item, None, bvhview::cores()))
        .map_err(|e| to_python(py, e))
}

/// The up axis of a target: its take's, or its rest pose's when it has one frame or none.
fn up_of(target: &Loaded, mode: OffsetMode) -> Up {
    if target.motion.frame_count() > 1 {
        target.stance(mode).up
    } else {
        Up::guess(&target.skeleton)
    }
}

/// `source.retarget(target, names)`: the guessed map overridden by `names` (source joint →
/// target joint; "" leaves a source joint out), checked, then the motion carried over.
pub(crate) fn retarget(
    py: Python<'_>,
    source: &Motion,
    target: &Bound<'_, PyAny>,
    names: Option<HashMap<String, String>>,
) -> PyResult<Motion> {
    let target = target_of(py, target)?;
    let loaded = &source.loaded;
    let work = || -> Result<(bvhview::Skeleton, bvhview::Motion), Error> {
        let mut map = Map::guess(&loaded.skeleton, &target.skeleton);
        if let Some(names) = &names {
            let mut pairs: Vec<(String, String)> =
                names.iter().map(|(s, t)| (s.clone(), t.clone())).collect();
            pairs.sort();
            map.apply(&pairs, &loaded.skeleton, &target.skeleton)?;
        }
        map.check("the source", "the target")?;
        let ups = Ups {
            source: loaded.stance(source.offset_mode).up,
            target: up_of(&target, OffsetMode::Replace),
        };
        retarget::retarget(&loaded.skeleton, &loaded.motion, &target.skeleton, &map, ups)
    };
    let (skeleton, motion) = py.detach(work).map_err(|e| to_python(py, e))?;
    Ok(source.edited(skeleton, motion, false))
}

/// `Motion.retarget_map(target)`: the guessed map as {source joint: target joint}.
pub(crate) fn retarget_map(
    py: Python<'_>,
    source: &Motion,
    target: &Bound<'_, PyAny>,
) -> PyResult<HashMap<String, String>> {
    let target = target_of(py, target)?;
    let map = Map::guess(&source.loaded.skeleton, &target.skeleton);
    Ok(map
        .source_of
        .iter()
        .enumerate()
        .filter_map(|(t, s)| {
            s.map(|s| {
                (
                    source.loaded.skeleton.joints[s].name.clone(),
                    target.skeleton.joints[t].name.clone(),
                )
            })
        })
        .collect())
}
