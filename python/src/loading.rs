//! Loading takes into `Motion`s: what to load (a file, or an ASF with its AMC), which take of a
//! file that holds several, and `load` / `load_many`.

use crate::common::{guard, parse_offset_mode, planted_pause_without_the_gil, to_python};
use crate::datasets::warn_skipped;
use crate::loaded::{Item, Motion};
use bvhview::Error;
use bvhview::take::{self, Take};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::io;
use std::path::PathBuf;

/// Loads one item with the crate's checks, on `threads` threads. A folder is refused as the OS
/// refuses to read one, so that Python sees an `IsADirectoryError`.
pub(crate) fn load_item(
    item: &Item,
    frame_time: Option<f64>,
    threads: usize,
) -> Result<Take, Error> {
    for path in std::iter::once(&item.path).chain(&item.motion) {
        if path.is_dir() {
            return Err(Error::io(path, io::ErrorKind::IsADirectory.into()));
        }
    }
    open_options(item, frame_time, threads).open(&item.path)
}

/// How `load` opens `item`: its AMC, `frame_time` over the file's, on `threads` threads.
fn open_options(item: &Item, frame_time: Option<f64>, threads: usize) -> take::OpenOptions {
    let mut options = take::OpenOptions::new().threads(threads);
    if let Some(amc) = &item.motion {
        options = options.motion(amc);
    }
    if let Some(seconds) = frame_time {
        options = options.frame_time(seconds);
    }
    options
}

/// `take=` of `load`: a take's name, or its index (as `bvhview info FILE` lists them).
pub(crate) struct TakeChoice(pub(crate) String);

impl<'py> FromPyObject<'_, 'py> for TakeChoice {
    type Error = PyErr;

    fn extract(value: Borrowed<'_, 'py, PyAny>) -> PyResult<TakeChoice> {
        if let Ok(index) = value.extract::<u64>() {
            return Ok(TakeChoice(index.to_string()));
        }
        value
            .extract::<String>()
            .map(TakeChoice)
            .map_err(|_| PyValueError::new_err("take=: expected a take's name or its index"))
    }
}

/// Loads a take: a .bvh, .fbx, .gltf, .glb or AMASS .npz file, or an .asf skeleton with `motion` its .amc
/// take (an .asf alone gives the rest pose). `offset_mode`: "replace" (default) or "add";
/// `frame_time` overrides the file's (AMC files have none: 1/120 s is the default); `take`
/// picks one take of an FBX or glTF file that holds several, by name or index (default: the
/// first); `units` ("mm", "cm", "m", "in", "ft" or metres per unit) says what the lengths are
/// in, over the guess (`up_axis`/`units` then say so; every measure in metres takes them);
/// `body_model` is the user's SMPL-family model file (or a folder with one per gender) an
/// AMASS file's body is read with: the joints of the file's betas.
#[pyfunction]
#[pyo3(signature = (path, motion=None, offset_mode="replace", frame_time=None, *, take=None, units=None, up=None, body_model=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn load(
    py: Python<'_>,
    path: PathBuf,
    motion: Option<PathBuf>,
    offset_mode: &str,
    frame_time: Option<f64>,
    take: Option<TakeChoice>,
    units: Option<Bound<'_, PyAny>>,
    up: Option<&str>,
    body_model: Option<PathBuf>,
) -> PyResult<Motion> {
    guard("load", || {
        let offset_mode = parse_offset_mode(offset_mode)?;
        let units = units.as_ref().map(crate::common::parse_units).transpose()?;
        let up = up.map(crate::common::parse_up).transpose()?;
        let item = Item { path, motion };
        let mut loaded = py
            .detach(|| {
                planted_pause_without_the_gil("load")?;
                match (&take, &body_model) {
                    (None, None) => load_item(&item, frame_time, bvhview::plumbing::cores()),
                    (None, Some(model)) => {
                        if item.path.is_dir() {
                            return Err(Error::io(&item.path, io::ErrorKind::IsADirectory.into()));
                        }
                        open_options(&item, frame_time, bvhview::plumbing::cores())
                            .body_model(model)
                            .open(&item.path)
                    }
                    (Some(take), _) => {
                        if item.path.is_dir() {
                            return Err(Error::io(&item.path, io::ErrorKind::IsADirectory.into()));
                        }
                        let mut options = open_options(&item, frame_time, bvhview::plumbing::cores())
                            .take(take.0.as_str());
                        if let Some(model) = &body_model {
                            options = options.body_model(model);
                        }
                        options.open(&item.path)
                    }
                }
            })
            .map_err(|e| to_python(py, e))?;
        loaded.given(units, up).map_err(|e| to_python(py, e))?;
        Ok(Motion {
            loaded,
            item,
            offset_mode,
            check: None,
        })
    })
}

