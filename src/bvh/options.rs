//! What a load is given beside the file: the input (a path, or bytes already in memory), and
//! the settings the article's `loadFile` has no say in (threads, size limit, first read, which
//! row reader runs). `loader` re-exports them.

use std::path::Path;

/// What the article's `loadFile` has no say in: how many threads read the rows, how large a
/// file may be, how much the first read takes, and which row reader runs.
///
/// ```
/// use bvhview::bvh::{load_file, loader::Settings};
/// use std::path::Path;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let settings = Settings { threads: 1, max_size: 1 << 20, ..Settings::default() };
/// let bvh = load_file(Path::new("tests/oracle/inputs/tiny_crlf.bvh"), settings)?;
/// assert_eq!(bvh.motion.frame_count(), 3);
/// // Past `max_size`, reading stops with an error.
/// let small = Settings { max_size: 100, ..settings };
/// assert!(load_file(Path::new("tests/oracle/inputs/tiny_crlf.bvh"), small).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Threads the row engine may use (1 when many files load at once).
    pub threads: usize,
    /// Bytes read from the path at most, whatever it is (a file, a pipe, a device).
    pub max_size: u64,
    /// Bytes the cursor's first read takes; it reads more as it needs them. A file this small is
    /// read whole and its rows are parsed where they lie; a larger one streams (tests give tiny
    /// values to stream small files too).
    pub first_read: usize,
    /// The row engine, or the article's plain loop (`rows::read_rows_simple`).
    pub rows: RowReader,
    /// The deepest nesting accepted, End Sites included: [`crate::limits::MAX_DEPTH`];
    /// `trace --explain` reads a file refused only for its depth again, deeper, to compare the
    /// article's reading with what the file says.
    pub max_depth: usize,
}

impl Default for Settings {
    /// Every core, no size limit, 64 KB first, the engine.
    fn default() -> Settings {
        Settings {
            threads: crate::io::parallel::cores(),
            max_size: u64::MAX,
            first_read: 64 << 10,
            rows: RowReader::Engine,
            max_depth: crate::limits::MAX_DEPTH,
        }
    }
}

/// Which reader the row loop runs; both give the same values and errors.
///
/// ```
/// use bvhview::bvh::{load_file, loader::{RowReader, Settings}};
/// use std::path::Path;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let path = Path::new("tests/data/bvh/bvhparser_walk_01.bvh");
/// let engine = load_file(path, Settings::default())?;
/// let simple = load_file(path, Settings { rows: RowReader::Simple, ..Settings::default() })?;
/// assert_eq!(engine.motion, simple.motion);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RowReader {
    /// [`RowParser`](super::rows::RowParser): on every core, as the file streams in.
    #[default]
    Engine,
    /// [`super::rows::read_rows_simple`]: the article's loop, one line and one word at a time.
    Simple,
}

/// What [`load_file`](super::load_file) reads: a file by its path, or bytes already in memory
/// with a name for the error messages.
///
/// ```
/// use bvhview::bvh::{load_file, loader::{Input, Settings}};
/// use std::path::Path;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let path = Path::new("tests/oracle/inputs/tiny_crlf.bvh");
/// let bytes = std::fs::read(path).unwrap();
/// let from_file = load_file(Input::Path(path), Settings::default())?;
/// let from_memory = load_file(Input::Bytes(&bytes, "tiny"), Settings::default())?;
/// assert_eq!(from_file.skeleton, from_memory.skeleton);
/// // Errors name the input as given.
/// let error = load_file(Input::Bytes(b"HIERARCHY\nROOT", "tiny"), Settings::default());
/// assert!(error.unwrap_err().to_string().starts_with("tiny:"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub enum Input<'a> {
    /// A file (or a pipe, or a device) read from its path.
    Path(&'a Path),
    /// Bytes in memory, and the name errors give them.
    Bytes(&'a [u8], &'a str),
}

impl<'a> From<&'a Path> for Input<'a> {
    fn from(path: &'a Path) -> Input<'a> {
        Input::Path(path)
    }
}

impl<'a> From<&'a std::path::PathBuf> for Input<'a> {
    fn from(path: &'a std::path::PathBuf) -> Input<'a> {
        Input::Path(path)
    }
}
