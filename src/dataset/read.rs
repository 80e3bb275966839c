//! A dataset folder read back, trusting nothing in it: a dataset is often downloaded, and its
//! manifest and files were made by someone else.
//!
//! - Every name inside the folder is one bvhview makes (`manifest.json`, `group_K/…npy`,
//!   `group_K/skeleton.bvh`); the manifest's own file names must be exactly those.
//! - Each file is opened relative to the folder's descriptor with `O_NOFOLLOW` (a symbolic link
//!   anywhere inside is refused, so nothing outside the folder is read) and `O_NONBLOCK` (a FIFO
//!   cannot hang the open), and must be a regular file, whose size is known before it is read.
//! - Every `.npy` header must be the very bytes bvhview writes for the dtype and shape the
//!   manifest gives, and every file exactly as long as that shape.
//! - Clip ranges are checked against the arrays: in order, one after the other, inside them,
//!   with no arithmetic overflow; `offsets.npy` must say the same.
//!
//! What passes is a [`Dataset`]: the manifest and an open handle per file, so that what was
//! checked is what is read (a file swapped after the check is not the one read).

pub use super::folder::MAX_MANIFEST;
use super::folder::{check_settings, open_in, open_manifest, read_whole};
use super::store::{self, HEADER, Manifest};
use crate::io::error::Error;
use crate::io::message::Message;
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// The largest `skeleton.bvh` read.
pub const MAX_SKELETON: u64 = 64 << 20;

/// A dataset whose every file has been checked, with its files open.
///
/// ```
/// # fn main() -> Result<(), bvhview::Error> {
/// use bvhview::dataset::{self, Options};
///
/// // A dataset of one take.
/// let folder = tempfile::tempdir().unwrap();
/// # let bvh = std::fs::read("tests/data/bvh/bvhparser_walk_01.bvh").unwrap();
/// # std::fs::write(folder.path().join("walk.bvh"), bvh).unwrap();
/// let (takes, out) = (dataset::takes(folder.path())?, folder.path().join("dataset"));
/// let list = dataset::whole_list(folder.path(), &takes);
/// dataset::compile(folder.path(), takes, &Options::default(), 1, &out, list, |_, _, _, _| true)?;
///
/// let dataset = dataset::read::open(&out)?;
/// assert_eq!(dataset.manifest.clips.len(), 1);
/// assert_eq!(dataset.groups.len(), dataset.manifest.groups.len());
/// assert_eq!(dataset.skeleton(0)?.joints.len(), 38); // the walk's joints and End Sites
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Dataset {
    /// The folder, as given to [`open`].
    pub path: PathBuf,
    /// `manifest.json`, checked against the files.
    pub manifest: Manifest,
    /// Each group's files, in the manifest's order of groups.
    pub groups: Vec<GroupFiles>,
}

/// One group's open files, in the manifest's order of arrays.
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
/// // `out` is the dataset of one take: the walk, resampled to 86 frames at 30 fps.
/// let dataset = bvhview::dataset::read::open(&out)?;
/// let group = &dataset.groups[0];
/// assert_eq!(group.offsets, [0, 86]); // where the one clip starts, and the end
/// assert_eq!(group.arrays.len(), dataset.manifest.groups[0].arrays.len());
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct GroupFiles {
    /// The group's `.npy` files, opened and checked.
    pub arrays: Vec<ArrayFile>,
    /// Where each clip starts, and the end (`offsets.npy`, checked).
    pub offsets: Vec<usize>,
    /// `skeleton.bvh`: the group's skeleton as a BVH file of one frame, its rest pose.
    pub skeleton: File,
}

/// An open `.npy` file: its data starts at [`HEADER`].
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
/// let dataset = bvhview::dataset::read::open(&out)?;
/// let arrays = &dataset.groups[0].arrays;
/// let positions = arrays.iter().find(|a| a.name == "group_0/positions.npy").unwrap();
/// // 86 frames of 38 points (joints and End Sites), x y z each.
/// assert_eq!(positions.dtype, "<f4");
/// assert_eq!(positions.shape, [86, 38, 3]);
/// let first = positions.read_rows(0..1)?;
/// assert_eq!(first.len(), positions.row_bytes());
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct ArrayFile {
    /// The file's path inside the dataset (`group_0/positions.npy`), as errors name it.
    pub name: String,
    /// numpy's type string: `<f4` (32-bit floats), `<i8` (64-bit integers) or `|u1` (bytes).
    pub dtype: String,
    /// The array's shape; the first number counts rows.
    pub shape: Vec<usize>,
    /// The open file, checked against `dtype` and `shape`.
    pub file: File,
}

