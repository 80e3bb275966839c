//! The plumbing every reader, writer and command stands on: errors, bounded reads, line
//! numbers, atomic outputs and the cores, and the limits (public as `crate::limits`). It uses nothing above it.

// Only a build without FBX, glTF or video refuses their files.
#[cfg(not(all(feature = "fbx", feature = "gltf", feature = "video")))]
pub mod absent;
pub mod error;
pub mod limits;
pub mod lines;
pub mod message;
pub mod npy;
pub mod output;
pub mod parallel;
pub mod place;
pub mod read;
pub mod whole;
