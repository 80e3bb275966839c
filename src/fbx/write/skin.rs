//! A character's mesh as FBX writes it: each part of the [`Mesh`] (a mesh of the file it was
//! read from) a `Geometry` with its vertices, triangles and normals, a `Model` of type Mesh at
//! the origin, and a skin `Deformer` with one `Cluster` per bone holding every influence
//! (FBX has no limit on a vertex's influences, so none is dropped).
//!
//! A cluster's `Transform` is the bone's bind matrix (from the mesh's coordinates to the
//! joint's frame, as ufbx reads it back: `mesh_node_to_bone`) and its `TransformLink` the
//! joint's world matrix when the mesh was bound (its inverse, the mesh's node being at the
//! origin): every reader's `TransformLink⁻¹ · Transform` or `Transform` alone then gives the
//! same bind.

use super::bones::{Bone, Turn};
use super::ids::{cluster_id, geometry_id, mesh_model_id, model_id, skin_id};
use super::records::{Records, Value};
use crate::io::error::Error;
use crate::model::mesh::Mesh;
use glam::{DMat4, DVec3};

/// The mesh's parts that have triangles, and the bone index of the node that stands for
/// "bound to no joint" when some bone is (a bone that never moves).
pub(super) struct Skin<'a> {
    mesh: &'a Mesh,
    /// Written units per unit of the take.
    scale: f64,
    /// The turn of a Z-up take to Y up, as the joints are turned.
    turn: Turn,
    /// The parts written (a part without vertices or triangles is left out).
    parts: Vec<usize>,
    /// The bone (index into the written bones) a joint-less mesh bone links to.
    origin: Option<usize>,
}

impl<'a> Skin<'a> {
    /// The parts of `mesh` to write, lengths times `scale`; `origin` is the written bone that
    /// stands at the origin for mesh bones bound to no joint (see [`Skin::needs_origin`]).
    pub(super) fn new(
        mesh: &'a Mesh,
        scale: f64,
        turn: Turn,
        origin: Option<usize>,
    ) -> Result<Self, Error> {
        mesh.check()
            .map_err(|why| Error::usage(format!("cannot write the mesh: {why}")))?;
        let parts = (0..mesh.parts.len())
            .filter(|&k| {
                let (vertices, corners, _) = mesh.part_ranges(k);
                !vertices.is_empty() && !corners.is_empty()
            })
            .collect();
        Ok(Skin {
            mesh,
            scale,
            turn,
            parts,
            origin,
        })
    }

    /// Whether a bone of `mesh` is bound to no joint: its vertices stay where the bind put them,
    /// so its cluster links to a node at the origin that never moves.
    pub(super) fn needs_origin(mesh: &Mesh) -> bool {
        mesh.bones.iter().any(|b| b.joint.is_none())
    }

    /// How many of each object type it writes: models, geometries, deformers (skins and
    /// clusters).
    pub(super) fn counts(&self) -> (usize, usize, usize) {
        let clusters: usize = self
            .parts
            .iter()
            .map(|&k| self.mesh.part_ranges(k).2.len())
            .sum();
        (
            self.parts.len(),
            self.parts.len(),
            self.parts.len() + clusters,
        )
    }

    /// The written bone a mesh bone links to.
    fn link(&self, bone: usize) -> Result<usize, Error> {
        match self.mesh.bones[bone].joint {
            Some(joint) => Ok(joint),
            None => self
                .origin
                .ok_or_else(|| Error::usage("cannot write the mesh: no node at the origin")),
        }
    }

    /// A bone's bind matrix in written units (the translation scaled, the rest kept), turned
    /// as the joints and the mesh are: Q·B·Q⁻¹.
    fn bind(&self, bone: usize) -> DMat4 {
        let bind = self.mesh.bones[bone].bind.as_dmat4();
        let (x, y, z) = (bind.x_axis, bind.y_axis, bind.z_axis);
        let w = bind.w_axis.truncate() * self.scale;
        let q = self.turn.matrix();
        q * DMat4::from_cols(x, y, z, w.extend(1.0)) * q.transpose()
    }

    /// Each linked joint's world matrix when the mesh was bound (first part that binds it
    /// wins), for the bind pose: `(written bone, matrix)`.
    pub(super) fn bind_pose(&self) -> Vec<(usize, DMat4)> {
        let mut seen = Vec::new();
        for &k in &self.parts {
            for bone in self.mesh.part_ranges(k).2 {
                if let Ok(link) = self.link(bone)
                    && !seen.iter().any(|(l, _)| *l == link)
                {
                    seen.push((link, self.bind(bone).inverse()));
                }
            }
        }
        seen
    }

