//! Property tests (proptest) of the writer and the loaders. Failing cases proptest saves go to
//! tests/proptest-regressions/MODULE.txt, and are tried first on every run.

#[path = "../common/mod.rs"]
mod common;

mod writer_and_loaders;
