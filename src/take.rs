//! What every command reads: a BVH, FBX or glTF/GLB file, or an ASF skeleton with an optional AMC
//! motion.

use crate::acclaim;
use crate::bvh;
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;
use std::path::Path;

/// A skeleton and its motion, from whichever format.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub skeleton: Skeleton,
    pub motion: Motion,
    pub warnings: Vec<String>,
    /// The units the file states (an ASF's `:units length`), if any.
    pub stated_units: Option<crate::model::stance::Units>,
}

impl Loaded {
    /// How the take stands (up axis, units, height), guessed from its motion in `mode`.
    pub fn stance(&self, mode: crate::model::pose::OffsetMode) -> crate::model::stance::Stance {
        crate::model::stance::Stance::guess(&self.skeleton, &self.motion, mode, self.stated_units)
    }
}

/// A path's extension in lower case (`TAKE.BVH` → `bvh`), empty when it has none.
pub fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// Loads `path` (`.bvh`, or `.asf` with `motion` an `.amc`). `frame_time` overrides the file's
/// (AMC has none: CMU's 120 Hz is the default).
pub fn load(path: &Path, motion: Option<&Path>, frame_time: Option<f64>) -> Result<Loaded, Error> {
    load_checked(
        path,
        motion,
        frame_time,
        crate::io::parallel::cores(),
        DEFAULT_MAX_SIZE,
    )
}

/// Files larger than this are refused unless `--max-size` says otherwise (8 GiB).
pub const DEFAULT_MAX_SIZE: u64 = 8 << 30;

/// Fails unless `path` is a readable regular file of at most `max_size` bytes. A FIFO, a device
/// or a socket is refused by its type before any read (a FIFO would wait for a writer for good,
/// /dev/zero never ends); standard input is read as `-`.
pub fn check_file(path: &Path, max_size: u64) -> Result<(), Error> {
    let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if metadata.is_dir() {
        return Err(Error::Usage(format!(
            "{}: is a folder, not a file (`bvhview info FOLDER` reads every file in one)",
            path.display()
        )));
    }
    if !metadata.is_file() {
        let what = crate::io::read::kind_of(&metadata.file_type());
        return Err(Error::Usage(format!(
            "{}: {what}, not a regular file; bvhview reads takes from files (`-` reads standard \
             input)",
            path.display()
        )));
    }
    if metadata.len() > max_size {
        return Err(Error::Usage(format!(
            "{}: {} bytes, more than --max-size {max_size}",
            path.display(),
            metadata.len()
        )));
    }
    Ok(())
}

/// [`load`] parsing a BVH on at most `threads` threads and refusing files larger than `max_size`
/// bytes before reading them.
pub fn load_checked(
    path: &Path,
    motion: Option<&Path>,
    frame_time: Option<f64>,
    threads: usize,
    max_size: u64,
) -> Result<Loaded, Error> {
    load_take(path, motion, frame_time, threads, max_size, None)
}

/// Whether bvhview reads files with this (lower-case) extension as takes of their own: `bvh`,
/// `fbx`, `gltf`, `glb` (an `asf` needs its `amc`).
pub fn is_take_extension(extension: &str) -> bool {
    matches!(extension, "bvh" | "fbx" | "gltf" | "glb")
}

/// Whether a file holds takes that `--take` picks among (FBX animation stacks, glTF animations).
pub fn has_takes(path: &Path) -> bool {
    matches!(extension(path).as_str(), "fbx" | "gltf" | "glb")
}

/// The takes of an FBX or glTF file (name, frames, frame time), in file order; empty for the
/// formats that hold one take.
pub fn takes(path: &Path, max_size: u64) -> Result<Vec<crate::model::reading::TakeInfo>, Error> {
    check_file(path, max_size)?;
    match extension(path).as_str() {
        "fbx" => crate::fbx::takes(path, max_size),
        "gltf" | "glb" => crate::gltf::takes(path, max_size),
        _ => Ok(Vec::new()),
    }
}

