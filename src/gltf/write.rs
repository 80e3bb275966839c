//! glTF 2.0 out (`bvhview convert IN -o OUT.glb|.gltf`): one node per joint and End Site in
//! pre-order, the OFFSET as each node's translation, and one animation: a single time accessor
//! (frame i at i × Frame Time, reckoned in f64), a rotation track per joint with rotation
//! channels (the channels' product in file order as a unit quaternion; an ASF bone's C·R·C⁻¹),
//! and a translation track per joint with position channels (bvhview's offset mode). With a skin,
//! the viewer's generated skin as a mesh bound to the joint nodes. Built with the gltf-json crate.

use super::container::Container;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::bone_skin::Body;
use crate::model::mesh::Mesh;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, joint_translation, local_rotation};
use crate::model::skeleton::Skeleton;
use crate::model::skeleton::export_name;
use gltf_json as json;
use json::validation::{Checked, USize64};

/// The binary data and the accessors that read it.
struct Data {
    bytes: Vec<u8>,
    root: json::Root,
    buffer: json::Index<json::Buffer>,
    /// What the first value that is not finite belonged to: glTF (JSON) has no infinity, and
    /// a reader refuses the file.
    not_finite: Option<&'static str>,
}

impl Data {
    /// Appends floats as one view and an accessor of `count` elements of `kind`.
    fn accessor(
        &mut self,
        values: &[f32],
        count: usize,
        kind: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        if self.not_finite.is_none() && !values.iter().all(|v| v.is_finite()) {
            self.not_finite = Some("an animation or skin value");
        }
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let bounds = min_max.map(|(min, max)| (json::Value::from(min), json::Value::from(max)));
        self.raw_accessor(
            &bytes,
            json::accessor::ComponentType::F32,
            count,
            kind,
            bounds,
            target,
        )
    }

