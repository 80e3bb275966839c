//! Pose estimators' keypoint layouts: Human3.6M's 17 joints (VideoPose3D, MotionBERT), COCO's
//! 17, MediaPipe's 33, OpenPose's BODY_25 and SMPL's 24, each point mapped to the body's roles
//! as SMPL's 22 joints name them (`pelvis`, `left_knee`, …), so that any skeleton can be solved
//! onto from them ([`crate::solve`] after [`onto_skeleton`]).
//!
//! A layout lacks some of SMPL's joints: COCO has no pelvis, neck or spine, Human3.6M no feet.
//! Those are placed from the others where the body allows (the pelvis between the hips, the
//! neck between the shoulders, the spine along the line between them, each collar two fifths
//! of the way from the neck to its shoulder), and said; the feet of a layout without toes are
//! not placed (they keep their rest pose under the ankles). Points a frame does not have (NaN,
//! or a confidence under the threshold) are filled from the same point's frames before and
//! after, and said per point.

use super::positions::{Positions, SMPL22_ORDER};
use crate::io::error::Error;
use glam::{DQuat, DVec3};

/// A keypoint layout.
///
/// ```
/// use bvhview::solve::layouts::Layout;
///
/// let coco = Layout::named("coco17").unwrap();
/// assert_eq!(coco.points().len(), 17);
/// assert_eq!(coco.points()[5], "left_shoulder");
/// assert_eq!(Layout::named("H36M").unwrap(), Layout::H36m17);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Human3.6M's 17 joints, in VideoPose3D's and MotionBERT's order.
    H36m17,
    /// COCO's 17 keypoints.
    Coco17,
    /// MediaPipe Pose's 33 landmarks.
    Mediapipe33,
    /// OpenPose's BODY_25.
    Body25,
    /// SMPL's 24 joints.
    Smpl24,
}

const H36M17: [&str; 17] = [
    "pelvis",
    "right_hip",
    "right_knee",
    "right_ankle",
    "left_hip",
    "left_knee",
    "left_ankle",
    "spine",
    "thorax",
    "neck_nose",
    "head_top",
    "left_shoulder",
    "left_elbow",
    "left_wrist",
    "right_shoulder",
    "right_elbow",
    "right_wrist",
];

const COCO17: [&str; 17] = [
    "nose",
    "left_eye",
    "right_eye",
    "left_ear",
    "right_ear",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
];

const MEDIAPIPE33: [&str; 33] = [
    "nose",
    "left_eye_inner",
    "left_eye",
    "left_eye_outer",
    "right_eye_inner",
    "right_eye",
    "right_eye_outer",
    "left_ear",
    "right_ear",
    "mouth_left",
    "mouth_right",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_pinky",
    "right_pinky",
    "left_index",
    "right_index",
    "left_thumb",
    "right_thumb",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
    "left_heel",
    "right_heel",
    "left_foot_index",
    "right_foot_index",
];

const BODY25: [&str; 25] = [
    "nose",
    "neck",
    "right_shoulder",
    "right_elbow",
    "right_wrist",
    "left_shoulder",
    "left_elbow",
    "left_wrist",
    "mid_hip",
    "right_hip",
    "right_knee",
    "right_ankle",
    "left_hip",
    "left_knee",
    "left_ankle",
    "right_eye",
    "left_eye",
    "right_ear",
    "left_ear",
    "left_big_toe",
    "left_small_toe",
    "left_heel",
    "right_big_toe",
    "right_small_toe",
    "right_heel",
];

/// SMPL's 24 joints: the body's 22 (the solver's list) and a hand each side.
const SMPL24: [&str; 24] = {
    let mut all = [""; 24];
    let mut k = 0;
    while k < 22 {
        all[k] = SMPL22_ORDER[k];
        k += 1;
    }
    all[22] = "left_hand";
    all[23] = "right_hand";
    all
};

/// The limbs' joints every layout has under the same names as SMPL's.
const LIMBS: [&str; 12] = [
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
];

impl Layout {
    /// Every layout.
    pub const ALL: [Layout; 5] = [
        Layout::H36m17,
        Layout::Coco17,
        Layout::Mediapipe33,
        Layout::Body25,
        Layout::Smpl24,
    ];