/// [`load_checked`] with the take of a file that holds several (FBX, glTF): `take` is its name
/// or its index in [`takes`]; `None` reads the first.
pub fn load_take(
    path: &Path,
    motion: Option<&Path>,
    frame_time: Option<f64>,
    threads: usize,
    max_size: u64,
    take: Option<&str>,
) -> Result<Loaded, Error> {
    check_file(path, max_size)?;
    if let Some(motion) = motion {
        check_file(motion, max_size)?;
    }
    crate::io::limits::frame_time_option(frame_time)?;
    match extension(path).as_str() {
        "asf" => {
            let asf = acclaim::load_asf(path, max_size)?;
            let (skeleton, maps) = asf.to_skeleton();
            let frame_time = frame_time.unwrap_or(acclaim::DEFAULT_FRAME_TIME);
            let channels = skeleton.channel_count();
            let motion = match motion {
                Some(amc) => {
                    if extension(amc) != "amc" {
                        return Err(Error::Usage(format!(
                            "--motion {}: expected an .amc file",
                            amc.display()
                        )));
                    }
                    acclaim::load_amc(
                        amc,
                        max_size,
                        &maps,
                        channels,
                        asf.units.degrees,
                        frame_time,
                    )?
                }
                None => Motion::new(frame_time, channels, 0, Vec::new()),
            };
            Ok(Loaded {
                skeleton,
                motion,
                warnings: asf.warnings,
                stated_units: crate::model::stance::asf_units(asf.units.length),
            })
        }
        "amc" => Err(Error::Usage(format!(
            "{}: an AMC file holds motion only; give its skeleton: bvhview COMMAND SKELETON.asf --motion {}",
            path.display(),
            path.display()
        ))),
        "fbx" | "gltf" | "glb" => {
            if let Some(amc) = motion {
                return Err(Error::Usage(format!(
                    "--motion {}: only an ASF skeleton takes a motion file",
                    amc.display()
                )));
            }
            let read = if extension(path) == "fbx" {
                crate::fbx::load(path, max_size, take, threads)?
            } else {
                crate::gltf::load(path, max_size, take)?
            };
            let mut motion = read.motion;
            if let Some(time) = frame_time {
                motion.frame_time = time;
            }
            Ok(Loaded {
                skeleton: read.skeleton,
                motion,
                warnings: read.warnings,
                // Both readers give metres (ufbx converts the FBX's UnitScaleFactor; glTF is
                // metres by definition); the stance's guess from the figure's size says so.
                stated_units: None,
            })
        }
        "bvh" => {
            if take.is_some() {
                return Err(Error::Usage(format!(
                    "--take: {} holds one take (only FBX and glTF files hold several)",
                    path.display()
                )));
            }
            if let Some(amc) = motion {
                return Err(Error::Usage(format!(
                    "--motion {}: only an ASF skeleton takes a motion file",
                    amc.display()
                )));
            }
            let settings = bvh::loader::Settings {
                threads,
                max_size,
                ..Default::default()
            };
            let mut file = bvh::load_file(path, settings)?;
            if let Some(time) = frame_time {
                file.motion.frame_time = time;
            }
            Ok(Loaded {
                skeleton: file.skeleton,
                motion: file.motion,
                warnings: file.warnings,
                stated_units: None,
            })
        }
        other => Err(Error::Usage(format!(
            "{}: unknown extension '{other}': bvhview reads .bvh, .fbx, .gltf and .glb files and .asf skeletons (with --motion .amc)",
            path.display()
        ))),
    }
}

/// The format of a take's bytes by how they begin, for standard input, which has no extension:
/// `HIERARCHY` (after a byte-order mark or blanks) is BVH, `glTF` binary GLB, `{` glTF text,
/// and FBX's binary magic or an ASCII FBX's `; FBX` comment FBX.
pub fn format_of_bytes(bytes: &[u8]) -> Option<&'static str> {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(text.len());
    let text = &text[start..];
    if text.len() >= 9 && text[..9].eq_ignore_ascii_case(b"HIERARCHY") {
        Some("bvh")
    } else if bytes.starts_with(b"glTF") {
        Some("glb")
    } else if text.starts_with(b"{") {
        Some("gltf")
    } else if bytes.starts_with(b"Kaydara FBX Binary") || text.starts_with(b"; FBX") {
        Some("fbx")
    } else {
        None
    }
}

/// A take from bytes in memory (standard input, `-`): in `format` (`bvh`, `fbx`, `gltf` or
/// `glb`), or, given none, the one [`format_of_bytes`] tells. `name` is what messages call it;
/// a glTF read so has no folder, so its buffers must be inside it (GLB or data URIs).
pub fn load_bytes_as(
    bytes: &[u8],
    format: Option<&str>,
    name: &str,
    frame_time: Option<f64>,
    threads: usize,
    take: Option<&str>,
) -> Result<Loaded, Error> {
    crate::io::limits::frame_time_option(frame_time)?;
    if bytes.is_empty() {
        return Err(Error::Usage(format!("{name}: empty: no take to read")));
    }
    let format = match format.or_else(|| format_of_bytes(bytes)) {
        Some(format) => format,
        None => {
            return Err(Error::Usage(format!(
                "{name}: not a take bvhview can tell by its first bytes; name its format with \
                 --from bvh, fbx, gltf or glb"
            )));
        }
    };
    let (skeleton, mut motion, warnings) = match format {
        "bvh" => {
            if take.is_some() {
                return Err(Error::Usage(format!(
                    "--take: {name} is a BVH, which holds one take"
                )));
            }
            let file = bvh::load_bytes(bytes, name)?;
            (file.skeleton, file.motion, file.warnings)
        }
        "fbx" => {
            let read = crate::fbx::load_bytes(bytes, name, take, threads)?;
            (read.skeleton, read.motion, read.warnings)
        }
        "gltf" | "glb" => {
            let read = crate::gltf::load_bytes(bytes, name, take)?;
            (read.skeleton, read.motion, read.warnings)
        }
        other => {
            return Err(Error::Usage(format!(
                "--from {other}: bvhview reads bvh, fbx, gltf or glb from standard input"
            )));
        }
    };
    if let Some(time) = frame_time {
        motion.frame_time = time;
    }
    Ok(Loaded {
        skeleton,
        motion,
        warnings,
        stated_units: None,
    })
}

/// The bundled walk.
pub fn default_motion() -> Result<Loaded, Error> {
    let file = bvh::load_bytes(crate::DEFAULT_MOTION, crate::DEFAULT_MOTION_NAME)?;
    Ok(Loaded {
        skeleton: file.skeleton,
        motion: file.motion,
        warnings: file.warnings,
        stated_units: None,
    })
}
