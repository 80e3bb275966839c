//! glTF 2.0: reading a take from `.gltf`/`.glb` ([`read`]) and writing one ([`mod@write`]),
//! behind the default feature `gltf`. Without the feature, the same entry points refuse with
//! what to do.

mod container;
#[cfg(feature = "gltf")]
pub mod read;
#[cfg(feature = "gltf")]
pub mod write;

pub use container::Container;
#[cfg(feature = "gltf")]
pub use read::{
    KEY_VALUES_FLOOR, KEY_VALUES_PER_BYTE, load, load_bytes, load_character, load_character_bytes,
    takes,
};
#[cfg(feature = "gltf")]
pub use write::{to_gltf, to_gltf_character};

#[cfg(not(feature = "gltf"))]
pub use absent::{
    load, load_bytes, load_character, load_character_bytes, takes, to_gltf, to_gltf_character,
};

/// The entry points of a build without glTF: each refuses, naming the feature.
#[cfg(not(feature = "gltf"))]
mod absent {
    use super::container::Container;
    use crate::io::absent::without;
    use crate::io::error::Error;
    use crate::model::motion::Motion;
    use crate::model::pose::OffsetMode;
    use crate::model::reading::{Read, TakeInfo};
    use crate::model::skeleton::Skeleton;
    use crate::take::options::OpenOptions;
    use std::path::Path;

    /// Refuses: this build reads no glTF.
    pub fn load(path: &Path, _: &OpenOptions) -> Result<Read, Error> {
        Err(without("gltf", "glTF", &path.display().to_string()))
    }

    /// Refuses: this build reads no glTF.
    pub fn load_bytes(_: &[u8], name: &str, _: &OpenOptions) -> Result<Read, Error> {
        Err(without("gltf", "glTF", name))
    }

    /// Refuses: this build reads no glTF.
    pub fn load_character(
        path: &Path,
        _: &OpenOptions,
    ) -> Result<(Read, crate::model::mesh::Mesh), Error> {
        Err(without("gltf", "glTF", &path.display().to_string()))
    }

    /// Refuses: this build reads no glTF.
    pub fn load_character_bytes(
        _: &[u8],
        name: &str,
        _: &OpenOptions,
    ) -> Result<(Read, crate::model::mesh::Mesh), Error> {
        Err(without("gltf", "glTF", name))
    }

    /// Refuses: this build reads no glTF.
    pub fn takes(path: &Path, _: u64) -> Result<Vec<TakeInfo>, Error> {
        Err(without("gltf", "glTF", &path.display().to_string()))
    }

    /// Refuses: this build writes no glTF.
    pub fn to_gltf_character(
        _: &Skeleton,
        _: &Motion,
        _: &crate::model::mesh::Mesh,
        container: Container,
    ) -> Result<Vec<u8>, Error> {
        to_gltf(
            &Skeleton::default(),
            &Motion::default(),
            OffsetMode::Replace,
            container,
            false,
        )
    }

    /// Refuses: this build writes no glTF.
    pub fn to_gltf(
        _: &Skeleton,
        _: &Motion,
        _: OffsetMode,
        container: Container,
        _: bool,
    ) -> Result<Vec<u8>, Error> {
        let name = match container {
            Container::Glb => "a .glb output",
            Container::Gltf => "a .gltf output",
        };
        Err(without("gltf", "glTF", name))
    }
}