    /// Appends `bytes` (4-byte aligned) as one view and an accessor over it.
    fn raw_accessor(
        &mut self,
        bytes: &[u8],
        component: json::accessor::ComponentType,
        count: usize,
        kind: json::accessor::Type,
        bounds: Option<(json::Value, json::Value)>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(bytes);
        let view = self.root.push(json::buffer::View {
            buffer: self.buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            target: target.map(Checked::Valid),
        });
        let (min, max) = match bounds {
            Some((min, max)) => (Some(min), Some(max)),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: Default::default(),
            extras: Default::default(),
            type_: Checked::Valid(kind),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Appends a mesh's vertex places as one accessor with their bounds, as glTF asks of
    /// `POSITION`.
    fn positions(&mut self, points: &[glam::Vec3]) -> json::Index<json::Accessor> {
        let positions: Vec<f32> = points.iter().flat_map(|p| p.to_array()).collect();
        let (lo, hi) = points.iter().fold(
            (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        self.accessor(
            &positions,
            points.len(),
            json::accessor::Type::Vec3,
            Some((lo.to_array().to_vec(), hi.to_array().to_vec())),
            Some(json::buffer::Target::ArrayBuffer),
        )
    }

    /// Appends a mesh's triangle corners (`count` of them) as one accessor of indices.
    fn indices(&mut self, bytes: &[u8], count: usize) -> json::Index<json::Accessor> {
        self.raw_accessor(
            bytes,
            json::accessor::ComponentType::U32,
            count,
            json::accessor::Type::Scalar,
            None,
            Some(json::buffer::Target::ElementArrayBuffer),
        )
    }

    /// Appends one skinned mesh named `name`: its triangles with `attributes`, a skin of
    /// `joints` with `inverse_bind`, and a node in the scene that holds both.
    fn skinned_node(
        &mut self,
        name: &str,
        attributes: Vec<(json::mesh::Semantic, json::Index<json::Accessor>)>,
        indices: json::Index<json::Accessor>,
        inverse_bind: json::Index<json::Accessor>,
        joints: Vec<json::Index<json::Node>>,
        targets: Vec<json::Index<json::Accessor>>,
    ) -> json::Index<json::Node> {
        let weights = (!targets.is_empty()).then(|| vec![0.0; targets.len()]);
        let targets = (!targets.is_empty()).then(|| {
            targets
                .into_iter()
                .map(|positions| json::mesh::MorphTarget {
                    positions: Some(positions),
                    normals: None,
                    tangents: None,
                })
                .collect()
        });
        let primitive = json::mesh::Primitive {
            attributes: attributes
                .into_iter()
                .map(|(semantic, accessor)| (Checked::Valid(semantic), accessor))
                .collect(),
            extensions: Default::default(),
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets,
        };
        let mesh = self.root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(name.to_string()),
            primitives: vec![primitive],
            weights,
        });
        let skin = self.root.push(json::Skin {
            extensions: Default::default(),
            extras: Default::default(),
            inverse_bind_matrices: Some(inverse_bind),
            joints,
            name: Some(name.to_string()),
            skeleton: None,
        });
        let node = self.root.push(json::Node {
            name: Some(name.to_string()),
            mesh: Some(mesh),
            skin: Some(skin),
            ..Default::default()
        });
        if let Some(scene) = self.root.scenes.first_mut() {
            scene.nodes.push(node);
        }
        node
    }

    /// The generated skin (`render::body`) as a mesh on a root node, bound to every joint node
    /// by a glTF skin whose inverse bind matrices are the body's own.
    fn skin(&mut self, skeleton: &Skeleton, mode: OffsetMode) -> Result<(), Error> {
        let joints = skeleton.joints.len();
        if joints > usize::from(u16::MAX) {
            return Err(Error::limit(
                "joints",
                u16::MAX.into(),
                joints as u64,
                format!(
                    "cannot write a glTF skin for {joints} joints: at most {} fit",
                    u16::MAX
                ),
            ));
        }
        let body = Body::new(skeleton, mode);
        let vertices = &body.skin.vertices;
        if vertices.is_empty() || body.indices.is_empty() {
            return Err(Error::usage(
                "cannot write a glTF skin: the skeleton has no bone long enough to wrap",
            ));
        }
        let count = vertices.len();
        let array = Some(json::buffer::Target::ArrayBuffer);
        let points: Vec<glam::Vec3> = vertices.iter().map(|v| v.position).collect();
        let position = self.positions(&points);
        let normals: Vec<f32> = vertices
            .iter()
            .flat_map(|v| v.normal.normalize().to_array())
            .collect();
        let normal = self.accessor(&normals, count, json::accessor::Type::Vec3, None, array);
        // Unused influence slots get joint 0 with weight 0, as the format asks.
        let joint_bytes: Vec<u8> = vertices
            .iter()
            .flat_map(|v| v.influences.iter())
            .flat_map(|&(bone, weight)| {
                let bone = if weight > 0.0 { bone as u16 } else { 0 };
                bone.to_le_bytes()
            })
            .collect();
        let joints_0 = self.raw_accessor(
            &joint_bytes,
            json::accessor::ComponentType::U16,
            count,
            json::accessor::Type::Vec4,
            None,
            array,
        );
        let weights: Vec<f32> = vertices
            .iter()
            .flat_map(|v| v.influences.iter().map(|&(_, weight)| weight))
            .collect();
        let weights_0 = self.accessor(&weights, count, json::accessor::Type::Vec4, None, array);
        let index_bytes: Vec<u8> = body.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = self.indices(&index_bytes, body.indices.len());
        let inverse: Vec<f32> = body
            .skin
            .inverse_bind
            .iter()
            .flat_map(|m| m.to_cols_array())
            .collect();
        let inverse_bind = self.accessor(&inverse, joints, json::accessor::Type::Mat4, None, None);
        let attributes = vec![
            (json::mesh::Semantic::Positions, position),
            (json::mesh::Semantic::Normals, normal),
            (json::mesh::Semantic::Joints(0), joints_0),
            (json::mesh::Semantic::Weights(0), weights_0),
        ];
        let joints = (0..joints).map(|j| json::Index::new(j as u32)).collect();
        self.skinned_node(
            "skin",
            attributes,
            indices,
            inverse_bind,
            joints,
            Vec::new(),
        );
        Ok(())
    }

    /// A character's mesh ([`Mesh`]), bound to the joint nodes: each of its parts (the meshes
    /// of the file it was read from) one mesh node with a skin of its own whose inverse bind
    /// matrices are the part's bind matrices, each vertex's strongest
    /// [`crate::model::mesh::MAX_WRITTEN_INFLUENCES`] influences written (four a `JOINTS_n` /
    /// `WEIGHTS_n` pair, as many pairs as the vertex with the most needs). A bone bound to no
    /// joint is bound to one extra node at the origin.
    fn character(
        &mut self,
        skeleton: &Skeleton,
        mesh: &Mesh,
        shapes: Option<&BlendWeights>,
    ) -> Result<Morphed, Error> {
        mesh.check()
            .map_err(|why| Error::usage(format!("cannot write the mesh: {why}")))?;
        let mut morphed = Vec::new();
        let mut fixed_node: Option<json::Index<json::Node>> = None;
        for k in 0..mesh.parts.len() {
            let (vertices, corners, bones) = mesh.part_ranges(k);
            if vertices.is_empty() || corners.is_empty() {
                continue;
            }
            if bones.len() > usize::from(u16::MAX) {
                return Err(Error::limit(
                    "bones",
                    u16::MAX.into(),
                    bones.len() as u64,
                    format!(
                        "cannot write a glTF skin of {} bones: at most {} fit",
                        bones.len(),
                        u16::MAX
                    ),
                ));
            }
            let count = vertices.len();
            let position = self.positions(&mesh.positions[vertices.clone()]);
            let normals: Vec<f32> = mesh.normals[vertices.clone()]
                .iter()
                .map(|n| n.try_normalize().unwrap_or(glam::Vec3::Y))
                .flat_map(|n| n.to_array())
                .collect();
            let array = Some(json::buffer::Target::ArrayBuffer);
            let normal = self.accessor(&normals, count, json::accessor::Type::Vec3, None, array);
            let mut attributes = vec![
                (json::mesh::Semantic::Positions, position),
                (json::mesh::Semantic::Normals, normal),
            ];
            attributes.extend(self.influences(mesh, vertices.clone(), bones.clone()));
            let index_bytes: Vec<u8> = mesh.triangles[corners.clone()]
                .iter()
                .flat_map(|&c| (c - vertices.start as u32).to_le_bytes())
                .collect();
            let indices = self.indices(&index_bytes, corners.len());
            let inverse: Vec<f32> = mesh.bones[bones.clone()]
                .iter()
                .flat_map(|b| b.bind.to_cols_array())
                .collect();
            let inverse_bind = self.accessor(
                &inverse,
                bones.len(),
                json::accessor::Type::Mat4,
                None,
                None,
            );
            let joints = self.part_joints(skeleton, &mesh.bones[bones], &mut fixed_node)?;
            // The pose blend shapes of a body model (its one part) as morph targets: one a
            // feature, its weights animated with the take.
            let blend = mesh
                .pose_blend
                .as_deref()
                .filter(|b| vertices.start == 0 && b.vertex_count() >= vertices.end)
                .zip(shapes.filter(|s| !s.targets.is_empty()));
            let targets = match blend {
                Some((blend, shapes)) => self.blend_targets(blend, shapes, vertices.clone()),
                None => Vec::new(),
            };
            let node = self.skinned_node(
                &format!("mesh{k}"),
                attributes,
                indices,
                inverse_bind,
                joints,
                targets,
            );
            if let Some((_, shapes)) = blend {
                morphed.push((node, shapes.weights.clone()));
            }
        }
        Ok(morphed)
    }

    /// The morph targets of `blend` that `shapes` weighs: each vertex's offset for a feature,
    /// or its opposite.
    fn blend_targets(
        &mut self,
        blend: &crate::model::mesh::PoseBlend,
        shapes: &BlendWeights,
        vertices: std::ops::Range<usize>,
    ) -> Vec<json::Index<json::Accessor>> {
        let width = 9 * blend.joints.len();
        shapes
            .targets
            .iter()
            .map(|&(feature, sign)| {
                let offsets: Vec<glam::Vec3> = vertices
                    .clone()
                    .map(|v| {
                        let at = |axis: usize| blend.dirs[(3 * v + axis) * width + feature];
                        glam::Vec3::new(at(0), at(1), at(2)) * sign
                    })
                    .collect();
                self.positions(&offsets)
            })
            .collect()
    }

    /// The `JOINTS_n` / `WEIGHTS_n` accessors of one part of a character's mesh: each vertex's
    /// strongest influences, four a pair, as many pairs as the vertex with the most needs
    /// (unused slots: joint 0 of weight 0, as the format asks).
    fn influences(
        &mut self,
        mesh: &Mesh,
        vertices: std::ops::Range<usize>,
        bones: std::ops::Range<usize>,
    ) -> Vec<(json::mesh::Semantic, json::Index<json::Accessor>)> {
        let array = Some(json::buffer::Target::ArrayBuffer);
        let count = vertices.len();
        let most = crate::model::mesh::MAX_WRITTEN_INFLUENCES;
        let sets = vertices
            .clone()
            .map(|v| mesh.influences_of(v).len().min(most))
            .max()
            .unwrap_or(1)
            .div_ceil(4)
            .max(1);
        // Each vertex's strongest influences, `4 * sets` slots a vertex (unused: joint 0
        // of weight 0, as the format asks).
        let unused = crate::model::mesh::Influence {
            bone: bones.start as u32,
            weight: 0.0,
        };
        let mut written = Vec::with_capacity(count * 4 * sets);
        let mut kept = Vec::new();
        for v in vertices {
            crate::model::mesh::strongest(mesh.influences_of(v), most, &mut kept);
            kept.resize(4 * sets, unused);
            written.extend_from_slice(&kept);
        }
        let mut attributes = Vec::with_capacity(2 * sets);
        for set in 0..sets {
            let (mut joints, mut weights) = (Vec::new(), Vec::new());
            for slots in written.chunks_exact(4 * sets) {
                for i in &slots[4 * set..4 * set + 4] {
                    joints.extend(((i.bone as usize - bones.start) as u16).to_le_bytes());
                    weights.push(i.weight);
                }
            }
            let joints = self.raw_accessor(
                &joints,
                json::accessor::ComponentType::U16,
                count,
                json::accessor::Type::Vec4,
                None,
                array,
            );
            let weights = self.accessor(&weights, count, json::accessor::Type::Vec4, None, array);
            attributes.push((json::mesh::Semantic::Joints(set as u32), joints));
            attributes.push((json::mesh::Semantic::Weights(set as u32), weights));
        }
        attributes
    }

    /// The nodes a part's skin names, one per bone: the bone's joint node, a helper child node
    /// of it where the joint is bound twice, or (bound to no joint) a node at the origin,
    /// `fixed_node`, shared by the parts while none names it twice.
    fn part_joints(
        &mut self,
        skeleton: &Skeleton,
        bones: &[crate::model::mesh::Bone],
        fixed_node: &mut Option<json::Index<json::Node>>,
    ) -> Result<Vec<json::Index<json::Node>>, Error> {
        let mut joints: Vec<json::Index<json::Node>> = Vec::with_capacity(bones.len());
        for bone in bones {
            joints.push(match bone.joint {
                // A joint bound twice in one part (two clusters on one bone) is bound the
                // second time through a child node of its own at the joint (a skin names
                // each node once).
                Some(j) if joints.contains(&json::Index::new(j as u32)) => {
                    let helper = self.root.push(json::Node {
                        name: Some(format!("{}_bind", export_name(skeleton, j))),
                        ..Default::default()
                    });
                    let node = &mut self.root.nodes[j];
                    node.children.get_or_insert_with(Vec::new).push(helper);
                    helper
                }
                Some(j) if j < skeleton.joints.len() => json::Index::new(j as u32),
                Some(j) => {
                    return Err(Error::usage(format!(
                        "cannot write the mesh: a bone of joint {j} of {}",
                        skeleton.joints.len()
                    )));
                }
                // Bones bound to no joint: a node at the origin, another for each more in one
                // part (a skin names each node once).
                None => match fixed_node.filter(|node| !joints.contains(node)) {
                    Some(node) => node,
                    None => {
                        let node = self.root.push(json::Node {
                            name: Some("mesh_origin".to_string()),
                            ..Default::default()
                        });
                        if let Some(scene) = self.root.scenes.first_mut() {
                            scene.nodes.push(node);
                        }
                        *fixed_node = Some(node);
                        node
                    }
                },
            });
        }
        Ok(joints)
    }
}

/// The skeleton and its motion as glTF: the bytes of the `.glb` or `.gltf` file.
pub fn to_gltf(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    container: Container,
    with_skin: bool,
) -> Result<Vec<u8>, Error> {
    let skin = if with_skin {
        Skin::Generated
    } else {
        Skin::None
    };
    write(skeleton, motion, mode, container, skin)
}

/// A character's take as glTF: the skeleton and motion as [`to_gltf`] writes them, and the
/// character's mesh bound to the joint nodes (see [`crate::character`]). Its vertices move in
/// any glTF viewer as bvhview skins them.
pub fn to_gltf_character(
    skeleton: &Skeleton,
    motion: &Motion,
    mesh: &Mesh,
    container: Container,
) -> Result<Vec<u8>, Error> {
    write(
        skeleton,
        motion,
        OffsetMode::Replace,
        container,
        Skin::Mesh(mesh),
    )
}

/// The mesh nodes whose morph targets are a body model's pose blend shapes, with their weights
/// (frame after frame).
type Morphed = Vec<(json::Index<json::Node>, Vec<f32>)>;

/// A body model's pose blend shapes as a take weighs them, for morph targets. Each feature
/// (`R − I`, an entry of a joint's rotation) is written as a target where the take moves it
/// above zero and as its opposite where below, each weighed by that part of the feature:
/// every weight is then from 0 to 2 (Blender's importer clamps negative weights to 0), and a
/// reader that ignores morph targets sees the body's shaped rest mesh.
struct BlendWeights {
    /// Each target: its feature and sign.
    targets: Vec<(usize, f32)>,
    /// Each frame's weights, one a target.
    weights: Vec<f32>,
}

impl BlendWeights {
    /// The weights of `blend` over `motion`'s frames of `skeleton`.
    fn of(
        blend: &crate::model::mesh::PoseBlend,
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
    ) -> BlendWeights {
        let mut world = Vec::new();
        let features: Vec<Vec<f32>> = (0..motion.frame_count())
            .map(|frame| {
                crate::model::pose::world_matrices(skeleton, motion.frame(frame), mode, &mut world);
                blend.features(&world)
            })
            .collect();
        let width = 9 * blend.joints.len();
        let mut targets = Vec::new();
        for feature in 0..width {
            for sign in [1.0f32, -1.0] {
                if features.iter().any(|f| f[feature] * sign > 0.0) {
                    targets.push((feature, sign));
                }
            }
        }
        let weights = features
            .iter()
            .flat_map(|f| targets.iter().map(|&(k, sign)| (f[k] * sign).max(0.0)))
            .collect();
        BlendWeights { targets, weights }
    }
}

/// What skin a glTF carries.
enum Skin<'a> {
    None,
    /// The viewer's generated skin.
    Generated,
    /// A character's own mesh.
    Mesh(&'a Mesh),
}

/// The glTF file of a skeleton, its motion and its skin, as `container` holds it. Each step
/// appends to one [`Data`]: the nodes, the skin, the animation, then the file.
fn write(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    container: Container,
    skin: Skin,
) -> Result<Vec<u8>, Error> {
    let mut data = Data::new();
    data.nodes(skeleton);
    let morphed = match skin {
        Skin::None => Vec::new(),
        Skin::Generated => {
            data.skin(skeleton, mode)?;
            Vec::new()
        }
        Skin::Mesh(mesh) => {
            let shapes = mesh
                .pose_blend
                .as_deref()
                .map(|blend| BlendWeights::of(blend, skeleton, motion, mode));
            data.character(skeleton, mesh, shapes.as_ref())?
        }
    };
    data.animation(skeleton, motion, mode, &morphed)?;
    data.file(container)
}

impl Data {
    /// No data yet: one buffer, and the generator said.
    fn new() -> Data {
        let mut data = Data {
            bytes: Vec::new(),
            root: json::Root::default(),
            buffer: json::Index::new(0),
            not_finite: None,
        };
        data.root.asset.generator = Some(format!("bvhview {}", env!("CARGO_PKG_VERSION")));
        data.buffer = data.root.push(json::Buffer {
            byte_length: USize64(0),
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            uri: None,
        });
        data
    }

    /// One node per joint and End Site in pre-order, so a joint's index is its node's, each at
    /// its OFFSET; and the scene of the roots.
    fn nodes(&mut self, skeleton: &Skeleton) {
        for (index, joint) in skeleton.joints.iter().enumerate() {
            if !joint.offset.is_finite() {
                self.not_finite.get_or_insert("an OFFSET");
            }
            let children = joint
                .children
                .iter()
                .map(|&c| json::Index::new(c as u32))
                .collect::<Vec<_>>();
            self.root.push(json::Node {
                name: Some(export_name(skeleton, index)),
                translation: Some(joint.offset.to_array()),
                children: (!children.is_empty()).then_some(children),
                ..Default::default()
            });
        }
        let roots = skeleton
            .roots()
            .map(|r| json::Index::new(r as u32))
            .collect();
        let scene = self.root.push(json::Scene {
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            nodes: roots,
        });
        self.root.scene = Some(scene);
    }

    /// The take as one animation (none for a take of no frames, or without channels): one time
    /// accessor, then a rotation track per joint with rotation channels and a translation
    /// track per joint with position channels.
    fn animation(
        &mut self,
        skeleton: &Skeleton,
        motion: &Motion,
        mode: OffsetMode,
        morphed: &Morphed,
    ) -> Result<(), Error> {
        let frames = motion.frame_count();
        if frames == 0 {
            return Ok(());
        }
        let times: Vec<f32> = (0..frames)
            .map(|i| (i as f64 * motion.frame_time) as f32)
            .collect();
        // glTF wants keyframe times that rise strictly: a frame time of 0 (which BVH allows) or
        // one too small for f32 at the take's length cannot be written as it is.
        if let Some(i) = times
            .windows(2)
            .position(|w| !(w[1] > w[0] && w[1].is_finite()))
        {
            return Err(Error::usage(
                Message::from(format!(
                    "cannot write glTF: with a frame time of {} s frames {i} and {} fall at the \
                     same time ({} s); give the take its rate with ",
                    crate::limits::show(motion.frame_time),
                    i + 1,
                    crate::limits::show(times[i + 1])
                ))
                .argument("frame_time", Some("SECONDS")),
            ));
        }
        let last = *times.last().expect("frames > 0");
        let time = self.accessor(
            &times,
            frames,
            json::accessor::Type::Scalar,
            Some((vec![0.0], vec![last])),
            None,
        );
        let mut tracks = Tracks {
            time,
            frames,
            channels: Vec::new(),
            samplers: Vec::new(),
        };
        for (index, joint) in skeleton.joints.iter().enumerate() {
            if joint.channels.iter().any(|c| c.is_rotation()) {
                let mut values = Vec::with_capacity(frames * 4);
                for frame in 0..frames {
                    let matrix = local_rotation(joint, joint.values(motion.frame(frame)));
                    let q = glam::Quat::from_mat4(&matrix).normalize();
                    values.extend(q.to_array());
                }
                tracks.push(self, index, values, true);
            }
            if joint.channels.iter().any(|c| c.is_position()) {
                let mut values = Vec::with_capacity(frames * 3);
                for frame in 0..frames {
                    let t = joint_translation(joint, joint.values(motion.frame(frame)), mode);
                    values.extend(t.to_array());
                }
                tracks.push(self, index, values, false);
            }
        }
        for (node, weights) in morphed {
            tracks.push_weights(self, *node, weights.clone());
        }
        if !tracks.channels.is_empty() {
            self.root.push(json::Animation {
                extensions: Default::default(),
                extras: Default::default(),
                channels: tracks.channels,
                name: Some("take".to_string()),
                samplers: tracks.samplers,
            });
        }
        Ok(())
    }

    /// The file's bytes: the JSON with its buffer inline as base64 (`.gltf`), or the JSON and
    /// the buffer as a GLB's two chunks. A value that is not finite is refused here.
    fn file(mut self, container: Container) -> Result<Vec<u8>, Error> {
        // JSON has no infinity: a take whose values overflow 32-bit floats is refused, not
        // written with `null`s that no reader loads.
        if let Some(what) = self.not_finite {
            return Err(Error::usage(format!(
                "cannot write glTF: {what} is not finite (too large for a 32-bit float)"
            )));
        }
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        let length = self.bytes.len();
        self.root.buffers[0].byte_length = USize64::from(length);
        if length == 0 {
            // No data at all (a rest pose): no buffer either.
            self.root.buffers.clear();
        }
        let serialised = |root: &json::Root| {
            root.to_vec()
                .map_err(|e| Error::usage(format!("cannot write glTF: {e}")))
        };
        match container {
            Container::Gltf => {
                if length > 0 {
                    self.root.buffers[0].uri = Some(format!(
                        "data:application/octet-stream;base64,{}",
                        base64(&self.bytes)
                    ));
                }
                serialised(&self.root)
            }
            Container::Glb => {
                let mut text = serialised(&self.root)?;
                while !text.len().is_multiple_of(4) {
                    text.push(b' ');
                }
                let total = 12 + 8 + text.len() + if length > 0 { 8 + length } else { 0 };
                let mut out = Vec::with_capacity(total);
                out.extend_from_slice(b"glTF");
                out.extend_from_slice(&2u32.to_le_bytes());
                out.extend_from_slice(&(total as u32).to_le_bytes());
                out.extend_from_slice(&(text.len() as u32).to_le_bytes());
                out.extend_from_slice(b"JSON");
                out.extend_from_slice(&text);
                if length > 0 {
                    out.extend_from_slice(&(length as u32).to_le_bytes());
                    out.extend_from_slice(b"BIN\0");
                    out.extend_from_slice(&self.bytes);
                }
                Ok(out)
            }
        }
    }
}

/// The animation being written: its one time accessor over `frames` frames, and a sampler and
/// a channel per track.
struct Tracks {
    time: json::Index<json::Accessor>,
    frames: usize,
    channels: Vec<json::animation::Channel>,
    samplers: Vec<json::animation::Sampler>,
}

impl Tracks {
    /// A track of `node`: its values per frame (rotations as quaternions, or translations)
    /// as one accessor, sampled linearly.
    fn push(&mut self, data: &mut Data, node: usize, values: Vec<f32>, rotation: bool) {
        let (kind, property) = if rotation {
            (
                json::accessor::Type::Vec4,
                json::animation::Property::Rotation,
            )
        } else {
            (
                json::accessor::Type::Vec3,
                json::animation::Property::Translation,
            )
        };
        let output = data.accessor(&values, self.frames, kind, None, None);
        self.channel(node as u32, output, property);
    }

    /// The morph target weights of the mesh `node`, all of a frame after another's.
    fn push_weights(&mut self, data: &mut Data, node: json::Index<json::Node>, values: Vec<f32>) {
        let count = values.len();
        let output = data.accessor(&values, count, json::accessor::Type::Scalar, None, None);
        self.channel(
            node.value() as u32,
            output,
            json::animation::Property::MorphTargetWeights,
        );
    }

    /// A linear sampler of `output` over the take's times, and its channel to `node`.
    fn channel(
        &mut self,
        node: u32,
        output: json::Index<json::Accessor>,
        property: json::animation::Property,
    ) {
        self.samplers.push(json::animation::Sampler {
            extensions: Default::default(),
            extras: Default::default(),
            input: self.time,
            interpolation: Checked::Valid(json::animation::Interpolation::Linear),
            output,
        });
        self.channels.push(json::animation::Channel {
            sampler: json::Index::new(self.samplers.len() as u32 - 1),
            target: json::animation::Target {
                extensions: Default::default(),
                extras: Default::default(),
                node: json::Index::new(node),
                path: Checked::Valid(property),
            },
            extensions: Default::default(),
            extras: Default::default(),
        });
    }
}

/// Standard base64 with padding, for a `.gltf` file's inline buffer.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for group in bytes.chunks(3) {
        let b = [
            group[0],
            *group.get(1).unwrap_or(&0),
            *group.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= group.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_is_the_standard_alphabet_with_padding() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }
}
