//! A dataset on disk: `manifest.json`, and per skeleton topology a folder `group_K` holding one
//! `.npy` file per array (every clip's frames one after the other, memory-mappable) and
//! `offsets.npy`, where each clip starts. The folder is filled under a temporary name beside
//! `out` and renamed at the end, so a dataset is there whole or not at all.

use super::clip::{Clip, Skipped, Topology};
use super::options::{FeatureSet, Options};
use super::summary::Summary;
use crate::io::error::Error;
use crate::model::pose::RotationKind;
use std::collections::HashMap;
use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use super::manifest::Moments;
pub use super::manifest::{
    ArrayEntry, ArrayStats, ClipEntry, FORMAT, Group, HEADER, Manifest, Settings, Takes,
    list_digest,
};

/// The arrays of a group, in the order the manifest lists them: name, element type, and the
/// shape of one frame.
pub fn layout(
    topology: &Topology,
    rotations: RotationKind,
) -> [(&'static str, &'static str, Vec<usize>); 6] {
    let (points, rotated) = (topology.joints.len(), topology.rotated.len());
    let translated = topology.translated.len();
    let rotation_shape = match rotations {
        RotationKind::Matrix => vec![rotated, 3, 3],
        kind => vec![rotated, kind.width()],
    };
    [
        ("positions", "<f4", vec![points, 3]),
        ("rotations", "<f4", rotation_shape),
        ("translations", "<f4", vec![translated, 3]),
        ("root_translations", "<f4", vec![3]),
        ("velocities", "<f4", vec![points, 3]),
        ("foot_contacts", "|u1", vec![topology.feet.len()]),
    ]
}

/// The `.npy` header (version 1.0) of an array of `descr` with `shape`, [`HEADER`] bytes long.
pub fn npy_header(descr: &str, shape: &[usize]) -> Vec<u8> {
    crate::io::npy::header(descr, shape, HEADER)
}

/// An array written frame by frame; its header, which holds the row count, is written each
/// time the file is closed. Only the group being written keeps its files open (each is closed
/// when a clip of another group comes): a folder of many skeletons would otherwise hold six
/// files open per skeleton, past the process's limit, and takes of one skeleton often come one
/// after another.
struct ArrayFile {
    path: PathBuf,
    descr: &'static str,
    frame_shape: Vec<usize>,
    rows: usize,
    /// Bytes in the file so far.
    length: u64,
    open: Option<File>,
}

impl ArrayFile {
    fn create(
        path: PathBuf,
        descr: &'static str,
        frame_shape: Vec<usize>,
    ) -> Result<ArrayFile, Error> {
        let made = || -> io::Result<File> {
            let mut file = File::create(&path)?;
            file.write_all(&[0; HEADER])?;
            Ok(file)
        };
        let file = made().map_err(|e| Error::output(&path, e))?;
        Ok(ArrayFile {
            path,
            descr,
            frame_shape,
            rows: 0,
            length: HEADER as u64,
            open: Some(file),
        })
    }

    fn shape(&self) -> Vec<usize> {
        std::iter::once(self.rows)
            .chain(self.frame_shape.iter().copied())
            .collect()
    }

    /// The file, at its end. Not opened to append: the header is written at its start, and
    /// Linux appends whatever the offset to a file opened so.
    fn file(&mut self) -> io::Result<&mut File> {
        use std::io::Seek;
        match &mut self.open {
            Some(file) => Ok(file),
            empty => {
                let mut file = std::fs::OpenOptions::new().write(true).open(&self.path)?;
                file.seek(io::SeekFrom::Start(self.length))?;
                Ok(empty.insert(file))
            }
        }
    }

    /// Writes the header for the rows so far and closes the file: a closed array's header is
    /// always up to date, and only an open one is written to.
    fn close(&mut self) -> Result<(), Error> {
        use std::os::unix::fs::FileExt;
        let Some(file) = self.open.take() else {
            return Ok(());
        };
        let header = npy_header(self.descr, &self.shape());
        file.write_all_at(&header, 0)
            .map_err(|e| Error::output(&self.path, e))
    }

