//! AMASS's motion files as takes: SMPL, SMPL-H and SMPL-X parameters in an `.npz`.
//!
//! A file holds, per frame, each joint's rotation as an axis-angle (`poses`, or SMPL-X's split
//! `root_orient`, `pose_body`, `pose_hand`, `pose_jaw`, `pose_eye`) and the body's translation
//! (`trans`, metres), with its rate (`mocap_framerate` or `mocap_frame_rate`), shape (`betas`),
//! `gender` and `surface_model_type`. The take is the model type's own kinematic tree and joint
//! names; each axis-angle becomes its rotation exactly (in 64-bit floats), split once into the
//! joint's channels; AMASS's Z up is turned to bvhview's Y up (a quarter turn about X applied to
//! the root's rotation and place: the figure moves the same), and lengths are metres.
//!
//! Joint offsets come from the built-in skeleton of the model type (bvhview's own adult figure:
//! no model file is shipped, and reading the user's is not done yet), said in one line: the
//! file's `betas` shape a body this reading does not have. The pelvis rests at the origin, so the
//! figure stands where `trans` puts the model's origin, not its pelvis.

use super::layout::ModelType;
use super::npz::{Npz, numbers};
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use crate::solve::input::NpyArray;
use glam::DQuat;

/// An AMASS file's parameters, checked.
///
/// ```
/// use bvhview::smpl::{ModelType, amass, npz};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let bytes = std::fs::read("tests/data/smpl/amass_smplx_walk.npz").unwrap();
/// let params = amass::read(&npz::read(&bytes, "walk.npz")?, "walk.npz", None)?;
/// assert_eq!((params.model, params.frame_count(), params.fps), (ModelType::Smplx, 60, 30.0));
/// assert_eq!(params.gender.as_deref(), Some("female"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Amass {
    /// The body model the poses are for.
    pub model: ModelType,
    /// Frames a second.
    pub fps: f64,
    /// Per frame, each joint's axis-angle (radians), [`ModelType::pose_width`] values.
    pub poses: Vec<f64>,
    /// Per frame, the model's translation (metres, AMASS's Z up).
    pub trans: Vec<f64>,
    /// The shape parameters, as the file gives them.
    pub betas: Vec<f64>,
    /// `male`, `female` or `neutral`, as the file says.
    pub gender: Option<String>,
    /// What was said while reading it.
    pub warnings: Vec<Message>,
}

impl Amass {
    /// Frames in the take.
    pub fn frame_count(&self) -> usize {
        self.poses.len() / self.model.pose_width()
    }
}

/// The one text of `key` (a 0-d or one-element string array), if it holds one.
fn text(npz: &Npz, key: &str) -> Option<String> {
    match npz.get(key)? {
        NpyArray::Text { values, .. } if values.len() == 1 => Some(values[0].clone()),
        _ => None,
    }
}

/// A frames × `width` array of `key`: its frames.
fn rows(
    shape: &[usize],
    values: &[f64],
    width: usize,
    key: &str,
    shown: &str,
) -> Result<usize, Error> {
    match shape {
        [frames, w] if *w == width && frames * w == values.len() => Ok(*frames),
        _ => Err(Error::decoding(
            shown,
            format!("'{key}' has shape {shape:?}; expected frames × {width}"),
        )),
    }
}

/// The SMPL-X keys that split a pose, and the values each holds a frame.
const SPLIT: [(&str, usize); 5] = [
    ("root_orient", 3),
    ("pose_body", 63),
    ("pose_hand", 90),
    ("pose_jaw", 3),
    ("pose_eye", 6),
];

