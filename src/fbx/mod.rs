//! FBX (binary and ASCII, FBX 6 and 7) → the same `Skeleton` + `Motion` a BVH loads into, read
//! by ufbx as Blender reads it ([`read`], behind the default feature `fbx`). Without the
//! feature, the same three entry points refuse every file with what to do.

#[cfg(feature = "fbx")]
mod matrix;
#[cfg(feature = "fbx")]
mod mesh;
#[cfg(feature = "fbx")]
mod plain;
#[cfg(feature = "fbx")]
pub mod read;
#[cfg(feature = "fbx")]
mod records;
#[cfg(feature = "fbx")]
pub mod write;

#[cfg(feature = "fbx")]
pub use read::{load, load_bytes, load_character, load_character_bytes, takes, takes_of_bytes};

#[cfg(not(feature = "fbx"))]
pub use absent::{load, load_bytes, load_character, load_character_bytes, takes, takes_of_bytes};

/// The entry points of a build without FBX: each refuses, naming the feature.
#[cfg(not(feature = "fbx"))]
mod absent {
    use crate::io::absent::without;
    use crate::io::error::Error;
    use crate::model::reading::{Read, TakeInfo};
    use crate::take::options::OpenOptions;
    use std::path::Path;

    /// Refuses: this build reads no FBX.
    pub fn load(path: &Path, _: &OpenOptions) -> Result<Read, Error> {
        Err(without("fbx", "FBX", &path.display().to_string()))
    }

    /// Refuses: this build reads no FBX.
    pub fn load_bytes(_: &[u8], name: &str, _: &OpenOptions) -> Result<Read, Error> {
        Err(without("fbx", "FBX", name))
    }

    /// Refuses: this build reads no FBX.
    pub fn load_character(
        path: &Path,
        _: &OpenOptions,
    ) -> Result<(Read, crate::model::mesh::Mesh), Error> {
        Err(without("fbx", "FBX", &path.display().to_string()))
    }

    /// Refuses: this build reads no FBX.
    pub fn load_character_bytes(
        _: &[u8],
        name: &str,
        _: &OpenOptions,
    ) -> Result<(Read, crate::model::mesh::Mesh), Error> {
        Err(without("fbx", "FBX", name))
    }

    /// Refuses: this build reads no FBX.
    pub fn takes(path: &Path, _: u64) -> Result<Vec<TakeInfo>, Error> {
        Err(without("fbx", "FBX", &path.display().to_string()))
    }

    /// Refuses: this build reads no FBX.
    pub fn takes_of_bytes(_: &[u8], name: &str) -> Result<Vec<TakeInfo>, Error> {
        Err(without("fbx", "FBX", name))
    }
}
