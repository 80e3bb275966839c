//! What one take becomes: where it came from, its skeleton's topology, what the manifest says
//! of it, its arrays; and a take that could not be compiled.

use crate::info::batch::Item;
use std::path::Path;

/// Where a take came from, as the manifest names it: paths relative to the folder compiled.
///
/// ```
/// use bvhview::dataset::{self, Options, Source};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let source = Source::of(folder.path(), &takes[0]);
/// assert_eq!(source, Source { path: "walk.bvh".to_string(), motion: None });
/// let clip = dataset::compile_take(folder.path(), &takes[0], &Options::default())?;
/// assert_eq!(clip.about.source, source);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Source {
    /// The file loaded: a BVH, or the ASF of an ASF/AMC pair.
    pub path: String,
    /// The AMC an ASF was paired with; `None` for a BVH.
    pub motion: Option<String>,
}

impl Source {
    /// Where `item` came from, its paths made relative to `dir` (kept whole when outside it).
    pub fn of(dir: &Path, item: &Item) -> Source {
        let relative = |p: &Path| {
            p.strip_prefix(dir)
                .unwrap_or(p)
                .to_string_lossy()
                .into_owned()
        };
        Source {
            path: relative(&item.path),
            motion: item.motion.as_deref().map(relative),
        }
    }
}

/// The skeleton a clip's arrays are laid out by; clips with equal topologies share a group.
///
/// ```
/// use bvhview::dataset::{self, Options};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let topology = dataset::compile_take(folder.path(), &takes[0], &Options::default())?.topology;
/// assert_eq!((topology.joints[0].as_str(), topology.parents[0]), ("Hips", -1));
/// assert_eq!(topology.translated, [0]); // only the root has position channels
/// assert_eq!(topology.rotation_orders[0], "ZYX");
/// let name = |&p: &u32| topology.joints[p as usize].as_str();
/// let feet: Vec<&str> = topology.feet.iter().map(name).collect();
/// assert_eq!(feet, ["LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Topology {
    /// Every point: joints and End Sites (named `<parent>_End`), in file order.
    pub joints: Vec<String>,
    /// Each point's parent, -1 for a root.
    pub parents: Vec<i32>,
    /// The points that have a rotation (every joint that is not an End Site).
    pub rotated: Vec<u32>,
    /// The points whose translation moves: every joint with position channels. The others'
    /// translations are their rest offsets.
    pub translated: Vec<u32>,
    /// The points foot contacts are given for (named by `--feet`, or
    /// [`guess_feet`](crate::dataset::guess_feet)).
    pub feet: Vec<u32>,
    /// Each rotated point's rotation channels in file order (`ZXY`; empty without any): the
    /// order of its Euler angles, and of the product `R1 · R2 · R3`.
    pub rotation_orders: Vec<String>,
}

impl Topology {
    pub(crate) fn of(skeleton: &crate::Skeleton, feet: Vec<u32>) -> Topology {
        let joints: Vec<String> = (0..skeleton.joints.len())
            .map(|i| crate::model::skeleton::export_name(skeleton, i))
            .collect();
        let points = 0..skeleton.joints.len() as u32;
        let rotated: Vec<u32> = points
            .clone()
            .filter(|&i| !skeleton.joints[i as usize].end_site)
            .collect();
        let translated = points
            .filter(|&i| {
                skeleton.joints[i as usize]
                    .channels
                    .iter()
                    .any(|c| c.is_position())
            })
            .collect();
        let rotation_orders = rotated
            .iter()
            .map(|&i| {
                skeleton.joints[i as usize]
                    .channels
                    .iter()
                    .filter(|c| c.is_rotation())
                    .map(|c| ["X", "Y", "Z"][c.axis()])
                    .collect()
            })
            .collect();
        Topology {
            parents: skeleton
                .joints
                .iter()
                .map(|j| j.parent.map_or(-1, |p| p as i32))
                .collect(),
            rotated,
            translated,
            feet,
            joints,
            rotation_orders,
        }
    }
}

/// What the manifest says of one clip besides its arrays.
///
/// ```
/// use bvhview::dataset::{self, Options};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let about = dataset::compile_take(folder.path(), &takes[0], &Options::default())?.about;
/// assert_eq!((about.source.path.as_str(), about.source_frames), ("walk.bvh", 344));
/// assert_eq!((about.up.as_str(), about.units.as_str()), ("y", "CMU units (1/0.45 inch)"));
/// assert_eq!(about.travel_joint, "Hips");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct About {
    /// The take's file (and its AMC), relative to the folder compiled.
    #[serde(flatten)]
    pub source: Source,
    /// The take's own frame time (seconds, as the file gives it) and length, before resampling.
    pub source_frame_time: f64,
    /// The take's number of frames, before resampling.
    pub source_frames: usize,
    /// The guessed up axis and units the take was turned from.
    pub up: String,
    /// The guessed units' name (`metres`, `centimetres`, `inches`, `CMU units (1/0.45 inch)`…).
    pub units: String,
    /// Metres in one of those units: what every length was multiplied by to make metres (then
    /// divided by the dataset's `out_units`' own, when the manifest names other units).
    pub metres_per_unit: f32,
    /// Whether the units were given (`--units`, `units=`) rather than guessed or stated by the
    /// file; absent (false) in older manifests.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub units_given: bool,
    /// Whether the up axis was given (`--up`, `up=`) rather than guessed or stated by the file;
    /// absent (false) in older manifests.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub up_given: bool,
    /// How position channels combined with OFFSETs (the mode the file looks written for).
    pub offset_mode: String,
    /// The point whose travel `root_translations` holds and root-relative positions remove.
    pub travel_joint: String,
    /// The take's warnings as `info` gives them, and one when its foot points were guessed
    /// from the rest pose.
    pub warnings: Vec<String>,
    /// With `--onto`: the retargeted take measured against its source (sides, widths, bones,
    /// path, floor), as `retarget` prints it; absent otherwise and in older manifests.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retarget_check: Option<crate::retarget::Check>,
    /// How plausible the clip is as written, as `bvhview metrics` measures it (the floor read
    /// from the motion); absent for a clip without two feet and in older manifests.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metrics: Option<ClipMetrics>,
}

