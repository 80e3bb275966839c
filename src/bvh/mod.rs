//! The article's `BVH` class: loading, printing and writing BVH files.

#[doc(hidden)] // what the original program does with a file: `print --explain` and the tests
pub mod article;
pub mod built_in;
pub mod loader;
mod options;
pub mod print;
pub mod rows;
pub mod writer;

pub use loader::{Bvh, load_bytes, load_file};
