//! A dataset's folder opened without trusting it: each file by a plain name relative to the
//! folder, never through a link, read whole at a size known up front; and its manifest read
//! and its settings checked. The dataset's readers ([`super::read`], [`super::humanml3d`])
//! both start here.

use super::options::Options;
use super::store::{self, Manifest};
use crate::io::error::Error;
use std::ffi::CString;
use std::fs::File;
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::FileExt;
use std::path::Path;

/// The largest `manifest.json` read (a dataset of a million clips needs less).
pub const MAX_MANIFEST: u64 = 1 << 30;

/// The dataset folder at `path`, opened, and its manifest, read (not yet checked with its
/// files) in a format this bvhview reads.
pub(super) fn open_manifest(path: &Path) -> Result<(File, Manifest), Error> {
    let refuse = |why: String| Error::decoding(path.display(), why);
    let folder = open_folder(path)?;
    let manifest_file = open_in(&folder, "manifest.json", false)
        .map_err(|why| refuse(format!("manifest.json: {why}")))?;
    let text = read_whole(&manifest_file, MAX_MANIFEST)
        .map_err(|why| refuse(format!("manifest.json: {why}")))?;
    let manifest_path = path.join("manifest.json");
    let manifest: Manifest = serde_json::from_slice(&text).map_err(|e| Error::Parse {
        path: manifest_path.display().to_string(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    if manifest.format != store::FORMAT {
        return Err(refuse(format!(
            "format {:?}; this bvhview reads {:?}",
            manifest.format,
            store::FORMAT
        )));
    }
    Ok((folder, manifest))
}

/// The manifest's options and its place in the list of takes, checked.
pub(super) fn check_settings(manifest: &Manifest) -> Result<Options, String> {
    let options = manifest.options.options().map_err(|e| e.to_string())?;
    crate::limits::fps(options.fps, false).map_err(|e| e.to_string())?;
    let units = &manifest.options;
    let metres = units.metres_per_unit;
    let units_read = (1e-9..=1e3).contains(&metres)
        && crate::model::stance::Units::of_metres(metres).name == units.units;
    if manifest.options.up != "y" || !units_read {
        return Err(format!(
            "the manifest's up axis or units are not bvhview's (y; metres, or units and their \
             metres_per_unit): {} and {} ({metres} m)",
            units.up, units.units
        ));
    }
    let takes = &manifest.takes;
    if takes
        .first
        .checked_add(takes.count)
        .is_none_or(|end| end > takes.listed)
    {
        return Err(format!(
            "takes {} to {} of a list of {}",
            takes.first,
            takes.first.saturating_add(takes.count),
            takes.listed
        ));
    }
    Ok(options)
}

/// The dataset's own folder, as the user named it.
fn open_folder(path: &Path) -> Result<File, Error> {
    use std::os::unix::fs::OpenOptionsExt;
    let folder = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_DIRECTORY | libc::O_NONBLOCK)
        .open(path)
        .map_err(|e| match e.raw_os_error() {
            Some(libc::ENOTDIR) => Error::usage(format!("{}: not a folder", path.display())),
            _ => Error::io(path, e),
        })?;
    Ok(folder)
}

/// `name` inside `folder`: never through a link, a folder or a regular file as asked.
pub(super) fn open_in(folder: &File, name: &str, want_folder: bool) -> Result<File, String> {
    use std::os::fd::AsRawFd;
    let plain = !name.is_empty() && name != "." && name != ".." && !name.contains('/');
    if !plain {
        return Err(format!(
            "{} is not a plain file name",
            crate::io::error::quoted(name)
        ));
    }
    let c_name = CString::new(Path::new(name).as_os_str().as_bytes())
        .map_err(|_| format!("{} holds a NUL byte", crate::io::error::quoted(name)))?;
    let mut flags = libc::O_RDONLY | libc::O_CLOEXEC | libc::O_NOFOLLOW | libc::O_NONBLOCK;
    if want_folder {
        flags |= libc::O_DIRECTORY;
    }
    // SAFETY: openat reads the NUL-terminated name and the folder's descriptor, which `folder`
    // keeps open for the call; the descriptor returned is new and owned by the File below.
    let fd = unsafe { libc::openat(folder.as_raw_fd(), c_name.as_ptr(), flags) };
    if fd < 0 {
        let error = std::io::Error::last_os_error();
        // SAFETY: a zeroed stat is a valid buffer for fstatat to fill.
        let mut status: libc::stat = unsafe { std::mem::zeroed() };
        // SAFETY: fstatat reads the name and the folder's descriptor (both live for the call)
        // and writes only into `status`.
        let is_link = unsafe {
            libc::fstatat(
                folder.as_raw_fd(),
                c_name.as_ptr(),
                &mut status,
                libc::AT_SYMLINK_NOFOLLOW,
            ) == 0
        } && status.st_mode & libc::S_IFMT == libc::S_IFLNK;
        return Err(match error.raw_os_error() {
            _ if is_link => "a symbolic link, which a dataset never holds".to_string(),
            Some(libc::ENOTDIR) if want_folder => "not a folder".to_string(),
            _ => error.to_string(),
        });
    }
    // SAFETY: `fd` was just returned by openat and is owned by nobody else.
    let file = File::from(unsafe { OwnedFd::from_raw_fd(fd) });
    let kind = file.metadata().map_err(|e| e.to_string())?.file_type();
    match (want_folder, kind.is_dir(), kind.is_file()) {
        (true, true, _) | (false, _, true) => Ok(file),
        (true, _, _) => Err("not a folder".to_string()),
        (false, _, _) => Err("not a regular file".to_string()),
    }
}

/// A whole regular file of at most `most` bytes, its size known before it is read.
pub(super) fn read_whole(file: &File, most: u64) -> Result<Vec<u8>, String> {
    let size = file.metadata().map_err(|e| e.to_string())?.len();
    if size > most {
        return Err(format!("{size} bytes; at most {most} are read"));
    }
    let mut bytes = vec![0u8; size as usize];
    file.read_exact_at(&mut bytes, 0)
        .map_err(|e| e.to_string())?;
    // A file that grew while being read is refused, not read on.
    let mut more = [0u8; 1];
    if file.read_at(&mut more, size).map_err(|e| e.to_string())? != 0 {
        return Err("its size changed while it was read".to_string());
    }
    Ok(bytes)
}
