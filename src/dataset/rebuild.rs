//! The way back: arrays in a dataset's layout (a clip, or a model's output shaped like one)
//! turned into a take on the group's skeleton, to save as BVH or glTF.

use super::clip::Topology;
use crate::io::error::Error;
use crate::model::pose::RotationKind;
use crate::{Motion, Skeleton};

/// Arrays in the dataset's layout, frame after frame (row-major).
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// # use bvhview::dataset::{self, Options};
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// # let (takes, out) = (dataset::takes(folder.path())?, folder.path().join("dataset"));
/// # let list = dataset::whole_list(folder.path(), &takes);
/// # dataset::compile(folder.path(), takes, &Options::default(), 1, &out, list, |_, _, _, _| true)?;
/// use bvhview::dataset::rebuild::{Arrays, motion_of};
/// use bvhview::model::pose::RotationKind;
///
/// // `out` is a dataset of one clip (the walk, 86 frames at 30 fps, 6D rotations).
/// let dataset = dataset::read::open(&out)?;
/// let file = &dataset.groups[0].arrays[1];
/// assert_eq!(file.name, "group_0/rotations.npy");
/// let bytes = file.read_rows(0..86)?;
/// let rotations: Vec<f32> =
///     bytes.chunks_exact(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect();
/// let kind = RotationKind::SixD;
/// let (translations, root_translations) = (None, None); // the rest offsets, and the root's
/// let arrays = Arrays { frames: 86, rotations: &rotations, kind, translations, root_translations };
/// let topology = &dataset.manifest.groups[0].topology;
/// let (skeleton, motion) = motion_of(&dataset.skeleton(0)?, topology, 0, None, &arrays, 30.0)?;
/// assert_eq!((motion.frame_count(), skeleton.joints.len()), (86, 38));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Arrays<'a> {
    /// How many frames the arrays hold.
    pub frames: usize,
    /// frames × rotated × `kind.width()`: each rotated point's local rotation.
    pub rotations: &'a [f32],
    /// How `rotations` writes each rotation as numbers.
    pub kind: RotationKind,
    /// frames × translated × 3: each translated point's local translation. Without them the
    /// translated points stand at their rest offsets, but for `root_translations`.
    pub translations: Option<&'a [f32]>,
    /// frames × 3: the travel joint's world position; used (when `translations` are not given)
    /// for a travel joint that is a root, whose world position is its translation.
    pub root_translations: Option<&'a [f32]>,
}

/// The take `arrays` make on `skeleton` (a group's `skeleton.bvh`, laid out as `topology`),
/// with `rest` (points × 3) as its OFFSETs when given (a clip's `rest_offsets`), at `fps`.
/// Position channels hold the whole translation (the replace mode every reader assumes);
/// rotation channels hold the Euler angles of each rotation in the joint's own channel order.
pub fn motion_of(
    skeleton: &Skeleton,
    topology: &Topology,
    travel_joint: usize,
    rest: Option<&[f32]>,
    arrays: &Arrays,
    fps: f64,
) -> Result<(Skeleton, Motion), Error> {
    crate::limits::fps(fps, false)?;
    check_shapes(topology, arrays)?;
    check_numbers(topology, arrays)?;
    let skeleton = placed(skeleton, topology, travel_joint, rest, arrays)?;
    let channels = skeleton.channel_count();
    let data = rows(&skeleton, topology, travel_joint, arrays)?;
    let motion = Motion::new(1.0 / fps, channels, arrays.frames, data);
    crate::edit::finite("rebuilding the take", skeleton, motion)
}

/// A refusal: the arrays do not make a take, and `why`.
fn refuse<T>(why: String) -> Result<T, Error> {
    Err(Error::usage(why))
}

/// Refuses arrays without frames, or whose numbers are not as many as their frames of
/// `topology` make.
fn check_shapes(topology: &Topology, arrays: &Arrays) -> Result<(), Error> {
    let (rotated, translated) = (topology.rotated.len(), topology.translated.len());
    let width = arrays.kind.width();
    let frames = arrays.frames;
    let shape_of = |name: &str, values: usize, per_frame: usize, shape: String| match frames
        .checked_mul(per_frame)
        == Some(values)
    {
        true => Ok(()),
        false => Err(Error::usage(format!(
            "{name}: {values} numbers where {frames} frames of {shape} make {}",
            frames.saturating_mul(per_frame)
        ))),
    };
    if frames == 0 {
        return refuse("no frames: a take needs at least one".to_string());
    }
    let rotation_shape = match arrays.kind {
        RotationKind::Matrix => format!("{rotated} x 3 x 3"),
        kind => format!("{rotated} x {}", kind.width()),
    };
    shape_of(
        "rotations",
        arrays.rotations.len(),
        rotated * width,
        rotation_shape,
    )
    .map_err(|error| kinds_that_fit(error, arrays, rotated))?;
    if let Some(t) = arrays.translations {
        shape_of(
            "translations",
            t.len(),
            translated * 3,
            format!("{translated} x 3"),
        )?;
    }
    if let Some(t) = arrays.root_translations {
        shape_of("root_translations", t.len(), 3, "3".to_string())?;
    }
    Ok(())
}