/// Reads an AMASS-layout `.npz` from its arrays. `frame_time` (seconds) stands in for a file
/// that states no rate.
pub fn read(npz: &Npz, shown: &str, frame_time: Option<f64>) -> Result<Amass, Error> {
    let bad = |why: String| Error::decoding(shown, why);
    let mut warnings: Vec<Message> = Vec::new();
    let stated = match text(npz, "surface_model_type") {
        Some(name) => Some(ModelType::named(&name).ok_or_else(|| {
            bad(format!(
                "surface_model_type '{}': not a model bvhview reads (smpl, smplh, smplx)",
                crate::limits::quoted(&name)
            ))
        })?),
        None => None,
    };
    let (model, poses) = if let Some((shape, values)) = numbers(npz, "poses", shown)? {
        let width = shape.get(1).copied().unwrap_or(0);
        let model = match (ModelType::of_pose_width(width), stated) {
            (Some(model), Some(said)) if model != said => {
                return Err(bad(format!(
                    "'poses' has {width} values a frame, {}'s, and surface_model_type says {}",
                    model.label(),
                    said.label()
                )));
            }
            (Some(model), _) => model,
            (None, _) => {
                return Err(bad(format!(
                    "'poses' has shape {shape:?}; expected frames × 72 (SMPL), 156 (SMPL-H) or \
                     165 (SMPL-X)"
                )));
            }
        };
        rows(shape, values, width, "poses", shown)?;
        (model, values.to_vec())
    } else if npz.get("root_orient").is_some() || npz.get("pose_body").is_some() {
        split_poses(npz, shown, stated, &mut warnings)?
    } else {
        let keys: Vec<&str> = npz.names().collect();
        return Err(bad(format!(
            "no poses: an AMASS file holds 'poses' (or SMPL-X's 'root_orient' and \
             'pose_body'); this one holds {}",
            if keys.is_empty() {
                "nothing".to_string()
            } else {
                keys.iter()
                    .map(|k| format!("'{}'", crate::limits::quoted(k)))
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        )));
    };
    let frames = poses.len() / model.pose_width();
    if frames == 0 {
        return Err(bad("no frames: 'poses' has none".into()));
    }
    if let Some(bad_value) = poses.iter().position(|v| !v.is_finite()) {
        return Err(bad(format!(
            "'poses', frame {}: a value that is not finite",
            bad_value / model.pose_width()
        )));
    }
    let trans = match numbers(npz, "trans", shown)? {
        Some((shape, values)) => {
            let rows = rows(shape, values, 3, "trans", shown)?;
            if rows != frames {
                return Err(bad(format!(
                    "'trans' has {rows} frames and the poses {frames}"
                )));
            }
            if let Some(at) = values.iter().position(|v| !v.is_finite()) {
                return Err(bad(format!(
                    "'trans', frame {}: a value that is not finite",
                    at / 3
                )));
            }
            values.to_vec()
        }
        None => {
            warnings.push("no 'trans': the body stays at the origin".into());
            vec![0.0; 3 * frames]
        }
    };
    let fps = rate(npz, shown, frame_time)?;
    let betas = match numbers(npz, "betas", shown)? {
        Some((_, values)) => values.to_vec(),
        None => Vec::new(),
    };
    Ok(Amass {
        model,
        fps,
        poses,
        trans,
        betas,
        gender: text(npz, "gender"),
        warnings,
    })
}

/// The frames a second a file states (`mocap_framerate`, or `mocap_frame_rate` as AMASS's
/// SMPL-X files spell it), else 1 / `frame_time`; refused when neither says.
fn rate(npz: &Npz, shown: &str, frame_time: Option<f64>) -> Result<f64, Error> {
    for key in ["mocap_framerate", "mocap_frame_rate"] {
        if let Some((_, values)) = numbers(npz, key, shown)? {
            let [fps] = values[..] else {
                return Err(Error::decoding(
                    shown,
                    format!("'{key}' holds {} values; expected one", values.len()),
                ));
            };
            if !(crate::limits::MIN_FPS..=crate::limits::MAX_FPS).contains(&fps) {
                return Err(Error::decoding(
                    shown,
                    format!(
                        "'{key}' is {}; a rate is {} to {} frames a second",
                        crate::limits::brief(fps),
                        crate::limits::MIN_FPS,
                        crate::limits::MAX_FPS
                    ),
                ));
            }
            return Ok(fps);
        }
    }
    match frame_time {
        Some(time) => Ok(1.0 / time),
        None => Err(Error::usage(
            Message::from(format!(
                "{shown}: no rate ('mocap_framerate' or 'mocap_frame_rate'); give it with "
            ))
            .argument("frame_time", Some("SECONDS")),
        )),
    }
}

/// SMPL-X's split keys (or SMPL-H's `root_orient`, `pose_body` and `pose_hand`) as one pose a
/// frame, the model type from the keys present (or `stated`); a part the file lacks is zero, said.
fn split_poses(
    npz: &Npz,
    shown: &str,
    stated: Option<ModelType>,
    warnings: &mut Vec<Message>,
) -> Result<(ModelType, Vec<f64>), Error> {
    let has = |key: &str| npz.get(key).is_some();
    let model = stated.unwrap_or(if has("pose_jaw") || has("pose_eye") {
        ModelType::Smplx
    } else {
        ModelType::Smplh
    });
    let mut frames: Option<usize> = None;
    let mut parts: Vec<(&str, usize, Option<&[f64]>)> = Vec::new();
    for (key, width) in SPLIT {
        let wanted = match model {
            ModelType::Smplx => true,
            ModelType::Smplh => matches!(key, "root_orient" | "pose_body" | "pose_hand"),
            ModelType::Smpl => matches!(key, "root_orient" | "pose_body"),
        };
        if !wanted {
            continue;
        }
        let values = match numbers(npz, key, shown)? {
            Some((shape, values)) => {
                let rows = rows(shape, values, width, key, shown)?;
                if frames.is_some_and(|f| f != rows) {
                    return Err(Error::decoding(
                        shown,
                        format!(
                            "'{key}' has {rows} frames, the keys before it {}",
                            frames.unwrap_or(0)
                        ),
                    ));
                }
                frames = Some(rows);
                Some(values)
            }
            None if matches!(key, "root_orient" | "pose_body") => {
                return Err(Error::decoding(
                    shown,
                    format!("no '{key}': a split pose needs 'root_orient' and 'pose_body'"),
                ));
            }
            None => {
                warnings.push(format!("no '{key}': zero in every frame").into());
                None
            }
        };
        parts.push((key, width, values));
    }
    let frames = frames.unwrap_or(0);
    let mut poses = Vec::with_capacity(frames * model.pose_width());
    for f in 0..frames {
        for &(_, width, values) in &parts {
            match values {
                Some(values) => poses.extend_from_slice(&values[f * width..(f + 1) * width]),
                None => poses.extend(std::iter::repeat_n(0.0, width)),
            }
        }
        // SMPL's two hand joints have no key of their own in a split file.
        if model == ModelType::Smpl {
            poses.extend([0.0; 6]);
        }
    }
    Ok((model, poses))
}

/// The quarter turn about X that stands AMASS's Z up in bvhview's Y up: (x, y, z) → (x, z, −y).
fn z_up_to_y_up() -> DQuat {
    DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2)
}

