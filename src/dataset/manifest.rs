//! `manifest.json`: what a dataset holds and how it was made (the options, the takes' list,
//! each group's arrays and statistics, each clip's place), and the statistics' running sums.

use super::clip::{About, Skipped, Source, Topology};
use super::options::{FeatureSet, Options};
use crate::io::error::Error;
use crate::model::pose::RotationKind;

/// What the manifest's `format` says; a reader refuses any other.
pub const FORMAT: &str = "bvhview-dataset 2";

/// Every `.npy` header takes this many bytes (numpy's own writer pads to a multiple of 64).
pub const HEADER: usize = 128;

/// `manifest.json`.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// use bvhview::dataset::{self, Options};
///
/// let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, CMU's walk (172 frames at 60 fps).
/// let (takes, out) = (dataset::takes(folder.path())?, folder.path().join("dataset"));
/// let list = dataset::whole_list(folder.path(), &takes);
/// dataset::compile(folder.path(), takes, &Options::default(), 1, &out, list, |_, _, _, _| true)?;
///
/// let manifest = dataset::read::read_manifest(&out)?;
/// assert_eq!(manifest.format, "bvhview-dataset 2");
/// assert_eq!((manifest.takes.first, manifest.takes.count), (0, 1)); // the whole list
/// let clip = &manifest.clips[0];
/// assert_eq!((clip.about.source.path.as_str(), clip.group, clip.frames), ("walk.bvh", 0, 86));
/// assert_eq!(manifest.groups[0].name, "group_0");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// [`FORMAT`]: a reader refuses any other.
    pub format: String,
    /// The version that wrote it.
    pub bvhview: String,
    /// The options it was compiled with.
    pub options: Settings,
    /// Which takes of which list this dataset holds (a piece of a compile holds a run of them).
    pub takes: Takes,
    /// One per skeleton topology, `group_K` in the order first met.
    pub groups: Vec<Group>,
    /// Every clip kept, in the list's order.
    pub clips: Vec<ClipEntry>,
    /// Every take left out, with why.
    pub skipped: Vec<Skipped>,
}

/// The takes a dataset was compiled from: takes `first..first + count` of a list of `listed`
/// takes (the folder's, in path order) whose paths hash to `list` ([`list_digest`]). A whole
/// compile holds all of them; merging pieces needs every take of one list, once, in order.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Takes {
    /// The list's digest ([`list_digest`] of its paths).
    pub list: String,
    /// How many takes the list holds.
    pub listed: usize,
    /// The first of them this dataset holds.
    pub first: usize,
    /// How many, from `first` on.
    pub count: usize,
}

/// A name for a list of takes (their paths relative to the folder, in order): 64-bit FNV-1a of
/// the paths, each ended by a 0 byte, in hex. It tells pieces of one compile from pieces of
/// another; it is not a guard against anyone forging it.
pub fn list_digest(sources: &[Source]) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for source in sources {
        let motion = source.motion.as_deref().unwrap_or("");
        for byte in [source.path.as_bytes(), &[1], motion.as_bytes(), &[0]].concat() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    }
    format!("{hash:016x}")
}

