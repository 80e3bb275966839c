//! An FBX's meshes as one [`Mesh`] on the skeleton the reader made, as ufbx gives them: each
//! mesh's vertices (ufbx's `vertices`, one per control point, as Blender's importer keeps them),
//! its polygons cut into triangles by ufbx, and its skin deformers' clusters with their
//! `geometry_to_bone` bind matrices and every weight (any number a vertex). A mesh without a
//! skin moves rigidly with the joint at or above its node, or stays where it stands.

use super::matrix::matrix;
use crate::io::error::Error;
use crate::model::mesh::{Bone, Mesh, MeshBuilder};
use glam::{DMat4, Vec3};

/// bvhview's frame of a joint in the rest pose: a character's skeleton is read with its rest
/// pose as its zero pose (`baked::build_with`), so every joint's frame there is the world's
/// axes at the joint's place.
fn our_frame(world: &DMat4) -> DMat4 {
    DMat4::from_translation(world.w_axis.truncate())
}

/// The bone that binds geometry given in `node`'s frame (`geometry_to_node`) to the joint at or
/// above `node` (or to nothing): `bind = ours(joint)⁻¹ · world(node) · geometry_to_node`, every
/// world matrix at rest and turned by `turn`.
fn bone_of(
    scene: &ufbx::Scene,
    joint: &[Option<usize>],
    turn: DMat4,
    node: usize,
    geometry_to_node: DMat4,
) -> Bone {
    let world = |n: usize| turn * matrix(&scene.nodes[n].node_to_world);
    let geometry_to_world = world(node) * geometry_to_node;
    let mut up = Some(node);
    while let Some(n) = up.filter(|&n| n < scene.nodes.len()) {
        if let Some(j) = joint[n] {
            return Bone {
                joint: Some(j),
                bind: (our_frame(&world(n)).inverse() * geometry_to_world).as_mat4(),
            };
        }
        up = scene.nodes[n]
            .parent
            .as_ref()
            .map(|p| p.element.typed_id as usize);
    }
    Bone {
        joint: None,
        bind: geometry_to_world.as_mat4(),
    }
}

/// Most corners of a polygon cut by ufbx's ear clipping, whose time grows with the square of
/// the corners (a 278 KB FBX of one 1,000,000-corner polygon ran past a minute). Below it the
/// cost is at most this many steps a corner; past it a polygon is cut into a fan.
const MAX_CLIPPED_CORNERS: usize = 1024;

/// The triangles of a fan over the polygon of `count` corners from `first` (indices into the
/// mesh's corners), replacing `out`.
fn fan(first: u32, count: u32, out: &mut Vec<u32>) {
    out.clear();
    for k in 1..count.saturating_sub(1) {
        out.extend([first, first + k, first + k + 1]);
    }
}

/// Every mesh instance of the scene on the skeleton; `joint` gives the skeleton joint each scene
/// node became, `turn` the turn the reader applies to the scene (FBX 5's unstated axes).
pub(super) fn read(
    scene: &ufbx::Scene,
    name: &str,
    bytes: u64,
    joint: &[Option<usize>],
    turn: DMat4,
) -> Result<(Mesh, Vec<String>), Error> {
    let mut reading = Reading {
        scene,
        name,
        joint,
        turn,
        builder: MeshBuilder::new(name, bytes),
        said: Vec::new(),
        dual_quaternion: 0,
        blend_shapes: 0,
        fans: 0,
    };
    for node in scene.nodes.iter() {
        let Some(mesh) = node.mesh.as_ref() else {
            continue;
        };
        reading.node(node, mesh)?;
    }
    Ok(reading.finish())
}

/// The meshes read so far, and what is said of them at the end.
struct Reading<'a> {
    scene: &'a ufbx::Scene,
    name: &'a str,
    joint: &'a [Option<usize>],
    turn: DMat4,
    builder: MeshBuilder,
    said: Vec<String>,
    /// Skins that ask for dual quaternion skinning.
    dual_quaternion: usize,
    /// Meshes with blend shapes.
    blend_shapes: usize,
    /// Polygons of more corners than ufbx's ear clipping is given, cut into fans.
    fans: usize,
}