/// A clip's plausibility figures in the manifest ([`crate::metrics::Metrics`]).
///
/// ```
/// use bvhview::dataset::{self, Options};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let item = &dataset::takes(folder.path())?[0];
/// let clip = dataset::compile_take(folder.path(), item, &Options::default())?;
/// let metrics = clip.about.metrics.unwrap();
/// assert!((0.0..=1.0).contains(&metrics.skating_ratio));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClipMetrics {
    /// GMD's skating ratio.
    pub skating_ratio: f64,
    /// PhysDiff's Penetrate (mm).
    pub penetrate_mm: f64,
    /// PhysDiff's Float (mm).
    pub float_mm: f64,
    /// The share of frames that float, flights aside ([`crate::metrics::Metrics`]).
    #[serde(default)]
    pub floating_frames: f64,
    /// PhysDiff's Skate (mm).
    pub skate_mm: f64,
    /// Mean jerk (m/s³).
    pub jitter_m_s3: f64,
    /// The floor measured against (metres).
    pub floor_m: f64,
}

impl ClipMetrics {
    /// The manifest's figures of `metrics`.
    pub fn of(metrics: &crate::metrics::Metrics) -> ClipMetrics {
        ClipMetrics {
            skating_ratio: metrics.skating_ratio,
            penetrate_mm: metrics.penetrate,
            float_mm: metrics.float,
            floating_frames: metrics.floating_frames,
            skate_mm: metrics.skate,
            jitter_m_s3: metrics.jitter,
            floor_m: metrics.floor,
        }
    }
}

/// One take's arrays, frame after frame (row-major, float32 but for the contacts).
///
/// ```
/// use bvhview::dataset::{self, Options};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let clip = dataset::compile_take(folder.path(), &takes[0], &Options::default())?;
/// let points = clip.topology.joints.len();
/// assert_eq!((clip.frames, points), (86, 38)); // 344 frames at 120 fps, resampled to 30
/// assert_eq!(clip.positions.len(), clip.frames * points * 3);
/// assert_eq!(clip.contacts.len(), clip.frames * clip.topology.feet.len());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// What the manifest says of the clip.
    pub about: About,
    /// The skeleton the arrays are laid out by: the key of the clip's group.
    pub topology: Topology,
    /// Frames at the dataset's rate.
    pub frames: usize,
    /// frames × points × 3: world positions, Y up, metres (root-relative when asked).
    pub positions: Vec<f32>,
    /// frames × rotated × width of the rotation kind: local rotations.
    pub rotations: Vec<f32>,
    /// frames × translated × 3: the local translation of each point with position channels
    /// (its OFFSET with the channels combined, metres, Y up).
    pub translations: Vec<f32>,
    /// frames × 3: the world position of the travel joint (the root in most files).
    pub root_translations: Vec<f32>,
    /// frames × points × 3: world velocities, metres per second.
    pub velocities: Vec<f32>,
    /// frames × feet: 1 in contact, 0 not.
    pub contacts: Vec<u8>,
    /// points × 3: each point's OFFSET (metres, Y up).
    pub rest_offsets: Vec<f32>,
    /// The skeleton the arrays are of (metres, Y up), written as its group's `skeleton.bvh`;
    /// `None` for a clip read back from a dataset, whose group has that file already.
    pub skeleton: Option<crate::Skeleton>,
    /// With `--features humanml3d`: the take in HumanML3D's representation, made from
    /// `positions` (the other arrays are not written).
    pub humanml3d: Option<crate::humanml3d::Features>,
}

/// Why a take is not in the dataset.
///
/// ```
/// use bvhview::dataset::{self, Options};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// # std::fs::write(folder.path().join("broken.bvh"), "HIERARCHY\nROOT Hips\n").unwrap();
/// // and broken.bvh, whose hierarchy stops after its root's name.
/// let (takes, out) = (dataset::takes(folder.path())?, folder.path().join("dataset"));
/// let list = dataset::whole_list(folder.path(), &takes);
/// let (dir, options) = (folder.path(), Options::default());
/// let summary = dataset::compile(dir, takes, &options, 1, &out, list, |_, _, _, _| true)?;
/// let skipped = &summary.skipped[0];
/// assert_eq!(skipped.source.path, "broken.bvh");
/// assert_eq!(skipped.error, "broken.bvh:3:1: expected '{' after 'Hips', found end of file");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Skipped {
    /// The take that failed.
    #[serde(flatten)]
    pub source: Source,
    /// The error it failed with, paths in it relative to the folder compiled.
    pub error: String,
}