/// The options a dataset was made with, as the manifest records them.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    /// The one frame rate every clip was resampled to.
    pub fps: f64,
    /// How rotations are stored: `quat`, `6d`, `matrix` or `euler` (`--rotations`).
    pub rotations: String,
    /// Positions relative to the root's place on the floor in each frame (`--root-relative`).
    pub root_relative: bool,
    /// The points `--feet` named; `None`: the ankles and toes the reading of the body found.
    pub feet: Option<Vec<String>>,
    /// A foot point is in contact below this height over its floor (metres).
    pub contact_height_m: f32,
    /// … and slower than this (metres per second).
    pub contact_speed_m_per_s: f32,
    /// A foot point's own floor is the lowest it comes within this many seconds each way.
    pub floor_window_s: f64,
    /// The up axis of the arrays: `y`.
    pub up: String,
    /// The units of the arrays' lengths: `metres`, or those `--out-units` named
    /// (`centimetres`).
    pub units: String,
    /// Metres per unit of the arrays' lengths (`--out-units`); absent for metres, as in older
    /// manifests.
    #[serde(default = "one_metre", skip_serializing_if = "is_one_metre")]
    pub metres_per_unit: f32,
    /// Each clip's lowest foot point put on y = 0 (`--ground`); absent in older manifests.
    #[serde(default)]
    pub ground: bool,
    /// Quaternions' signs chosen against the previous frame's (`--quat-continuous`); absent in
    /// older manifests.
    #[serde(default)]
    pub quat_continuous: bool,
    /// The skeleton every take was retargeted onto (`--onto`: a built-in name or the file as
    /// given); absent in older manifests.
    #[serde(default)]
    pub onto: Option<String>,
    /// Each take's planted feet held where they landed first (`--lock-feet`).
    #[serde(default)]
    pub lock_feet: bool,
    /// The `SRC = DST` pairs over every take's guessed map (`--map`, with `--onto`): for every
    /// skeleton, and for one skeleton by its fingerprint.
    #[serde(default)]
    pub map: crate::retarget::MapPairs,
    /// What each take is written as (`--features`): `arrays`, or `humanml3d`; absent in
    /// older manifests and for arrays, so that their manifests stay as they were.
    #[serde(default = "arrays", skip_serializing_if = "is_arrays")]
    pub features: String,
}

fn one_metre() -> f32 {
    1.0
}

fn is_one_metre(metres: &f32) -> bool {
    *metres == 1.0
}

fn arrays() -> String {
    FeatureSet::Arrays.name().to_string()
}

fn is_arrays(name: &str) -> bool {
    name == FeatureSet::Arrays.name()
}

impl Settings {
    pub(super) fn of(options: &Options) -> Settings {
        Settings {
            fps: options.fps,
            rotations: options.rotations.name().to_string(),
            root_relative: options.root_relative,
            feet: options.feet.clone(),
            contact_height_m: options.contact_height,
            contact_speed_m_per_s: options.contact_speed,
            floor_window_s: crate::model::body::contact::Planting::default().window,
            up: "y".to_string(),
            units: options.out_units.map_or("metres", |u| u.name).to_string(),
            metres_per_unit: options.out_units.map_or(1.0, |u| u.metres),
            ground: options.ground,
            quat_continuous: options.quat_continuous,
            onto: options.onto.as_ref().map(|target| target.name.clone()),
            lock_feet: options.lock_feet,
            map: options.map.clone(),
            features: options.features.name().to_string(),
        }
    }

    /// The options again, as far as the manifest records them (the `onto` skeleton by its name
    /// only, so `onto` is left `None`; the file-size limit the default's): what a merge and a
    /// reader of the dataset compare and rebuild with.
    pub fn options(&self) -> Result<Options, Error> {
        let rotations = RotationKind::parse(&self.rotations).ok_or_else(|| {
            Error::usage(format!(
                "rotations {:?}: not a kind bvhview writes",
                self.rotations
            ))
        })?;
        Ok(Options {
            fps: self.fps,
            rotations,
            root_relative: self.root_relative,
            feet: self.feet.clone(),
            contact_height: self.contact_height_m,
            contact_speed: self.contact_speed_m_per_s,
            ground: self.ground,
            quat_continuous: self.quat_continuous,
            lock_feet: self.lock_feet,
            map: self.map.clone(),
            out_units: (self.metres_per_unit != 1.0)
                .then(|| crate::model::stance::Units::of_metres(self.metres_per_unit)),
            features: FeatureSet::parse(&self.features).ok_or_else(|| {
                Error::usage(format!(
                    "features {:?}: not a set bvhview writes (arrays, humanml3d)",
                    self.features
                ))
            })?,
            ..Options::default()
        })
    }
}

