//! A character: a skinned mesh read from an FBX or a glTF with the skeleton it is bound to, and
//! the take the file holds (its own animation, or its rest pose as one frame). Any take put on
//! its skeleton (by [`crate::retarget`]) moves the mesh by linear blend skinning
//! ([`crate::model::mesh`]).
//!
//! ```
//! # fn main() -> Result<(), bvhview::Error> {
//! # #[cfg(feature = "fbx")]
//! # {
//! use bvhview::character::Character;
//!
//! let kenney = Character::open("tests/data/characters/maya_kenney_character_7700_binary.fbx")?;
//! assert_eq!(kenney.mesh.vertex_count(), 804);
//! // The file's own take, frame 4, skinned: every vertex where it belongs.
//! let vertices = kenney.vertices(&kenney.take.skeleton, kenney.take.frame(4).unwrap());
//! assert_eq!(vertices.len(), 804);
//! # }
//! # Ok(())
//! # }
//! ```

use crate::io::error::Error;
use crate::model::mesh::Mesh;
use crate::model::pose::{OffsetMode, world_matrices};
use crate::model::skeleton::Skeleton;
use crate::take::{Format, Take, extension};
use glam::{Mat4, Vec3};
use std::path::Path;

/// A skinned mesh and the take of its file.
#[derive(Clone, Debug)]
pub struct Character {
    /// The skeleton the mesh is bound to, with the file's own take (or its rest pose).
    pub take: Take,
    /// The mesh, bound to `take.skeleton`'s joints.
    pub mesh: Mesh,
}

impl Character {
    /// Opens a character from an `.fbx`, `.glb` or `.gltf` file with at least one mesh.
    pub fn open(path: impl AsRef<Path>) -> Result<Character, Error> {
        Character::open_with(path.as_ref(), crate::take::DEFAULT_MAX_SIZE, None, 0)
    }

    /// [`Character::open`] with the file's take `take` (name or index), a size limit and
    /// threads (0: every core).
    pub fn open_with(
        path: &Path,
        max_size: u64,
        take: Option<&str>,
        threads: usize,
    ) -> Result<Character, Error> {
        crate::take::check_file(path, max_size)?;
        let threads = if threads == 0 {
            crate::io::parallel::cores()
        } else {
            threads
        };
        let (read, mesh, format) = match extension(path).as_str() {
            "fbx" => {
                let (read, mesh) = crate::fbx::load_character(path, max_size, take, threads)?;
                (read, mesh, Format::Fbx)
            }
            "glb" | "gltf" => {
                let (read, mesh) = crate::gltf::load_character(path, max_size, take)?;
                (read, mesh, Format::Gltf)
            }
            _ => {
                return Err(Error::Usage(format!(
                    "{}: a character is an FBX or glTF file (.fbx, .glb, .gltf) with a skinned \
                     mesh",
                    path.display()
                )));
            }
        };
        if mesh.vertex_count() == 0 || mesh.triangles.is_empty() {
            return Err(Error::Usage(format!(
                "{}: no mesh to draw (a character needs a mesh with triangles)",
                path.display()
            )));
        }
        let mut take = Take::new(read.skeleton, read.motion, path.display().to_string());
        take.warnings = read.warnings;
        take.format = Some(format);
        take.take = read.take;
        Ok(Character { take, mesh })
    }

    /// The joints' world matrices of `skeleton` (the character's, or one with the same joints
    /// in the same order) in `frame`.
    fn world(&self, skeleton: &Skeleton, frame: &[f32]) -> Vec<Mat4> {
        let mut world = Vec::new();
        world_matrices(skeleton, frame, OffsetMode::Replace, &mut world);
        world
    }

    /// The mesh's vertices skinned by a MOTION row of `skeleton` (the character's skeleton,
    /// as a retarget onto it gives it), in the take's world coordinates.
    pub fn vertices(&self, skeleton: &Skeleton, frame: &[f32]) -> Vec<Vec3> {
        let world = self.world(skeleton, frame);
        let (mut positions, mut normals) = (Vec::new(), Vec::new());
        self.mesh.deform(&world, &mut positions, &mut normals);
        positions
    }
}

impl Character {
    /// `take` put on this character's skeleton by role ([`crate::retarget::Target::apply`]:
    /// rest poses aligned, the path scaled by leg length, the feet on the take's floor), ready
    /// to skin. `pairs` (`SRC = DST` joint names) override the map; a body that is not a biped
    /// is refused onto a biped character unless `any_body`.
    pub fn dress(
        &self,
        take: &Take,
        pairs: &[(String, String)],
        any_body: bool,
        threads: usize,
    ) -> Result<Take, Error> {
        let target = crate::retarget::Target::new(
            self.take.name.clone(),
            self.take.skeleton.clone(),
            &self.take.motion,
        );
        let (skeleton, motion) = if any_body {
            target.apply_any_body(&take.name, &take.skeleton, &take.motion, pairs, threads)?
        } else {
            target.apply(&take.name, &take.skeleton, &take.motion, pairs, threads)?
        };
        let mut dressed = take.edited(skeleton, motion, false);
        dressed.offset_mode = OffsetMode::Replace;
        Ok(dressed)
    }
}
