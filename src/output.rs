//! Files written whole or not at all, safely on a shared machine. The crate `tempfile` makes the
//! temporary file beside the output (a random name, created exclusively, so nobody can plant a
//! symbolic link under it), and renames it over the output once everything is written. What
//! `tempfile` does not do is here: an output that is a symbolic link is written through to its
//! target (`>` in a shell does the same), an existing file keeps its mode and owner, and a FIFO
//! or character device (`-o /dev/stdout`, a named pipe) is written to directly instead of being
//! replaced. An error (or a panic) removes the temporary file. A program that calls
//! [`remove_partials_on_signal`] (the CLI does; a library must not take signals from its host,
//! Python for one) also removes them when it is interrupted or terminated.

use crate::error::Error;
use crate::parallel::PerProcess;
use std::fs::{File, Metadata};
use std::io::{self, BufWriter, Write};
use std::os::unix::fs::{FileTypeExt, MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};
use tempfile::NamedTempFile;

/// The temporary files being written, for the signal handler. Each process has its own: a child
/// forked while its parent's thread was writing (Python's `save` releases the GIL) would wait
/// for good for the lock that thread held, and the parent's files are not the child's.
static PARTIAL: PerProcess<Mutex<Vec<PathBuf>>> = PerProcess::new(|| Mutex::new(Vec::new()));

fn partial() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PARTIAL.get().lock().unwrap_or_else(PoisonError::into_inner)
}

/// On SIGINT, SIGTERM or SIGHUP, every temporary file still being written is removed and the
/// process exits with 128 + the signal's number, as a shell reports a command a signal ended
/// (130 for Ctrl-C, 143 for `kill`, 129 for a closed terminal).
pub fn remove_partials_on_signal() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    // The signals arrive on a thread of its own, so it may lock and remove files.
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let left: Vec<PathBuf> = partial().drain(..).collect();
            for path in &left {
                let _ = std::fs::remove_file(path);
            }
            let what = match signal {
                SIGINT => "interrupted",
                SIGTERM => "terminated",
                _ => "hung up",
            };
            eprintln!("bvhview: {what}; no output was left half-written");
            // `_exit`, not `process::exit`: the exit handlers of the GL libraries must not run
            // while the main thread may still be drawing with them (that crashed with SIGSEGV).
            // SAFETY: ends the process at once; nothing after it runs.
            unsafe { libc::_exit(128 + signal) }
        }
    });
}

/// An output file being written; [`AtomicFile::commit`] finishes it.
pub struct AtomicFile {
    /// The path as the caller named it, for messages.
    path: PathBuf,
    writer: Option<Writer>,
}

enum Writer {
    /// A regular file (or none yet): a temporary file beside it takes its name at the end.
    Replace {
        temporary: BufWriter<NamedTempFile>,
        /// Where the rename goes: the output, or the file its symbolic links lead to.
        target: PathBuf,
        /// The file being replaced, whose mode and owner the new one keeps.
        old: Option<Box<Metadata>>,
    },
    /// A FIFO or a character device: there is nothing to replace, it is written to.
    Direct(BufWriter<File>),
}

impl AtomicFile {
    /// Starts writing `path` (its folder must exist).
    pub fn create(path: &Path) -> Result<AtomicFile, Error> {
        let target = follow_links(path)?;
        let old = match std::fs::metadata(&target) {
            Ok(metadata) => Some(metadata),
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(Error::output(path, e)),
        };
        let writer = match &old {
            Some(m) if m.file_type().is_fifo() || m.file_type().is_char_device() => {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&target)
                    .map_err(|e| Error::output(path, e))?;
                Writer::Direct(BufWriter::new(file))
            }
            Some(m) if m.is_dir() => {
                // As the OS says it (Python raises IsADirectoryError).
                let error = io::Error::new(io::ErrorKind::IsADirectory, "is a folder");
                return Err(Error::output(path, error));
            }
            Some(m) if !m.is_file() => {
                let what = if m.file_type().is_block_device() {
                    "a block device"
                } else {
                    "a socket"
                };
                return Err(Error::Usage(format!(
                    "-o {}: is {what}; bvhview writes regular files, FIFOs and character devices",
                    path.display()
                )));
            }
            _ => {
                let folder = match target.parent() {
                    Some(folder) if !folder.as_os_str().is_empty() => folder,
                    _ => Path::new("."),
                };
                let name = target
                    .file_name()
                    .map_or("out".into(), |n| n.to_string_lossy());
                // A new file gets the mode any new file gets (0666 less the umask); one that
                // replaces another stays private until it takes the old one's mode.
                let mode = if old.is_some() { 0o600 } else { 0o666 };
                // Held while the file is made and listed, so that a signal in between finds it
                // listed (the handler waits for the lock).
                let mut partial = partial();
                let temporary = tempfile::Builder::new()
                    .prefix(&format!(".{name}."))
                    .suffix(".partial")
                    .permissions(std::fs::Permissions::from_mode(mode))
                    .tempfile_in(folder)
                    .map_err(|e| Error::output(path, e))?;
                partial.push(temporary.path().to_path_buf());
                drop(partial);
                Writer::Replace {
                    temporary: BufWriter::new(temporary),
                    target,
                    old: old.map(Box::new),
                }
            }
        };
        Ok(AtomicFile {
            path: path.to_path_buf(),
            writer: Some(writer),
        })
    }

    /// Flushes the file and gives it its name (with the old file's mode and owner).
    pub fn commit(mut self) -> Result<(), Error> {
        let path = self.path.clone();
        let failed = |e: io::Error| Error::output(&path, e);
        match self.writer.take().expect("committed once") {
            Writer::Direct(mut writer) => writer.flush().map_err(failed),
            Writer::Replace {
                temporary,
                target,
                old,
            } => {
                let temporary = temporary.into_inner().map_err(|e| failed(e.into_error()))?;
                let kept = partial_path(&temporary);
                let result = finish(temporary, &target, old.as_deref()).map_err(failed);
                partial().retain(|p| *p != kept);
                result
            }
        }
    }
}

