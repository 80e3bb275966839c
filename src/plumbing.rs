//! The few pieces of plumbing the Python package (another crate) shares with the command line:
//! cores and threads, atomic outputs. Not part of the API; the rest of `io` is private to the
//! crate.

pub use crate::io::output::AtomicFile;
pub use crate::io::parallel::{cores, map_in_order, on_threads};