impl ArrayFile {
    /// Bytes per element.
    pub fn item_size(&self) -> usize {
        item_size(&self.dtype)
    }

    /// Bytes per row (one frame; one clip for `rest_offsets`).
    pub fn row_bytes(&self) -> usize {
        self.shape[1..].iter().product::<usize>() * self.item_size()
    }

    /// Rows `rows` of the array, as stored (little-endian).
    pub fn read_rows(&self, rows: std::ops::Range<usize>) -> Result<Vec<u8>, Error> {
        let width = self.row_bytes();
        if rows.end > self.shape[0] || rows.start > rows.end {
            return Err(Error::usage(format!(
                "{}: rows {} to {} of {}",
                self.name, rows.start, rows.end, self.shape[0]
            )));
        }
        let mut bytes = vec![0u8; (rows.end - rows.start) * width];
        self.file
            .read_exact_at(&mut bytes, (HEADER + rows.start * width) as u64)
            .map_err(|e| Error::usage(format!("{}: {e}", self.name)))?;
        Ok(bytes)
    }
}

fn item_size(dtype: &str) -> usize {
    match dtype {
        "<f4" => 4,
        "<i8" => 8,
        _ => 1,
    }
}

/// Opens and checks the dataset at `path` (the folder itself may be reached through a link the
/// user named; nothing inside it may be one).
pub fn open(path: &Path) -> Result<Dataset, Error> {
    let refuse = |why: String| Error::decoding(path.display(), why);
    let (folder, manifest) = open_manifest(path)?;
    if manifest.options.features != super::FeatureSet::Arrays.name() {
        return Err(Error::usage(
            Message::from(format!("{}: made with ", path.display()))
                .argument("features", Some(&manifest.options.features))
                .text(
                    ": HumanML3D's layout (new_joint_vecs/ID.npy, Mean.npy, Std.npy), which \
                     numpy reads as it is; bvhview's dataset reader reads its own arrays",
                ),
        ));
    }
    check_manifest(&manifest).map_err(refuse)?;
    let mut groups = Vec::with_capacity(manifest.groups.len());
    for group in &manifest.groups {
        let dir = open_in(&folder, &group.name, true)
            .map_err(|why| refuse(format!("{}: {why}", group.name)))?;
        let mut arrays = Vec::with_capacity(group.arrays.len());
        for entry in &group.arrays {
            let file_name = format!("{}.npy", entry.name);
            let where_ = |why: String| refuse(format!("{}: {why}", entry.file));
            let file = open_in(&dir, &file_name, false).map_err(where_)?;
            let bytes = entry
                .shape
                .iter()
                .try_fold(item_size(&entry.dtype), |n, &d| n.checked_mul(d))
                .and_then(|n| n.checked_add(HEADER))
                .ok_or_else(|| where_("its shape overflows".to_string()))?;
            let size = file.metadata().map_err(|e| where_(e.to_string()))?.len();
            if size != bytes as u64 {
                return Err(where_(format!(
                    "{size} bytes where its dtype and shape {:?} make {bytes}",
                    entry.shape
                )));
            }
            let mut header = [0u8; HEADER];
            file.read_exact_at(&mut header, 0)
                .map_err(|e| where_(e.to_string()))?;
            if header[..] != store::npy_header(&entry.dtype, &entry.shape)[..] {
                return Err(where_(format!(
                    "its .npy header is not the one for {} of shape {:?}",
                    entry.dtype, entry.shape
                )));
            }
            arrays.push(ArrayFile {
                name: entry.file.clone(),
                dtype: entry.dtype.clone(),
                shape: entry.shape.clone(),
                file,
            });
        }
        let offsets_file = arrays
            .iter()
            .find(|a| a.name.ends_with("/offsets.npy"))
            .expect("checked: every group lists its offsets");
        let offsets: Vec<usize> = offsets_file
            .read_rows(0..offsets_file.shape[0])?
            .chunks_exact(8)
            .map(|b| i64::from_le_bytes(b.try_into().expect("8 bytes")))
            .map(|n| usize::try_from(n).unwrap_or(usize::MAX))
            .collect();
        let starts: Vec<usize> = manifest
            .clips
            .iter()
            .filter(|c| manifest.groups[c.group].name == group.name)
            .map(|c| c.start)
            .chain(std::iter::once(group.frames))
            .collect();
        if offsets != starts {
            return Err(refuse(format!(
                "{}/offsets.npy does not give the clips' starts the manifest gives",
                group.name
            )));
        }
        let skeleton = open_in(&dir, "skeleton.bvh", false)
            .map_err(|why| refuse(format!("{}: {why}", group.skeleton)))?;
        groups.push(GroupFiles {
            arrays,
            offsets,
            skeleton,
        });
    }
    Ok(Dataset {
        path: path.to_path_buf(),
        manifest,
        groups,
    })
}

