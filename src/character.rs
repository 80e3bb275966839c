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
use crate::io::message::Message;
use crate::model::mesh::Mesh;
use crate::model::pose::{OffsetMode, world_matrices};
use crate::model::skeleton::Skeleton;
use crate::retarget::{Check, Insist};
use crate::smpl::model::BodyModel;
use crate::take::{Format, OpenOptions, Take};
use glam::{Mat4, Vec3};
use std::io::Write;
use std::path::Path;
use std::sync::Arc;

/// A skinned mesh and the take of its file.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// # #[cfg(all(feature = "fbx", feature = "gltf"))]
/// # {
/// use bvhview::{Take, character::Character};
///
/// let capsule = Character::open("tests/data/characters/capsule_mixamo.glb")?;
/// // A CMU walk put on capsule man (Mixamo's names): retargeted by role, then skinned.
/// let walk = Take::open("tests/data/bvh/bvh11_131_01.bvh")?.trim(0..10);
/// let (dressed, said) = capsule.dress(&walk, &[], Default::default(), 1)?;
/// assert_eq!(dressed.skeleton, capsule.take.skeleton);
/// assert!(said.check.unwrap().refusal().is_none());
/// let vertices = capsule.vertices(&dressed.skeleton, dressed.frame(9).unwrap());
/// assert_eq!(vertices.len(), capsule.mesh.vertex_count());
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Character {
    /// The skeleton the mesh is bound to, with the file's own take (or its rest pose).
    pub take: Take,
    /// The mesh, bound to `take.skeleton`'s joints.
    pub mesh: Mesh,
    /// The body model it was made of, and whether its betas were given (else an AMASS take
    /// put on it lends its own).
    body: Option<(Arc<BodyModel>, bool)>,
}

/// What [`Character::dress`] says of a take it put on a character: the retarget's check of
/// the result against the take, what was kept only because the caller insisted, and what the
/// map could not carry. Empty for a take of the character's own skeleton (nothing retargeted).
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// # #[cfg(feature = "gltf")]
/// # {
/// use bvhview::{Take, character::Character};
///
/// let capsule = Character::open("tests/data/characters/capsule_mixamo.glb")?;
/// let walk = Take::open("tests/data/bvh/bvh11_131_01.bvh")?.trim(0..10);
/// let (_, said) = capsule.dress(&walk, &[], Default::default(), 1)?;
/// assert!(said.warnings("walk", "capsule").is_empty());
/// assert!(said.check.unwrap().line().starts_with("check: sides held"));
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dressed {
    /// The result measured against the take, when it was retargeted.
    pub check: Option<Check>,
    /// Why the check refuses the result, when the caller's `force` kept it anyway.
    pub forced: Option<String>,
    /// What the map could not carry ([`crate::retarget::Retargeted::uncarried`]).
    pub uncarried: Vec<String>,
}

impl Dressed {
    /// Its warnings for a user, each a whole line (`TAKE: warning: …`).
    pub fn warnings(&self, take_name: &str, character_name: &str) -> Vec<Message> {
        let mut lines: Vec<Message> = self
            .uncarried
            .iter()
            .map(|why| format!("{take_name}: warning: {why}").into())
            .collect();
        if let Some(why) = &self.forced {
            lines.push(
                Message::from(format!(
                    "{take_name} onto {character_name}: warning: kept as "
                ))
                .argument("force", None)
                .text(format!(" asks though {why}")),
            );
        }
        lines
    }
}

impl Character {
    /// Opens a character from an `.fbx`, `.glb` or `.gltf` file with at least one mesh.
    pub fn open(path: impl AsRef<Path>) -> Result<Character, Error> {
        Character::open_with(path.as_ref(), &OpenOptions::new())
    }

    /// [`Character::open`] with `options`: the file's take (name or index), a size limit,
    /// threads.
    pub fn open_with(path: &Path, options: &OpenOptions) -> Result<Character, Error> {
        Character::open_if_any(path, options)?.ok_or_else(|| {
            Error::usage(format!(
                "{}: no mesh to draw (a character needs a mesh with triangles)",
                path.display()
            ))
        })
    }