    /// Appends float32 values: on a little-endian machine their memory is the file's bytes; on
    /// another, converted a piece at a time.
    fn append_floats(&mut self, values: &[f32]) -> io::Result<()> {
        #[cfg(target_endian = "little")]
        return self.append_bytes(bytemuck::cast_slice(values));
        #[cfg(not(target_endian = "little"))]
        {
            let mut bytes = Vec::with_capacity(4 * PIECE.min(values.len()));
            for piece in values.chunks(PIECE) {
                bytes.clear();
                bytes.extend(piece.iter().flat_map(|v| v.to_le_bytes()));
                self.append_bytes(&bytes)?;
            }
            Ok(())
        }
    }

    /// Appends bytes, and asks the disk to take them now, without waiting: the sync before the
    /// dataset takes its name then finds most of the arrays written while later takes compiled.
    fn append_bytes(&mut self, bytes: &[u8]) -> io::Result<()> {
        let from = self.length;
        let file = self.file()?;
        file.write_all(bytes)?;
        crate::io::output::start_writeback(file, from..from + bytes.len() as u64);
        self.length += bytes.len() as u64;
        Ok(())
    }
}

/// Floats converted to bytes at a time.
#[cfg(not(target_endian = "little"))]
const PIECE: usize = 1 << 16;

/// One group's files while they are written.
struct OpenGroup {
    topology: Topology,
    arrays: Vec<ArrayFile>,
    starts: Vec<usize>,
    frames: usize,
    /// Every clip's OFFSETs, clip after clip.
    rest_offsets: Vec<f32>,
    /// Per float array (positions, rotations, translations, root translations, velocities).
    moments: Vec<Moments>,
}

/// The arrays [`Group::stats`] are given for: every float array of [`layout`].
const STATS_OF: [usize; 5] = [0, 1, 2, 3, 4];

/// A dataset being written: clips in the order they come, each to its topology's group.
pub struct Writer {
    out: PathBuf,
    /// `None` once finished.
    folder: Option<crate::io::output::NewFolder>,
    options: Options,
    /// What the manifest says of the options: a merge keeps its datasets' (their `onto` is a
    /// name, not a skeleton to load again).
    settings: Settings,
    takes: Takes,
    groups: Vec<OpenGroup>,
    /// The group whose files are open: the last one a clip was added to.
    writing: Option<usize>,
    by_topology: HashMap<Topology, usize>,
    clips: Vec<ClipEntry>,
    skipped: Vec<Skipped>,
    /// With `--features humanml3d`: the mean and spread of every vector written.
    vectors: Moments,
}

/// The folders of HumanML3D's layout: the vectors, and the positions they stand for.
pub const HUMANML3D_FOLDERS: [&str; 2] = ["new_joint_vecs", "new_joints"];

impl Writer {
    /// Starts a dataset at `out`, which must not exist or be an empty folder: made as every
    /// folder of outputs is ([`crate::io::output::NewFolder`]), under a temporary name beside it.
    pub fn create(out: &Path, options: &Options, takes: Takes) -> Result<Writer, Error> {
        options.check()?;
        Writer::create_unchecked(out, options, takes)
    }

    /// [`Writer::create`] for options checked before: a merge's, whose skeleton is a name.
    pub(super) fn create_unchecked(
        out: &Path,
        options: &Options,
        takes: Takes,
    ) -> Result<Writer, Error> {
        let folder = crate::io::output::NewFolder::create(
            out,
            "a dataset goes into a new (or empty) folder",
        )?;
        if options.features == FeatureSet::HumanMl3d {
            crate::io::output::in_partial_folder(|| {
                for name in HUMANML3D_FOLDERS {
                    let path = folder.path().join(name);
                    std::fs::create_dir(&path).map_err(|e| Error::output(&path, e))?;
                }
                Ok(())
            })?;
        }
        Ok(Writer {
            out: out.to_path_buf(),
            folder: Some(folder),
            options: options.clone(),
            settings: Settings::of(options),
            takes,
            groups: Vec::new(),
            writing: None,
            by_topology: HashMap::new(),
            clips: Vec::new(),
            skipped: Vec::new(),
            vectors: Moments::default(),
        })
    }

    /// The options the manifest records, as the datasets a merge joins recorded them.
    pub(crate) fn keep_settings(&mut self, settings: Settings) {
        self.settings = settings;
    }