    /// The mesh models, for the bind pose (each at the origin).
    pub(super) fn model_ids(&self) -> impl Iterator<Item = i64> + '_ {
        self.parts.iter().map(|&k| mesh_model_id(k))
    }

    /// The objects: per part its geometry, model, skin and clusters.
    /// `bones` are the written bones (a cluster is named after the one it links to).
    pub(super) fn write_objects(&self, out: &mut Records, bones: &[Bone]) -> Result<(), Error> {
        for &k in &self.parts {
            let name = self
                .mesh
                .part_names
                .get(k)
                .map_or_else(|| format!("mesh{k}"), |n| super::bones::fbx_name(n));
            self.geometry(out, k, &name)?;
            mesh_model(out, k, &name)?;
            let skin = format!("{name}\0\x01Deformer");
            out.open(
                "Deformer",
                &[
                    Value::I64(skin_id(k)),
                    Value::Str(&skin),
                    Value::Str("Skin"),
                ],
            )?;
            out.leaf("Version", &[Value::I32(101)])?;
            out.leaf("Link_DeformAcuracy", &[Value::F64(50.0)])?;
            out.close()?;
            self.clusters(out, k, bones)?;
        }
        Ok(())
    }

    /// Part `k`'s `Geometry`: vertices, triangles (FBX ends a polygon with its last index's
    /// ones' complement), and one normal per vertex.
    fn geometry(&self, out: &mut Records, k: usize, name: &str) -> Result<(), Error> {
        let (vertices, corners, _) = self.mesh.part_ranges(k);
        let first = vertices.start as u32;
        let positions: Vec<f64> = self.mesh.positions[vertices.clone()]
            .iter()
            .flat_map(|p| self.turn.point((p.as_dvec3() * self.scale).to_array()))
            .collect();
        let polygons: Vec<i32> = self.mesh.triangles[corners]
            .chunks_exact(3)
            .flat_map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| (i - first) as i32);
                [a, b, !c]
            })
            .collect();
        let normals: Vec<f64> = self.mesh.normals[vertices]
            .iter()
            .flat_map(|n| {
                let n = n.as_dvec3().try_normalize().unwrap_or(DVec3::Y);
                self.turn.point(n.to_array())
            })
            .collect();
        let geometry = format!("{name}\0\x01Geometry");
        out.open(
            "Geometry",
            &[
                Value::I64(geometry_id(k)),
                Value::Str(&geometry),
                Value::Str("Mesh"),
            ],
        )?;
        out.open("Properties70", &[])?;
        out.close()?;
        out.leaf("GeometryVersion", &[Value::I32(124)])?;
        out.array("Vertices", &positions)?;
        out.array("PolygonVertexIndex", &polygons)?;
        out.open("LayerElementNormal", &[Value::I32(0)])?;
        out.leaf("Version", &[Value::I32(101)])?;
        out.leaf("Name", &[Value::Str("")])?;
        out.leaf("MappingInformationType", &[Value::Str("ByVertice")])?;
        out.leaf("ReferenceInformationType", &[Value::Str("Direct")])?;
        out.array("Normals", &normals)?;
        out.close()?;
        out.open("Layer", &[Value::I32(0)])?;
        out.leaf("Version", &[Value::I32(100)])?;
        out.open("LayerElement", &[])?;
        out.leaf("Type", &[Value::Str("LayerElementNormal")])?;
        out.leaf("TypedIndex", &[Value::I32(0)])?;
        out.close()?;
        out.close()?;
        out.close()
    }

    /// Part `k`'s clusters, one per bone: the vertices it moves, their weights, and its bind.
    fn clusters(&self, out: &mut Records, k: usize, written: &[Bone]) -> Result<(), Error> {
        let (vertices, _, bones) = self.mesh.part_ranges(k);
        let mut indexes: Vec<Vec<i32>> = vec![Vec::new(); bones.len()];
        let mut weights: Vec<Vec<f64>> = vec![Vec::new(); bones.len()];
        for v in vertices.clone() {
            for influence in self.mesh.influences_of(v) {
                let b = influence.bone as usize - bones.start;
                indexes[b].push((v - vertices.start) as i32);
                weights[b].push(f64::from(influence.weight));
            }
        }
        for (b, bone) in bones.enumerate() {
            let transform = self.bind(bone);
            let cluster = format!("{}\0\x01SubDeformer", written[self.link(bone)?].name);
            out.open(
                "Deformer",
                &[
                    Value::I64(cluster_id(bone)),
                    Value::Str(&cluster),
                    Value::Str("Cluster"),
                ],
            )?;
            out.leaf("Version", &[Value::I32(100)])?;
            out.leaf("UserData", &[Value::Str(""), Value::Str("")])?;
            out.array("Indexes", &indexes[b])?;
            out.array("Weights", &weights[b])?;
            out.array("Transform", &transform.to_cols_array())?;
            out.array("TransformLink", &transform.inverse().to_cols_array())?;
            out.close()?;
        }
        Ok(())
    }

    /// Geometry → model → root, skin → geometry, cluster → skin, joint → cluster.
    pub(super) fn connect(
        &self,
        oo: &mut impl FnMut(i64, i64) -> Result<(), Error>,
    ) -> Result<(), Error> {
        for &k in &self.parts {
            oo(mesh_model_id(k), 0)?;
            oo(geometry_id(k), mesh_model_id(k))?;
            oo(skin_id(k), geometry_id(k))?;
            for bone in self.mesh.part_ranges(k).2 {
                oo(cluster_id(bone), skin_id(k))?;
                oo(model_id(self.link(bone)?), cluster_id(bone))?;
            }
        }
        Ok(())
    }
}

/// Part `k`'s `Model` of type Mesh, at the origin.
fn mesh_model(out: &mut Records, k: usize, name: &str) -> Result<(), Error> {
    let model = format!("{name}\0\x01Model");
    out.open(
        "Model",
        &[
            Value::I64(mesh_model_id(k)),
            Value::Str(&model),
            Value::Str("Mesh"),
        ],
    )?;
    out.leaf("Version", &[Value::I32(232)])?;
    out.open("Properties70", &[])?;
    out.property("InheritType", ["enum", "", ""], &[Value::I32(1)])?;
    out.close()?;
    out.leaf("Shading", &[Value::Bool(true)])?;
    out.leaf("Culling", &[Value::Str("CullingOff")])?;
    out.close()
}