/// `error` (rotations of the wrong count) with the other kinds whose count the rotations fit
/// (quaternions given to a 6D dataset) and how to name them, if any.
fn kinds_that_fit(error: Error, arrays: &Arrays, rotated: usize) -> Error {
    let (width, frames) = (arrays.kind.width(), arrays.frames);
    let fits: Vec<&str> = [
        RotationKind::Quat,
        RotationKind::Matrix,
        RotationKind::SixD,
        RotationKind::Euler,
        RotationKind::AxisAngle,
    ]
    .into_iter()
    .filter(|k| {
        k.width() != width
            && frames.saturating_mul(rotated).saturating_mul(k.width()) == arrays.rotations.len()
    })
    .map(RotationKind::name)
    .collect();
    match fits.is_empty() {
        true => error,
        false => Error::usage(format!(
            "{error}; they fit {} numbers: name their kind (kind=\"{}\")",
            fits.join(" or "),
            fits.join("\" or kind=\"")
        )),
    }
}

/// Refuses a number that is not finite, or rotation numbers that are no rotation, by where
/// they are.
fn check_numbers(topology: &Topology, arrays: &Arrays) -> Result<(), Error> {
    let rotated = topology.rotated.len();
    let width = arrays.kind.width();
    for (name, values) in [
        ("rotations", Some(arrays.rotations)),
        ("translations", arrays.translations),
        ("root_translations", arrays.root_translations),
    ] {
        if let Some(at) = values.and_then(|v| v.iter().position(|x| !x.is_finite())) {
            return refuse(format!("{name}: number {at} is not finite"));
        }
    }
    if arrays.kind != RotationKind::Euler {
        for (at, numbers) in arrays.rotations.chunks_exact(width).enumerate() {
            if let Some(why) = crate::model::pose::rotation_numbers_problem(arrays.kind, numbers) {
                return refuse(format!(
                    "rotations[{}, {}]: {why}",
                    at / rotated.max(1),
                    at % rotated.max(1)
                ));
            }
        }
    }
    Ok(())
}

/// `skeleton` with `rest` as its OFFSETs when given; refuses root translations for a travel
/// joint that is not a root (its world position is not its translation).
fn placed(
    skeleton: &Skeleton,
    topology: &Topology,
    travel_joint: usize,
    rest: Option<&[f32]>,
    arrays: &Arrays,
) -> Result<Skeleton, Error> {
    let points = topology.joints.len();
    let translated = topology.translated.len();
    let mut skeleton = skeleton.clone();
    if let Some(rest) = rest {
        if rest.len() != points * 3 {
            return refuse(format!(
                "rest offsets: {} numbers for {points} points",
                rest.len()
            ));
        }
        for (joint, offset) in skeleton.joints.iter_mut().zip(rest.chunks_exact(3)) {
            joint.offset = glam::Vec3::from_slice(offset);
        }
    }
    let travel_is_root = skeleton
        .joints
        .get(travel_joint)
        .is_some_and(|j| j.parent.is_none());
    if arrays.translations.is_none() && arrays.root_translations.is_some() && !travel_is_root {
        return refuse(format!(
            "root_translations are the world positions of {}, which is not a root: give \
             translations (frames x {translated} x 3) instead",
            crate::io::error::quoted(
                topology
                    .joints
                    .get(travel_joint)
                    .map_or("?", |n| n.as_str())
            )
        ));
    }
    Ok(skeleton)
}

/// The MOTION rows: each joint's channels in each frame, positions from its translation (the
/// arrays', the root translations' for the travel joint, else its OFFSET), rotations from its
/// rotation's Euler angles (0 for a joint the arrays do not rotate).
fn rows(
    skeleton: &Skeleton,
    topology: &Topology,
    travel_joint: usize,
    arrays: &Arrays,
) -> Result<Vec<f32>, Error> {
    let points = topology.joints.len();
    let (rotated, translated) = (topology.rotated.len(), topology.translated.len());
    let width = arrays.kind.width();
    let frames = arrays.frames;
    let channels = skeleton.channel_count();
    let values = frames
        .checked_mul(channels)
        .filter(|&n| n as u64 <= crate::limits::MAX_GENERATED_VALUES)
        .ok_or_else(|| {
            Error::usage(format!(
                "{frames} frames of {channels} values: more than a take holds"
            ))
        })?;
    let slot_of = |list: &[u32]| {
        let mut slots = vec![None; points];
        for (slot, &p) in list.iter().enumerate() {
            slots[p as usize] = Some(slot);
        }
        slots
    };
    let (rotation_slot, translation_slot) =
        (slot_of(&topology.rotated), slot_of(&topology.translated));
    let mut data = Vec::with_capacity(values);
    for frame in 0..frames {
        for (index, joint) in skeleton.joints.iter().enumerate() {
            let translation = match (arrays.translations, translation_slot[index]) {
                (Some(t), Some(slot)) => {
                    glam::Vec3::from_slice(&t[(frame * translated + slot) * 3..][..3])
                }
                _ => match arrays.root_translations {
                    Some(t) if index == travel_joint => {
                        glam::Vec3::from_slice(&t[frame * 3..][..3])
                    }
                    _ => joint.offset,
                },
            };
            let angles = match rotation_slot[index] {
                Some(slot) => {
                    let numbers = &arrays.rotations[(frame * rotated + slot) * width..][..width];
                    crate::edit::channel_angles(joint, arrays.kind, numbers)
                }
                None => Vec::new(),
            };
            let mut angles = angles.into_iter();
            for channel in &joint.channels {
                data.push(match channel.is_position() {
                    true => translation[channel.axis()],
                    false => angles.next().unwrap_or(0.0),
                });
            }
        }
    }
    Ok(data)
}
