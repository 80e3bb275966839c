//! A dataset on disk: `manifest.json`, and per skeleton topology a folder `group_K` holding one
//! `.npy` file per array (every clip's frames one after the other, memory-mappable) and
//! `offsets.npy`, where each clip starts. The folder is filled under a temporary name beside
//! `out` and renamed at the end, so a dataset is there whole or not at all.

use super::{About, Clip, Options, Skipped, Summary, Topology};
use crate::error::Error;
use crate::pose::RotationKind;
use std::collections::HashMap;
use std::fs::File;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

/// What the manifest's `format` says; a reader refuses any other.
pub const FORMAT: &str = "bvhview-dataset 1";

/// Every `.npy` header takes this many bytes (numpy's own writer pads to a multiple of 64).
const HEADER: usize = 128;

/// `manifest.json`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    pub format: String,
    /// The version that wrote it.
    pub bvhview: String,
    pub options: Settings,
    pub groups: Vec<Group>,
    pub clips: Vec<ClipEntry>,
    pub skipped: Vec<Skipped>,
}

/// The options a dataset was made with, as the manifest records them.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    pub fps: f64,
    pub rotations: String,
    pub root_relative: bool,
    pub contact_height_m: f32,
    pub contact_speed_m_per_s: f32,
    pub up: String,
    pub units: String,
}

impl Settings {
    fn of(options: &Options) -> Settings {
        Settings {
            fps: options.fps,
            rotations: options.rotations.name().to_string(),
            root_relative: options.root_relative,
            contact_height_m: options.contact_height,
            contact_speed_m_per_s: options.contact_speed,
            up: "y".to_string(),
            units: "metres".to_string(),
        }
    }

    fn options(&self) -> Result<Options, Error> {
        let rotations = RotationKind::parse(&self.rotations).ok_or_else(|| {
            Error::Usage(format!(
                "rotations {:?}: not a kind bvhview writes",
                self.rotations
            ))
        })?;
        Ok(Options {
            fps: self.fps,
            rotations,
            root_relative: self.root_relative,
            contact_height: self.contact_height_m,
            contact_speed: self.contact_speed_m_per_s,
            ..Options::default()
        })
    }
}

/// One topology's clips.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Group {
    /// Its folder.
    pub name: String,
    #[serde(flatten)]
    pub topology: Topology,
    pub clips: usize,
    pub frames: usize,
    /// Each array's file, element type and shape.
    pub arrays: Vec<ArrayEntry>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ArrayEntry {
    pub name: String,
    pub file: String,
    pub dtype: String,
    pub shape: Vec<usize>,
}

/// One clip: where its frames are in its group's arrays, and what it came from.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClipEntry {
    #[serde(flatten)]
    pub about: About,
    pub group: usize,
    /// Its first frame's row in the group's arrays.
    pub start: usize,
    pub frames: usize,
}

/// The arrays of a group, in the order the manifest lists them: name, element type, and the
/// shape of one frame.
fn layout(
    topology: &Topology,
    rotations: RotationKind,
) -> [(&'static str, &'static str, Vec<usize>); 5] {
    let (points, rotated) = (topology.joints.len(), topology.rotated.len());
    let rotation_shape = match rotations {
        RotationKind::Matrix => vec![rotated, 3, 3],
        kind => vec![rotated, kind.width()],
    };
    [
        ("positions", "<f4", vec![points, 3]),
        ("rotations", "<f4", rotation_shape),
        ("root_translations", "<f4", vec![3]),
        ("velocities", "<f4", vec![points, 3]),
        ("foot_contacts", "|u1", vec![topology.feet.len()]),
    ]
}

