//! Whole binary files (FBX, GLB, glTF JSON and buffers, NumPy positions) read into memory,
//! refused by their size on disk before a byte is read.

use crate::io::error::Error;
use crate::io::read::kind_of;
use std::path::Path;

/// `path` opened for reading, and its length, refused (before any read) unless it is a regular
/// file: it is opened with `O_NONBLOCK`, so that opening a FIFO does not wait for a writer, and
/// the opened handle's type is what is checked (no race between a look and the open). The error
/// says what the path is instead: `a FIFO, not a regular file (…)`.
pub fn open_regular(path: &Path) -> std::io::Result<(std::fs::File, u64)> {
    use std::os::unix::fs::OpenOptionsExt;
    let refuse = |kind: &str| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{kind}, not a regular file (bvhview reads only regular files)"),
        )
    };
    let file = match std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
    {
        Ok(file) => file,
        // A socket cannot be opened at all (ENXIO): say what it is.
        Err(error) if error.raw_os_error() == Some(libc::ENXIO) => {
            return Err(match std::fs::metadata(path) {
                Ok(metadata) if !metadata.is_file() => refuse(kind_of(&metadata.file_type())),
                _ => error,
            });
        }
        Err(error) => return Err(error),
    };
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(refuse(kind_of(&metadata.file_type())));
    }
    Ok((file, metadata.len()))
}

/// Exactly `length` bytes from the start of `file`, their room asked for first so that a
/// refusal is an error, not an abort; fewer when the file shrinks while it is read.
fn read_start(file: std::fs::File, length: u64) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    read_more(file, length, &mut bytes)?;
    Ok(bytes)
}

/// The next `length` bytes of `file` after `bytes`, their room asked for first (as
/// [`read_start`]).
fn read_more(file: std::fs::File, length: u64, bytes: &mut Vec<u8>) -> std::io::Result<()> {
    use std::io::Read;
    let room = usize::try_from(length).unwrap_or(usize::MAX);
    bytes.try_reserve_exact(room).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::OutOfMemory,
            format!("{length} bytes do not fit in memory"),
        )
    })?;
    file.take(length).read_to_end(bytes)?;
    Ok(())
}

/// The whole of a binary file (FBX, GLB, glTF JSON, `.npy`, `.npz`), refused before any read
/// unless it is a regular file of at most `max_size` and
/// [`crate::io::limits::MAX_WHOLE_FILE_BYTES`] bytes: these readers hold the whole file in
/// memory, so its size on disk (a sparse file of 6 GB takes 4 KB) is what is checked, never
/// what a read gets to.
pub fn read_binary_file(path: &Path, max_size: u64) -> Result<Vec<u8>, Error> {
    let (file, length) = open_regular(path).map_err(|e| Error::io(path, e))?;
    whole_file_size(&path.display().to_string(), length, max_size)?;
    read_start(file, length).map_err(|e| Error::io(path, e))
}

/// [`read_binary_file`] for a format whose first bytes say what it is (`.npy`'s magic and
/// header length, a CSV's header): at most `head` bytes are read first and `check`ed with the
/// file's size (its error is the caller's whole message), and the rest is read only if they pass, so that a large file of something else
/// (or one whose header promises more than it holds) is refused having read a few bytes.
pub fn read_binary_file_checked(
    path: &Path,
    max_size: u64,
    head: u64,
    check: impl FnOnce(&[u8], u64) -> Result<(), Error>,
) -> Result<Vec<u8>, Error> {
    use std::io::Read;
    let (mut file, length) = open_regular(path).map_err(|e| Error::io(path, e))?;
    let mut start = Vec::new();
    (&mut file)
        .take(head)
        .read_to_end(&mut start)
        .map_err(|e| Error::io(path, e))?;
    check(&start, length)?;
    whole_file_size(&path.display().to_string(), length, max_size)?;
    read_more(file, length.saturating_sub(start.len() as u64), &mut start)
        .map_err(|e| Error::io(path, e))?;
    Ok(start)
}

/// Why `input`, a file of `length` bytes, is not read whole, if it is not.
fn whole_file_size(input: &str, length: u64, max_size: u64) -> Result<(), Error> {
    let budget = crate::io::limits::MAX_WHOLE_FILE_BYTES;
    if length > max_size {
        return Err(Error::too_big(input, length, max_size));
    }
    if length > budget {
        return Err(Error::Limit {
            what: "bytes",
            limit: budget,
            found: length,
            message: format!(
                "{input}: {length} bytes, more than the {} GiB bvhview reads of a binary file \
                 (FBX, glTF, .npy: read whole into memory); not read",
                budget >> 30
            )
            .into(),
        });
    }
    Ok(())
}

/// The first `length` bytes of the regular file at `path` (a glTF buffer of `byteLength`
/// bytes: what lies past it is never read), or why not, said of `input` (how the caller names
/// the file): not a regular file, shorter than `length`, or `length` past `max_size` or
/// [`crate::io::limits::MAX_WHOLE_FILE_BYTES`].
#[cfg(feature = "gltf")]
pub fn read_file_start(
    path: &Path,
    length: u64,
    max_size: u64,
    input: &str,
) -> Result<Vec<u8>, Error> {
    // The system's words without the path, which `input` says.
    let said = |e: std::io::Error| {
        let text = Error::io(path, e).to_string();
        let prefix = format!("{}: ", path.display());
        let why = text.strip_prefix(&prefix).unwrap_or(&text);
        Error::usage(format!("{input}: {why}"))
    };
    let (file, size) = open_regular(path).map_err(said)?;
    whole_file_size(input, length, max_size)?;
    if size < length {
        return Err(Error::usage(format!(
            "{input}: {size} bytes, fewer than its byteLength {length}"
        )));
    }
    read_start(file, length).map_err(said)
}
