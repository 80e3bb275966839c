//! The steps between a take and its clip: how long each stage took, a take prepared (loaded,
//! checked, how it stands), its frames posed (the group's skeleton, world positions, rotations),
//! and the group's topology.

use super::clip::Topology;
use super::feet::{feet_of, named_feet};
use super::options::Options;
use crate::io::error::Error;
use crate::model::pose::OffsetMode;
use glam::Vec3;
use std::path::Path;

/// How long each stage of [`compile_take`](super::compile_take) took, for the benchmark's shares.
///
/// ```
/// use bvhview::dataset::{self, Options, Stages};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// # let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, a copy of tests/data/bvh/bvhparser_walk_01.bvh.
/// let takes = dataset::takes(folder.path())?;
/// let options = Options::default();
/// let (clip, stages) = dataset::compile_take_timed(folder.path(), &takes[0], &options)?;
/// assert_eq!(clip.frames, 86);
/// let mut total = Stages::default();
/// total.add(&stages);
/// total.add(&stages);
/// assert_eq!(total.fk, stages.fk * 2);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Stages {
    /// Reading and parsing the file (and retargeting it, with `onto`).
    pub load: std::time::Duration,
    /// The kept frames' channels to quaternions and translations.
    pub rotations: std::time::Duration,
    /// Interpolating, scaling and turning them to the dataset's rate, metres and Y up.
    pub resample: std::time::Duration,
    /// World positions from them.
    pub fk: std::time::Duration,
    /// The rotations as the kind asked for, and the translations.
    pub kinds: std::time::Duration,
    /// Root path, velocities, foot contacts, root-relative positions.
    pub derived: std::time::Duration,
}

impl Stages {
    /// Another take's stages added to these.
    pub fn add(&mut self, other: &Stages) {
        self.load += other.load;
        self.rotations += other.rotations;
        self.resample += other.resample;
        self.fk += other.fk;
        self.kinds += other.kinds;
        self.derived += other.derived;
    }
}

/// A take loaded and checked for compiling, with the offset mode it is read in and how it
/// stands.
pub(crate) struct Prepared {
    pub(super) loaded: crate::take::Take,
    pub(super) mode: OffsetMode,
    pub(super) stance: crate::model::stance::Stance,
    /// What `--onto` could not carry (the manifest's warnings).
    pub(super) uncarried: Vec<String>,
    /// With `--onto`: the output measured against its source.
    pub(super) check: Option<crate::retarget::Check>,
    /// The source's frame time and frames, as the file gives them.
    pub(super) source: (f64, usize),
}

/// What a take's frames become: the group's skeleton (metres, Y up, bone axes baked) and, at
/// the dataset's rate, every point's world position and the rotated and translated joints'
/// local rotations and translations.
pub(crate) struct Posed {
    pub(super) skeleton: crate::Skeleton,
    pub(super) topology: Topology,
    pub(super) names: Vec<String>,
    pub(super) frames: usize,
    pub(super) world: Vec<Vec3>,
    pub(super) rotations: Vec<f32>,
    pub(super) translations: Vec<f32>,
}

/// The group's topology for `skeleton` (the feet named in `options`, or guessed) and the names
/// its points are exported by.
pub(super) fn topology_of(
    path: &Path,
    skeleton: &crate::Skeleton,
    options: &Options,
    mode: OffsetMode,
) -> Result<(Topology, Vec<String>), Error> {
    let names: Vec<String> = (0..skeleton.joints.len())
        .map(|i| crate::model::skeleton::export_name(skeleton, i))
        .collect();
    let feet = match &options.feet {
        Some(wanted) => named_feet(path, &names, wanted)?,
        None => feet_of(skeleton, mode).0,
    };
    Ok((Topology::of(skeleton, feet), names))
}