impl Reading<'_> {
    /// The mesh of `node` as a part of its own: its bones (its first skin's clusters, or its
    /// node), its vertices with their weights, and its polygons cut into triangles.
    fn node(&mut self, node: &ufbx::Node, mesh: &ufbx::Mesh) -> Result<(), Error> {
        let builder = &mut self.builder;
        builder.begin_part(&mesh.element.name, false);
        builder.reserve((mesh.vertices.len() + mesh.num_triangles) as u64)?;
        // A vertex without weights stays where the bind pose put it.
        let fixed = Bone {
            joint: None,
            bind: (self.turn * matrix(&node.geometry_to_world)).as_mat4(),
        };
        if !mesh.blend_deformers.is_empty() {
            self.blend_shapes += 1;
        }
        let skin = mesh.skin_deformers.first();
        if mesh.skin_deformers.len() > 1 {
            self.said.push(format!(
                "mesh '{}' has {} skins: the first is used",
                crate::limits::quoted(&mesh.element.name),
                mesh.skin_deformers.len()
            ));
        }
        let clusters = self.bones(node, skin.map(|s| &**s))?;
        if let Some(skin) = skin {
            self.check_clusters(mesh, skin)?;
        }
        let first = self.builder.vertex_count();
        let triangles_from = self.builder.triangle_corner_count();
        for (v, position) in mesh.vertices.iter().enumerate() {
            let position = Vec3::new(position.x as f32, position.y as f32, position.z as f32);
            let influences: Vec<(u32, f32)> = match skin {
                None => vec![(clusters[0], 1.0)],
                Some(skin) => self.influences(mesh, skin, &clusters, v)?,
            };
            self.builder
                .vertex(position, Vec3::ZERO, influences, fixed)?;
        }
        self.triangles(mesh, first)?;
        self.builder.smooth_normals(first as usize, triangles_from);
        Ok(())
    }

    /// The bones a node's mesh binds to: one per cluster of its skin (a cluster without a bone
    /// moves nothing), or without a skin the one of its node (or the joint above it).
    fn bones(
        &mut self,
        node: &ufbx::Node,
        skin: Option<&ufbx::SkinDeformer>,
    ) -> Result<Vec<u32>, Error> {
        let (scene, joint, turn) = (self.scene, self.joint, self.turn);
        let Some(skin) = skin else {
            // A mesh without a skin moves with its node (or the joint above it).
            let n = node.element.typed_id as usize;
            let geometry_to_node =
                matrix(&node.node_to_world).inverse() * matrix(&node.geometry_to_world);
            let bone = bone_of(scene, joint, turn, n, geometry_to_node);
            return Ok(vec![self.builder.bone(bone)?]);
        };
        if skin.skinning_method != ufbx::SkinningMethod::Linear
            && skin.skinning_method != ufbx::SkinningMethod::Rigid
        {
            self.dual_quaternion += 1;
        }
        skin.clusters
            .iter()
            .map(|cluster| {
                let bone = match cluster.bone_node.as_ref() {
                    Some(bone) => bone_of(
                        scene,
                        joint,
                        turn,
                        bone.element.typed_id as usize,
                        matrix(&cluster.geometry_to_bone),
                    ),
                    // A cluster without a bone moves nothing.
                    None => Bone {
                        joint: None,
                        bind: (turn * matrix(&cluster.geometry_to_world)).as_mat4(),
                    },
                };
                self.builder.bone(bone)
            })
            .collect()
    }

    /// Refuses a skin whose clusters name vertices past the mesh's: ufbx leaves out a
    /// cluster's indices past the mesh's vertices (a negative one among them) without a word,
    /// and the weights the file gives there are lost.
    fn check_clusters(&self, mesh: &ufbx::Mesh, skin: &ufbx::SkinDeformer) -> Result<(), Error> {
        self.builder.reserve(skin.weights.len() as u64)?;
        for cluster in skin.clusters.iter() {
            let past = cluster
                .vertices
                .iter()
                .find(|&&v| v as usize >= mesh.vertices.len());
            if let Some(&v) = past {
                return Err(Error::decoding(
                    self.name,
                    format!(
                        "mesh '{}': skin cluster '{}' names vertex {}, past the mesh's \
                     {} vertices (the skin is damaged: export it again)",
                        crate::limits::quoted(&mesh.element.name),
                        crate::limits::quoted(&cluster.element.name),
                        v as i32,
                        mesh.vertices.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The bones and weights of vertex `v` of a skinned mesh, each weight's cluster one of
    /// the skin's.
    fn influences(
        &self,
        mesh: &ufbx::Mesh,
        skin: &ufbx::SkinDeformer,
        clusters: &[u32],
        v: usize,
    ) -> Result<Vec<(u32, f32)>, Error> {
        let name = self.name;
        let Some(vertex) = skin.vertices.get(v) else {
            return Err(Error::decoding(
                name,
                format!(
                    "mesh '{}' has {} vertices and its skin {}",
                    crate::limits::quoted(&mesh.element.name),
                    mesh.vertices.len(),
                    skin.vertices.len()
                ),
            ));
        };
        let begin = vertex.weight_begin as usize;
        let end = begin.saturating_add(vertex.num_weights as usize);
        let Some(weights) = skin.weights.get(begin..end) else {
            return Err(Error::decoding(
                name,
                format!(
                    "mesh '{}', vertex {v}: its weights lie past the skin's",
                    crate::limits::quoted(&mesh.element.name)
                ),
            ));
        };
        let mut out = Vec::with_capacity(weights.len());
        for weight in weights {
            let Some(&bone) = clusters.get(weight.cluster_index as usize) else {
                return Err(Error::decoding(
                    name,
                    format!(
                        "mesh '{}', vertex {v}: cluster {} of {}",
                        crate::limits::quoted(&mesh.element.name),
                        weight.cluster_index,
                        clusters.len()
                    ),
                ));
            };
            out.push((bone, weight.weight as f32));
        }
        Ok(out)
    }

    /// A mesh's polygons as triangles on its vertices from `first`: by ufbx's ear clipping,
    /// or cut into fans past [`MAX_CLIPPED_CORNERS`] corners.
    fn triangles(&mut self, mesh: &ufbx::Mesh, first: u32) -> Result<(), Error> {
        let mut corners = vec![
            0u32;
            mesh.max_face_triangles
                .min(MAX_CLIPPED_CORNERS)
                .saturating_mul(3)
        ];
        let mut fanned = Vec::new();
        for face in mesh.faces.iter() {
            if face.num_indices < 3 {
                continue;
            }
            let cut: &[u32] = if face.num_indices as usize > MAX_CLIPPED_CORNERS {
                self.fans += 1;
                fan(face.index_begin, face.num_indices, &mut fanned);
                &fanned
            } else {
                let triangles = mesh.triangulate_face(&mut corners, *face) as usize;
                &corners[..3 * triangles]
            };
            for t in cut.chunks_exact(3) {
                let mut vertices = [0u32; 3];
                for (slot, &index) in vertices.iter_mut().zip(t) {
                    let Some(&vertex) = mesh.vertex_indices.get(index as usize) else {
                        return Err(Error::decoding(
                            self.name,
                            format!(
                                "mesh '{}': a polygon corner past its indices",
                                crate::limits::quoted(&mesh.element.name)
                            ),
                        ));
                    };
                    *slot = first + vertex;
                }
                self.builder.triangle(vertices)?;
            }
        }
        Ok(())
    }

    /// The mesh, and what was said of it: the skins past the first, the builder's lines, then
    /// one line each for dual quaternion skins, polygons cut into fans and blend shapes.
    fn finish(self) -> (Mesh, Vec<String>) {
        let mut said = self.said;
        let (mesh, mut mended) = self.builder.finish();
        said.append(&mut mended);
        let (dual_quaternion, fans, blend_shapes) =
            (self.dual_quaternion, self.fans, self.blend_shapes);
        if dual_quaternion > 0 {
            said.push(format!(
                "{dual_quaternion} skins ask for dual quaternion skinning: drawn with linear blend \
                 skinning"
            ));
        }
        if fans > 0 {
            said.push(format!(
                "{} of more than {MAX_CLIPPED_CORNERS} corners cut into fans from their first corner \
                 (a concave one may be drawn wrong: cut it into smaller polygons)",
                crate::io::error::counted(fans, "polygon")
            ));
        }
        if blend_shapes > 0 {
            said.push(format!(
                "{blend_shapes} meshes have blend shapes: not applied"
            ));
        }
        (mesh, said)
    }
}
