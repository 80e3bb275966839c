//! FBX out: a take as an FBX 7.4 binary file (version 7400, what Unreal, Unity, Maya,
//! MotionBuilder and Blender read). The records are fbxcel's; the scene is ours: each joint a
//! `Model` of type LimbNode with a Skeleton `NodeAttribute`, its rest pose in `Lcl Translation`
//! and `Lcl Rotation`, its motion in one `AnimationCurveNode` per animated property with a curve
//! keyed at every frame, its Euler order in `RotationOrder` (the six BVH orders are FBX's six:
//! kept, not split again), the rest pose as the bind pose, centimetres and Y up in
//! `GlobalSettings` (a Z-up take turned exactly as it is written).

mod bones;
mod ids;
mod records;
mod skin;

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::mesh::Mesh;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up};
use crate::model::skeleton::Skeleton;
use bones::Bone;
use ids::{
    AXES, DOCUMENT_ID, LAYER_ID, POSE_ID, PROPERTIES, STACK_ID, attribute_id, curve_id,
    curve_node_id, model_id,
};
use records::{Records, Value};
use skin::Skin;

/// FBX time: ticks per second.
pub const TICKS_PER_SECOND: f64 = 46_186_158_000.0;

/// What a file states beside the joints: the take's name, how position channels count, the
/// take's units and up axis, and the units written.
///
/// ```
/// use bvhview::fbx::write::Settings;
/// use bvhview::model::pose::{OffsetMode, Up};
///
/// // A take in inches, Z up, written in centimetres as engines expect.
/// let settings = Settings {
///     take_name: "walk".into(),
///     offset_mode: OffsetMode::Replace,
///     metres_per_unit: 0.0254,
///     up: Up::Z,
///     out_metres_per_unit: 0.01,
/// };
/// assert_eq!(settings.take_name, "walk");
/// ```
#[derive(Clone, Debug)]
pub struct Settings {
    /// The animation stack's name (what an engine lists the take as).
    pub take_name: String,
    /// How position channels combine with OFFSET.
    pub offset_mode: OffsetMode,
    /// Metres per unit of the take.
    pub metres_per_unit: f64,
    /// The take's up axis: a Z-up take is turned to Y up as it is written (exactly: channels
    /// moved to the turned axes, not split again), so the file is Y up as engines expect.
    pub up: Up,
    /// Metres per unit written: 0.01 (centimetres, what engines expect) unless asked otherwise.
    pub out_metres_per_unit: f64,
}

/// An FBX file in memory, and the joints whose names it had to change.
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let written = Take::open("tests/data/bvh/bvhparser_simple.bvh")?.fbx()?;
/// assert!(written.bytes.starts_with(b"Kaydara FBX Binary"));
/// assert!(written.renamed.is_empty());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Written {
    /// The file's bytes.
    pub bytes: Vec<u8>,
    /// `old → new` for each name FBX cannot hold (a control character, FBX's own separator).
    pub renamed: Vec<String>,
}

/// Most bytes an FBX 7.4 file holds: its records' offsets are 32-bit.
const MAX_FILE_BYTES: u64 = u32::MAX as u64;

/// `skeleton` and `motion` as an FBX 7.4 binary file.
///
/// ```
/// use bvhview::Take;
/// use bvhview::fbx::write::{Settings, to_bytes};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_simple.bvh")?;
/// let settings = Settings {
///     take_name: "simple".into(),
///     offset_mode: take.offset_mode,
///     metres_per_unit: 0.01,
///     up: bvhview::model::pose::Up::Y,
///     out_metres_per_unit: 0.01,
/// };
/// let written = to_bytes(&take.skeleton, &take.motion, &settings)?;
/// assert!(written.bytes.starts_with(b"Kaydara FBX Binary  \0\x1a\0"));
/// # Ok(())
/// # }
/// ```
pub fn to_bytes(
    skeleton: &Skeleton,
    motion: &Motion,
    settings: &Settings,
) -> Result<Written, Error> {
    write(skeleton, motion, None, settings)
}

