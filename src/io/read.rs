//! Reading input files within the limits: a reader that stops at a size, and whole text files
//! (ASF, AMC) refused at their first NUL byte; whole binary files are `whole`.

use crate::io::error::{Error, PastMaxSize};
use std::path::Path;

/// A reader that fails once more than `max_size` bytes come out of `inner`: a size check that
/// also holds for what has no size up front (a pipe, a device such as /dev/zero).
pub struct Bounded<R> {
    inner: R,
    limit: u64,
    left: u64,
    /// What is said past the limit, when not [`PastMaxSize`].
    too_large: Option<String>,
}

impl<R: std::io::Read> Bounded<R> {
    /// Fails past `max_size` bytes with [`PastMaxSize`], which [`Error::io`] says as a
    /// [`Error::Limit`] naming the `max_size` argument.
    pub fn new(inner: R, max_size: u64) -> Bounded<R> {
        Bounded {
            inner,
            limit: max_size,
            left: max_size,
            too_large: None,
        }
    }

    /// Fails past `limit` bytes with `too_large` as the message.
    pub fn saying(inner: R, limit: u64, too_large: String) -> Bounded<R> {
        Bounded {
            inner,
            limit,
            left: limit,
            too_large: Some(too_large),
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
                _ => Err(match &self.too_large {
                    Some(said) => {
                        std::io::Error::new(std::io::ErrorKind::FileTooLarge, said.clone())
                    }
                    None => std::io::Error::new(
                        std::io::ErrorKind::FileTooLarge,
                        PastMaxSize {
                            max_size: self.limit,
                        },
                    ),
                }),
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
    read_within(path, max_size, None)
}

/// What a path that is not a regular file is, in words (one wording for every reader and the
/// folder walk).
pub(crate) fn kind_of(file_type: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_fifo() {
        "a FIFO"
    } else if file_type.is_socket() {
        "a socket"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// The whole of an ASF skeleton: refused past `max_size` or [`crate::io::limits::MAX_HEADER_BYTES`],
/// so that a link to /dev/zero is not read for gigabytes.
pub fn read_skeleton_file(path: &Path, max_size: u64) -> Result<Vec<u8>, Error> {
    let limit = crate::io::limits::MAX_HEADER_BYTES as u64;
    if max_size < limit {
        return read_file(path, max_size);
    }
    read_within(
        path,
        limit,
        Some(format!(
            "more than {} MiB: not an ASF skeleton",
            limit >> 20
        )),
    )
}

/// The whole file, read a megabyte at a time and refused at its first NUL byte: ASF and AMC are
/// text, so a link to /dev/zero or a binary file fails at once instead of at the size limit.
fn read_within(path: &Path, limit: u64, too_large: Option<String>) -> Result<Vec<u8>, Error> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // Room for the whole file at once (reading in doubling steps could hold twice its size).
    let length = file.metadata().map_or(0, |m| m.len()).min(limit);
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0).saturating_add(1));
    let mut input = match too_large {
        Some(said) => Bounded::saying(file, limit, said),
        None => Bounded::new(file, limit),
    };
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