/// One entry of `load_many`: a path, or an (asf, amc) pair.
pub(crate) fn item_of(entry: &Bound<'_, PyAny>) -> PyResult<Item> {
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
pub(crate) fn items_of(paths: &Bound<'_, PyAny>) -> PyResult<Vec<Item>> {
    // A str or os.PathLike is one path: not a sequence of one-letter paths.
    if let Ok(path) = paths.extract::<PathBuf>() {
        if path.is_dir() {
            let found = bvhview::info::batch::collect(&path)
                .map_err(|e| PyOSError::new_err(e.to_string()))?;
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
/// `units` and `up` say what every take is, as `load`'s do.
#[pyfunction]
#[pyo3(signature = (paths, offset_mode="replace", frame_time=None, errors="raise", *, units=None, up=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn load_many(
    py: Python<'_>,
    paths: &Bound<'_, PyAny>,
    offset_mode: &str,
    frame_time: Option<f64>,
    errors: &str,
    units: Option<Bound<'_, PyAny>>,
    up: Option<&str>,
) -> PyResult<Vec<Py<PyAny>>> {
    guard("load_many", || {
        let offset_mode = parse_offset_mode(offset_mode)?;
        let units = units.as_ref().map(crate::common::parse_units).transpose()?;
        let up = up.map(crate::common::parse_up).transpose()?;
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
            let cores = bvhview::plumbing::cores();
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
            let mut slots: Vec<Option<Result<Take, Error>>> =
                (0..items.len()).map(|_| None).collect();
            bvhview::plumbing::map_in_order(
                items.len(),
                cores,
                2 * cores,
                |turn| {
                    let mut take = load_item(&items[order[turn]], frame_time, threads_per_file)?;
                    take.given(units, up)?;
                    Ok(take)
                },
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
                        check: None,
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
    })
}

/// How plausible `take` is, as `bvhview metrics` measures it: a dict of GMD's `skating_ratio`,
/// PhysDiff's `penetrate_mm`, `float_mm`, `skate_mm`, `phys_err_mm`, `jitter_m_s3`, the
/// `floor_m` (given by `floor`, else read from the motion) and per foot its contact and skating
/// frame pairs. The thresholds default to the papers' (5 cm, 0.5 m/s, 5 frames, 5 mm).
#[pyfunction]
#[pyo3(signature = (take, *, floor=None, contact_height=0.05, skate_speed=0.5, window=5, float_tolerance=0.005))]
pub(crate) fn metrics<'py>(
    py: Python<'py>,
    take: &Motion,
    floor: Option<f64>,
    contact_height: f64,
    skate_speed: f64,
    window: usize,
    float_tolerance: f64,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    guard("metrics", || {
        for (name, value) in [
            ("contact_height", contact_height),
            ("skate_speed", skate_speed),
            ("float_tolerance", float_tolerance),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "{name}={value}: a number above 0"
                )));
            }
        }
        let thresholds = bvhview::metrics::Thresholds {
            contact_height,
            skate_speed,
            window: window.max(1),
            float_tolerance,
            floor,
        };
        let mut loaded = take.loaded.clone();
        loaded.offset_mode = take.offset_mode;
        let measured = py
            .detach(|| {
                let figure = bvhview::metrics::figure_of_take(&loaded)?;
                bvhview::metrics::measure(&figure, &thresholds)
            })
            .map_err(|e| to_python(py, e))?;
        let out = pyo3::types::PyDict::new(py);
        out.set_item("frames", measured.frames)?;
        out.set_item("fps", measured.fps)?;
        out.set_item("skating_ratio", measured.skating_ratio)?;
        out.set_item("penetrate_mm", measured.penetrate)?;
        out.set_item("penetrate_worst_mm", measured.penetrate_worst)?;
        out.set_item("float_mm", measured.float)?;
        out.set_item("floating_frames", measured.floating_frames)?;
        out.set_item("skate_mm", measured.skate)?;
        out.set_item("phys_err_mm", measured.phys_err())?;
        out.set_item("jitter_m_s3", measured.jitter)?;
        out.set_item(
            "bone_drift",
            measured.bone_drift.as_ref().map_or(0.0, |(d, _)| *d),
        )?;
        out.set_item("floor_m", measured.floor)?;
        out.set_item("floor_from", measured.floor_from)?;
        let feet = pyo3::types::PyList::empty(py);
        for foot in &measured.feet {
            let entry = pyo3::types::PyDict::new(py);
            entry.set_item("point", &foot.name)?;
            entry.set_item("contact_pairs", foot.contact_pairs)?;
            entry.set_item("skating_pairs", foot.skating_pairs)?;
            entry.set_item("mean_slide_m_s", foot.mean_slide)?;
            feet.append(entry)?;
        }
        out.set_item("feet", feet)?;
        Ok(out)
    })
}
