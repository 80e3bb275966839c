//! What every command reads: a BVH file, or an ASF skeleton with an optional AMC motion.

use crate::acclaim;
use crate::bvh;
use crate::error::Error;
use crate::motion::Motion;
use crate::skeleton::Skeleton;
use std::path::Path;

/// A skeleton and its motion, from whichever format.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub skeleton: Skeleton,
    pub motion: Motion,
    pub warnings: Vec<String>,
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
    load_checked(path, motion, frame_time, crate::cores(), DEFAULT_MAX_SIZE)
}

/// Files larger than this are refused unless `--max-size` says otherwise (8 GiB).
pub const DEFAULT_MAX_SIZE: u64 = 8 << 30;

/// A reader that fails once more than `max_size` bytes come out of `inner`: a size check that
/// also holds for what has no size up front (a pipe, a device such as /dev/zero).
pub struct Bounded<R> {
    inner: R,
    left: u64,
    /// What is said past the limit.
    too_large: String,
}

impl<R: std::io::Read> Bounded<R> {
    pub fn new(inner: R, max_size: u64) -> Bounded<R> {
        Bounded::saying(
            inner,
            max_size,
            format!("more than --max-size {max_size} bytes"),
        )
    }

    /// Fails past `limit` bytes with `too_large` as the message.
    pub fn saying(inner: R, limit: u64, too_large: String) -> Bounded<R> {
        Bounded {
            inner,
            left: limit,
            too_large,
        }
    }
}

impl<R: std::io::Read> std::io::Read for Bounded<R> {
    fn read(&mut self, buffer: &mut [u8]) -> std::io::Result<usize> {
        if buffer.is_empty() {
            return Ok(0);
        }
        if self.left == 0 {
            // At the limit: one byte more is one too many.
            let mut probe = [0u8; 1];
            return match self.inner.read(&mut probe)? {
                0 => Ok(0),
                _ => Err(std::io::Error::new(
                    std::io::ErrorKind::FileTooLarge,
                    self.too_large.clone(),
                )),
            };
        }
        let room = buffer
            .len()
            .min(usize::try_from(self.left).unwrap_or(usize::MAX));
        let read = self.inner.read(&mut buffer[..room])?;
        self.left -= read as u64;
        Ok(read)
    }
}

/// The whole of `path`, refused past `max_size` bytes.
pub fn read_file(path: &Path, max_size: u64) -> Result<Vec<u8>, Error> {
    read_within(
        path,
        max_size,
        format!("more than --max-size {max_size} bytes"),
    )
}

/// The whole of an ASF skeleton: refused past `max_size` or [`crate::limits::MAX_HEADER_BYTES`],
/// so that a link to /dev/zero is not read for gigabytes.
pub fn read_skeleton_file(path: &Path, max_size: u64) -> Result<Vec<u8>, Error> {
    let limit = crate::limits::MAX_HEADER_BYTES as u64;
    if max_size < limit {
        return read_file(path, max_size);
    }
    read_within(
        path,
        limit,
        format!("more than {} MiB: not an ASF skeleton", limit >> 20),
    )
}

/// The whole file, read a megabyte at a time and refused at its first NUL byte: ASF and AMC are
/// text, so a link to /dev/zero or a binary file fails at once instead of at the size limit.
fn read_within(path: &Path, limit: u64, too_large: String) -> Result<Vec<u8>, Error> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // Room for the whole file at once (reading in doubling steps could hold twice its size).
    let length = file.metadata().map_or(0, |m| m.len()).min(limit);
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0).saturating_add(1));
    let mut input = Bounded::saying(file, limit, too_large);
    loop {
        let before = bytes.len();
        let read = (&mut input)
            .take(1 << 20)
            .read_to_end(&mut bytes)
            .map_err(|e| Error::io(path, e))?;
        if let Some(at) = bytes[before..].iter().position(|&b| b == 0) {
            let message = format!("not a text file: a NUL byte at byte {}", before + at);
            return Err(Error::io(
                path,
                std::io::Error::new(std::io::ErrorKind::InvalidData, message),
            ));
        }
        if read == 0 {
            return Ok(bytes);
        }
    }
}

/// Fails unless `path` is a readable file of at most `max_size` bytes.
pub fn check_file(path: &Path, max_size: u64) -> Result<(), Error> {
    let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if metadata.is_dir() {
        return Err(Error::Usage(format!(
            "{}: is a folder, not a file (`bvhview info FOLDER` reads every file in one)",
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
    check_file(path, max_size)?;
    if let Some(motion) = motion {
        check_file(motion, max_size)?;
    }
    crate::limits::frame_time_option(frame_time)?;
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
            })
        }
        "amc" => Err(Error::Usage(format!(
            "{}: an AMC file holds motion only; give its skeleton: bvhview COMMAND SKELETON.asf --motion {}",
            path.display(),
            path.display()
        ))),
        "bvh" => {
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
            })
        }
        other => Err(Error::Usage(format!(
            "{}: unknown extension '{other}': bvhview reads .bvh files and .asf skeletons (with --motion .amc)",
            path.display()
        ))),
    }
}

/// The bundled walk.
pub fn default_motion() -> Result<Loaded, Error> {
    let file = bvh::load_bytes(crate::DEFAULT_MOTION, crate::DEFAULT_MOTION_NAME)?;
    Ok(Loaded {
        skeleton: file.skeleton,
        motion: file.motion,
        warnings: file.warnings,
    })
}