    /// [`Character::open_with`], or `None` for a file without a mesh with triangles (a take
    /// alone): what `convert CHAR.fbx -o copy.fbx` asks to keep a file's mesh.
    pub fn open_if_any(path: &Path, options: &OpenOptions) -> Result<Option<Character>, Error> {
        let max_size = options.max_size_or_default();
        crate::take::check_file(path, max_size)?;
        let (read, mesh, format) = match Format::from_path(path) {
            Some(Format::Fbx) => {
                let (read, mesh) = crate::fbx::load_character(path, options)?;
                (read, mesh, Format::Fbx)
            }
            Some(Format::Gltf) => {
                let (read, mesh) = crate::gltf::load_character(path, options)?;
                (read, mesh, Format::Gltf)
            }
            Some(Format::Amass) => {
                let model = crate::smpl::open_model(path, None, None, max_size)?;
                let betas = options.betas.as_deref();
                return Character::from_body_model(model, betas, &[]).map(Some);
            }
            _ => {
                return Err(Error::usage(format!(
                    "{}: a character is an FBX or glTF file (.fbx, .glb, .gltf) with a skinned \
                     mesh, or a SMPL-family model file (.npz)",
                    path.display()
                )));
            }
        };
        if mesh.vertex_count() == 0 || mesh.triangles.is_empty() {
            return Ok(None);
        }
        skinnable(path, &read.skeleton, &mesh)?;
        let mut take = Take::new(read.skeleton, read.motion, path.display().to_string());
        take.warnings = read.warnings;
        take.format = Some(format);
        take.take_name = read.take;
        Ok(Some(Character {
            take,
            mesh,
            body: None,
        }))
    }

    /// The user's body model as a character: its mesh of shape `betas` (none: the mean shape,
    /// and an AMASS take put on it by [`Character::for_take`] lends its own) and SMPL-X's
    /// `expression` (empty: none), bound by the
    /// model's weights to the built-in figure of its type with the model's joints, moved by
    /// its pose blend shapes and linear blend skinning as `smplx` moves it. Its take is the rest
    /// pose, one frame, metres, Y up.
    pub fn from_body_model(
        model: Arc<BodyModel>,
        betas: Option<&[f64]>,
        expression: &[f64],
    ) -> Result<Character, Error> {
        let shaped = model.shaped(betas.unwrap_or(&[]), expression)?;
        let (mut skeleton, index_of) = crate::smpl::amass::figure(model.model)?;
        crate::smpl::amass::model_offsets(&mut skeleton, &index_of, &shaped.joints);
        let joint_of: Vec<usize> = (0..model.model.joint_count())
            .map(|k| index_of.iter().position(|&i| i == Some(k)))
            .collect::<Option<_>>()
            .ok_or_else(|| {
                Error::usage(format!(
                    "the built-in {} lacks a joint of {}",
                    model.model.built_in(),
                    model.model.label()
                ))
            })?;
        // One rest frame: no joint turned, the root where the model rests its pelvis.
        let channels = skeleton.channel_count();
        let mut rest = vec![0.0f32; channels];
        let root = &skeleton.joints[joint_of[0]];
        for (c, channel) in root.channels.iter().enumerate() {
            if channel.is_position() {
                rest[root.first_channel + c] = root.offset[channel.axis()];
            }
        }
        let motion = crate::model::motion::Motion::new(1.0 / 30.0, channels, 1, rest);
        let vertices = model.vertex_count();
        let bytes = (vertices * joint_of.len() * 8) as u64;
        let mut builder = crate::model::mesh::MeshBuilder::new(&model.name, bytes);
        builder.begin_part(&model.name, false);
        for (k, joint) in shaped.joints.iter().enumerate() {
            builder.bone(crate::model::mesh::Bone {
                joint: Some(joint_of[k]),
                bind: Mat4::from_translation(-joint.as_vec3()),
            })?;
        }
        let still = crate::model::mesh::Bone {
            joint: None,
            bind: Mat4::IDENTITY,
        };
        for (v, position) in shaped.vertices.iter().enumerate() {
            let weights = model.weights_of(v).iter().map(|&(k, w)| (k, w as f32));
            builder.vertex(position.as_vec3(), Vec3::Y, weights, still)?;
        }
        for corners in model.faces.chunks_exact(3) {
            builder.triangle([corners[0], corners[1], corners[2]])?;
        }
        builder.smooth_normals(0, 0);
        let (mut mesh, said) = builder.finish();
        let parents = model.parents();
        mesh.pose_blend = Some(Arc::new(crate::model::mesh::PoseBlend {
            joints: (1..joint_of.len())
                .map(|k| (joint_of[k], joint_of[parents[k].unwrap_or(0)]))
                .collect(),
            dirs: model.pose_dirs().iter().map(|&d| d as f32).collect(),
        }));
        // A model's joints are checked as a file's skin is: bind matrices within bounds.
        skinnable(Path::new(&model.name), &skeleton, &mesh)?;
        let mut take = Take::new(skeleton, motion, model.name.clone());
        take.warnings = said.into_iter().map(Message::from).collect();
        take.stated_units = Some(crate::model::stance::Units::of_metres(1.0));
        take.body = Some(crate::smpl::Body {
            model: model.model,
            betas: betas.unwrap_or(&[]).to_vec(),
            gender: model.gender.clone(),
            rest_pelvis: Some(shaped.joints[0].to_array()),
        });
        Ok(Character {
            take,
            mesh,
            body: Some((model, betas.is_some())),
        })
    }

