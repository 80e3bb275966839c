//! How datasets are joined by a merge.

/// How [`merge`](super::merge::merge()) joins its pieces.
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
/// use bvhview::dataset::merge::{Join, merge};
///
/// // `out` is a dataset of one clip (the walk, 86 frames at 30 fps); join it to itself.
/// let twice = folder.path().join("twice");
/// let summary = merge(&[out.clone(), out], &twice, Join::Folders)?;
/// assert_eq!((summary.clips, summary.frames, summary.groups), (2, 172, 1));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Join {
    /// Pieces of one compile: every take of its list once, the pieces given in order, no gap.
    /// The result is byte for byte the dataset one compile would have written.
    #[default]
    Pieces,
    /// Datasets of any folders made with the same options: clips one after the other, grouped
    /// by skeleton topology.
    Folders,
}
