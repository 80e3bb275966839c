//! A dataset in HumanML3D's layout (`--features humanml3d`) read back, as hostile as any
//! dataset ([`super::read`]): its manifest checked, each clip's two files opened inside the
//! folder without following links, their headers and sizes those of the manifest's clip. And
//! such datasets merged (the pieces of a cluster's compile, or folders).

use super::clip::Clip;
use super::folder::{check_settings, open_in, open_manifest};
use super::join::Join;
use super::options::FeatureSet;
use super::store::{HEADER, HUMANML3D_FOLDERS, Manifest, Takes, Writer, npy_header};
use super::summary::Summary;
use crate::humanml3d::{Features, JOINTS, WIDTH};
use crate::io::error::Error;
use crate::io::message::Message;
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// A dataset in HumanML3D's layout, its manifest checked and its two folders open.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// use bvhview::dataset::{self, FeatureSet, Options};
///
/// let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// // `folder` holds walk.bvh, CMU's walk (172 frames at 60 fps).
/// let options = Options {
///     fps: 20.0,
///     onto: Some(bvhview::retarget::Target::load("smpl22", u64::MAX)?),
///     features: FeatureSet::HumanMl3d,
///     ..Options::default()
/// };
/// let (takes, out) = (dataset::takes(folder.path())?, folder.path().join("humanml3d"));
/// let list = dataset::whole_list(folder.path(), &takes);
/// dataset::compile(folder.path(), takes, &options, 1, &out, list, |_, _, _, _| true)?;
///
/// let dataset = dataset::humanml3d::open(&out)?;
/// let features = dataset.features(0)?;
/// assert_eq!(dataset.manifest.clips[0].id.as_deref(), Some("000000"));
/// assert_eq!(features.frames(), 57); // 58 frames at 20 fps, one vector per step
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Dataset {
    /// The folder, as given to [`open`].
    pub path: PathBuf,
    /// `manifest.json`, checked.
    pub manifest: Manifest,
    /// `new_joint_vecs` and `new_joints`, open.
    folders: [File; 2],
}

/// Opens the HumanML3D-layout dataset at `path`, checking its manifest: its options, its
/// place in the list of takes, and its clips (each with a six-digit ID, in rising order, their
/// vectors' rows one after another).
pub fn open(path: &Path) -> Result<Dataset, Error> {
    let refuse = |why: String| Error::decoding(path.display(), why);
    let (folder, manifest) = open_manifest(path)?;
    let options = check_settings(&manifest).map_err(refuse)?;
    if options.features != FeatureSet::HumanMl3d {
        return Err(Error::usage(
            Message::from(format!(
                "{}: not a dataset in HumanML3D's layout (made without ",
                path.display()
            ))
            .argument("features", Some("humanml3d"))
            .text(")"),
        ));
    }
    if !manifest.groups.is_empty() {
        return Err(refuse(
            "a dataset in HumanML3D's layout with groups of arrays".to_string(),
        ));
    }
    let mut start = 0usize;
    let mut last: Option<&str> = None;
    for (k, clip) in manifest.clips.iter().enumerate() {
        let id = clip.id.as_deref().unwrap_or_default();
        let six_digits = id.len() == 6 && id.bytes().all(|b| b.is_ascii_digit());
        if !six_digits || last.is_some_and(|before| before >= id) {
            return Err(refuse(format!(
                "clip {k}: ID {id:?}; IDs are six digits, rising clip after clip"
            )));
        }
        if clip.frames == 0 || clip.start != start {
            return Err(refuse(format!(
                "clip {k} ({id}) starts at vector {} with {} vectors; clips follow one another \
                 from vector 0, each with vectors",
                clip.start, clip.frames
            )));
        }
        start = start
            .checked_add(clip.frames)
            .ok_or_else(|| refuse(format!("clip {k}: {} vectors", clip.frames)))?;
        last = Some(id);
    }
    let [vectors, joints] = HUMANML3D_FOLDERS
        .map(|name| open_in(&folder, name, true).map_err(|why| refuse(format!("{name}: {why}"))));
    Ok(Dataset {
        path: path.to_path_buf(),
        manifest,
        folders: [vectors?, joints?],
    })
}

