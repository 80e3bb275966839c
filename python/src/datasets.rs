//! Datasets: the folder of takes compiled (`bvhview::dataset`), read back through the crate's
//! hardened reader (`dataset::read`), and arrays in a dataset's layout turned back into a take.

use crate::common::{guard, to_python};
use crate::loaded::Item;
use crate::loaded::Motion;
use bvhview::Error;
use bvhview::dataset::{read, rebuild};
use bvhview::model::pose::{self, OffsetMode};
use bvhview::take::Take;
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::os::fd::IntoRawFd;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// One array of a checked dataset, as Python maps it: (name, file descriptor, dtype, shape). The
/// descriptor is the one the check read through: Python maps it and closes it.
pub(crate) type OpenArray = (String, i32, String, Vec<usize>);

/// A checked dataset as Python maps it: the manifest's JSON, per group its arrays, per group its
/// clips' starts and end.
pub(crate) type OpenDataset = (String, Vec<Vec<OpenArray>>, Vec<Vec<usize>>);

/// A skipped take as Python gets it: its path, its AMC's if any, and why.
pub(crate) type SkippedTake = (String, Option<String>, String);

/// The native half of `bvhview.Dataset`: the dataset at `path` checked whole (names, links,
/// file kinds and sizes, `.npy` headers, clip ranges), as (manifest JSON, per group its arrays
/// open, per group its clips' starts and end).
#[pyfunction]
pub(crate) fn _open_dataset(py: Python<'_>, path: PathBuf) -> PyResult<OpenDataset> {
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

/// The manifest of the dataset at `path` as JSON, the dataset checked by bvhview's reader
/// first: its arrays, or with `features="humanml3d"` HumanML3D's layout.
#[pyfunction]
pub(crate) fn _dataset_manifest(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    guard("_dataset_manifest", || {
        let manifest = py
            .detach(|| read::read_manifest(&path))
            .map_err(|e| to_python(py, e))?;
        serde_json::to_string(&manifest).map_err(|e| PyValueError::new_err(e.to_string()))
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
            None => *members
                .first()
                .ok_or_else(|| PyValueError::new_err(format!("{} has no clips", entry.name)))?,
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
                rebuild::motion_of(
                    &skeleton,
                    &entry.topology,
                    travel,
                    Some(&rest),
                    &arrays,
                    fps,
                )
            })
            .map_err(|e| to_python(py, e))?;
        let mut loaded = Take::new(
            skeleton,
            motion,
            path.join(&entry.skeleton).display().to_string(),
        );
        // The dataset's units, as its manifest says them (metres, or `out_units`): stated, not
        // guessed again from the figure.
        let metres = manifest.options.metres_per_unit;
        loaded.stated_units = Some(bvhview::model::stance::Units::of_metres(metres));
        loaded.units_given = true;
        loaded.stated_up = Some(bvhview::model::pose::Up::Y);
        Ok(Motion {
            loaded,
            item: Item {
                path: path.join(&entry.skeleton),
                motion: None,
            },
            offset_mode: OffsetMode::Replace,
            check: None,
        })
    })
}