    /// The layout a name says (`h36m17`, `coco17`, `mediapipe33`, `body25`, `smpl24`; case,
    /// `-`, `_` and the count aside where unambiguous: `h36m`, `coco`, `mediapipe`).
    pub fn named(name: &str) -> Option<Layout> {
        let name = name.trim().to_ascii_lowercase().replace(['-', '_'], "");
        Layout::ALL.into_iter().find(|l| {
            let label = l.label();
            name == label || name == label.trim_end_matches(char::is_numeric)
        })
    }

    /// [`Layout::named`], or why not, naming every layout (for the caller to put after its
    /// option: `--layout X: …`, `layout="X": …`).
    ///
    /// ```
    /// use bvhview::solve::layouts::Layout;
    ///
    /// assert_eq!(Layout::parse("COCO"), Ok(Layout::Coco17));
    /// assert_eq!(
    ///     Layout::parse("vicon").unwrap_err(),
    ///     "not a layout bvhview knows (h36m17, coco17, mediapipe33, body25, smpl24)"
    /// );
    /// ```
    pub fn parse(name: &str) -> Result<Layout, String> {
        Layout::named(name).ok_or_else(|| {
            let names: Vec<&str> = Layout::ALL.iter().map(|l| l.label()).collect();
            format!("not a layout bvhview knows ({})", names.join(", "))
        })
    }

    /// Its name, as `--layout` takes it.
    pub fn label(self) -> &'static str {
        match self {
            Layout::H36m17 => "h36m17",
            Layout::Coco17 => "coco17",
            Layout::Mediapipe33 => "mediapipe33",
            Layout::Body25 => "body25",
            Layout::Smpl24 => "smpl24",
        }
    }

    /// Its points' names, in its order.
    pub fn points(self) -> &'static [&'static str] {
        match self {
            Layout::H36m17 => &H36M17,
            Layout::Coco17 => &COCO17,
            Layout::Mediapipe33 => &MEDIAPIPE33,
            Layout::Body25 => &BODY25,
            Layout::Smpl24 => &SMPL24,
        }
    }

    fn index(self, name: &str) -> Option<usize> {
        self.points().iter().position(|p| *p == name)
    }

    /// The layout point that stands where SMPL's joint `smpl` does, if one does.
    fn point_of(self, smpl: &str) -> Option<usize> {
        let same = |name: &str| self.index(name);
        match (self, smpl) {
            (_, limb) if LIMBS.contains(&limb) => same(limb),
            (Layout::Smpl24, name) => same(name),
            (Layout::H36m17, "pelvis") => same("pelvis"),
            (Layout::H36m17, "spine2") => same("spine"),
            (Layout::H36m17, "neck") => same("thorax"),
            (Layout::Body25, "pelvis") => same("mid_hip"),
            (Layout::Body25, "neck") => same("neck"),
            (Layout::Mediapipe33, "left_foot") => same("left_foot_index"),
            (Layout::Mediapipe33, "right_foot") => same("right_foot_index"),
            _ => None,
        }
    }
}

/// Keypoints of a layout: frame after frame, each point's position, and how sure the
/// estimator was of it (1 where the input gives none).
///
/// ```
/// use bvhview::solve::layouts::{Keypoints, Layout};
///
/// // One frame of COCO's 17 points, x, y, z and a confidence each.
/// let values = vec![0.5; 17 * 4];
/// let keypoints = Keypoints::new(Layout::Coco17, &[1, 17, 4], &values, 1.0 / 30.0, "k.npy")?;
/// assert_eq!((keypoints.frames(), keypoints.confidence[0]), (1, 0.5));
/// # Ok::<(), bvhview::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Keypoints {
    /// The layout.
    pub layout: Layout,
    /// Frame after frame, each point (NaN where a frame lacks it).
    pub points: Vec<DVec3>,
    /// Frame after frame, each point's confidence.
    pub confidence: Vec<f64>,
    /// Seconds between frames.
    pub frame_time: f64,
}

