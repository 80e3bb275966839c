//! The article's `BVH` class: loading, printing and writing BVH files.

pub mod article;
pub mod loader;
pub mod print;
pub mod rows;
pub mod writer;

pub use loader::{Bvh, load_bytes, load_file};
