//! An FBX's meshes as one [`Mesh`] on the skeleton the reader made, as ufbx gives them: each
//! mesh's vertices (ufbx's `vertices`, one per control point, as Blender's importer keeps them),
//! its polygons cut into triangles by ufbx, and its skin deformers' clusters with their
//! `geometry_to_bone` bind matrices and every weight (any number a vertex). A mesh without a
//! skin moves rigidly with the joint at or above its node, or stays where it stands.

use super::read::matrix;
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
    let mut builder = MeshBuilder::new(name, bytes);
    let mut said = Vec::new();
    let mut dual_quaternion = 0;
    let mut blend_shapes = 0;
    // Polygons of more corners than ufbx's ear clipping is given, cut into fans.
    let mut fans = 0;
    for node in scene.nodes.iter() {
        let Some(mesh) = node.mesh.as_ref() else {
            continue;
        };
        builder.begin_part(&mesh.element.name, false);
        let n = node.element.typed_id as usize;
        builder.reserve((mesh.vertices.len() + mesh.num_triangles) as u64)?;
        let geometry_to_node =
            matrix(&node.node_to_world).inverse() * matrix(&node.geometry_to_world);
        // A vertex without weights stays where the bind pose put it.
        let fixed = Bone {
            joint: None,
            bind: (turn * matrix(&node.geometry_to_world)).as_mat4(),
        };
        if !mesh.blend_deformers.is_empty() {
            blend_shapes += 1;
        }
        let skin = mesh.skin_deformers.first();
        if mesh.skin_deformers.len() > 1 {
            said.push(format!(
                "mesh '{}' has {} skins: the first is used",
                crate::limits::quoted(&mesh.element.name),
                mesh.skin_deformers.len()
            ));
        }
        let clusters: Vec<u32> = match skin {
            Some(skin) => {
                if skin.skinning_method != ufbx::SkinningMethod::Linear
                    && skin.skinning_method != ufbx::SkinningMethod::Rigid
                {
                    dual_quaternion += 1;
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
                        builder.bone(bone)
                    })
                    .collect::<Result<_, _>>()?
            }
            // A mesh without a skin moves with its node (or the joint above it).
            None => vec![builder.bone(bone_of(scene, joint, turn, n, geometry_to_node))?],
        };
        if let Some(skin) = skin {
            builder.reserve(skin.weights.len() as u64)?;
            // ufbx leaves out a cluster's indices past the mesh's vertices (a negative one
            // among them) without a word: the weights the file gives there are lost.
            for cluster in skin.clusters.iter() {
                let past = cluster
                    .vertices
                    .iter()
                    .find(|&&v| v as usize >= mesh.vertices.len());
                if let Some(&v) = past {
                    return Err(Error::Usage(format!(
                        "{name}: mesh '{}': skin cluster '{}' names vertex {}, past the mesh's \
                         {} vertices (the skin is damaged: export it again)",
                        crate::limits::quoted(&mesh.element.name),
                        crate::limits::quoted(&cluster.element.name),
                        v as i32,
                        mesh.vertices.len()
                    )));
                }
            }
        }
        let first = builder.vertex_count();
        let triangles_from = builder.triangle_corner_count();
        for (v, position) in mesh.vertices.iter().enumerate() {
            let position = Vec3::new(position.x as f32, position.y as f32, position.z as f32);
            let influences: Vec<(u32, f32)> = match skin {
                None => vec![(clusters[0], 1.0)],
                Some(skin) => {
                    let Some(vertex) = skin.vertices.get(v) else {
                        return Err(Error::Usage(format!(
                            "{name}: mesh '{}' has {} vertices and its skin {}",
                            crate::limits::quoted(&mesh.element.name),
                            mesh.vertices.len(),
                            skin.vertices.len()
                        )));
                    };
                    let begin = vertex.weight_begin as usize;
                    let end = begin.saturating_add(vertex.num_weights as usize);
                    let Some(weights) = skin.weights.get(begin..end) else {
                        return Err(Error::Usage(format!(
                            "{name}: mesh '{}', vertex {v}: its weights lie past the skin's",
                            crate::limits::quoted(&mesh.element.name)
                        )));
                    };
                    let mut out = Vec::with_capacity(weights.len());
                    for weight in weights {
                        let Some(&bone) = clusters.get(weight.cluster_index as usize) else {
                            return Err(Error::Usage(format!(
                                "{name}: mesh '{}', vertex {v}: cluster {} of {}",
                                crate::limits::quoted(&mesh.element.name),
                                weight.cluster_index,
                                clusters.len()
                            )));
                        };
                        out.push((bone, weight.weight as f32));
                    }
                    out
                }
            };
            builder.vertex(position, Vec3::ZERO, influences, fixed)?;
        }
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
                fans += 1;
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
                        return Err(Error::Usage(format!(
                            "{name}: mesh '{}': a polygon corner past its indices",
                            crate::limits::quoted(&mesh.element.name)
                        )));
                    };
                    *slot = first + vertex;
                }
                builder.triangle(vertices)?;
            }
        }
        builder.smooth_normals(first as usize, triangles_from);
    }
    let (mesh, mut mended) = builder.finish();
    said.append(&mut mended);
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
    Ok((mesh, said))
}