impl Keypoints {
    /// Keypoints of `layout` from `values`, frames × points × 3 (or × 4, a confidence last),
    /// named `shown` in errors. Refused: no frames, a point count that is not the layout's.
    pub fn new(
        layout: Layout,
        shape: &[usize],
        values: &[f64],
        frame_time: f64,
        shown: &str,
    ) -> Result<Keypoints, Error> {
        let count = layout.points().len();
        let refuse = |why: String| Error::usage(format!("{shown}: {why}"));
        let (frames, points, width) = match *shape {
            [frames, points, width @ (3 | 4)] => (frames, points, width),
            [points, width @ (3 | 4)] => (1, points, width),
            _ => {
                return Err(refuse(format!(
                    "shape {shape:?}: keypoints are frames × points × 3 (or × 4, a confidence \
                     last); {} has {count} points",
                    layout.label()
                )));
            }
        };
        if points != count {
            return Err(refuse(format!(
                "{points} points a frame; {} has {count} ({} …)",
                layout.label(),
                layout.points()[..3].join(", ")
            )));
        }
        if frames == 0 {
            return Err(refuse(format!("no frames of {} keypoints", layout.label())));
        }
        if values.len() != frames * points * width {
            return Err(refuse(format!(
                "{} values for shape {shape:?}",
                values.len()
            )));
        }
        if !(frame_time > 0.0 && frame_time.is_finite()) {
            return Err(refuse(format!("a frame time of {frame_time} s")));
        }
        let rows = values.chunks_exact(width);
        Ok(Keypoints {
            layout,
            points: rows.clone().map(|r| DVec3::new(r[0], r[1], r[2])).collect(),
            confidence: rows.map(|r| if width == 4 { r[3] } else { 1.0 }).collect(),
            frame_time,
        })
    }

    /// How many frames.
    pub fn frames(&self) -> usize {
        self.points.len() / self.layout.points().len()
    }
}

/// What [`to_smpl`] made of keypoints: SMPL-named positions, and what it said.
///
/// ```
/// use bvhview::solve::layouts::{Layout, of_take, to_smpl};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = bvhview::Take::open("tests/data/bvh/bvh11_131_01.bvh")?.trim(0..10);
/// let coco = of_take(&walk, Layout::Coco17, 0.01)?; // the walk is in centimetres
/// let placed = to_smpl(&coco, 0.3, None, "walk")?;
/// assert!(placed.positions.names.iter().any(|n| n == "pelvis")); // between the hips
/// assert!(placed.said.iter().any(|s| s.contains("coco17 has no pelvis")));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// The positions, named as SMPL's joints (those the layout has or places).
    pub positions: Positions,
    /// The joints placed from other points (not the layout's own): a fit of lengths leaves
    /// their bones out.
    pub placed: Vec<String>,
    /// What was placed, filled, turned or left out, a line each.
    pub said: Vec<String>,
}