    /// This character as `take` would have it: a body model whose betas were not given, shaped
    /// by the betas of an AMASS take of its model type; else itself.
    pub fn for_take(self: &Arc<Self>, take: &Take) -> Result<Arc<Character>, Error> {
        match (&self.body, &take.body) {
            (Some((model, false)), Some(body)) if body.model == model.model => Ok(Arc::new(
                Character::from_body_model(model.clone(), Some(&body.betas), &[])?,
            )),
            _ => Ok(self.clone()),
        }
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

/// Largest value a bind matrix may hold: a vertex 1e12 units from its joint (a million
/// kilometres in metres) is no character's. Past it, skinned positions overflow f32 (an inverse
/// bind scale of 3e38 drew a blank picture and wrote a GLB bvhview then refused): the joint
/// moves its vertices by a rotation and a translation, so a bind held to this keeps every
/// vertex finite in any take.
const MAX_BIND_VALUE: f32 = 1e12;

/// Refuses a mesh whose vertices could not be skinned to finite positions: a bone's bind
/// matrix past [`MAX_BIND_VALUE`] (naming its joint and a vertex it moves), or a vertex not
/// finite in the rest pose (naming its mesh and index).
fn skinnable(path: &Path, skeleton: &Skeleton, mesh: &Mesh) -> Result<(), Error> {
    let joint_name = |b: usize| match mesh.bones[b].joint {
        Some(j) => format!(
            "joint '{}'",
            crate::limits::quoted(&skeleton.joints[j].name)
        ),
        None => "the mesh's fixed frame".to_string(),
    };
    let huge = |m: &Mat4| m.to_cols_array().iter().any(|v| v.abs() > MAX_BIND_VALUE);
    if let Some(b) = mesh.bones.iter().position(|b| huge(&b.bind)) {
        let moved = (0..mesh.vertex_count())
            .find(|&v| mesh.influences_of(v).iter().any(|i| i.bone as usize == b));
        let vertex = moved.map_or(String::new(), |v| {
            format!(" ({} is bound to it)", mesh.vertex_name(v))
        });
        let largest = mesh.bones[b]
            .bind
            .to_cols_array()
            .iter()
            .fold(0.0f32, |m, v| m.max(v.abs()));
        return Err(Error::usage(format!(
            "{}: the bind matrix of {}{vertex} holds {largest:.2e}, past {MAX_BIND_VALUE:e}: its \
             vertices would be skinned past what a float holds (the skin's inverse bind matrix \
             is damaged: export the skin again)",
            path.display(),
            joint_name(b)
        )));
    }
    let mut world = Vec::new();
    world_matrices(skeleton, &[], OffsetMode::Replace, &mut world);
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    mesh.deform(&world, &mut positions, &mut normals);
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::usage(format!(
            "{}: {} is skinned to a position that is not finite in the rest pose (its bones' \
             bind matrices are damaged: export the skin again)",
            path.display(),
            mesh.vertex_name(v)
        )));
    }
    Ok(())
}