/// A character's take as an FBX 7.4 binary file: `skeleton` and `motion` as [`to_bytes`]
/// writes them, and `mesh` bound to the joints by a skin deformer with one cluster per bone
/// (every influence kept): one file an engine imports as an animated skinned character.
///
/// ```
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// # #[cfg(feature = "gltf")]
/// # {
/// use bvhview::character::Character;
/// use bvhview::fbx::write::{Settings, character_to_bytes};
///
/// let capsule = Character::open("tests/data/characters/capsule_mixamo.glb")?;
/// let take = &capsule.take;
/// let settings = Settings {
///     take_name: "capsule".into(),
///     offset_mode: take.offset_mode,
///     metres_per_unit: 1.0,
///     up: bvhview::model::pose::Up::Y,
///     out_metres_per_unit: 0.01,
/// };
/// let written = character_to_bytes(&take.skeleton, &take.motion, &capsule.mesh, &settings)?;
/// // Read back, the mesh has every vertex.
/// let folder = tempfile::tempdir()?;
/// std::fs::write(folder.path().join("capsule.fbx"), &written.bytes)?;
/// let back = Character::open(folder.path().join("capsule.fbx"))?;
/// assert_eq!(back.mesh.vertex_count(), capsule.mesh.vertex_count());
/// # }
/// # Ok(())
/// # }
/// ```
pub fn character_to_bytes(
    skeleton: &Skeleton,
    motion: &Motion,
    mesh: &Mesh,
    settings: &Settings,
) -> Result<Written, Error> {
    write(skeleton, motion, Some(mesh), settings)
}

fn write(
    skeleton: &Skeleton,
    motion: &Motion,
    mesh: Option<&Mesh>,
    settings: &Settings,
) -> Result<Written, Error> {
    // A take of no frames is written as its rest pose, one frame: what a reader makes of a file
    // without animation, so that it writes again the same.
    let rest;
    let motion = if motion.frame_count() == 0 {
        rest = rest_frame(skeleton, motion, settings.offset_mode);
        &rest
    } else {
        motion
    };
    let frames = motion.frame_count();
    if frames > 1 && !(motion.frame_time > 0.0 && motion.frame_time.is_finite()) {
        return Err(Error::usage(
            Message::from(format!(
                "cannot write FBX: a frame time of {} s puts every frame at one time; give the \
                 take its rate with ",
                motion.frame_time
            ))
            .argument("frame_time", Some("SECONDS")),
        ));
    }
    let scale = scale_between(settings.metres_per_unit, settings.out_metres_per_unit);
    let turn = bones::Turn::to_y_up(settings.up);
    let (mut bones, renamed) = bones::of(skeleton, motion, settings.offset_mode, scale, turn)?;
    let skin = match mesh {
        Some(mesh) => {
            let origin = Skin::needs_origin(mesh).then(|| {
                bones.push(Bone::fixed("mesh_origin"));
                bones.len() - 1
            });
            Some(Skin::new(mesh, scale, turn, origin)?)
        }
        None => None,
    };
    if let Some(fault) = bones.iter().find_map(Bone::not_finite) {
        return Err(Error::usage(format!("cannot write FBX: {fault}")));
    }
    fits(bones.iter().map(Bone::curve_count).sum(), frames)?;
    // A rate FBX names is keyed at that rate exactly: `Frame Time: 0.0083333` is 1/120 written
    // with 7 digits, and an importer counts frames at 120 per second.
    let (_, mut rate) = time_mode(motion.frame_time);
    // One frame has no span: a rate no reader takes is written as FBX's default instead.
    if frames <= 1 && !(crate::limits::MIN_FPS..=crate::limits::MAX_FPS).contains(&rate) {
        rate = 30.0;
    }
    if frames > 1 && rate < crate::limits::MIN_FPS {
        let most = 1.0 / crate::limits::MIN_FPS;
        return Err(Error::limit(
            "seconds a frame",
            most as u64,
            motion.frame_time.ceil() as u64,
            Message::from(format!(
                "cannot write FBX: a frame every {} s, slower than the one every {most} s \
                 bvhview reads back from FBX; resample the take with ",
                crate::limits::show(motion.frame_time)
            ))
            .argument("fps", None),
        ));
    }
    if frames > 1 && rate > crate::limits::MAX_FPS {
        return Err(Error::limit(
            "frames per second",
            crate::limits::MAX_FPS as u64,
            rate.ceil() as u64,
            Message::from(format!(
                "cannot write FBX: {} frames a second, more than the {} bvhview reads back from \
                 FBX; resample the take with ",
                crate::limits::show(rate),
                crate::limits::MAX_FPS
            ))
            .argument("fps", None),
        ));
    }
    let scene = Scene {
        bones: &bones,
        skin: skin.as_ref(),
        settings,
        frames,
        frame_time: 1.0 / rate,
    };
    Ok(Written {
        bytes: scene.write()?,
        renamed,
    })
}