/// The keypoints as SMPL's joints, Y up: each point the layout has for a joint taken, the
/// joints it lacks placed from the others where the body allows, points missing from a frame
/// (NaN, infinite, or under `min_confidence`) filled from the point's frames before and after,
/// and the figure turned so that it stands along +y (its up guessed from pelvis to neck, unless
/// `up_given`, which names the axis the keypoints stand along).
pub fn to_smpl(
    keypoints: &Keypoints,
    min_confidence: f64,
    up_given: Option<DVec3>,
    shown: &str,
) -> Result<Placed, Error> {
    let layout = keypoints.layout;
    let count = layout.points().len();
    let frames = keypoints.frames();
    let mut said = Vec::new();
    // Fill each point's missing frames from its nearest good ones; a point with none is left
    // out (a layout's face points for a skeleton that has none).
    let mut points = keypoints.points.clone();
    let mut present = vec![true; count];
    for p in 0..count {
        let good = |f: usize| {
            let at = f * count + p;
            keypoints.points[at].is_finite() && keypoints.confidence[at] >= min_confidence
        };
        let kept: Vec<usize> = (0..frames).filter(|&f| good(f)).collect();
        if kept.is_empty() {
            present[p] = false;
            continue;
        }
        if kept.len() == frames {
            continue;
        }
        for f in 0..frames {
            if good(f) {
                continue;
            }
            let after = kept.partition_point(|&k| k < f);
            let value = match (after.checked_sub(1).map(|i| kept[i]), kept.get(after)) {
                (Some(a), Some(&b)) => {
                    let t = (f - a) as f64 / (b - a) as f64;
                    keypoints.points[a * count + p].lerp(keypoints.points[b * count + p], t)
                }
                (Some(a), None) => keypoints.points[a * count + p],
                (None, Some(&b)) => keypoints.points[b * count + p],
                (None, None) => unreachable!("kept is not empty"),
            };
            points[f * count + p] = value;
        }
        said.push(format!(
            "{}: {} of {frames} frames filled from the frames around them (missing or under \
             confidence {min_confidence})",
            layout.points()[p],
            frames - kept.len()
        ));
    }
    let absent: Vec<&str> = (0..count)
        .filter(|&p| !present[p])
        .map(|p| layout.points()[p])
        .collect();
    if !absent.is_empty() {
        said.push(format!(
            "{} of {}'s points in no frame: left out ({})",
            absent.len(),
            layout.label(),
            absent.join(", ")
        ));
    }
    let at = |f: usize, name: &str| -> Option<DVec3> {
        let p = layout.index(name)?;
        present[p].then(|| points[f * count + p])
    };
    // Each of SMPL's 22 joints: the layout's own point, or placed from others (the pelvis and
    // the neck first: the spine and the collars are placed from them).
    let mut by_name: std::collections::HashMap<&str, Vec<DVec3>> = Default::default();
    let mut placed_said: Vec<&str> = Vec::new();
    let order = ["pelvis", "neck"].into_iter().chain(
        SMPL22_ORDER
            .into_iter()
            .filter(|n| !matches!(*n, "pelvis" | "neck")),
    );
    for name in order {
        let own = layout.point_of(name).filter(|&p| present[p]).map(|p| {
            (0..frames)
                .map(|f| points[f * count + p])
                .collect::<Vec<_>>()
        });
        let column = match own {
            Some(column) => Some(column),
            None => {
                let placed = place(name, frames, &at, &by_name);
                if placed.is_some() {
                    placed_said.push(name);
                }
                placed
            }
        };
        if let Some(column) = column {
            by_name.insert(name, column);
        }
    }
    let placed_names: Vec<&str> = SMPL22_ORDER
        .into_iter()
        .filter(|n| by_name.contains_key(n))
        .collect();
    let missing: Vec<&str> = SMPL22_ORDER
        .into_iter()
        .filter(|n| !by_name.contains_key(n))
        .collect();
    placed_said.sort_by_key(|n| SMPL22_ORDER.iter().position(|m| m == n));
    let columns: Vec<&Vec<DVec3>> = placed_names.iter().map(|n| &by_name[n]).collect();
    for limb in LIMBS {
        if !by_name.contains_key(limb) {
            return Err(Error::usage(format!(
                "{shown}: {}'s {limb} is in no frame: a body needs its limbs",
                layout.label()
            )));
        }
    }
    if !placed_said.is_empty() {
        said.push(format!(
            "{} has no {}: placed from its other points (the pelvis between the hips, the neck \
             between the shoulders, the head between the ears, the spine along pelvis to neck, \
             each collar 2/5 of the way from the neck to its shoulder)",
            layout.label(),
            placed_said.join(", ")
        ));
    }
    if !missing.is_empty() {
        said.push(format!(
            "{} has no {}: those joints keep their rest pose",
            layout.label(),
            missing.join(", ")
        ));
    }
    // Stand the figure along +y: the axis pelvis to neck runs along, as given or guessed.
    let up = match up_given {
        Some(up) => up,
        None => {
            let (pelvis, neck) = (&by_name["pelvis"], &by_name["neck"]);
            let mean: DVec3 = pelvis.iter().zip(neck).map(|(p, n)| *n - *p).sum();
            let axis = nearest_axis(mean);
            if axis != DVec3::Y {
                said.push(format!(
                    "stands along {} (pelvis to neck, guessed): turned to stand along y",
                    axis_name(axis)
                ));
            }
            axis
        }
    };
    let turn = to_stand_up(up);
    let mut flat = Vec::with_capacity(frames * columns.len());
    for f in 0..frames {
        flat.extend(columns.iter().map(|c| turn * c[f]));
    }
    let names = placed_names.iter().map(|n| n.to_string()).collect();
    let positions =
        Positions::new(names, flat, keypoints.frame_time).map_err(|e| e.about(shown))?;
    let placed = placed_said.iter().map(|n| n.to_string()).collect();
    Ok(Placed {
        positions,
        placed,
        said,
    })
}