/// A `UserWarning` for each thing a folder walk skipped (a loop, a folder or file reached again,
/// a link out of the folder, what is not a regular file or cannot be read), the first
/// `SKIPS_SAID` one each, then one with how many more; `stacklevel` as `warnings.warn` takes it.
pub(crate) fn warn_skipped(
    py: Python<'_>,
    walk: &bvhview::info::batch::Walk,
    stacklevel: u32,
) -> PyResult<()> {
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
pub(crate) type TakePaths = (PathBuf, Option<PathBuf>);

/// Every take under `folder` in path order, as `(path, motion)` relative to it: BVH files and
/// ASF/AMC pairs (`motion` the AMC), an AMC without a skeleton and an ASF without motion too (a
/// compile skips and lists them). The list `compile_dataset(takes=…)` takes pieces of.
#[pyfunction]
pub(crate) fn list_takes(py: Python<'_>, folder: PathBuf) -> PyResult<Vec<TakePaths>> {
    guard("list_takes", || {
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
    })
}

/// The native half of `bvhview.compile_dataset` (which adds Parquet): returns (clips, frames,
/// groups, skipped as (path, motion, reason) triples). `takes`: a list of its own (relative
/// paths); `piece`: (index, pieces), the run of the folder's list a Dask worker compiles.
#[pyfunction]
#[pyo3(signature = (folder, out, fps=None, rotations="6d", root_relative=false, feet=None,
    contact_height=0.05, contact_speed=0.5, takes=None, piece=None, threads=None, onto=None,
    ground=false, quat_continuous=false, names=None, lock_feet=false, features="arrays",
    any_body=false, force=false, units=None, up=None, out_units=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _compile_dataset(
    py: Python<'_>,
    folder: PathBuf,
    out: PathBuf,
    fps: Option<f64>,
    rotations: &str,
    root_relative: bool,
    feet: Option<Vec<String>>,
    contact_height: f32,
    contact_speed: f32,
    takes: Option<Vec<(PathBuf, Option<PathBuf>)>>,
    piece: Option<(usize, usize)>,
    threads: Option<usize>,
    onto: Option<String>,
    ground: bool,
    quat_continuous: bool,
    names: Option<Bound<'_, PyAny>>,
    lock_feet: bool,
    features: &str,
    any_body: bool,
    force: bool,
    units: Option<Bound<'_, PyAny>>,
    up: Option<&str>,
    out_units: Option<Bound<'_, PyAny>>,
) -> PyResult<(usize, usize, usize, Vec<SkippedTake>)> {
    guard("_compile_dataset", || {
        if names.is_some() && onto.is_none() {
            return Err(PyValueError::new_err(
                "names= needs onto=: its pairs name joints of the skeleton every take is put on",
            ));
        }
        let rotations = pose::RotationKind::parse(rotations).ok_or_else(|| {
            PyValueError::new_err(format!(
                "rotations={rotations:?}: expected {}",
                pose::RotationKind::NAMES
            ))
        })?;
        let features = bvhview::dataset::FeatureSet::parse(features).ok_or_else(|| {
            PyValueError::new_err(format!(
                "features={features:?}: expected \"arrays\" or \"humanml3d\""
            ))
        })?;
        let fps = fps.unwrap_or(match features {
            bvhview::dataset::FeatureSet::HumanMl3d => bvhview::humanml3d::FPS,
            bvhview::dataset::FeatureSet::Arrays => bvhview::dataset::Options::default().fps,
        });
        let options = bvhview::dataset::Options {
            fps,
            features,
            rotations,
            root_relative,
            feet,
            contact_height,
            contact_speed,
            ground,
            quat_continuous,
            lock_feet,
            map: crate::retarget::map_pairs_of(py, names.as_ref())?,
            onto: onto
                .map(|onto| bvhview::retarget::Target::load(&onto, bvhview::take::DEFAULT_MAX_SIZE))
                .transpose()
                .map_err(|e| to_python(py, e))?,
            any_body,
            force,
            units: units.as_ref().map(crate::common::parse_units).transpose()?,
            up: up.map(crate::common::parse_up).transpose()?,
            out_units: out_units
                .as_ref()
                .map(crate::common::parse_units)
                .transpose()?,
            ..Default::default()
        };
        let threads = threads.unwrap_or_else(bvhview::plumbing::cores).max(1);
        let interrupt: Mutex<Option<PyErr>> = Mutex::new(None);
        let mut walk = bvhview::info::batch::Walk::default();
        let result = py.detach(|| {
            let (items, list) = match (&takes, piece) {
                (Some(_), Some(_)) => {
                    return Err(Error::usage("takes= and piece= cannot be given together"));
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
            // With `BVHVIEW_PLANT_PAUSE=_compile_dataset` (a test's switch: no test waits on the
            // clock) the first check waits there until a signal comes, so that a test signals
            // the compile at that known point.
            let pause = std::env::var_os("BVHVIEW_PLANT_PAUSE")
                .is_some_and(|point| point == "_compile_dataset");
            let interrupted = |_: &_, _: Option<&Error>, _: usize, _: usize| loop {
                let checked = Python::attach(|py| py.check_signals());
                match checked {
                    Err(raised) => {
                        *interrupt.lock().unwrap_or_else(PoisonError::into_inner) = Some(raised);
                        break false;
                    }
                    Ok(()) if !pause => break true,
                    Ok(()) => std::thread::sleep(std::time::Duration::from_millis(5)),
                }
            };
            bvhview::dataset::compile(&folder, items, &options, threads, &out, list, interrupted)
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
pub(crate) fn _merge_datasets(
    py: Python<'_>,
    pieces: Vec<PathBuf>,
    out: PathBuf,
    join: &str,
) -> PyResult<(usize, usize, usize, usize)> {
    guard("_merge_datasets", || {
        let join = match join {
            "pieces" => bvhview::dataset::merge::Join::Pieces,
            "folders" => bvhview::dataset::merge::Join::Folders,
            other => {
                return Err(PyValueError::new_err(format!(
                    "join={other:?}: expected \"pieces\" or \"folders\""
                )));
            }
        };
        py.detach(|| bvhview::dataset::merge::merge(&pieces, &out, join))
            .map(|s| (s.clips, s.frames, s.groups, s.skipped.len()))
            .map_err(|e| to_python(py, e))
    })
}