/// One frame of `skeleton`'s rest pose at `motion`'s rate: every rotation 0, each position
/// channel where the OFFSET puts the joint (the OFFSET's value replacing it, 0 added to it).
fn rest_frame(skeleton: &Skeleton, motion: &Motion, mode: OffsetMode) -> Motion {
    let mut row = Vec::with_capacity(skeleton.channel_count());
    for joint in &skeleton.joints {
        for channel in &joint.channels {
            row.push(match (channel.is_position(), mode) {
                (true, OffsetMode::Replace) => joint.offset[channel.axis()],
                _ => 0.0,
            });
        }
    }
    Motion::new(motion.frame_time, row.len(), 1, row)
}

/// Refuses, before a byte is written, a take whose `curves` curves of `frames` keys (a 64-bit
/// time and a 32-bit value each) pass the 4 GiB an FBX 7.4 file's 32-bit offsets reach.
fn fits(curves: usize, frames: usize) -> Result<(), Error> {
    let estimate = (curves as u64)
        .saturating_mul(frames as u64)
        .saturating_mul(12);
    if estimate > MAX_FILE_BYTES {
        return Err(Error::limit(
            "bytes",
            MAX_FILE_BYTES,
            estimate,
            format!(
                "cannot write FBX: {curves} curves of {frames} keys make about {estimate} bytes, \
                 more than an FBX file's 32-bit offsets reach ({MAX_FILE_BYTES})"
            ),
        ));
    }
    Ok(())
}

/// Written units per unit of the take, exact for the usual pairs (centimetres to centimetres is
/// 1, inches to centimetres 2.54, not 2.5399999): the ratio is rounded to 7 significant digits,
/// what the take's 32-bit metres per unit hold.
fn scale_between(metres_per_unit: f64, out_metres_per_unit: f64) -> f64 {
    let ratio = metres_per_unit / out_metres_per_unit;
    if !(ratio.is_finite() && ratio > 0.0) {
        return 1.0;
    }
    let digits = 10f64.powi(6 - ratio.log10().floor() as i32);
    (ratio * digits).round() / digits
}

/// The scene being written, and the ids of its objects.
struct Scene<'a> {
    bones: &'a [Bone],
    skin: Option<&'a Skin<'a>>,
    settings: &'a Settings,
    frames: usize,
    frame_time: f64,
}