impl Character {
    /// `take` put on this character's skeleton by role ([`crate::retarget::Target::apply`]:
    /// (a take of a body model character's own type, an AMASS file's, is put on as it is:
    /// its rotations on the model's joints, nothing retargeted)
    /// rest poses aligned, the path scaled by leg length, the feet on the take's floor), ready
    /// to skin. `pairs` (`SRC = DST` joint names) override the map. Refused as a retarget is: a
    /// body that is not a biped onto a biped character, or the reverse, unless
    /// `insist.any_body`; a result whose check against the take finds a side crossed or a width
    /// collapsed unless `insist.force`. What the result measures against the take and what
    /// was kept as insisted come back beside it, for the caller to say.
    pub fn dress(
        &self,
        take: &Take,
        pairs: &[(String, String)],
        insist: Insist,
        threads: usize,
    ) -> Result<(Take, Dressed), Error> {
        if let Some(own) = self.same_body_model(take) {
            return Ok((own, Dressed::default()));
        }
        let target = crate::retarget::Target::new(
            self.take.name.clone(),
            self.take.skeleton.clone(),
            &self.take.motion,
        );
        let put = target.apply_up(
            &take.name,
            &take.skeleton,
            &take.motion,
            take.stated_up,
            pairs,
            insist,
            threads,
        )?;
        let mut dressed = take.edited(put.skeleton, put.motion, false);
        dressed.offset_mode = OffsetMode::Replace;
        // On the character it stands as the character does.
        dressed.stated_up = None;
        let said = Dressed {
            check: Some(put.check),
            forced: put.forced,
            uncarried: put.uncarried,
        };
        Ok((dressed, said))
    }

    /// `take`, read from the file `path`, on this character: a take of the character's own
    /// skeleton (any take of its file, whichever `--take` chose) as the file has it, nothing
    /// retargeted, so exact; any other by [`Character::dress`] with the guessed map (`insist`:
    /// whether a body that is not two-legged goes onto a two-legged character, or the reverse).
    pub fn dress_file(
        &self,
        take: &Take,
        path: &Path,
        insist: Insist,
        threads: usize,
    ) -> Result<(Take, Dressed), Error> {
        let same_file = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if same_file(path, Path::new(&self.take.name)) {
            if take.take_name == self.take.take_name {
                return Ok((self.take.clone(), Dressed::default()));
            }
            // Another take of the character's file (`--take`): read as the character reads its
            // own, on the skeleton its mesh is bound to (a take read alone keeps the nodes' own
            // frames, not the bind pose's).
            let mut options = OpenOptions::new().threads(threads);
            options.take = take.take_name.clone();
            let other = Character::open_with(path, &options)?;
            if self.is_own_skeleton(&other.take.skeleton) {
                return Ok((other.take, Dressed::default()));
            }
        }
        if self.is_own_skeleton(&take.skeleton) {
            let mut own = take.clone();
            // The mesh is bound to joints whose OFFSETs its positions replace.
            own.offset_mode = OffsetMode::Replace;
            return Ok((own, Dressed::default()));
        }
        self.dress(take, &[], insist, threads)
    }

    /// Writes `take` with this character's mesh bound to it, by the extension of `path`: glTF
    /// (`.glb`, `.gltf`) or FBX (`.fbx`), the file whole or not at all. `take` must be on the
    /// character's skeleton: its own take, or one [`Character::dress`] made.
    ///
    /// ```
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// # #[cfg(feature = "fbx")]
    /// # {
    /// use bvhview::character::Character;
    ///
    /// let kenney = Character::open("tests/data/characters/maya_kenney_character_7700_binary.fbx")?;
    /// let folder = tempfile::tempdir()?;
    /// kenney.save(&kenney.take, folder.path().join("kenney.fbx"))?;
    /// let back = Character::open(folder.path().join("kenney.fbx"))?;
    /// assert_eq!(back.mesh.vertex_count(), 804);
    /// # }
    /// # Ok(())
    /// # }
    /// ```
    pub fn save(&self, take: &Take, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        if !self.is_own_skeleton(&take.skeleton) {
            return Err(Error::usage(format!(
                "{}: the take is not on this character's skeleton ({} joints, {} here): put it \
                 on the character first (dress)",
                path.display(),
                take.skeleton.joints.len(),
                self.take.skeleton.joints.len()
            )));
        }
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let gltf = |container| {
            crate::gltf::to_gltf_character(&take.skeleton, &take.motion, &self.mesh, container)
        };
        let bytes = match extension.as_str() {
            "glb" => gltf(crate::gltf::Container::Glb)?,
            "gltf" => gltf(crate::gltf::Container::Gltf)?,
            "fbx" => take.fbx_bytes(Some(&self.mesh), &path.display().to_string())?,
            other => {
                return Err(Error::usage(format!(
                    "{}: a character is saved as .glb, .gltf or .fbx, not '{other}'",
                    path.display()
                )));
            }
        };
        crate::io::output::AtomicFile::write_whole(path, &bytes)
    }