    fn folder(&self) -> &Path {
        self.folder.as_ref().expect("open until finished").path()
    }

    /// Adds a clip after those added before; a clip of a new topology starts its group with its
    /// skeleton ([`Clip::skeleton`]).
    pub fn add(&mut self, clip: &Clip) -> Result<(), Error> {
        let skeleton = || match &clip.skeleton {
            Some(skeleton) => skeleton_bvh(skeleton),
            None => Err(Error::usage("a clip without its skeleton")),
        };
        // Clips and skips come in list order: this is the take's place in the list.
        let id = format!(
            "{:06}",
            self.takes.first + self.clips.len() + self.skipped.len()
        );
        crate::io::output::in_partial_folder(|| self.add_files(clip, &skeleton, id))
    }

    /// Adds a clip of a dataset being merged: a new group takes `skeleton` (its piece's); with
    /// HumanML3D's layout the clip is named `id`.
    pub(super) fn add_merged(
        &mut self,
        clip: &Clip,
        skeleton: &str,
        id: String,
    ) -> Result<(), Error> {
        crate::io::output::in_partial_folder(|| {
            self.add_files(clip, &|| Ok(skeleton.to_string()), id)
        })
    }

    /// The clips added so far.
    pub(super) fn clip_count(&self) -> usize {
        self.clips.len()
    }

    fn add_files(
        &mut self,
        clip: &Clip,
        skeleton: &dyn Fn() -> Result<String, Error>,
        id: String,
    ) -> Result<(), Error> {
        if self.options.features == FeatureSet::HumanMl3d {
            return self.add_humanml3d(clip, id);
        }
        let group = match self.by_topology.get(&clip.topology) {
            Some(&k) => k,
            None => {
                let k = self.groups.len();
                let folder = self.folder().join(format!("group_{k}"));
                std::fs::create_dir(&folder).map_err(|e| Error::output(&folder, e))?;
                let arrays = layout(&clip.topology, self.options.rotations)
                    .into_iter()
                    .map(|(name, descr, shape)| {
                        ArrayFile::create(folder.join(format!("{name}.npy")), descr, shape)
                    })
                    .collect::<Result<Vec<_>, Error>>()?;
                let skeleton = skeleton()?;
                let path = folder.join("skeleton.bvh");
                std::fs::write(&path, &skeleton).map_err(|e| Error::output(&path, e))?;
                self.groups.push(OpenGroup {
                    topology: clip.topology.clone(),
                    arrays,
                    starts: Vec::new(),
                    frames: 0,
                    rest_offsets: Vec::new(),
                    moments: vec![Moments::default(); STATS_OF.len()],
                });
                self.by_topology.insert(clip.topology.clone(), k);
                k
            }
        };
        if let Some(last) = self.writing.replace(group)
            && last != group
        {
            for array in &mut self.groups[last].arrays {
                array.close()?;
            }
        }
        let open = &mut self.groups[group];
        let start = open.frames;
        let [
            positions,
            rotations,
            translations,
            roots,
            velocities,
            contacts,
        ] = &mut open.arrays[..]
        else {
            unreachable!("six arrays per group")
        };
        let floats = [
            &clip.positions,
            &clip.rotations,
            &clip.translations,
            &clip.root_translations,
            &clip.velocities,
        ];
        for (moments, (values, array)) in open.moments.iter_mut().zip(floats.iter().zip([
            &*positions,
            &*rotations,
            &*translations,
            &*roots,
            &*velocities,
        ])) {
            moments.add(values, array.frame_shape.iter().product());
        }
        let mut written = || -> io::Result<()> {
            positions.append_floats(&clip.positions)?;
            rotations.append_floats(&clip.rotations)?;
            translations.append_floats(&clip.translations)?;
            roots.append_floats(&clip.root_translations)?;
            velocities.append_floats(&clip.velocities)?;
            contacts.append_bytes(&clip.contacts)
        };
        written().map_err(|e| Error::output(&self.out, e))?;
        for array in &mut open.arrays {
            array.rows += clip.frames;
        }
        open.starts.push(start);
        open.frames += clip.frames;
        open.rest_offsets.extend_from_slice(&clip.rest_offsets);
        self.clips.push(ClipEntry {
            about: clip.about.clone(),
            group,
            start,
            frames: clip.frames,
            id: None,
        });
        Ok(())
    }