/// `amass` as a skeleton and motion in metres, Y up: the built-in skeleton of its model type
/// (its joints' offsets those of `model`'s body of the file's betas, when a model file is
/// given), each joint's axis-angle split into its channels, the root placed by `trans`; what is
/// said; and the model's pelvis at rest, when a model gave it.
pub fn to_take(amass: &Amass, model: Option<&super::model::BodyModel>) -> Result<OnFigure, Error> {
    let model_type = amass.model;
    let (mut skeleton, index_of) = figure(model_type)?;
    let mut said = amass.warnings.clone();
    let rest_pelvis = match model {
        Some(body) => {
            let shaped = body.shaped(&amass.betas, &[])?;
            model_offsets(&mut skeleton, &index_of, &shaped.joints);
            said.push(body_line(amass, body, shaped.betas_used).into());
            Some(shaped.joints[0].to_array())
        }
        None => {
            said.push(
                Message::from(format!(
                    "{} parameters read on bvhview's built-in {} figure (its lengths, not this \
                     body's shape, and trans taken as the pelvis's place: the file's betas need \
                     the model file, given by ",
                    model_type.label(),
                    model_type.built_in()
                ))
                .argument("body_model", Some("MODEL.npz"))
                .text("); AMASS's Z up turned to Y up"),
            );
            None
        }
    };
    let pelvis = glam::DVec3::from(rest_pelvis.unwrap_or([0.0; 3]));
    let frames = amass.frame_count();
    let width = model_type.pose_width();
    let turn = z_up_to_y_up();
    let channels = skeleton.channel_count();
    let mut data = Vec::with_capacity(frames * channels);
    let mut previous: Vec<Option<[f64; 3]>> = vec![None; skeleton.joints.len()];
    for f in 0..frames {
        let pose = &amass.poses[f * width..(f + 1) * width];
        for (j, joint) in skeleton.joints.iter().enumerate() {
            let Some(k) = index_of[j] else { continue };
            let axis_angle = glam::DVec3::from_slice(&pose[3 * k..3 * k + 3]);
            let mut rotation = DQuat::from_scaled_axis(axis_angle);
            if joint.parent.is_none() {
                rotation = turn * rotation;
                let place =
                    turn * (glam::DVec3::from_slice(&amass.trans[3 * f..3 * f + 3]) + pelvis);
                data.extend(place.to_array().map(|v| v as f32));
            }
            let order = joint.rotation_order.unwrap_or(crate::RotationOrder::Zyx);
            let angles = crate::model::euler::split(rotation, order, previous[j]);
            previous[j] = Some(angles);
            data.extend(angles.map(|a| a.to_degrees() as f32));
        }
    }
    let motion = Motion::new(amass_frame_time(amass), channels, frames, data);
    Ok(OnFigure {
        skeleton,
        motion,
        said,
        rest_pelvis,
    })
}

