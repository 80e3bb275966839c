//! What every module of the Python crate shares: Python's exception for a malformed file, the
//! guard every entry point runs in, the crate's errors as Python exceptions (with arguments
//! spelled as keywords), the offset mode's names, and the tests' planted pause.

use bvhview::model::pose::OffsetMode;
use bvhview::{Argument, Error, Spelling};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyMemoryError, PyOSError, PyPermissionError,
    PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use std::io;
use std::path::{Path, PathBuf};

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
pub(crate) fn guard<T>(entry: &str, work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
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

/// A test's switch (no test waits on the clock). With `BVHVIEW_PLANT_PAUSE` set to
/// `entry` and `BVHVIEW_PLANT_FOLDER` to a folder, the entry point, once it has let go of the
/// GIL, makes `paused` in that folder and waits until `release` appears there: only a thread that
/// runs Python meanwhile can make it, which proves the GIL let go. Not released within 60 s, the
/// call fails.
pub(crate) fn planted_pause_without_the_gil(entry: &str) -> Result<(), Error> {
    if std::env::var_os("BVHVIEW_PLANT_PAUSE").is_none_or(|name| name != entry) {
        return Ok(());
    }
    let Some(folder) = std::env::var_os("BVHVIEW_PLANT_FOLDER").map(PathBuf::from) else {
        return Err(Error::usage(
            "BVHVIEW_PLANT_PAUSE needs BVHVIEW_PLANT_FOLDER",
        ));
    };
    std::fs::write(folder.join("paused"), b"").map_err(|e| Error::io(&folder, e))?;
    let start = std::time::Instant::now();
    while !folder.join("release").exists() {
        if start.elapsed() > std::time::Duration::from_secs(60) {
            return Err(Error::usage(format!(
                "the pause planted in {entry} was not released within 60 s"
            )));
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    Ok(())
}

/// How a Python user writes the crate's arguments: as keywords of the same names (`fps=0`,
/// `contact_speed`), and an ASF skeleton with its motion as the call that reads the pair
/// (`bvhview.load("SKELETON.asf", motion="WALK.amc")`).
#[derive(Debug)]
pub(crate) struct Keywords;

impl Spelling for Keywords {
    fn argument(&self, argument: &Argument) -> String {
        match &argument.value {
            Some(value) => format!("{}={value}", argument.name),
            None => argument.name.to_string(),
        }
    }

    fn opening(&self, file: &str, with: &Argument) -> String {
        let value = with.value.as_deref().unwrap_or("");
        format!("bvhview.load({file:?}, {}={value:?})", with.name)
    }
}

/// Every error of the crate as the Python exception a Python user expects: a malformed file is a
/// `ParseError` (a `ValueError`), a missing file a `FileNotFoundError`, other I/O an `OSError`,
/// a request that cannot be met a `ValueError`.
pub(crate) fn to_python(py: Python<'_>, error: Error) -> PyErr {
    let text = error.spelled(&Keywords);
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
        Error::Memory(_) => PyMemoryError::new_err(text),
        Error::Environment(_) => PyRuntimeError::new_err(text),
        // A format this build lacks, a request that cannot be done: the caller's to change.
        _ => PyValueError::new_err(text),
    }
}

/// An `OSError` of the subclass Python itself would raise, with `errno`, `strerror` and
/// `filename` set when the OS gave a number.
pub(crate) fn os_error(path: &Path, source: &io::Error, text: &str) -> PyErr {
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

pub(crate) fn parse_offset_mode(text: &str) -> PyResult<OffsetMode> {
    match text {
        "replace" => Ok(OffsetMode::Replace),
        "add" => Ok(OffsetMode::Add),
        other => Err(PyValueError::new_err(format!(
            "offset_mode={other:?}: expected \"replace\" (position channels replace the OFFSET, \
             as Blender and bvhio) or \"add\" (added to it, as three.js)"
        ))),
    }
}

pub(crate) fn offset_mode_name(mode: OffsetMode) -> &'static str {
    match mode {
        OffsetMode::Replace => "replace",
        OffsetMode::Add => "add",
    }
}

/// One Python warning (`UserWarning`), said from the caller's line.
pub(crate) fn warn(py: Python<'_>, text: &str) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    py.import("warnings")?
        .call_method1("warn", (text, &category, 2))?;
    Ok(())
}

/// `up=`: "y", "z", "x", "-y", "-z" or "-x" (a take said to stand along one of the last
/// four is turned to stand along y as it is read).
pub(crate) fn parse_up(value: &str) -> PyResult<bvhview::model::pose::UpAxis> {
    value.parse().map_err(|_| {
        PyValueError::new_err(format!(
            "up={value:?}: expected \"y\", \"z\", \"x\", \"-y\", \"-z\" or \"-x\""
        ))
    })
}

/// `units=`: a unit's name ("mm", "cm", "m", "in", "ft") or a number of metres per unit.
pub(crate) fn parse_units(value: &Bound<'_, PyAny>) -> PyResult<bvhview::model::stance::Units> {
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyValueError::new_err(
            "units=: expected \"mm\", \"cm\", \"m\", \"in\", \"ft\" or metres per unit, not a bool",
        ));
    }
    let text = match value.extract::<f64>() {
        Ok(metres) => metres.to_string(),
        Err(_) => value.extract::<String>().map_err(|_| {
            PyValueError::new_err("units=: expected \"mm\", \"cm\", \"m\", \"in\", \"ft\" or metres per unit")
        })?,
    };
    bvhview::model::stance::Units::named(&text).ok_or_else(|| {
        PyValueError::new_err(format!(
            "units={text:?}: expected \"mm\", \"cm\", \"m\", \"in\", \"ft\" or a number of metres per unit from 1e-9 to 1000"
        ))
    })
}