/// SMPL's joint `name` placed from the layout's points (`at`) and the pelvis and neck already
/// taken or placed (`by_name`), for every frame; `None` where the layout does not allow it.
fn place(
    name: &str,
    frames: usize,
    at: &dyn Fn(usize, &str) -> Option<DVec3>,
    by_name: &std::collections::HashMap<&str, Vec<DVec3>>,
) -> Option<Vec<DVec3>> {
    let column =
        |f: &dyn Fn(usize) -> Option<DVec3>| (0..frames).map(f).collect::<Option<Vec<_>>>();
    let mid = |a: &str, b: &str| column(&|f| Some(at(f, a)?.lerp(at(f, b)?, 0.5)));
    let anchor = |n: &str, f: usize| by_name.get(n).map(|c| c[f]);
    // Along the spine: through Human3.6M's mid-spine point where there is one, else straight.
    let spine = |t: f64| {
        column(&|f| {
            let (pelvis, neck) = (anchor("pelvis", f)?, anchor("neck", f)?);
            Some(match at(f, "spine") {
                Some(mid) if t <= 0.5 => pelvis.lerp(mid, 2.0 * t),
                Some(mid) => mid.lerp(neck, 2.0 * t - 1.0),
                None => pelvis.lerp(neck, t),
            })
        })
    };
    match name {
        "pelvis" => mid("left_hip", "right_hip"),
        "neck" => mid("left_shoulder", "right_shoulder"),
        "head" => mid("left_ear", "right_ear").or_else(|| mid("neck_nose", "head_top")),
        "spine1" => spine(0.25),
        "spine2" => spine(0.5),
        "spine3" => spine(0.75),
        "left_collar" | "right_collar" => {
            let side = name.trim_end_matches("_collar");
            let shoulder = format!("{side}_shoulder");
            column(&|f| Some(anchor("neck", f)?.lerp(at(f, &shoulder)?, 0.4)))
        }
        "left_foot" | "right_foot" => {
            let side = name.trim_end_matches("_foot");
            mid(&format!("{side}_big_toe"), &format!("{side}_small_toe"))
        }
        _ => None,
    }
}

/// The turn that stands a figure along `up` (the signed axis nearest it) along +y: a half or
/// quarter turn about x for ±y and ±z (so that a camera's x, to the right, stays), a quarter
/// turn about z for ±x.
fn to_stand_up(up: DVec3) -> DQuat {
    use std::f64::consts::{FRAC_PI_2, PI};
    let axis = nearest_axis(up);
    match (axis.x, axis.y, axis.z) {
        (_, y, _) if y > 0.0 => DQuat::IDENTITY,
        (_, y, _) if y < 0.0 => DQuat::from_rotation_x(PI),
        (_, _, z) if z > 0.0 => DQuat::from_rotation_x(-FRAC_PI_2),
        (_, _, z) if z < 0.0 => DQuat::from_rotation_x(FRAC_PI_2),
        (x, _, _) if x > 0.0 => DQuat::from_rotation_z(FRAC_PI_2),
        _ => DQuat::from_rotation_z(-FRAC_PI_2),
    }
}

/// The signed axis nearest `direction`.
fn nearest_axis(direction: DVec3) -> DVec3 {
    let a = direction.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        DVec3::X * direction.x.signum()
    } else if a.y >= a.z {
        DVec3::Y * direction.y.signum()
    } else {
        DVec3::Z * direction.z.signum()
    };
    if direction.is_finite() && a.max_element() > 0.0 {
        axis
    } else {
        DVec3::Y
    }
}

/// `x`, `-y` and the like.
fn axis_name(axis: DVec3) -> String {
    let (name, value) = if axis.x != 0.0 {
        ("x", axis.x)
    } else if axis.y != 0.0 {
        ("y", axis.y)
    } else {
        ("z", axis.z)
    };
    if value < 0.0 {
        format!("-{name}")
    } else {
        name.to_string()
    }
}

