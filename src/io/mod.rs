//! The plumbing every reader, writer and command stands on: errors, bounded reads, line
//! numbers, atomic outputs, limits, and the cores. It uses nothing above it.

pub mod absent;
pub mod error;
pub mod limits;
pub mod lines;
pub mod output;
pub mod parallel;
pub mod read;
