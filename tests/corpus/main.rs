//! The repository's test data is what tests/data/SOURCES.md says it is.

#[path = "../common/mod.rs"]
mod common;

mod data_matches_sources;