fn partial_path(temporary: &NamedTempFile) -> PathBuf {
    temporary.path().to_path_buf()
}

/// Syncs, takes the old file's owner and mode, renames over the target and syncs its folder.
/// On an error the temporary file is dropped, which removes it.
fn finish(temporary: NamedTempFile, target: &Path, old: Option<&Metadata>) -> io::Result<()> {
    let file = temporary.as_file();
    file.sync_all()?;
    if let Some(old) = old {
        let ours = file.metadata()?;
        if (ours.uid(), ours.gid()) != (old.uid(), old.gid()) {
            // Only root may give a file away; anyone else keeps what the file would get
            // anyway, as `sed -i` does.
            match std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid())) {
                Err(e) if e.kind() == io::ErrorKind::PermissionDenied => {}
                other => other?,
            }
        }
        // After the owner: a change of owner clears the set-id bits.
        file.set_permissions(std::fs::Permissions::from_mode(old.mode() & 0o7777))?;
    }
    temporary.persist(target).map_err(|e| e.error)?;
    if let Some(folder) = target.parent().filter(|f| !f.as_os_str().is_empty())
        && let Ok(folder) = File::open(folder)
    {
        // The rename is durable once the folder is: a crash now leaves the old or the new file.
        let _ = folder.sync_all();
    }
    Ok(())
}