    /// `take` on this body model character when it holds that model type's parameters (an
    /// AMASS file read with or without the model): the same rotations, exactly, on the model's
    /// joints, the root moved from where the take's reading rested the pelvis to where the
    /// model rests it.
    fn same_body_model(&self, take: &Take) -> Option<Take> {
        let (model, _) = self.body.as_ref()?;
        let body = take.body.as_ref().filter(|b| b.model == model.model)?;
        let own = &self.take.skeleton;
        let same_joints = own.joints.len() == take.skeleton.joints.len()
            && own.joints.iter().zip(&take.skeleton.joints).all(|(a, b)| {
                a.name == b.name
                    && a.parent == b.parent
                    && a.channels == b.channels
                    && a.rotation_order == b.rotation_order
            });
        if !same_joints {
            return None;
        }
        let rest = |p: Option<[f64; 3]>| glam::DVec3::from(p.unwrap_or([0.0; 3]));
        let own_pelvis = self.take.body.as_ref().and_then(|b| b.rest_pelvis);
        let delta = rest(own_pelvis) - rest(body.rest_pelvis);
        // The take stands AMASS's Z up in Y up: (x, y, z) → (x, z, −y).
        let shift = glam::DVec3::new(delta.x, delta.z, -delta.y).as_vec3();
        let root = &own.joints[0];
        let mut motion = take.motion.clone();
        let width = motion.channels.max(1);
        for row in motion.data.chunks_exact_mut(width) {
            for (c, channel) in root.channels.iter().enumerate() {
                if channel.is_position() {
                    row[root.first_channel + c] += shift[channel.axis()];
                }
            }
        }
        let mut dressed = take.edited(own.clone(), motion, false);
        dressed.offset_mode = OffsetMode::Replace;
        dressed.body = Some(crate::smpl::Body {
            rest_pelvis: own_pelvis,
            ..body.clone()
        });
        Some(dressed)
    }

    /// Whether `skeleton` is the one the mesh is bound to: the same joints in the same order,
    /// each with its parent, channels and OFFSET (another take of the character's own file, or
    /// a file of the very same rig). Its motion then moves the mesh as it is.
    pub fn is_own_skeleton(&self, skeleton: &Skeleton) -> bool {
        let own = &self.take.skeleton;
        own.joints.len() == skeleton.joints.len()
            && own.joints.iter().zip(&skeleton.joints).all(|(a, b)| {
                a.name == b.name
                    && a.parent == b.parent
                    && a.channels == b.channels
                    && a.rotation_order == b.rotation_order
                    && a.offset == b.offset
            })
    }
}

/// How [`write_vertices`] writes: `frame,vertex,x,y,z` lines, a JSON document, or a NumPy
/// array of shape (frames, vertices, 3), little-endian `float32`.
///
/// ```
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// # #[cfg(feature = "fbx")]
/// # {
/// use bvhview::character::{Character, VertexFormat, write_vertices};
///
/// let kenney = Character::open("tests/data/characters/maya_kenney_character_7700_binary.fbx")?;
/// let (skeleton, motion) = (&kenney.take.skeleton, &kenney.take.motion);
/// let mut csv = Vec::new();
/// write_vertices(&mut csv, &kenney, skeleton, motion, 0..1, VertexFormat::Csv)?;
/// let text = String::from_utf8(csv)?;
/// assert_eq!(text.lines().next(), Some("frame,vertex,x,y,z"));
/// assert_eq!(text.lines().count(), 1 + 804);
/// # }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexFormat {
    /// `frame,vertex,x,y,z`, one vertex per line.
    Csv,
    /// `{"frame_time":…,"vertices":N,"triangles":[[a,b,c],…],"frames":[{"frame":0,"positions":[[x,y,z],…]},…]}`.
    Json,
    /// A `.npy` array (frames, vertices, 3) of `<f4`.
    Npy,
}

