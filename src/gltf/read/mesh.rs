//! A glTF's meshes as one [`Mesh`] on the skeleton the reader made: skinned primitives through
//! their skin's joints and inverse bind matrices, every `JOINTS_n`/`WEIGHTS_n` pair read (any
//! number of influences); a mesh without a skin on a node at or under a joint moves rigidly with
//! that joint, one under no joint stays where it stands. Triangles only (strips, fans, lines and
//! points are left out, said once).

use crate::gltf::read::file::{File, accessor_integers, accessor_values, bad};
use crate::io::error::Error;
use crate::model::mesh::{Bone, Mesh, MeshBuilder};
use glam::DMat4;
use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};

/// What [`read`] needs of the skeleton the reader made, per node of the file.
pub(super) struct NodeFrames<'a> {
    /// Each node's parent.
    pub parent: &'a [Option<usize>],
    /// Each node's world matrix in the file's rest pose (its static transforms).
    pub rest: &'a [DMat4],
    /// The skeleton joint a node became, if it did.
    pub joint: &'a [Option<usize>],
}

/// bvhview's frame of a joint in the rest pose: a character's skeleton is read with its rest
/// pose as its zero pose (`baked::build_with`), so every joint's frame there is the world's
/// axes at the joint's place.
fn our_frame(world: &DMat4) -> DMat4 {
    DMat4::from_translation(world.w_axis.truncate())
}

/// The bone binding geometry given in `node`'s frame (`geometry`: the node's own coordinates,
/// or a skin joint's through its inverse bind matrix) to the joint at or above `node`, or to
/// nothing: `bind = ours(joint)⁻¹ · rest(node) · geometry`.
fn bone_of(frames: &NodeFrames, node: usize, geometry: DMat4) -> Bone {
    let geometry_to_world = frames.rest[node] * geometry;
    let mut up = Some(node);
    while let Some(n) = up {
        if let Some(j) = frames.joint[n] {
            let bind = our_frame(&frames.rest[n]).inverse() * geometry_to_world;
            return Bone {
                joint: Some(j),
                bind: bind.as_mat4(),
            };
        }
        up = frames.parent[n];
    }
    Bone {
        joint: None,
        bind: geometry_to_world.as_mat4(),
    }
}

/// Every mesh of the file's default scene (or every node, without scenes), on the skeleton.
pub(super) fn read(
    file: &File,
    path: &str,
    frames: &NodeFrames,
) -> Result<(Mesh, Vec<String>), Error> {
    let mut reading = Reading {
        file,
        path,
        builder: MeshBuilder::new(path, file.bytes),
        left_out: Vec::new(),
        short: Vec::new(),
    };
    for node in file.gltf.document.nodes() {
        let Some(mesh) = node.mesh() else { continue };
        reading.node(frames, &node, &mesh)?;
    }
    Ok(reading.finish())
}

/// One `JOINTS_n` with its `WEIGHTS_n`: four joints and four weights a vertex.
type WeightSet = (Vec<u32>, Vec<f32>);

/// The meshes read so far, and what is said of them at the end.
struct Reading<'a> {
    file: &'a File,
    path: &'a str,
    builder: MeshBuilder,
    /// Primitives that are not triangles or have no positions.
    left_out: Vec<String>,
    /// Primitives whose last corners are short of a triangle.
    short: Vec<String>,
}