impl Dataset {
    /// The text of group `k`'s `skeleton.bvh`.
    pub fn skeleton_text(&self, k: usize) -> Result<String, Error> {
        let file = &self.groups[k].skeleton;
        let bytes = read_whole(file, MAX_SKELETON).map_err(|why| {
            Error::usage(format!(
                "{}: {}: {why}",
                self.path.display(),
                self.manifest.groups[k].skeleton
            ))
        })?;
        String::from_utf8(bytes).map_err(|_| {
            Error::usage(format!(
                "{}: {}: not UTF-8",
                self.path.display(),
                self.manifest.groups[k].skeleton
            ))
        })
    }

    /// Group `k`'s skeleton, loaded by the BVH loader (as hostile as any BVH file), checked to
    /// be the group's topology.
    pub fn skeleton(&self, k: usize) -> Result<crate::Skeleton, Error> {
        let text = self.skeleton_text(k)?;
        let name = format!(
            "{}/{}",
            self.path.display(),
            self.manifest.groups[k].skeleton
        );
        let loaded = crate::bvh::loader::load_bytes(text.as_bytes(), &name)?;
        let skeleton = loaded.skeleton;
        let topology = &self.manifest.groups[k].topology;
        // The skeleton's own topology, as the compile made it (feet are the manifest's choice).
        let own = super::Topology::of(&skeleton, topology.feet.clone());
        if own.parents != topology.parents
            || own.rotated != topology.rotated
            || own.translated != topology.translated
            || own.rotation_orders != topology.rotation_orders
        {
            return Err(Error::usage(format!(
                "{name}: not the skeleton of its group (its joints, parents or channels differ from the manifest's)"
            )));
        }
        Ok(skeleton)
    }
}

/// Reads a dataset's manifest, checked with every file of the dataset ([`open`]), or for a
/// dataset in HumanML3D's layout, with its folders ([`super::humanml3d::open`]).
pub fn read_manifest(dataset: &Path) -> Result<Manifest, Error> {
    let (_, manifest) = open_manifest(dataset)?;
    match manifest.options.features == super::FeatureSet::HumanMl3d.name() {
        true => Ok(super::humanml3d::open(dataset)?.manifest),
        false => Ok(open(dataset)?.manifest),
    }
}