/// The `.npy` header (version 1.0) of an array of `descr` with `shape`, [`HEADER`] bytes long.
fn npy_header(descr: &str, shape: &[usize]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let shape = match dims.len() {
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    let mut header = b"\x93NUMPY\x01\x00".to_vec();
    header.extend(((HEADER - 10) as u16).to_le_bytes());
    header.extend(dict.as_bytes());
    header.resize(HEADER - 1, b' ');
    header.push(b'\n');
    header
}

/// An array written frame by frame; its header, which holds the row count, is written last.
/// The file is opened for each clip and closed after it: a folder of many skeletons would
/// otherwise hold five files open per skeleton, past the process's limit.
struct ArrayFile {
    path: PathBuf,
    descr: &'static str,
    frame_shape: Vec<usize>,
    rows: usize,
}

impl ArrayFile {
    fn create(
        path: PathBuf,
        descr: &'static str,
        frame_shape: Vec<usize>,
    ) -> Result<ArrayFile, Error> {
        std::fs::write(&path, [0; HEADER]).map_err(|e| Error::output(&path, e))?;
        Ok(ArrayFile {
            path,
            descr,
            frame_shape,
            rows: 0,
        })
    }

    fn shape(&self) -> Vec<usize> {
        std::iter::once(self.rows)
            .chain(self.frame_shape.iter().copied())
            .collect()
    }

    fn append(&self) -> io::Result<File> {
        std::fs::OpenOptions::new().append(true).open(&self.path)
    }

    /// Appends float32 values, converted a piece at a time: one write per piece.
    fn append_floats(&self, values: &[f32]) -> io::Result<()> {
        let mut file = self.append()?;
        let mut bytes = Vec::with_capacity(4 * PIECE.min(values.len()));
        for piece in values.chunks(PIECE) {
            bytes.clear();
            bytes.extend(piece.iter().flat_map(|v| v.to_le_bytes()));
            file.write_all(&bytes)?;
        }
        Ok(())
    }

    fn append_bytes(&self, values: &[u8]) -> io::Result<()> {
        self.append()?.write_all(values)
    }

    fn finish(self) -> Result<(), Error> {
        let header = npy_header(self.descr, &self.shape());
        let done = || -> io::Result<()> {
            let mut file = std::fs::OpenOptions::new().write(true).open(&self.path)?;
            file.write_all(&header)
        };
        done().map_err(|e| Error::output(&self.path, e))
    }
}

/// Floats converted to bytes at a time.
const PIECE: usize = 1 << 16;

/// One group's files while they are written.
struct OpenGroup {
    topology: Topology,
    arrays: Vec<ArrayFile>,
    starts: Vec<usize>,
    frames: usize,
    /// Every clip's OFFSETs, clip after clip.
    rest_offsets: Vec<f32>,
}

/// A dataset being written: clips in the order they come, each to its topology's group.
pub struct Writer {
    out: PathBuf,
    folder: Option<tempfile::TempDir>,
    options: Options,
    groups: Vec<OpenGroup>,
    by_topology: HashMap<Topology, usize>,
    clips: Vec<ClipEntry>,
    skipped: Vec<Skipped>,
}

impl Writer {
    /// Starts a dataset at `out`, which must not exist or be an empty folder. As for every
    /// output (`crate::output`): a link another user planted in a sticky shared folder on the
    /// way to `out` is refused, the temporary folder beside it has a random name made
    /// exclusively (`.OUT.XXXXXX`, `OUT` cut to fit a long name), and a failure names its cause.
    pub fn create(out: &Path, options: &Options) -> Result<Writer, Error> {
        options.check()?;
        crate::output::refuse_planted_folders(out)?;
        match std::fs::symlink_metadata(out) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(Error::output(out, e)),
            Ok(m) if m.is_dir() && std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_none()) => {
            }
            Ok(_) => {
                return Err(Error::Usage(format!(
                    "{}: already exists; a dataset goes into a new (or empty) folder",
                    out.display()
                )));
            }
        }
        let name = out
            .file_name()
            .ok_or_else(|| Error::Usage(format!("{}: not a folder name", out.display())))?;
        let parent = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let folder = tempfile::Builder::new()
            .prefix(&crate::output::temporary_prefix(Some(name)))
            .tempdir_in(parent)
            .map_err(|e| Error::output(out, e))?;
        crate::output::partial_folder(folder.path());
        Ok(Writer {
            out: out.to_path_buf(),
            folder: Some(folder),
            options: *options,
            groups: Vec::new(),
            by_topology: HashMap::new(),
            clips: Vec::new(),
            skipped: Vec::new(),
        })
    }

    fn folder(&self) -> &Path {
        self.folder.as_ref().expect("open until finished").path()
    }

    /// Adds a clip after those added before.
    pub fn add(&mut self, clip: &Clip) -> Result<(), Error> {
        crate::output::in_partial_folder(|| self.add_files(clip))
    }

    fn add_files(&mut self, clip: &Clip) -> Result<(), Error> {
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
                self.groups.push(OpenGroup {
                    topology: clip.topology.clone(),
                    arrays,
                    starts: Vec::new(),
                    frames: 0,
                    rest_offsets: Vec::new(),
                });
                self.by_topology.insert(clip.topology.clone(), k);
                k
            }
        };
        let open = &mut self.groups[group];
        let start = open.frames;
        let [positions, rotations, roots, velocities, contacts] = &mut open.arrays[..] else {
            unreachable!("five arrays per group")
        };
        let written = || -> io::Result<()> {
            positions.append_floats(&clip.positions)?;
            rotations.append_floats(&clip.rotations)?;
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
        });
        Ok(())
    }

    /// Lists a take that could not be compiled.
    pub fn skip(&mut self, skipped: Skipped) {
        self.skipped.push(skipped);
    }

    /// Writes the offsets and the manifest, and gives the folder its name.
    pub fn finish(mut self) -> Result<Summary, Error> {
        let made = self.folder().to_path_buf();
        let result = crate::output::in_partial_folder(|| self.complete());
        crate::output::finished_folder(&made);
        result
    }

    fn complete(&mut self) -> Result<Summary, Error> {
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
            for array in open.arrays {
                array.finish()?;
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
            groups.push(Group {
                name,
                topology: open.topology,
                clips: open.starts.len(),
                frames: open.frames,
                arrays,
            });
        }
        let summary = Summary {
            clips: self.clips.len(),
            frames: groups.iter().map(|g| g.frames).sum(),
            groups: groups.len(),
            skipped: self.skipped.clone(),
        };
        let manifest = Manifest {
            format: FORMAT.to_string(),
            bvhview: env!("CARGO_PKG_VERSION").to_string(),
            options: Settings::of(&self.options),
            groups,
            clips: std::mem::take(&mut self.clips),
            skipped: std::mem::take(&mut self.skipped),
        };
        let path = self.folder().join("manifest.json");
        let mut text = serde_json::to_string_pretty(&manifest).expect("a manifest serialises");
        text.push('\n');
        std::fs::write(&path, text).map_err(|e| Error::output(&path, e))?;
        let folder = self.folder.take().expect("open until finished");
        let made = folder.path().to_path_buf();
        let named = (|| -> io::Result<()> {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&made, std::fs::Permissions::from_mode(0o755))?;
            sync_file_system(&made)?;
            std::fs::rename(&made, &self.out)?;
            let parent = self.out.parent().filter(|p| !p.as_os_str().is_empty());
            File::open(parent.unwrap_or(Path::new(".")))?.sync_all()
        })();
        match named {
            Ok(()) => {
                // Renamed: the folder is the dataset now, not a temporary one to remove.
                let _ = folder.keep();
                Ok(summary)
            }
            Err(e) => Err(Error::output(&self.out, e)),
        }
    }
}