impl Scene<'_> {
    fn write(&self) -> Result<Vec<u8>, Error> {
        let mut out = Records::new()?;
        self.header(&mut out)?;
        self.global_settings(&mut out)?;
        self.documents(&mut out)?;
        out.leaf("References", &[])?;
        self.definitions(&mut out)?;
        out.open("Objects", &[])?;
        for (i, bone) in self.bones.iter().enumerate() {
            bone.write_objects(&mut out, i)?;
        }
        if let Some(skin) = self.skin {
            skin.write_objects(&mut out, self.bones)?;
        }
        self.bind_pose(&mut out)?;
        if self.animated() {
            self.animation_objects(&mut out)?;
        }
        out.close()?;
        self.connections(&mut out)?;
        self.takes(&mut out)?;
        out.finish()
    }

    fn animated(&self) -> bool {
        self.frames > 0
    }

    /// The last key's time in FBX ticks: (frames − 1) × frame time.
    fn stop(&self) -> i64 {
        key_time(self.frames.saturating_sub(1), self.frame_time)
    }

    fn header(&self, out: &mut Records) -> Result<(), Error> {
        let creator = format!("bvhview {}", env!("CARGO_PKG_VERSION"));
        out.open("FBXHeaderExtension", &[])?;
        out.leaf("FBXHeaderVersion", &[Value::I32(1003)])?;
        out.leaf("FBXVersion", &[Value::I32(7400)])?;
        out.leaf("EncryptionType", &[Value::I32(0)])?;
        // A fixed time: the same take makes the same bytes.
        out.open("CreationTimeStamp", &[])?;
        for (name, value) in [
            ("Version", 1000),
            ("Year", 1970),
            ("Month", 1),
            ("Day", 1),
            ("Hour", 0),
            ("Minute", 0),
            ("Second", 0),
            ("Millisecond", 0),
        ] {
            out.leaf(name, &[Value::I32(value)])?;
        }
        out.close()?;
        out.leaf("Creator", &[Value::Str(&creator)])?;
        out.close()?;
        out.leaf("FileId", &[Value::Raw(&[0x62; 16])])?;
        out.leaf("CreationTime", &[Value::Str("1970-01-01 00:00:00:000")])?;
        out.leaf("Creator", &[Value::Str(&creator)])
    }

    fn global_settings(&self, out: &mut Records) -> Result<(), Error> {
        // Centimetres per unit, exact for the usual units (2.54 for inches, not 2.5399999).
        let unit_cm = scale_between(self.settings.out_metres_per_unit, 0.01);
        // Y up, front +Z, right +X, as engines expect: a Z-up take was turned as it was written.
        let (up, front, front_sign) = (1, 2, 1);
        let (mode, rate) = time_mode(self.frame_time);
        out.open("GlobalSettings", &[])?;
        out.leaf("Version", &[Value::I32(1000)])?;
        out.open("Properties70", &[])?;
        let int = ["int", "Integer", ""];
        for (name, value) in [
            ("UpAxis", up),
            ("UpAxisSign", 1),
            ("FrontAxis", front),
            ("FrontAxisSign", front_sign),
            ("CoordAxis", 0),
            ("CoordAxisSign", 1),
            ("OriginalUpAxis", up),
            ("OriginalUpAxisSign", 1),
        ] {
            out.property(name, int, &[Value::I32(value)])?;
        }
        let number = ["double", "Number", ""];
        out.property("UnitScaleFactor", number, &[Value::F64(unit_cm)])?;
        out.property("OriginalUnitScaleFactor", number, &[Value::F64(unit_cm)])?;
        out.property("TimeMode", ["enum", "", ""], &[Value::I32(mode)])?;
        let time = ["KTime", "Time", ""];
        out.property("TimeSpanStart", time, &[Value::I64(0)])?;
        out.property("TimeSpanStop", time, &[Value::I64(self.stop())])?;
        out.property("CustomFrameRate", number, &[Value::F64(rate)])?;
        out.close()?;
        out.close()
    }

    fn documents(&self, out: &mut Records) -> Result<(), Error> {
        out.open("Documents", &[])?;
        out.leaf("Count", &[Value::I32(1)])?;
        out.open(
            "Document",
            &[
                Value::I64(DOCUMENT_ID),
                Value::Str("Scene"),
                Value::Str("Scene"),
            ],
        )?;
        out.open("Properties70", &[])?;
        out.property("SourceObject", ["object", "", ""], &[])?;
        out.property(
            "ActiveAnimStackName",
            ["KString", "", ""],
            &[Value::Str(&self.settings.take_name)],
        )?;
        out.close()?;
        out.leaf("RootNode", &[Value::I64(0)])?;
        out.close()?;
        out.close()
    }

    fn definitions(&self, out: &mut Records) -> Result<(), Error> {
        let bones = self.bones.len() as i32;
        let curve_nodes: i32 = self.bones.iter().map(|b| b.curve_count() as i32 / 3).sum();
        let (meshes, geometries, deformers) = self.skin.map_or((0, 0, 0), Skin::counts);
        let mut types = vec![
            ("GlobalSettings", 1),
            ("Model", bones + meshes as i32),
            ("NodeAttribute", bones),
            ("Pose", 1),
        ];
        if geometries > 0 {
            types.extend([
                ("Geometry", geometries as i32),
                ("Deformer", deformers as i32),
            ]);
        }
        if self.animated() {
            types.extend([
                ("AnimationStack", 1),
                ("AnimationLayer", 1),
                ("AnimationCurveNode", curve_nodes),
                ("AnimationCurve", 3 * curve_nodes),
            ]);
        }
        out.open("Definitions", &[])?;
        out.leaf("Version", &[Value::I32(100)])?;
        out.leaf("Count", &[Value::I32(types.iter().map(|t| t.1).sum())])?;
        for (name, count) in types {
            out.open("ObjectType", &[Value::Str(name)])?;
            out.leaf("Count", &[Value::I32(count)])?;
            out.close()?;
        }
        out.close()
    }

    /// The rest pose as the bind pose: every bone's world matrix with no rotation; a joint a
    /// mesh is bound to, its world matrix when the mesh was bound; each mesh at the origin.
    fn bind_pose(&self, out: &mut Records) -> Result<(), Error> {
        let name = format!("{}\0\x01Pose", self.settings.take_name);
        out.open(
            "Pose",
            &[
                Value::I64(POSE_ID),
                Value::Str(&name),
                Value::Str("BindPose"),
            ],
        )?;
        out.leaf("Type", &[Value::Str("BindPose")])?;
        out.leaf("Version", &[Value::I32(100)])?;
        let bound = self.skin.map_or_else(Vec::new, Skin::bind_pose);
        let meshes: Vec<i64> = self.skin.map_or_else(Vec::new, |s| s.model_ids().collect());
        let count = self.bones.len() + meshes.len();
        out.leaf("NbPoseNodes", &[Value::I32(count as i32)])?;
        let node = |out: &mut Records, id: i64, matrix: glam::DMat4| {
            out.open("PoseNode", &[])?;
            out.leaf("Node", &[Value::I64(id)])?;
            out.array("Matrix", &matrix.to_cols_array())?;
            out.close()
        };
        let mut world: Vec<glam::DVec3> = Vec::with_capacity(self.bones.len());
        for (i, bone) in self.bones.iter().enumerate() {
            let base = bone.parent.map_or(glam::DVec3::ZERO, |p| world[p]);
            let at = base + glam::DVec3::from_array(bone.translation);
            world.push(at);
            let matrix = match bound.iter().find(|(b, _)| *b == i) {
                Some(&(_, matrix)) => matrix,
                None => glam::DMat4::from_translation(at),
            };
            node(out, model_id(i), matrix)?;
        }
        for id in meshes {
            node(out, id, glam::DMat4::IDENTITY)?;
        }
        out.close()
    }

    fn animation_objects(&self, out: &mut Records) -> Result<(), Error> {
        let stack = format!("{}\0\x01AnimStack", self.settings.take_name);
        out.open(
            "AnimationStack",
            &[Value::I64(STACK_ID), Value::Str(&stack), Value::Str("")],
        )?;
        out.open("Properties70", &[])?;
        let time = ["KTime", "Time", ""];
        for name in ["LocalStart", "ReferenceStart"] {
            out.property(name, time, &[Value::I64(0)])?;
        }
        for name in ["LocalStop", "ReferenceStop"] {
            out.property(name, time, &[Value::I64(self.stop())])?;
        }
        out.close()?;
        out.close()?;
        // The layer holds a list of children (an empty `Properties70`), as every object does in
        // the FBX SDK's files (`AnimationLayer: …, "AnimLayer::BaseLayer", "" { }`): assimp (5.2)
        // builds an object only from a record with one ("expected compound scope" otherwise),
        // and a stack whose layer it cannot build has no layer, so no animation. fbxcel ends a
        // record with its list only when the record has a child or no values.
        out.open(
            "AnimationLayer",
            &[
                Value::I64(LAYER_ID),
                Value::Str("BaseLayer\0\x01AnimLayer"),
                Value::Str(""),
            ],
        )?;
        out.open("Properties70", &[])?;
        out.close()?;
        out.close()?;
        let times: Vec<i64> = (0..self.frames)
            .map(|f| key_time(f, self.frame_time))
            .collect();
        for (i, bone) in self.bones.iter().enumerate() {
            bone.write_curves(out, i, &times)?;
        }
        Ok(())
    }

    fn connections(&self, out: &mut Records) -> Result<(), Error> {
        out.open("Connections", &[])?;
        let oo = |out: &mut Records, child: i64, parent: i64| {
            out.leaf(
                "C",
                &[Value::Str("OO"), Value::I64(child), Value::I64(parent)],
            )
        };
        for (i, bone) in self.bones.iter().enumerate() {
            oo(out, model_id(i), bone.parent.map_or(0, model_id))?;
            oo(out, attribute_id(i), model_id(i))?;
        }
        if let Some(skin) = self.skin {
            skin.connect(&mut |child, parent| oo(out, child, parent))?;
        }
        if self.animated() {
            oo(out, LAYER_ID, STACK_ID)?;
            for (i, bone) in self.bones.iter().enumerate() {
                for p in bone.animated_properties() {
                    let node = curve_node_id(i, p);
                    oo(out, node, LAYER_ID)?;
                    let property = Value::Str(PROPERTIES[p].0);
                    let op = [Value::Str("OP"), Value::I64(node), Value::I64(model_id(i))];
                    out.leaf("C", &[op[0], op[1], op[2], property])?;
                    for (axis, name) in AXES.iter().enumerate() {
                        let curve = [Value::I64(curve_id(i, p, axis)), Value::I64(node)];
                        out.leaf(
                            "C",
                            &[Value::Str("OP"), curve[0], curve[1], Value::Str(name)],
                        )?;
                    }
                }
            }
        }
        out.close()
    }

    fn takes(&self, out: &mut Records) -> Result<(), Error> {
        out.open("Takes", &[])?;
        out.leaf("Current", &[Value::Str(&self.settings.take_name)])?;
        if self.animated() {
            let file = format!("{}.tak", self.settings.take_name);
            out.open("Take", &[Value::Str(&self.settings.take_name)])?;
            out.leaf("FileName", &[Value::Str(&file)])?;
            let span = [Value::I64(0), Value::I64(self.stop())];
            out.leaf("LocalTime", &span)?;
            out.leaf("ReferenceTime", &span)?;
            out.close()?;
        }
        out.close()
    }
}