/// An AMASS file's take on a figure ([`to_take`]).
///
/// ```
/// use bvhview::smpl::{amass, npz};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let bytes = std::fs::read("tests/data/smpl/amass_smplh_walk.npz").unwrap();
/// let params = amass::read(&npz::read(&bytes, "walk.npz")?, "walk.npz", None)?;
/// // No model file: bvhview's own figure, the pelvis where `trans` puts it.
/// let taken = amass::to_take(&params, None)?;
/// assert_eq!(taken.motion.frame_count(), 60);
/// assert!(taken.rest_pelvis.is_none());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct OnFigure {
    /// The figure: the built-in skeleton of the model type, its offsets the model's when given.
    pub skeleton: Skeleton,
    /// The frames.
    pub motion: Motion,
    /// What is said of the reading.
    pub said: Vec<Message>,
    /// The model's pelvis at rest (metres, its axes), when a model file gave the joints.
    pub rest_pelvis: Option<[f64; 3]>,
}

/// The built-in figure of `model_type` in metres, Y up stated, and each of its joints' index in
/// the model type's order (`None` for End Sites).
pub(crate) fn figure(model_type: ModelType) -> Result<(Skeleton, Vec<Option<usize>>), Error> {
    let (skeleton, _) = crate::bvh::built_in::built_in(model_type.built_in()).ok_or_else(|| {
        Error::usage(format!(
            "the built-in skeleton {} does not load",
            model_type.built_in()
        ))
    })?;
    // Centimetres to metres: the lengths alone (the built-in's one rest frame is not used).
    let no_frames = Motion::new(1.0 / 30.0, skeleton.channel_count(), 0, Vec::new());
    let (mut skeleton, _) = crate::edit::scale(&skeleton, &no_frames, 0.01)?;
    // AMASS and the models are metres; the take is Y up, which it states.
    skeleton.y_up_stated = true;
    let names = model_type.joint_names();
    let index_of = skeleton
        .joints
        .iter()
        .map(|joint| {
            (!joint.end_site)
                .then(|| names.iter().position(|n| *n == joint.name))
                .flatten()
        })
        .collect();
    Ok((skeleton, index_of))
}

/// Each model joint's OFFSET in `skeleton` (`index_of` its model index) made the model's: its
/// rest joint less its parent's (the root's: where the model's pelvis rests); End Sites keep
/// the built-in figure's.
pub(crate) fn model_offsets(
    skeleton: &mut Skeleton,
    index_of: &[Option<usize>],
    joints: &[glam::DVec3],
) {
    for j in 0..skeleton.joints.len() {
        let Some(k) = index_of[j] else { continue };
        let parent = skeleton.joints[j].parent.and_then(|p| index_of[p]);
        let offset = match (skeleton.joints[j].parent, parent) {
            (None, _) => joints[k],
            (Some(_), Some(p)) => joints[k] - joints[p],
            (Some(_), None) => continue,
        };
        skeleton.joints[j].offset = offset.as_vec3();
    }
}