impl Drop for Writer {
    fn drop(&mut self) {
        if let Some(folder) = &self.folder {
            crate::output::finished_folder(folder.path());
        }
    }
}

/// Everything written into `folder` reaches the disk before the folder takes its name: one
/// `syncfs` of its file system, rather than an fsync of each of its files (six per group).
fn sync_file_system(folder: &Path) -> io::Result<()> {
    use std::os::fd::AsRawFd;
    let folder = File::open(folder)?;
    // SAFETY: syncfs only reads the descriptor, which `folder` keeps open for the call.
    match unsafe { libc::syncfs(folder.as_raw_fd()) } {
        0 => Ok(()),
        _ => Err(io::Error::last_os_error()),
    }
}

/// Reads a dataset's manifest.
pub fn read_manifest(dataset: &Path) -> Result<Manifest, Error> {
    let path = dataset.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let manifest: Manifest = serde_json::from_str(&text).map_err(|e| Error::Parse {
        path: path.display().to_string(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    if manifest.format != FORMAT {
        return Err(Error::Usage(format!(
            "{}: format {:?}; this bvhview reads {FORMAT:?}",
            path.display(),
            manifest.format
        )));
    }
    Ok(manifest)
}

/// The data of one of our `.npy` files, past its header.
fn read_npy(path: &Path) -> Result<Vec<u8>, Error> {
    let mut bytes = Vec::new();
    File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| Error::io(path, e))?;
    let header = bytes
        .get(8..10)
        .filter(|_| bytes.starts_with(b"\x93NUMPY"))
        .map(|b| 10 + u16::from_le_bytes([b[0], b[1]]) as usize)
        .filter(|&n| n <= bytes.len())
        .ok_or_else(|| Error::Usage(format!("{}: not a .npy file", path.display())))?;
    bytes.drain(..header);
    Ok(bytes)
}

fn floats(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// Merges datasets compiled from consecutive pieces of one folder's takes (in path order) into
/// `out`: the dataset one compile of all of them would have written, byte for byte.
pub fn merge(pieces: &[PathBuf], out: &Path) -> Result<Summary, Error> {
    let manifests = pieces
        .iter()
        .map(|p| read_manifest(p))
        .collect::<Result<Vec<_>, Error>>()?;
    let Some(first) = manifests.first() else {
        return Err(Error::Usage(
            "nothing to merge: no datasets given".to_string(),
        ));
    };
    let options = first.options.options()?;
    for (piece, manifest) in pieces.iter().zip(&manifests) {
        if manifest.options != first.options {
            return Err(Error::Usage(format!(
                "{}: made with other options than {}; pieces of one dataset share them",
                piece.display(),
                pieces[0].display()
            )));
        }
    }
    // Pieces are consecutive runs of one folder's takes in path order: every take's path comes
    // after the one before, across pieces too.
    let mut last: Option<(String, &Path)> = None;
    for (piece, manifest) in pieces.iter().zip(&manifests) {
        let mut paths: Vec<String> = manifest
            .clips
            .iter()
            .map(|c| &c.about.source)
            .chain(manifest.skipped.iter().map(|s| &s.source))
            .map(|s| s.motion.clone().unwrap_or_else(|| s.path.clone()))
            .collect();
        // Path order, as `takes` lists them (by component: `a/b` before `a-b`).
        paths.sort_by(|a, b| Path::new(a).cmp(Path::new(b)));
        for path in paths {
            if let Some((before, where_before)) = &last
                && Path::new(before) >= Path::new(&path)
            {
                return Err(Error::Usage(format!(
                    "{}: {path} comes after {before} in {}; pieces must be consecutive runs of \
                     list_takes, given in order, each take in one piece",
                    piece.display(),
                    where_before.display()
                )));
            }
            last = Some((path, piece));
        }
    }
    let mut writer = Writer::create(out, &options)?;
    for (piece, manifest) in pieces.iter().zip(manifests) {
        let mut data: Vec<Vec<Vec<u8>>> = Vec::new();
        for (k, group) in manifest.groups.iter().enumerate() {
            let arrays = group
                .arrays
                .iter()
                .filter(|a| a.name != "offsets")
                .map(|a| {
                    // Only the piece's own files, as its writer named them.
                    let own = a.file.starts_with(&format!("group_{k}/"))
                        && !a.file.contains("..")
                        && a.file.matches('/').count() == 1;
                    if !own {
                        return Err(Error::Usage(format!(
                            "{}: the manifest names {:?}, not a file of its own",
                            piece.display(),
                            a.file
                        )));
                    }
                    read_npy(&piece.join(&a.file))
                })
                .collect::<Result<Vec<_>, Error>>()?;
            data.push(arrays);
        }
        let mut clip_in_group = vec![0usize; manifest.groups.len()];
        for entry in manifest.clips {
            let group = manifest.groups.get(entry.group).ok_or_else(|| {
                Error::Usage(format!(
                    "{}: a clip names group {}, which is not there",
                    piece.display(),
                    entry.group
                ))
            })?;
            let topology = group.topology.clone();
            let per_frame: Vec<usize> = layout(&topology, options.rotations)
                .iter()
                .map(|(_, descr, shape)| {
                    shape.iter().product::<usize>() * if *descr == "|u1" { 1 } else { 4 }
                })
                .collect();
            let slice = |k: usize| -> Result<&[u8], Error> {
                let (from, to) = (
                    entry.start * per_frame[k],
                    (entry.start + entry.frames) * per_frame[k],
                );
                data[entry.group][k].get(from..to).ok_or_else(|| {
                    Error::Usage(format!(
                        "{}: {} is shorter than its manifest says",
                        piece.display(),
                        group.arrays[k].file
                    ))
                })
            };
            let points = topology.joints.len();
            let index = clip_in_group[entry.group];
            clip_in_group[entry.group] += 1;
            let rest = data[entry.group][5]
                .get(index * points * 12..(index + 1) * points * 12)
                .ok_or_else(|| {
                    Error::Usage(format!(
                        "{}: {} is shorter than its manifest says",
                        piece.display(),
                        group.arrays[6].file
                    ))
                })?;
            let clip = Clip {
                about: entry.about,
                topology,
                frames: entry.frames,
                rest_offsets: floats(rest),
                positions: floats(slice(0)?),
                rotations: floats(slice(1)?),
                root_translations: floats(slice(2)?),
                velocities: floats(slice(3)?),
                contacts: slice(4)?.to_vec(),
            };
            writer.add(&clip)?;
        }
        for skipped in manifest.skipped {
            writer.skip(skipped);
        }
    }
    writer.finish()
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