impl Reading<'_> {
    /// An error of the file.
    fn fail(&self, why: String) -> Error {
        bad(self.path, why)
    }

    /// An error of one of its meshes, named.
    fn in_mesh(&self, mesh: &gltf::Mesh) -> impl Fn(String) -> Error + use<'_> {
        let label = mesh_label(mesh);
        move |why: String| bad(self.path, format!("mesh '{label}': {why}"))
    }

    /// The mesh of `node` as a part of its own: its bones, then each of its primitives.
    fn node(
        &mut self,
        frames: &NodeFrames,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
    ) -> Result<(), Error> {
        // glTF hides back faces unless a material says `doubleSided` (3.9.5).
        let single_sided = mesh.primitives().all(|p| !p.material().double_sided());
        self.builder.begin_part(&mesh_label(mesh), single_sided);
        let bones = self.bones(frames, node, mesh)?;
        // A vertex of a skinned mesh with no weight stays where its geometry is (the node's
        // own transform is not used for a skin).
        let fixed = Bone {
            joint: None,
            bind: if node.skin().is_some() {
                Mat4::IDENTITY
            } else {
                frames.rest[node.index()].as_mat4()
            },
        };
        for primitive in mesh.primitives() {
            self.primitive(node, mesh, &primitive, &bones, fixed)?;
        }
        Ok(())
    }

    /// The bones a node's mesh binds to. Skinned: each of the skin's joints binds through its
    /// inverse bind matrix; the mesh's node transform is not used (glTF 2.0, 3.7.3.3). Else the
    /// one bone of the joint at or above the node.
    fn bones(
        &mut self,
        frames: &NodeFrames,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
    ) -> Result<Vec<u32>, Error> {
        let Some(skin) = node.skin() else {
            let bone = bone_of(frames, node.index(), DMat4::IDENTITY);
            return Ok(vec![self.builder.bone(bone)?]);
        };
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let inverse_binds = match skin.inverse_bind_matrices() {
            Some(accessor) => {
                if accessor.count() != joints.len() {
                    return Err(self.fail(format!(
                        "skin {} has {} joints and {} inverse bind matrices",
                        skin.index(),
                        joints.len(),
                        accessor.count()
                    )));
                }
                matrices(self.file, &accessor).map_err(self.in_mesh(mesh))?
            }
            None => vec![DMat4::IDENTITY; joints.len()],
        };
        joints
            .iter()
            .zip(&inverse_binds)
            .map(|(&joint, inverse_bind)| {
                let bone = bone_of(frames, joint, *inverse_bind);
                self.builder.bone(bone)
            })
            .collect()
    }

    /// One primitive of a node's mesh: its vertices with their influences, then its triangles
    /// (its normals smoothed from them when it has none). A primitive that is not triangles,
    /// or has no positions, is left out.
    fn primitive(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        bones: &[u32],
        fixed: Bone,
    ) -> Result<(), Error> {
        if primitive.mode() != gltf::mesh::Mode::Triangles {
            self.left_out.push(format!(
                "a {:?} primitive of mesh {}",
                primitive.mode(),
                mesh.index()
            ));
            return Ok(());
        }
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            self.left_out.push(format!(
                "a primitive of mesh {} without positions",
                mesh.index()
            ));
            return Ok(());
        };
        let count = positions.count();
        self.builder.reserve(count as u64)?;
        let xyz = accessor_values(self.file, &positions, 3).map_err(self.in_mesh(mesh))?;
        let normals = match primitive.get(&gltf::Semantic::Normals) {
            Some(a) if a.count() == count => {
                Some(accessor_values(self.file, &a, 3).map_err(self.in_mesh(mesh))?)
            }
            Some(a) => {
                return Err(self.fail(format!(
                    "mesh {}: {} normals for {count} positions",
                    mesh.index(),
                    a.count()
                )));
            }
            None => None,
        };
        let sets = if node.skin().is_some() {
            self.weight_sets(mesh, primitive, count)?
        } else {
            Vec::new()
        };
        let first = self.builder.vertex_count();
        let triangles_from = self.builder.triangle_corner_count();
        for v in 0..count {
            let position = Vec3::from_slice(&xyz[3 * v..3 * v + 3]);
            let normal = normals
                .as_ref()
                .map_or(Vec3::ZERO, |n| Vec3::from_slice(&n[3 * v..3 * v + 3]));
            let influences: Vec<(u32, f32)> = if node.skin().is_some() {
                self.influences(mesh, &sets, bones, v)?
            } else {
                vec![(bones[0], 1.0)]
            };
            self.builder.vertex(position, normal, influences, fixed)?;
        }
        self.triangles(mesh, primitive, count, first)?;
        if normals.is_none() {
            self.builder.smooth_normals(first as usize, triangles_from);
        }
        Ok(())
    }

    /// Every `JOINTS_n` of a skinned primitive with its `WEIGHTS_n`, for `count` vertices.
    fn weight_sets(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        count: usize,
    ) -> Result<Vec<WeightSet>, Error> {
        let mut sets: Vec<WeightSet> = Vec::new();
        for set in 0.. {
            let joints = primitive.get(&gltf::Semantic::Joints(set));
            let weights = primitive.get(&gltf::Semantic::Weights(set));
            let (joints, weights) = match (joints, weights) {
                (None, None) => break,
                (Some(j), Some(w)) => (j, w),
                _ => {
                    return Err(self.fail(format!(
                        "mesh {}: JOINTS_{set} and WEIGHTS_{set} do not come in a pair",
                        mesh.index()
                    )));
                }
            };
            if joints.count() != count || weights.count() != count {
                return Err(self.fail(format!(
                    "mesh {}: JOINTS_{set}/WEIGHTS_{set} count {}/{} for {count} \
                     positions",
                    mesh.index(),
                    joints.count(),
                    weights.count()
                )));
            }
            // Every set read so far counts: a file may name the same accessors again
            // and again.
            self.builder
                .reserve((4 * count as u64).saturating_mul(sets.len() as u64 + 1))?;
            sets.push((
                accessor_integers(self.file, &joints, 4).map_err(self.in_mesh(mesh))?,
                accessor_values(self.file, &weights, 4).map_err(self.in_mesh(mesh))?,
            ));
        }
        Ok(sets)
    }

    /// The bones and weights of vertex `v` of a skinned primitive: every influence of every
    /// set with a weight, its joint one of the skin's.
    fn influences(
        &self,
        mesh: &gltf::Mesh,
        sets: &[WeightSet],
        bones: &[u32],
        v: usize,
    ) -> Result<Vec<(u32, f32)>, Error> {
        let mut out = Vec::with_capacity(4 * sets.len());
        for (joints, weights) in sets {
            for k in 0..4 {
                let (joint, weight) = (joints[4 * v + k], weights[4 * v + k]);
                if weight == 0.0 {
                    continue;
                }
                let Some(&bone) = bones.get(joint as usize) else {
                    return Err(self.fail(format!(
                        "mesh {}, vertex {v}: joint {joint} of a skin of {} joints",
                        mesh.index(),
                        bones.len()
                    )));
                };
                out.push((bone, weight));
            }
        }
        Ok(out)
    }

    /// A primitive's triangles, by its indices or, without them, its vertices three by three;
    /// corners short of a last triangle are left out (said once at the end).
    fn triangles(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        count: usize,
        first: u32,
    ) -> Result<(), Error> {
        match primitive.indices() {
            Some(indices) => {
                self.builder.reserve(indices.count() as u64 / 3)?;
                let corners =
                    accessor_integers(self.file, &indices, 1).map_err(self.in_mesh(mesh))?;
                if corners.len() % 3 != 0 {
                    self.short.push(format!("mesh '{}'", mesh_label(mesh)));
                }
                for t in corners.chunks_exact(3) {
                    if let Some(&c) = t.iter().find(|&&c| c as usize >= count) {
                        return Err(self.fail(format!(
                            "mesh {}: index {c} of a primitive of {count} vertices",
                            mesh.index()
                        )));
                    }
                    self.builder
                        .triangle([first + t[0], first + t[1], first + t[2]])?;
                }
            }
            None => {
                if !count.is_multiple_of(3) {
                    self.short.push(format!("mesh '{}'", mesh_label(mesh)));
                }
                for t in 0..count as u32 / 3 {
                    self.builder
                        .triangle([first + 3 * t, first + 3 * t + 1, first + 3 * t + 2])?;
                }
            }
        }
        Ok(())
    }

    /// The mesh, and what was said of it: the builder's lines, then the primitives left out
    /// and those short of a triangle, one line each.
    fn finish(self) -> (Mesh, Vec<String>) {
        let (mesh, mut said) = self.builder.finish();
        let (left_out, short) = (self.left_out, self.short);
        if !left_out.is_empty() {
            said.push(format!(
                "{} left out of the mesh (triangles only): {}",
                crate::io::error::counted(left_out.len(), "primitive"),
                left_out.join(", ")
            ));
        }
        if !short.is_empty() {
            // One line however many: the first three named.
            let more = if short.len() > 3 { ", …" } else { "" };
            said.push(format!(
                "the last 1 or 2 indices of {} fall short of a triangle and are left out: {}{more}",
                crate::io::error::counted(short.len(), "primitive"),
                short[..short.len().min(3)].join(", ")
            ));
        }
        (mesh, said)
    }
}

/// A glTF mesh's name for messages: its own, else its index (`3`).
fn mesh_label(mesh: &gltf::Mesh) -> String {
    mesh.name()
        .map_or_else(|| mesh.index().to_string(), str::to_string)
}

/// A MAT4 accessor's matrices (column-major, as glTF stores them).
fn matrices(file: &File, accessor: &gltf::Accessor) -> Result<Vec<DMat4>, String> {
    if accessor.dimensions() != Dimensions::Mat4 || accessor.data_type() != DataType::F32 {
        return Err(format!(
            "accessor {} (inverse bind matrices) is not MAT4 of floats",
            accessor.index()
        ));
    }
    let columns = accessor_values(file, accessor, 16)?;
    let out: Vec<DMat4> = columns
        .chunks_exact(16)
        .map(|m| DMat4::from_cols_slice(&m.iter().map(|&v| f64::from(v)).collect::<Vec<_>>()))
        .collect();
    if let Some(k) = out.iter().position(|m| !m.is_finite()) {
        return Err(format!("inverse bind matrix {k} is not finite"));
    }
    Ok(out)
}