/// Everything the manifest says that can be checked without its files.
fn check_manifest(manifest: &Manifest) -> Result<(), String> {
    let options = check_settings(manifest)?;
    let mut ends = vec![0usize; manifest.groups.len()];
    let mut counts = vec![0usize; manifest.groups.len()];
    for (k, group) in manifest.groups.iter().enumerate() {
        if group.name != format!("group_{k}") {
            return Err(format!(
                "group {k} is named {}; bvhview names it group_{k}",
                crate::io::error::quoted(&group.name)
            ));
        }
        if group.skeleton != format!("{}/skeleton.bvh", group.name) {
            return Err(format!(
                "{}: its skeleton is named {}",
                group.name,
                crate::io::error::quoted(&group.skeleton)
            ));
        }
        check_topology(&group.topology).map_err(|why| format!("{}: {why}", group.name))?;
        if group.clips == 0 {
            return Err(format!("{}: a group without clips", group.name));
        }
        let mut expected: Vec<(String, String, Vec<usize>)> =
            store::layout(&group.topology, options.rotations)
                .into_iter()
                .map(|(name, dtype, shape)| {
                    let shape = std::iter::once(group.frames).chain(shape).collect();
                    (name.to_string(), dtype.to_string(), shape)
                })
                .collect();
        let clips_plus_one = group
            .clips
            .checked_add(1)
            .ok_or_else(|| format!("{}: {} clips", group.name, group.clips))?;
        expected.push((
            "offsets".to_string(),
            "<i8".to_string(),
            vec![clips_plus_one],
        ));
        expected.push((
            "rest_offsets".to_string(),
            "<f4".to_string(),
            vec![group.clips, group.topology.joints.len(), 3],
        ));
        let listed: Vec<(String, String, Vec<usize>)> = group
            .arrays
            .iter()
            .map(|a| (a.name.clone(), a.dtype.clone(), a.shape.clone()))
            .collect();
        if listed != expected {
            return Err(format!(
                "{}: its arrays (names, dtypes, shapes) are not those its skeleton, frame count \
                 and rotation kind make",
                group.name
            ));
        }
        for array in &group.arrays {
            if array.file != format!("{}/{}.npy", group.name, array.name) {
                return Err(format!(
                    "{}: the array {} is named {}",
                    group.name,
                    crate::io::error::quoted(&array.name),
                    crate::io::error::quoted(&array.file)
                ));
            }
        }
        let stats_ok = group.stats.len() == 5
            && group.stats.iter().zip(&group.arrays).all(|(s, a)| {
                let width: usize = a.shape[1..].iter().product();
                s.name == a.name && s.mean.len() == width && s.std.len() == width
            });
        if !stats_ok {
            return Err(format!(
                "{}: its statistics do not match its arrays",
                group.name
            ));
        }
    }
    for (i, clip) in manifest.clips.iter().enumerate() {
        let k = clip.group;
        if k >= manifest.groups.len() {
            return Err(format!("clip {i} names group {k}, which is not there"));
        }
        if clip.frames == 0 || clip.start != ends[k] {
            return Err(format!(
                "clip {i} ({}) starts at row {} with {} frames; clips of a group follow one \
                 another from row 0, each with frames",
                clip.about.source.path, clip.start, clip.frames
            ));
        }
        ends[k] = clip
            .start
            .checked_add(clip.frames)
            .ok_or_else(|| format!("clip {i} ends past any array"))?;
        counts[k] += 1;
        let topology = &manifest.groups[k].topology;
        if topology
            .joints
            .iter()
            .all(|name| *name != clip.about.travel_joint)
        {
            return Err(format!(
                "clip {i}: its travel joint {} is not in its skeleton",
                crate::io::error::quoted(&clip.about.travel_joint)
            ));
        }
    }
    for (k, group) in manifest.groups.iter().enumerate() {
        if ends[k] != group.frames || counts[k] != group.clips {
            return Err(format!(
                "{}: {} clips of {} frames in all, where the manifest's clips give {} of {}",
                group.name, group.clips, group.frames, counts[k], ends[k]
            ));
        }
    }
    Ok(())
}

fn check_topology(topology: &super::Topology) -> Result<(), String> {
    let points = topology.joints.len();
    if points == 0 || topology.parents.len() != points {
        return Err(format!(
            "{} points with {} parents",
            points,
            topology.parents.len()
        ));
    }
    for (i, &parent) in topology.parents.iter().enumerate() {
        if parent < -1 || parent >= i as i32 {
            return Err(format!(
                "point {i} has parent {parent}: a parent comes before its children"
            ));
        }
    }
    let increasing = |name: &str, list: &[u32]| {
        let ok =
            list.windows(2).all(|w| w[0] < w[1]) && list.iter().all(|&p| (p as usize) < points);
        match ok {
            true => Ok(()),
            false => Err(format!(
                "{name}: point numbers must increase and be below {points}"
            )),
        }
    };
    increasing("rotated", &topology.rotated)?;
    increasing("translated", &topology.translated)?;
    increasing("feet", &topology.feet)?;
    let orders_ok = topology.rotation_orders.len() == topology.rotated.len()
        && topology
            .rotation_orders
            .iter()
            .all(|o| o.len() <= 3 && o.bytes().all(|b| matches!(b, b'X' | b'Y' | b'Z')));
    if !orders_ok {
        return Err("rotation_orders: one of X, Y, Z (up to three) per rotated point".to_string());
    }
    Ok(())
}