/// One topology's clips.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Group {
    /// Its folder.
    pub name: String,
    /// The skeleton its clips share: points, parents, which joints turn and move, the feet.
    #[serde(flatten)]
    pub topology: Topology,
    /// How many clips it holds.
    pub clips: usize,
    /// Their frames, all together: the arrays' first dimension.
    pub frames: usize,
    /// Each array's file, element type and shape.
    pub arrays: Vec<ArrayEntry>,
    /// The skeleton as a BVH file of one frame, its rest pose (metres, Y up; the first clip's
    /// bone lengths): `group_K/skeleton.bvh`.
    pub skeleton: String,
    /// Each float array's mean and standard deviation over every frame of the group, per
    /// number of a frame (in the order of the array's frame shape, flattened): what a model's
    /// inputs are normalised by. A number that never changes has a deviation of 0.
    pub stats: Vec<ArrayStats>,
}

/// One float array's statistics over a group: per number of a frame.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArrayStats {
    /// The array (`positions`, `rotations`, …).
    pub name: String,
    /// The mean of each number of a frame.
    pub mean: Vec<f32>,
    /// Its standard deviation (over all frames, not a sample's).
    pub std: Vec<f32>,
}

/// Mean and spread of each number of a frame, clip by clip (Chan et al.'s pairwise update, in
/// f64, in clip order: the same sums however the clips were compiled).
#[derive(Clone, Debug, Default)]
pub(super) struct Moments {
    count: f64,
    mean: Vec<f64>,
    /// Sum of squared differences from the mean.
    spread: Vec<f64>,
}

impl Moments {
    pub(super) fn add(&mut self, values: &[f32], width: usize) {
        if width == 0 || values.is_empty() {
            return;
        }
        let rows = (values.len() / width) as f64;
        let mut mean = vec![0.0f64; width];
        for row in values.chunks_exact(width) {
            for (m, &v) in mean.iter_mut().zip(row) {
                *m += f64::from(v);
            }
        }
        mean.iter_mut().for_each(|m| *m /= rows);
        let mut spread = vec![0.0f64; width];
        for row in values.chunks_exact(width) {
            for ((s, &m), &v) in spread.iter_mut().zip(&mean).zip(row) {
                *s += (f64::from(v) - m).powi(2);
            }
        }
        if self.count == 0.0 {
            *self = Moments {
                count: rows,
                mean,
                spread,
            };
            return;
        }
        let total = self.count + rows;
        for k in 0..width {
            let delta = mean[k] - self.mean[k];
            self.mean[k] += delta * rows / total;
            self.spread[k] += spread[k] + delta * delta * self.count * rows / total;
        }
        self.count = total;
    }

    pub(super) fn stats(&self, name: &str, width: usize) -> ArrayStats {
        let count = self.count.max(1.0);
        ArrayStats {
            name: name.to_string(),
            mean: (0..width)
                .map(|k| self.mean.get(k).copied().unwrap_or(0.0) as f32)
                .collect(),
            std: (0..width)
                .map(|k| (self.spread.get(k).copied().unwrap_or(0.0) / count).sqrt() as f32)
                .collect(),
        }
    }
}

/// One array of a group: its `.npy` file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArrayEntry {
    /// The array (`positions`, `rotations`, …).
    pub name: String,
    /// Its file in the group's folder.
    pub file: String,
    /// numpy's element type (`<f4`, `|u1`).
    pub dtype: String,
    /// The whole array's shape: frames, then one frame's.
    pub shape: Vec<usize>,
}

/// One clip: where its frames are in its group's arrays, and what it came from.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClipEntry {
    /// The take it came from and what was done to it.
    #[serde(flatten)]
    pub about: About,
    /// Its group's place in [`Manifest::groups`].
    pub group: usize,
    /// Its first frame's row in the group's arrays (with `--features humanml3d`, which has no
    /// groups: its first vector's row among all the dataset's vectors, in list order).
    pub start: usize,
    /// How many frames (or vectors) it has.
    pub frames: usize,
    /// With `--features humanml3d`: its files' name, `new_joint_vecs/ID.npy` (the take's place
    /// in the list of takes compiled, six digits).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<String>,
}