/// Frame `frame`'s time in FBX ticks.
fn key_time(frame: usize, frame_time: f64) -> i64 {
    (frame as f64 * frame_time * TICKS_PER_SECOND).round() as i64
}

/// `GlobalSettings`' `TimeMode` for a take of `frame_time` seconds a frame, and its rate: FBX's
/// own mode for the rates it names (24, 30, 60, 120, …), else custom with `CustomFrameRate`.
fn time_mode(frame_time: f64) -> (i32, f64) {
    let rate = if frame_time > 0.0 && frame_time.is_finite() {
        1.0 / frame_time
    } else {
        30.0
    };
    let named = [
        (120.0, 1),
        (100.0, 2),
        (60.0, 3),
        (50.0, 4),
        (48.0, 5),
        (30.0, 6),
        (25.0, 10),
        (24.0, 11),
        (1000.0, 12),
        (96.0, 15),
        (72.0, 16),
    ];
    // Frame times are written with few digits (.0083333 for 1/120): within a millionth.
    match named
        .iter()
        .find(|(fps, _)| ((rate - fps) / fps).abs() < 1e-5)
    {
        Some(&(fps, mode)) => (mode, fps),
        None => (14, significant(rate, 12)),
    }
}

/// `value` rounded to `digits` significant digits: a custom rate written so that the frame
/// time a reader takes from it (1 / rate) gives the same rate again, however the last bit of
/// 1 / (1 / rate) falls.
fn significant(value: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits - 1 - value.abs().log10().floor() as i32);
    (value * scale).round() / scale
}