    /// A clip in HumanML3D's layout: its vectors and positions as `ID.npy` in their folders.
    fn add_humanml3d(&mut self, clip: &Clip, id: String) -> Result<(), Error> {
        use crate::humanml3d::{JOINTS, WIDTH};
        let Some(features) = &clip.humanml3d else {
            return Err(Error::usage(format!(
                "{}: a clip without its HumanML3D vectors in a dataset of them",
                clip.about.source.path
            )));
        };
        let rows = features.frames();
        let [vectors, joints] = HUMANML3D_FOLDERS;
        for (folder, values, shape) in [
            (vectors, &features.vectors, vec![rows, WIDTH]),
            (joints, &features.joints, vec![rows, JOINTS, 3]),
        ] {
            let path = self.folder().join(folder).join(format!("{id}.npy"));
            let mut bytes = npy_header("<f4", &shape);
            bytes.extend(values.iter().flat_map(|v| v.to_le_bytes()));
            std::fs::write(&path, bytes).map_err(|e| Error::output(&path, e))?;
        }
        self.vectors.add(&features.vectors, WIDTH);
        let start = self.clips.iter().map(|c| c.frames).sum();
        self.clips.push(ClipEntry {
            about: clip.about.clone(),
            group: 0,
            start,
            frames: rows,
            id: Some(id),
        });
        Ok(())
    }

    /// HumanML3D's `Mean.npy` and `Std.npy` over every vector written (its spread one number
    /// per part of the vector, [`crate::humanml3d::spread_by_part`]) and `all.txt`, the IDs.
    fn finish_humanml3d(&self) -> Result<(), Error> {
        use crate::humanml3d::WIDTH;
        let stats = self.vectors.stats("vectors", WIDTH);
        let mut std = stats.std;
        crate::humanml3d::spread_by_part(&mut std);
        for (name, values) in [("Mean.npy", &stats.mean), ("Std.npy", &std)] {
            let path = self.folder().join(name);
            let mut bytes = npy_header("<f4", &[WIDTH]);
            bytes.extend(values.iter().flat_map(|v| v.to_le_bytes()));
            std::fs::write(&path, bytes).map_err(|e| Error::output(&path, e))?;
        }
        let ids: String = self
            .clips
            .iter()
            .filter_map(|c| c.id.as_deref())
            .map(|id| format!("{id}\n"))
            .collect();
        let path = self.folder().join("all.txt");
        std::fs::write(&path, ids).map_err(|e| Error::output(&path, e))
    }

    /// Lists a take that could not be compiled.
    pub fn skip(&mut self, skipped: Skipped) {
        self.skipped.push(skipped);
    }

    /// The takes listed as skipped so far.
    pub fn skipped(&self) -> &[Skipped] {
        &self.skipped
    }

    /// Writes the offsets and the manifest, and gives the folder its name.
    pub fn finish(mut self) -> Result<Summary, Error> {
        let summary = crate::io::output::in_partial_folder(|| self.complete())?;
        self.folder.take().expect("open until finished").commit()?;
        Ok(summary)
    }