/// SMPL-named positions renamed for `skeleton` by role: each of its joints the guessed map from
/// SMPL's 22 finds takes that joint's positions. A skeleton named as SMPL's is given them as
/// they are. Beside them, the SMPL joints the map finds no joint for (their points not used).
pub fn onto_skeleton(
    positions: &Positions,
    skeleton: &crate::model::skeleton::Skeleton,
) -> Result<(Positions, Vec<String>), Error> {
    let named = |n: &str| skeleton.joints.iter().any(|j| !j.end_site && j.name == n);
    if positions.names.iter().all(|n| named(n)) {
        return Ok((positions.clone(), Vec::new()));
    }
    let (smpl, _) = crate::bvh::built_in::built_in("smpl22")
        .ok_or_else(|| Error::usage("the built-in skeleton smpl22 does not load"))?;
    let map = crate::retarget::Map::guess(&smpl, skeleton);
    let points = crate::positions::export_points(skeleton);
    let count = positions.names.len();
    let mut names = Vec::new();
    let mut columns = Vec::new();
    for (j, source) in map.source_of.iter().enumerate() {
        let Some(source) = source else { continue };
        let Some(column) = positions
            .names
            .iter()
            .position(|n| *n == smpl.joints[*source].name)
        else {
            continue;
        };
        // The point the solver reads at joint j, as every export names it (an ASF names the
        // point where a bone ends by the bone).
        let Some((point, _)) = points.iter().find(|(_, at)| *at == j) else {
            continue;
        };
        if skeleton.joints[j].end_site || columns.contains(&column) {
            continue;
        }
        names.push(point.clone());
        columns.push(column);
    }
    let frames = positions.frames();
    let mut points = Vec::with_capacity(frames * columns.len());
    for f in 0..frames {
        points.extend(columns.iter().map(|&c| positions.points[f * count + c]));
    }
    let unused = (0..count)
        .filter(|c| !columns.contains(c))
        .map(|c| positions.names[c].clone())
        .collect();
    Ok((Positions::new(names, points, positions.frame_time)?, unused))
}

/// Keypoints of `layout` in `path`: an `.npy` of frames × points × 3 (or × 4, a confidence
/// last), a positions `.csv` (`frame,joint,x,y,z`, each point named as the layout names it,
/// every point in every frame), or a `.json` array of frames × points × 3 or 4 (or an object
/// whose `keypoints` holds one; at most [`MAX_JSON_BYTES`]); `frame_time` seconds apart.
pub fn read_keypoints(
    path: &std::path::Path,
    layout: Layout,
    frame_time: f64,
    max_size: u64,
) -> Result<Keypoints, Error> {
    let shown = path.display().to_string();
    let extension = crate::take::extension(path);
    let (shape, values) = match extension.as_str() {
        "npy" => {
            let bytes = super::read_npy_file(path, max_size)?;
            match super::input::npy_array(&bytes, &shown)? {
                super::input::NpyArray::Numbers { shape, values } => (shape, values),
                super::input::NpyArray::Text { .. } => {
                    return Err(Error::decoding(&shown, "text, not numbers"));
                }
                super::input::NpyArray::Other { dtype } => {
                    return Err(Error::decoding(
                        &shown,
                        format!(
                            "an array of dtype {dtype} (an object array is a pickle, which \
                             bvhview never loads); keypoints are numbers"
                        ),
                    ));
                }
            }
        }
        "csv" => {
            let (positions, _) = super::read_positions(path, None, frame_time, max_size)?;
            let names: Vec<&str> = positions.names.iter().map(String::as_str).collect();
            if names != layout.points() {
                return Err(Error::usage(format!(
                    "{shown}: its points are {} …, not {}'s ({} …) in its order",
                    names.iter().take(3).copied().collect::<Vec<_>>().join(", "),
                    layout.label(),
                    layout.points()[..3].join(", ")
                )));
            }
            let count = names.len();
            let values = positions.points.iter().flat_map(|p| p.to_array()).collect();
            (vec![positions.frames(), count, 3], values)
        }
        "json" => {
            // A JSON tree takes some 30 times its text in memory: keypoints as JSON are held to
            // what an .npy would carry easily.
            let bytes = crate::io::whole::read_binary_file(path, max_size.min(MAX_JSON_BYTES))?;
            json_keypoints(&bytes, &shown)?
        }
        _ => {
            return Err(Error::usage(format!(
                "{shown}: keypoints are read from .npy (frames × points × 3 or 4), .csv or .json"
            )));
        }
    };
    Keypoints::new(layout, &shape, &values, frame_time, &shown)
}