impl Dataset {
    /// Clip `k`'s vectors and positions, read from its two files, each checked to be exactly
    /// the float32 array of the manifest's shape.
    pub fn features(&self, k: usize) -> Result<Features, Error> {
        let clip = &self.manifest.clips[k];
        let id = clip.id.as_deref().unwrap_or_default();
        let rows = clip.frames;
        let mut arrays = Vec::with_capacity(2);
        for ((name, folder), shape) in HUMANML3D_FOLDERS
            .iter()
            .zip(&self.folders)
            .zip([vec![rows, WIDTH], vec![rows, JOINTS, 3]])
        {
            let shown = format!("{}/{name}/{id}.npy", self.path.display());
            let refuse = |why: String| Error::decoding(&shown, why);
            let file = open_in(folder, &format!("{id}.npy"), false).map_err(refuse)?;
            // A manifest's count is a claim: its byte size is checked without overflowing.
            let bytes_of = shape
                .iter()
                .try_fold(4usize, |n, &d| n.checked_mul(d))
                .and_then(|n| n.checked_add(HEADER))
                .ok_or_else(|| refuse(format!("{rows} vectors: more than any file holds")))?;
            let size = file.metadata().map_err(|e| refuse(e.to_string()))?.len();
            if size != bytes_of as u64 {
                return Err(refuse(format!(
                    "{size} bytes where float32 of shape {shape:?} make {bytes_of}"
                )));
            }
            let mut bytes = vec![0u8; bytes_of];
            file.read_exact_at(&mut bytes, 0)
                .map_err(|e| refuse(e.to_string()))?;
            if bytes[..HEADER] != npy_header("<f4", &shape)[..] {
                return Err(refuse(format!(
                    "its .npy header is not the one for <f4 of shape {shape:?}"
                )));
            }
            let floats: Vec<f32> = bytes[HEADER..]
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect();
            if let Some(at) = crate::edit::first_non_finite(&floats) {
                return Err(refuse(format!("value {at} is not a finite number")));
            }
            arrays.push(floats);
        }
        let joints = arrays.pop().expect("two arrays");
        let vectors = arrays.pop().expect("two arrays");
        Ok(Features { vectors, joints })
    }
}

/// [`super::merge::merge`] for datasets in HumanML3D's layout: each clip's files copied under
/// its ID (pieces of one compile keep theirs, the takes' places in the whole list; folders are
/// numbered anew, clip after clip), `Mean.npy` and `Std.npy` made again over all the vectors.
pub(super) fn merge(
    pieces: &[PathBuf],
    out: &Path,
    join: Join,
    takes: impl FnOnce(&[&Manifest]) -> Result<Takes, Error>,
) -> Result<Summary, Error> {
    let datasets = pieces
        .iter()
        .map(|p| open(p))
        .collect::<Result<Vec<_>, Error>>()?;
    let manifests: Vec<&Manifest> = datasets.iter().map(|d| &d.manifest).collect();
    let takes = takes(&manifests)?;
    let first = &datasets[0].manifest;
    let options = first.options.options()?;
    // Checked when the pieces were compiled (their `onto` is a name here, not a skeleton).
    let mut writer = Writer::create_unchecked(out, &options, takes)?;
    writer.keep_settings(first.options.clone());
    for (piece, dataset) in pieces.iter().zip(&datasets) {
        for (k, entry) in dataset.manifest.clips.iter().enumerate() {
            let clip = Clip {
                about: entry.about.clone(),
                topology: super::Topology::default(),
                frames: entry.frames,
                positions: Vec::new(),
                rotations: Vec::new(),
                translations: Vec::new(),
                root_translations: Vec::new(),
                velocities: Vec::new(),
                contacts: Vec::new(),
                rest_offsets: Vec::new(),
                skeleton: None,
                humanml3d: Some(dataset.features(k)?),
            };
            let id = match join {
                Join::Pieces => entry.id.clone().unwrap_or_default(),
                Join::Folders => format!("{:06}", writer.clip_count()),
            };
            writer
                .add_merged(&clip, "", id)
                .map_err(|e| e.about(&piece.display().to_string()))?;
        }
        for skipped in &dataset.manifest.skipped {
            writer.skip(skipped.clone());
        }
    }
    writer.finish()
}