    fn complete(&mut self) -> Result<Summary, Error> {
        if self.options.features == FeatureSet::HumanMl3d {
            self.finish_humanml3d()?;
        }
        let mut groups = Vec::new();
        for (k, open) in std::mem::take(&mut self.groups).into_iter().enumerate() {
            let name = format!("group_{k}");
            let mut arrays: Vec<ArrayEntry> = open
                .arrays
                .iter()
                .map(|a| ArrayEntry {
                    name: a
                        .path
                        .file_stem()
                        .unwrap_or_default()
                        .to_string_lossy()
                        .into_owned(),
                    file: format!(
                        "{name}/{}",
                        a.path.file_name().unwrap_or_default().to_string_lossy()
                    ),
                    dtype: a.descr.to_string(),
                    shape: a.shape(),
                })
                .collect();
            for mut array in open.arrays {
                array.close()?;
            }
            // Where each clip starts, and the end: clip i is rows offsets[i]..offsets[i + 1].
            let offsets: Vec<i64> = open
                .starts
                .iter()
                .chain(std::iter::once(&open.frames))
                .map(|&n| n as i64)
                .collect();
            let path = self.folder().join(&name).join("offsets.npy");
            let mut bytes = npy_header("<i8", &[offsets.len()]);
            bytes.extend(offsets.iter().flat_map(|n| n.to_le_bytes()));
            std::fs::write(&path, bytes).map_err(|e| Error::output(&path, e))?;
            arrays.push(ArrayEntry {
                name: "offsets".to_string(),
                file: format!("{name}/offsets.npy"),
                dtype: "<i8".to_string(),
                shape: vec![offsets.len()],
            });
            // Each clip's bone OFFSETs (metres, Y up): with the rotations and root
            // translations, what forward kinematics needs.
            let points = open.topology.joints.len();
            let shape = vec![open.starts.len(), points, 3];
            let path = self.folder().join(&name).join("rest_offsets.npy");
            let mut bytes = npy_header("<f4", &shape);
            bytes.extend(open.rest_offsets.iter().flat_map(|v| v.to_le_bytes()));
            std::fs::write(&path, bytes).map_err(|e| Error::output(&path, e))?;
            arrays.push(ArrayEntry {
                name: "rest_offsets".to_string(),
                file: format!("{name}/rest_offsets.npy"),
                dtype: "<f4".to_string(),
                shape,
            });
            let stats = STATS_OF
                .iter()
                .zip(&open.moments)
                .map(|(&k, moments)| {
                    let array = &arrays[k];
                    moments.stats(&array.name, array.shape[1..].iter().product())
                })
                .collect();
            groups.push(Group {
                skeleton: format!("{name}/skeleton.bvh"),
                name,
                topology: open.topology,
                clips: open.starts.len(),
                frames: open.frames,
                arrays,
                stats,
            });
        }
        let summary = Summary {
            clips: self.clips.len(),
            frames: self.clips.iter().map(|c| c.frames).sum(),
            groups: groups.len(),
            skipped: self.skipped.clone(),
        };
        let manifest = Manifest {
            format: FORMAT.to_string(),
            bvhview: env!("CARGO_PKG_VERSION").to_string(),
            options: self.settings.clone(),
            takes: self.takes.clone(),
            groups,
            clips: std::mem::take(&mut self.clips),
            skipped: std::mem::take(&mut self.skipped),
        };
        let path = self.folder().join("manifest.json");
        let mut text = serde_json::to_string_pretty(&manifest).expect("a manifest serialises");
        text.push('\n');
        std::fs::write(&path, text).map_err(|e| Error::output(&path, e))?;
        Ok(summary)
    }
}

/// A skeleton as `skeleton.bvh`: one frame, its rest pose (position channels hold the OFFSET's
/// components, rotations 0), so that any BVH reader shows the skeleton the arrays are of.
pub fn skeleton_bvh(skeleton: &crate::Skeleton) -> Result<String, Error> {
    let mut rest = Vec::with_capacity(skeleton.channel_count());
    for joint in &skeleton.joints {
        for channel in &joint.channels {
            rest.push(match channel.is_position() {
                true => joint.offset[channel.axis()],
                false => 0.0,
            });
        }
    }
    let motion = crate::Motion::new(1.0 / 30.0, rest.len(), 1, rest);
    crate::bvh::writer::to_string(skeleton, &motion)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_headers_are_128_bytes_and_end_in_a_newline() {
        let header = npy_header("<f4", &[12, 31, 3]);
        assert_eq!(header.len(), HEADER);
        assert_eq!(&header[..8], b"\x93NUMPY\x01\x00");
        assert_eq!(u16::from_le_bytes([header[8], header[9]]), 118);
        let text = String::from_utf8(header[10..].to_vec()).unwrap();
        assert!(
            text.starts_with("{'descr': '<f4', 'fortran_order': False, 'shape': (12, 31, 3), }")
        );
        assert!(text.ends_with(" \n"));
        let one = String::from_utf8(npy_header("<i8", &[5])[10..].to_vec()).unwrap();
        assert!(one.contains("'shape': (5,), }"));
    }
}