/// What a take read with a model file says: the model, the betas used, the genders.
fn body_line(amass: &Amass, body: &super::model::BodyModel, betas_used: usize) -> String {
    let betas = match (amass.betas.len(), betas_used) {
        (0, _) => "no betas in the file: its mean shape".to_string(),
        (given, used) if given == used => format!("its {given} betas"),
        (given, used) => format!(
            "{used} of its {given} betas (the model has {} shape components)",
            body.shape_count()
        ),
    };
    let gender = match (amass.gender.as_deref(), body.gender.as_deref()) {
        (Some(file), Some(model)) if !file.eq_ignore_ascii_case(model) => {
            format!("; the file says {file}, the model is {model}")
        }
        _ => String::new(),
    };
    format!(
        "{} parameters read on the body of {} ({betas}{gender}); AMASS's Z up turned to Y up",
        amass.model.label(),
        body.name
    )
}

fn amass_frame_time(amass: &Amass) -> f64 {
    1.0 / amass.fps
}

/// The model type whose joints a skeleton has, by name: the largest whose 22 body joints and
/// some of whose own joints (hands, jaw, eyes) it has; a skeleton of the body's 22 alone is
/// written as SMPL-H, hands zero, as AMASS and HumanML3D keep them.
fn model_of(skeleton: &Skeleton) -> Option<ModelType> {
    let has = |name: &str| {
        skeleton
            .joints
            .iter()
            .any(|j| !j.end_site && j.name == name)
    };
    let body = ModelType::Smpl.joint_names();
    if !body[..22].iter().all(|n| has(n)) {
        return None;
    }
    Some(
        if has("jaw") || has("left_eye_smplhf") || has("right_eye_smplhf") {
            ModelType::Smplx
        } else if has("left_hand") || has("right_hand") {
            ModelType::Smpl
        } else {
            ModelType::Smplh
        },
    )
}

/// A take on a SMPL-family skeleton (its joints named as the model's: the built-in `smpl22`,
/// `smpl24`, `smplh52`, `smplx55`, an AMASS file read, a take retargeted onto one) as AMASS's
/// parameters: each joint's rotation as an axis-angle, the root's turned from the take's up axis
/// to AMASS's Z up, `trans` the pelvis's place in metres (`metres` per unit of the take, position
/// channels meeting the OFFSET by `mode`); a
/// model joint the skeleton lacks (hands, jaw, eyes) is zero in every frame, said. `body` (an
/// AMASS file's, read on this skeleton) gives the betas and gender, and `trans` is then the
/// pelvis less where the body's model rests it; without one, `betas` zero (a neutral shape),
/// the gender neutral.
pub fn of_take(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: crate::model::pose::OffsetMode,
    metres: f64,
    up: crate::model::pose::Up,
    body: Option<&super::body::Body>,
    shown: &str,
) -> Result<Amass, Error> {
    let model = model_of(skeleton).ok_or_else(|| {
        Error::usage(
            Message::from(format!(
                "{shown}: an AMASS file is written from a take on a SMPL-family skeleton (joints \
                 named pelvis, left_hip, … as smpl22, smpl24, smplh52 and smplx55 name them); \
                 put the take on one first with retarget's "
            ))
            .argument("onto", Some("smplh")),
        )
    })?;
    let names = model.joint_names();
    let joint_of: Vec<Option<usize>> = names
        .iter()
        .map(|n| {
            skeleton
                .joints
                .iter()
                .position(|j| !j.end_site && &j.name == n)
        })
        .collect();
    let mut warnings: Vec<Message> = Vec::new();
    let missing: Vec<&str> = names
        .iter()
        .zip(&joint_of)
        .filter(|(_, j)| j.is_none())
        .map(|(n, _)| n.as_str())
        .collect();
    if !missing.is_empty() {
        warnings.push(
            format!(
                "{} of {}'s joints are not in the take ({} …): zero in every frame",
                missing.len(),
                model.label(),
                missing[0]
            )
            .into(),
        );
    }
    let root = joint_of[0].filter(|&j| skeleton.joints[j].parent.is_none());
    let Some(root) = root else {
        return Err(Error::usage(format!(
            "{shown}: the take's pelvis is not its root; an AMASS file poses the pelvis as the \
             root"
        )));
    };
    // The take's world to AMASS's: Y up turned to Z up (the inverse of the reader's turn).
    let back = match up {
        crate::model::pose::Up::Z => DQuat::IDENTITY,
        _ => z_up_to_y_up().inverse(),
    };
    // The body the take was read with, where it is of this model type.
    let body = body.filter(|b| b.model == model);
    if body.is_none() {
        warnings.push(
            Message::from(
                "betas zero and gender neutral (the model's mean shape; trans is the pelvis's \
                 place): put the take on a SMPL-family figure with a model file (",
            )
            .argument("onto", Some("smplh"))
            .text(" with ")
            .argument("body_model", Some("MODEL.npz"))
            .text(") to fit the betas to its bones"),
        );
    }
    let rest_pelvis = glam::DVec3::from(body.and_then(|b| b.rest_pelvis).unwrap_or([0.0; 3]));
    let frames = motion.frame_count();
    let width = model.pose_width();
    let mut poses = Vec::with_capacity(frames * width);
    let mut trans = Vec::with_capacity(frames * 3);
    let mut world = Vec::new();
    for f in 0..frames {
        let row = motion.frame(f);
        crate::model::pose::world_transforms_f64(skeleton, row, mode, &mut world);
        for (k, joint) in joint_of.iter().enumerate() {
            let rotation = match joint {
                Some(j) => {
                    let local = crate::model::pose::local_rotation_f64(
                        &skeleton.joints[*j],
                        skeleton.joints[*j].values(row),
                    );
                    if k == 0 { back * local } else { local }
                }
                None => DQuat::IDENTITY,
            };
            poses.extend(rotation.normalize().to_scaled_axis().to_array());
        }
        let place = back * (world[root].1 * metres) - rest_pelvis;
        trans.extend(place.to_array());
    }
    if !(motion.frame_time > 0.0 && motion.frame_time.is_finite()) {
        return Err(Error::usage(format!(
            "{shown}: a frame time of {} s; an AMASS file states its rate",
            motion.frame_time
        )));
    }
    Ok(Amass {
        model,
        fps: 1.0 / motion.frame_time,
        poses,
        trans,
        betas: body.map_or_else(|| vec![0.0; 16], |b| b.betas.clone()),
        gender: Some(
            body.and_then(|b| b.gender.clone())
                .unwrap_or_else(|| "neutral".into()),
        ),
        warnings,
    })
}

