//! Helpers shared by the integration tests: the CLI runner ([`bvhview`], [`bvhview_command`],
//! [`bvhview_stdout`]) and the paths of test data.
//!
//! Three places hold test input:
//! - `tests/data/`: the repository's own corpus, a redistributable subset of the shared corpus,
//!   byte for byte (tests/data/SOURCES.md), so a bare clone tests itself;
//! - `tests/oracle/` and `tests/edge/`: the article's own outputs, and one hand-written file per
//!   article defect;
//! - `../shared/data/`: the whole corpus beside the checkout (CI has it). Tests that need it are
//!   `#[ignore]`d with a reason; `scripts/test.sh` runs them with `--include-ignored` when the folder
//!   is there, and [`shared_data`] fails loudly when it is not.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod npz;
pub mod smpl_models;
pub mod video;

/// The `bvhview` binary cargo built for these tests, as a command to add arguments,
/// environment or a working folder to.
pub fn bvhview_command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bvhview"))
}

/// A new, empty folder of its own in the system's temporary folder, kept after the test (a
/// test reads its pictures when it fails). Never named by the process id: ids come round
/// again, and a folder left by an earlier run of the same id is not empty.
pub fn scratch_folder(label: &str) -> PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("bvhview-{label}-"))
        .tempdir()
        .unwrap()
        .keep()
}

/// Runs `bvhview ARGS` to its end: its exit status, stdout and stderr, whatever they are.
pub fn bvhview<S: AsRef<OsStr>>(args: &[S]) -> Output {
    bvhview_command().args(args).output().unwrap()
}

/// Runs `bvhview ARGS`, which must succeed (else the test fails with its stderr); its stdout.
pub fn bvhview_stdout<S: AsRef<OsStr> + std::fmt::Debug>(args: &[S]) -> String {
    let out = bvhview(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A path in the repository's own corpus, `tests/data/`.
pub fn repo_data(relative: &str) -> PathBuf {
    manifest().join("tests/data").join(relative)
}

/// A path in the whole corpus, `../shared/data/`; panics with what to do when it is missing.
pub fn shared_data(relative: &str) -> PathBuf {
    let root = manifest().join("../shared/data");
    assert!(
        root.is_dir(),
        "{} is missing: this test reads the whole corpus beside the checkout \
         (run it where ../shared/data exists, as CI does)",
        root.display()
    );
    root.join(relative)
}

/// A real file or folder by its corpus path (`bvh/NAME.bvh`) in the repository's own corpus.
/// There is no fallback to ../shared/data, so a test that runs on a bare clone cannot come to
/// depend on the whole corpus by accident; tests that need it call [`shared_data`].
pub fn data(relative: &str) -> PathBuf {
    repo_data(relative)
}

/// A file of the article's outputs, `tests/oracle/` (see its README).
pub fn oracle(relative: &str) -> PathBuf {
    manifest().join("tests/oracle").join(relative)
}

/// A hand-written input, `tests/edge/` (see its README).
pub fn edge(name: &str) -> PathBuf {
    manifest().join("tests/edge").join(name)
}

/// Every file with extension `ext` in a folder, sorted; fails if there is none.
pub fn files_in(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .{ext} files in {}", dir.display());
    files
}

pub fn load_path(path: &Path) -> bvhview::bvh::Bvh {
    bvhview::bvh::load_file(path, Default::default()).unwrap_or_else(|e| panic!("{e}"))
}

pub fn load(relative: &str) -> bvhview::bvh::Bvh {
    load_path(&data(relative))
}

pub fn load_text(text: &str) -> Result<bvhview::bvh::Bvh, bvhview::Error> {
    bvhview::bvh::load_bytes(text.as_bytes(), "t.bvh")
}

pub fn error_text(text: &str) -> String {
    match load_text(text) {
        Ok(_) => panic!("loaded, expected an error:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The ASF skeleton of an AMC motion in the same folder, by CMU's naming: `NAME.asf` for
/// `NAME.amc`, or for `NAME_TAKE.amc` (`heiden_12.asf` for `heiden_12_02_01.amc`) the longest
/// such `NAME`.
#[allow(dead_code)]
pub fn asf_of(amc: &Path) -> PathBuf {
    let stem = amc.file_stem().unwrap().to_str().unwrap();
    let folder = amc.parent().unwrap();
    (1..=stem.len())
        .rev()
        .filter(|&i| i == stem.len() || stem.as_bytes()[i] == b'_')
        .map(|i| folder.join(format!("{}.asf", &stem[..i])))
        .find(|p| p.exists())
        .unwrap_or_else(|| panic!("no ASF for {}", amc.display()))
}

/// A take through the library's one door ([`bvhview::take::OpenOptions`]): `path`, with
/// `motion` (an ASF's AMC) and `frame_time` over the file's when given.
pub fn load_take(
    path: &Path,
    motion: Option<&Path>,
    frame_time: Option<f64>,
) -> Result<bvhview::Take, bvhview::Error> {
    let mut options = bvhview::take::OpenOptions::new();
    if let Some(amc) = motion {
        options = options.motion(amc);
    }
    if let Some(seconds) = frame_time {
        options = options.frame_time(seconds);
    }
    options.open(path)
}