#[cfg(test)]
mod tests {
    use super::{fits, key_time, scale_between, time_mode};
    use crate::io::error::Error;

    #[test]
    fn units_rates_and_times_are_exact_where_they_can_be() {
        assert_eq!(scale_between(f64::from(0.01f32), 0.01), 1.0);
        assert_eq!(scale_between(f64::from(0.0254f32), 0.01), 2.54);
        assert_eq!(scale_between(1.0, 0.01), 100.0);
        assert_eq!(scale_between(0.001, 0.01), 0.1);
        assert_eq!(time_mode(1.0 / 30.0), (6, 30.0));
        assert_eq!(time_mode(0.0083333), (1, 120.0));
        assert_eq!(time_mode(1.0 / 29.0).0, 14);
        assert_eq!(key_time(30, 1.0 / 30.0), 46_186_158_000);
    }

    /// 180 curves (60 joints rotated and moved) of 2 million keys pass 4 GiB; of 1 million not.
    #[test]
    fn a_take_past_the_32_bit_offsets_is_refused_before_writing() {
        assert!(fits(180, 1_000_000).is_ok());
        match fits(180, 2_000_000) {
            Err(Error::Limit {
                what, limit, found, ..
            }) => {
                assert_eq!(
                    (what, limit, found),
                    ("bytes", u64::from(u32::MAX), 4_320_000_000)
                );
            }
            other => panic!("{other:?}"),
        }
    }
}