/// `amass` as an `.npz` in AMASS's layout (stored members, as numpy's `savez` writes them):
/// `poses`, `trans`, `betas`, `gender`, and the rate as AMASS's SMPL+H files name it
/// (`mocap_framerate`); a SMPL-X file also `surface_model_type`, `mocap_frame_rate` and the
/// split keys (`root_orient`, `pose_body`, `pose_hand`, `pose_jaw`, `pose_eye`).
pub fn to_npz(amass: &Amass) -> Result<Vec<u8>, Error> {
    let frames = amass.frame_count();
    let width = amass.model.pose_width();
    let mut members: Vec<(String, Vec<u8>)> = vec![
        (
            "poses".into(),
            super::npz::npy_f64(&[frames, width], &amass.poses),
        ),
        (
            "trans".into(),
            super::npz::npy_f64(&[frames, 3], &amass.trans),
        ),
        (
            "betas".into(),
            super::npz::npy_f64(&[amass.betas.len()], &amass.betas),
        ),
        (
            "gender".into(),
            super::npz::npy_text(amass.gender.as_deref().unwrap_or("neutral")),
        ),
    ];
    let rate = super::npz::npy_f64(&[], &[amass.fps]);
    if amass.model == ModelType::Smplx {
        members.push(("surface_model_type".into(), super::npz::npy_text("smplx")));
        members.push(("mocap_frame_rate".into(), rate));
        let mut start = 0;
        for (key, part) in SPLIT {
            let values: Vec<f64> = (0..frames)
                .flat_map(|f| amass.poses[f * width + start..f * width + start + part].to_vec())
                .collect();
            members.push((key.into(), super::npz::npy_f64(&[frames, part], &values)));
            start += part;
        }
    } else {
        members.push(("mocap_framerate".into(), rate));
    }
    super::npz::write(&members)
}
