//! Datasets: the folder of takes compiled (`bvhview::dataset`), read back through the crate's
//! hardened reader (`dataset::read`), and arrays in a dataset's layout turned back into a take.

use crate::{Item, Motion, guard, to_python};
use bvhview::dataset::{read, rebuild};
use bvhview::input::Loaded;
use bvhview::pose::{self, OffsetMode};
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::os::fd::IntoRawFd;
use std::path::PathBuf;

/// One array of a checked dataset, as Python maps it: (name, file descriptor, dtype, shape). The
/// descriptor is the one the check read through: Python maps it and closes it.
type OpenArray = (String, i32, String, Vec<usize>);

/// The native half of `bvhview.Dataset`: the dataset at `path` checked whole (names, links,
/// file kinds and sizes, `.npy` headers, clip ranges), as (manifest JSON, per group its arrays
/// open, per group its clips' starts and end).
#[pyfunction]
pub(crate) fn _open_dataset(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(String, Vec<Vec<OpenArray>>, Vec<Vec<usize>>)> {
    guard("_open_dataset", || {
        let opened = py
            .detach(|| read::open(&path))
            .map_err(|e| to_python(py, e))?;
        let text = serde_json::to_string(&opened.manifest)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let mut groups = Vec::with_capacity(opened.groups.len());
        let mut offsets = Vec::with_capacity(opened.groups.len());
        for (files, entry) in opened.groups.into_iter().zip(&opened.manifest.groups) {
            let arrays = files
                .arrays
                .into_iter()
                .zip(&entry.arrays)
                .map(|(array, listed)| {
                    (
                        listed.name.clone(),
                        array.file.into_raw_fd(),
                        array.dtype,
                        array.shape,
                    )
                })
                .collect();
            groups.push(arrays);
            offsets.push(files.offsets);
        }
        Ok((text, groups, offsets))
    })
}

/// The native half of `Dataset.to_motion`: arrays in the layout of group `group` of the dataset
/// at `path` as a take on the group's skeleton (`clip`: whose bone lengths and travel joint; by
/// default the group's first clip's).
#[pyfunction]
#[pyo3(signature = (path, group, rotations, kind, translations=None, root_translations=None,
    clip=None, fps=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _dataset_motion(
    py: Python<'_>,
    path: PathBuf,
    group: usize,
    rotations: numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>,
    kind: &str,
    translations: Option<numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>>,
    root_translations: Option<numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>>,
    clip: Option<usize>,
    fps: Option<f64>,
) -> PyResult<Motion> {
    guard("_dataset_motion", || {
        let kind = pose::RotationKind::parse(kind).ok_or_else(|| {
            PyValueError::new_err(format!(
                "kind={kind:?}: expected {}",
                pose::RotationKind::NAMES
            ))
        })?;
        let opened = py
            .detach(|| read::open(&path))
            .map_err(|e| to_python(py, e))?;
        let manifest = &opened.manifest;
        let entry = manifest.groups.get(group).ok_or_else(|| {
            PyValueError::new_err(format!(
                "group {group}: the dataset has {}",
                manifest.groups.len()
            ))
        })?;
        let members: Vec<usize> = (0..manifest.clips.len())
            .filter(|&i| manifest.clips[i].group == group)
            .collect();
        let clip = match clip {
            Some(clip) => clip,
            None => *members.first().ok_or_else(|| {
                PyValueError::new_err(format!("{} has no clips", entry.name))
            })?,
        };
        let index = members.iter().position(|&i| i == clip).ok_or_else(|| {
            PyValueError::new_err(format!("clip {clip} is not a clip of {}", entry.name))
        })?;
        let shape = rotations.shape().to_vec();
        let frames = shape.first().copied().unwrap_or(0);
        let flat = |array: &numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>| -> Vec<f32> {
            array.as_array().iter().copied().collect()
        };
        let rotations = flat(&rotations);
        let translations = translations.as_ref().map(flat);
        let root_translations = root_translations.as_ref().map(flat);
        let rest_file = &opened.groups[group].arrays[7];
        let rest: Vec<f32> = rest_file
            .read_rows(index..index + 1)
            .map_err(|e| to_python(py, e))?
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let about = &manifest.clips[clip].about;
        let travel = entry
            .topology
            .joints
            .iter()
            .position(|name| *name == about.travel_joint)
            .unwrap_or(0);
        let fps = fps.unwrap_or(manifest.options.fps);
        let skeleton = opened.skeleton(group).map_err(|e| to_python(py, e))?;
        let arrays = rebuild::Arrays {
            frames,
            rotations: &rotations,
            kind,
            translations: translations.as_deref(),
            root_translations: root_translations.as_deref(),
        };
        let (skeleton, motion) = py
            .detach(|| {
                rebuild::motion_of(&skeleton, &entry.topology, travel, Some(&rest), &arrays, fps)
            })
            .map_err(|e| to_python(py, e))?;
        Ok(Motion {
            loaded: Loaded {
                skeleton,
                motion,
                warnings: Vec::new(),
                stated_units: None,
            },
            item: Item {
                path: path.join(&entry.skeleton),
                motion: None,
            },
            offset_mode: OffsetMode::Replace,
        })
    })
}