/// The file `path` names once its symbolic links are followed. A link to nothing is refused
/// (`cp` does not write through one either), and so is a link that another user planted in a
/// sticky world-writable folder such as /tmp, as Linux's `fs.protected_symlinks` refuses it.
fn follow_links(path: &Path) -> Result<PathBuf, Error> {
    let mut current = path.to_path_buf();
    // As many links as the kernel follows (ELOOP past 40).
    for _ in 0..40 {
        let metadata = match std::fs::symlink_metadata(&current) {
            Ok(metadata) => metadata,
            Err(e) if e.kind() == io::ErrorKind::NotFound && current != path => {
                return Err(Error::Usage(format!(
                    "-o {}: is a symbolic link to {}, which does not exist",
                    path.display(),
                    current.display()
                )));
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(current),
            Err(e) => return Err(Error::output(path, e)),
        };
        if !metadata.file_type().is_symlink() {
            return Ok(current);
        }
        let folder = match current.parent() {
            Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
            _ => PathBuf::from("."),
        };
        refuse_planted_link(path, &current, &metadata, &folder)?;
        let link = std::fs::read_link(&current).map_err(|e| Error::output(path, e))?;
        current = folder.join(link);
    }
    Err(Error::Usage(format!(
        "-o {}: too many levels of symbolic links",
        path.display()
    )))
}

/// `fs.protected_symlinks`: in a sticky, world-writable folder, a link is followed only if it
/// belongs to whoever follows it or to the folder's owner.
fn refuse_planted_link(
    path: &Path,
    link: &Path,
    metadata: &Metadata,
    folder: &Path,
) -> Result<(), Error> {
    let folder = std::fs::metadata(folder).map_err(|e| Error::output(path, e))?;
    let sticky_and_shared = folder.mode() & 0o1002 == 0o1002;
    // SAFETY: geteuid has no preconditions and cannot fail.
    let me = unsafe { libc::geteuid() };
    if sticky_and_shared && metadata.uid() != me && metadata.uid() != folder.uid() {
        return Err(Error::Usage(format!(
            "-o {}: {} is a symbolic link another user (uid {}) made in a shared folder; \
             not followed",
            path.display(),
            link.display(),
            metadata.uid()
        )));
    }
    Ok(())
}

impl Write for AtomicFile {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        match self.writer.as_mut().expect("not committed") {
            Writer::Replace { temporary, .. } => temporary.write(bytes),
            Writer::Direct(writer) => writer.write(bytes),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self.writer.as_mut().expect("not committed") {
            Writer::Replace { temporary, .. } => temporary.flush(),
            Writer::Direct(writer) => writer.flush(),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Uncommitted: dropping the temporary file removes it (tempfile's own Drop).
        if let Some(Writer::Replace { temporary, .. }) = self.writer.take() {
            let kept = partial_path(temporary.get_ref());
            drop(temporary.into_parts().0);
            partial().retain(|p| *p != kept);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("bvhview-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn write(path: &Path, bytes: &[u8]) -> Result<(), Error> {
        let mut file = AtomicFile::create(path)?;
        file.write_all(bytes).unwrap();
        file.commit()
    }

    #[test]
    fn an_output_appears_whole_or_not_at_all() {
        let dir = folder("atomic");
        let path = dir.join("out.csv");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"half").unwrap();
        assert!(!path.exists(), "nothing under the name while writing");
        drop(file);
        assert!(!path.exists());
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            0,
            "no temporary left"
        );
        write(&path, b"whole").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"whole");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 26, row 1: the old temporary name was `.NAME.PID.partial`, created by following
    /// whatever was there. A link planted under that name (or any name) is never written.
    #[test]
    fn a_link_planted_under_the_old_temporary_name_is_not_followed() {
        let dir = folder("planted");
        let victim = dir.join("victim");
        std::fs::write(&victim, b"precious").unwrap();
        let planted = dir.join(format!(".out.csv.{}.partial", std::process::id()));
        std::os::unix::fs::symlink(&victim, &planted).unwrap();
        let path = dir.join("out.csv");
        write(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        // Two outputs being written at once have different temporary names.
        let (a, b) = (
            AtomicFile::create(&path).unwrap(),
            AtomicFile::create(&path).unwrap(),
        );
        let names = |f: &AtomicFile| match f.writer.as_ref().unwrap() {
            Writer::Replace { temporary, .. } => temporary.get_ref().path().to_path_buf(),
            Writer::Direct(_) => unreachable!(),
        };
        assert_ne!(names(&a), names(&b));
        drop((a, b));
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 26, row 9: the mode of the file replaced is kept; a link is written through.
    #[test]
    fn an_existing_file_keeps_its_mode_and_a_link_is_written_through() {
        let dir = folder("keep");
        let path = dir.join("out.csv");
        std::fs::write(&path, b"old").unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).unwrap();
        write(&path, b"new").unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().mode() & 0o7777, 0o600);
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink("out.csv", &link).unwrap();
        write(&link, b"through").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"through");
        assert_eq!(std::fs::metadata(&path).unwrap().mode() & 0o7777, 0o640);
        // A link to nothing is refused, and nothing is created.
        let dangling = dir.join("dangling.csv");
        std::os::unix::fs::symlink("missing.csv", &dangling).unwrap();
        let error = write(&dangling, b"x").unwrap_err().to_string();
        assert!(error.contains("which does not exist"), "{error}");
        assert!(!dir.join("missing.csv").exists());
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 26, row 9, the owner: only root can check it (only root may give files away).
    #[test]
    fn an_existing_file_keeps_its_owner_when_root_writes_it() {
        // SAFETY: geteuid has no preconditions.
        if unsafe { libc::geteuid() } != 0 {
            eprintln!("not root: the owner check needs root");
            return;
        }
        let dir = folder("owner");
        let path = dir.join("out.csv");
        std::fs::write(&path, b"old").unwrap();
        std::os::unix::fs::chown(&path, Some(1234), Some(2345)).unwrap();
        write(&path, b"new").unwrap();
        let metadata = std::fs::metadata(&path).unwrap();
        assert_eq!((metadata.uid(), metadata.gid()), (1234, 2345));
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Issue 26, row 3: a character device is written to, not replaced.
    #[test]
    fn a_character_device_is_written_to() {
        write(Path::new("/dev/null"), b"gone").unwrap();
        assert!(
            std::fs::metadata("/dev/null")
                .unwrap()
                .file_type()
                .is_char_device()
        );
        let error = write(Path::new("/tmp"), b"x").unwrap_err().to_string();
        assert!(error.contains("is a folder"), "{error}");
    }

    /// Issue 26, row 2: saves of one path at once each leave a whole file.
    #[test]
    fn concurrent_writes_of_one_path_each_leave_a_whole_file() {
        let dir = folder("concurrent");
        let path = dir.join("out.csv");
        std::thread::scope(|scope| {
            for thread in 0..4u8 {
                let path = &path;
                scope.spawn(move || {
                    for _ in 0..50 {
                        write(path, &[thread; 100_000]).unwrap();
                        let bytes = std::fs::read(path).unwrap();
                        assert_eq!(bytes.len(), 100_000);
                        assert!(bytes.iter().all(|&b| b == bytes[0]), "one writer's bytes");
                    }
                });
            }
        });
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary left"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