/// The skinned vertices of `character` moved by frames `frames` of a take on its skeleton
/// (`skeleton`, `motion`: the character's own take, or one [`Character::dress`] made), into
/// `out`. Every number is checked to be finite before it is written.
///
/// ```
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// # #[cfg(feature = "fbx")]
/// # {
/// use bvhview::character::{Character, VertexFormat, write_vertices};
///
/// let kenney = Character::open("tests/data/characters/maya_kenney_character_7700_binary.fbx")?;
/// let (skeleton, motion) = (&kenney.take.skeleton, &kenney.take.motion);
/// let mut npy = Vec::new();
/// write_vertices(&mut npy, &kenney, skeleton, motion, 0..2, VertexFormat::Npy)?;
/// assert_eq!(npy.len(), 128 + 2 * 804 * 3 * 4);
/// # }
/// # Ok(())
/// # }
/// ```
pub fn write_vertices(
    out: &mut dyn Write,
    character: &Character,
    skeleton: &Skeleton,
    motion: &crate::model::motion::Motion,
    frames: std::ops::Range<usize>,
    format: VertexFormat,
) -> std::io::Result<()> {
    let mesh = &character.mesh;
    let count = mesh.vertex_count();
    let mut world = Vec::new();
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    let mut numbers = crate::positions::Shortest::default();
    match format {
        VertexFormat::Csv => out.write_all(b"frame,vertex,x,y,z\n")?,
        VertexFormat::Json => {
            write!(
                out,
                "{{\"frame_time\":{},\"vertices\":{count},\"triangles\":[",
                motion.frame_time
            )?;
            for (k, t) in mesh.triangles.chunks_exact(3).enumerate() {
                let comma = if k > 0 { "," } else { "" };
                write!(out, "{comma}[{},{},{}]", t[0], t[1], t[2])?;
            }
            out.write_all(b"],\"frames\":[")?;
        }
        VertexFormat::Npy => {
            out.write_all(&crate::io::npy::header("<f4", &[frames.len(), count, 3], 0))?
        }
    }
    let first = frames.start;
    for f in frames {
        // A take of no frames has its rest pose as its one frame.
        let row = if motion.frame_count() == 0 {
            &[][..]
        } else {
            motion.frame(f)
        };
        world_matrices(skeleton, row, OffsetMode::Replace, &mut world);
        mesh.deform(&world, &mut positions, &mut normals);
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(std::io::Error::other(crate::positions::NotFinite(format!(
                "frame {f}, vertex {v}: a position that is not finite"
            ))));
        }
        let mut text = Vec::with_capacity(count * 32);
        match format {
            VertexFormat::Csv => {
                for (v, p) in positions.iter().enumerate() {
                    write!(text, "{f},{v}")?;
                    for c in p.to_array() {
                        text.push(b',');
                        text.extend_from_slice(numbers.format(c));
                    }
                    text.push(b'\n');
                }
            }
            VertexFormat::Json => {
                let comma = if f > first { "," } else { "" };
                write!(text, "{comma}{{\"frame\":{f},\"positions\":[")?;
                for (v, p) in positions.iter().enumerate() {
                    text.extend_from_slice(if v > 0 { b",[" } else { b"[" });
                    for (k, c) in p.to_array().into_iter().enumerate() {
                        if k > 0 {
                            text.push(b',');
                        }
                        text.extend_from_slice(numbers.format(c));
                    }
                    text.push(b']');
                }
                text.extend_from_slice(b"]}");
            }
            VertexFormat::Npy => {
                for p in &positions {
                    for c in p.to_array() {
                        text.extend_from_slice(&c.to_le_bytes());
                    }
                }
            }
        }
        out.write_all(&text)?;
    }
    if format == VertexFormat::Json {
        out.write_all(b"]}\n")?;
    }
    Ok(())
}