/// The largest keypoints file read as JSON (64 MiB): a longer take goes in an `.npy`.
pub const MAX_JSON_BYTES: u64 = 64 << 20;

/// A JSON array of frames × points × 3 or 4 numbers (`null` for a point a frame lacks), or an
/// object whose `keypoints` holds one: its shape and values.
fn json_keypoints(bytes: &[u8], shown: &str) -> Result<(Vec<usize>, Vec<f64>), Error> {
    let value: serde_json::Value = serde_json::from_slice(bytes)
        .map_err(|e| Error::decoding(shown, format!("not JSON ({e})")))?;
    let frames = match &value {
        serde_json::Value::Object(object) => object.get("keypoints"),
        array @ serde_json::Value::Array(_) => Some(array),
        _ => None,
    }
    .and_then(|v| v.as_array())
    .ok_or_else(|| {
        Error::decoding(
            shown,
            "expected an array of frames × points × 3 or 4, or an object with `keypoints`",
        )
    })?;
    let mut shape: Option<(usize, usize)> = None;
    let mut values = Vec::new();
    for (f, frame) in frames.iter().enumerate() {
        let points = frame
            .as_array()
            .ok_or_else(|| Error::decoding(shown, format!("frame {f} is not an array")))?;
        for (p, point) in points.iter().enumerate() {
            let numbers = point.as_array().ok_or_else(|| {
                Error::decoding(shown, format!("frame {f}, point {p} is not an array"))
            })?;
            let here = (points.len(), numbers.len());
            if *shape.get_or_insert(here) != here {
                return Err(Error::decoding(
                    shown,
                    format!(
                        "frame {f}, point {p}: {} points of {} numbers, where frame 0 has {} of \
                         {}",
                        here.0,
                        here.1,
                        shape.unwrap_or(here).0,
                        shape.unwrap_or(here).1
                    ),
                ));
            }
            for number in numbers {
                values.push(number.as_f64().unwrap_or(f64::NAN));
            }
        }
    }
    let (points, width) = shape.unwrap_or((0, 3));
    Ok((vec![frames.len(), points, width], values))
}

/// A take's joints as `layout`'s keypoints, in metres (`metres` per unit of the take): each
/// point that stands where one of SMPL's joints does, at the take's joint the guessed map from
/// its skeleton onto SMPL's 22 finds; NaN, confidence 0, where the skeleton has none (a face's
/// points).
pub fn of_take(take: &crate::Take, layout: Layout, metres: f64) -> Result<Keypoints, Error> {
    let (smpl, _) = crate::bvh::built_in::built_in("smpl22")
        .ok_or_else(|| Error::usage("the built-in skeleton smpl22 does not load"))?;
    let map = crate::retarget::Map::guess(&take.skeleton, &smpl);
    let joint_of_point: Vec<Option<usize>> = (0..layout.points().len())
        .map(|p| {
            let k = SMPL22_ORDER
                .iter()
                .position(|name| layout.point_of(name) == Some(p))?;
            map.source_of[smpl.joints.iter().position(|j| j.name == SMPL22_ORDER[k])?]
        })
        .collect();
    let frames = take.frame_count().max(1);
    let mut points = Vec::with_capacity(frames * joint_of_point.len());
    let mut confidence = Vec::with_capacity(points.capacity());
    for f in 0..frames {
        // Each joint's place, by joint (an ASF's exported points are not one a joint).
        let places = take.joint_places(f);
        for joint in &joint_of_point {
            let point = match joint {
                Some(j) => places[*j] * metres,
                None => DVec3::NAN,
            };
            confidence.push(if point.is_finite() { 1.0 } else { 0.0 });
            points.push(point);
        }
    }
    Ok(Keypoints {
        layout,
        points,
        confidence,
        frame_time: take.motion.frame_time,
    })
}
