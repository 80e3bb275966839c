//! What a compile did: the clips, frames and groups it wrote, and the takes it skipped.

use super::clip::Skipped;

/// How a compile went: clips written, takes skipped.
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
/// assert_eq!((summary.clips, summary.frames, summary.groups), (1, 86, 1));
/// assert_eq!(summary.skipped.len(), 1);
/// # Ok(())
/// # }
/// ```
#[derive(Debug, Default)]
pub struct Summary {
    /// Clips written.
    pub clips: usize,
    /// Frames in all the clips written, at the dataset's rate.
    pub frames: usize,
    /// Groups written: one per topology.
    pub groups: usize,
    /// The takes that failed, in list order, with why.
    pub skipped: Vec<Skipped>,
}
