//! glTF 2.0: reading a take from `.gltf`/`.glb` ([`read`]) and writing one ([`mod@write`]).

pub mod read;
pub mod write;

pub use read::*;
pub use write::*;
