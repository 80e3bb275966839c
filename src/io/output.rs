//! Files written whole or not at all, safely on a shared machine. The output's folder is found
//! by [`place::walk`] (no link or folder another user controls is followed on the way) and held
//! open; a temporary file is made in it under a random name, exclusively and following no link,
//! and renamed over the output once everything is written. An output that is a symbolic link is
//! written through to its target (`>` in a shell does the same), an existing file keeps its mode
//! and owner, and a FIFO or character device (`-o /dev/stdout`, a named pipe) is written to
//! directly instead of being replaced. An error (or a panic) removes the temporary file. A
//! program that calls [`remove_partials_on_signal`] (the CLI does; a library must not take
//! signals from its host, Python for one) also removes them when it is interrupted or
//! terminated.

use crate::io::error::Error;
use crate::io::parallel::PerProcess;
use crate::io::place::{self, Found, Place, Status};
use std::ffi::{OsStr, OsString};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::os::fd::OwnedFd;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

/// A temporary file or folder being written, for the signal handler: removed relative to the
/// folder it was made in, held open, so a folder renamed meanwhile does not send the removal
/// elsewhere. Only a program that removes them on a signal (the CLI) reads them back.
#[cfg_attr(not(feature = "cli"), allow(dead_code))]
struct Partial {
    /// Its path as walked: how it is told apart from the others, and how a folder is removed.
    path: PathBuf,
    folder: Arc<OwnedFd>,
    name: OsString,
    is_folder: bool,
}

impl Partial {
    #[cfg(feature = "cli")]
    fn remove(&self) {
        let _ = match self.is_folder {
            // std's remove_dir_all follows no link inside the folder.
            true => std::fs::remove_dir_all(&self.path),
            false => place::remove_at(place::folder_as(&self.folder), &self.name, 0),
        };
    }
}

/// The temporary files being written. Each process has its own: a child forked while its
/// parent's thread was writing (Python's `save` releases the GIL) would wait for good for the
/// lock that thread held, and the parent's files are not the child's.
static PARTIAL: PerProcess<Mutex<Vec<Partial>>> = PerProcess::new(|| Mutex::new(Vec::new()));

fn partial() -> std::sync::MutexGuard<'static, Vec<Partial>> {
    PARTIAL.get().lock().unwrap_or_else(PoisonError::into_inner)
}

fn forget_partial(path: &Path) {
    partial().retain(|p| p.path != path);
}

/// A test's switch (no test waits on the clock): with `BVHVIEW_PLANT_PAUSE=output` in its
/// environment, a process that has just made a temporary output (a file or a folder) stops there
/// for good, so that a test can send it a signal at that known point instead of guessing how long
/// the work takes. Only a signal ends the pause.
fn planted_pause() {
    if std::env::var_os("BVHVIEW_PLANT_PAUSE").is_some_and(|point| point == "output") {
        loop {
            std::thread::park();
        }
    }
}

/// Runs `work` (which writes into a folder a [`NewFolder`] made) while no signal cleanup can
/// run: a cleanup that started first keeps it from starting, as the process is ending; one that
/// comes during it waits for it, then removes the folder with everything `work` made.
pub fn in_partial_folder<R>(work: impl FnOnce() -> R) -> R {
    let _held = partial();
    work()
}

/// A folder of outputs (a dataset, `convert DIR`'s takes, `snapshot --frames`' pictures), there
/// whole or not at all, as a file is: it is filled under a temporary name beside `out` and takes
/// the name when [`NewFolder::commit`] is called. An error, a panic or a signal before that
/// removes it. Whatever is written into [`NewFolder::path`] goes through [`in_partial_folder`],
/// so that a signal's cleanup never races with a file being made there.
pub struct NewFolder {
    out: PathBuf,
    /// The folder `out` is in, held open; the temporary folder's name in it; its path.
    parent: Arc<OwnedFd>,
    name: OsString,
    temporary: OsString,
    path: PathBuf,
    committed: bool,
}

impl NewFolder {
    /// Starts the folder `out`, which must not exist or be an empty folder (`refusal` ends the
    /// message that says it does: `a dataset goes into a new (or empty) folder`). As for a file,
    /// nothing another user controls is followed on the way ([`place::walk`]), and an empty
    /// folder of another user's in a shared folder is refused. The temporary folder beside it has
    /// a random name made exclusively (`.OUT.XXXXXX`, `OUT` cut to fit a long name, mode 0700
    /// until it is whole), and a failure names its cause.
    pub fn create(out: &Path, refusal: &str) -> Result<NewFolder, Error> {
        let Place {
            folder,
            folder_path,
            name,
            found,
        } = place::walk(out, out)?;
        match found {
            Found::Nothing => {}
            Found::Folder
                if std::fs::read_dir(folder_path.join(&name))
                    .is_ok_and(|mut d| d.next().is_none()) => {}
            _ => {
                return Err(Error::usage(format!(
                    "{}: already exists; {refusal}",
                    out.display()
                )));
            }
        }
        let parent = Arc::new(folder);
        // Held while the folder is made and listed, as for a file: a signal in between waits
        // for the lock and finds it listed (one that came after the folder appeared and before
        // it was listed left it behind).
        let mut partial = partial();
        let (temporary, ()) = place::make_unique(&temporary_prefix(Some(&name)), "", |name| {
            place::make_folder_at(place::folder_as(&parent), name, 0o700)
        })
        .map_err(|e| Error::output(out, e))?;
        let path = folder_path.join(&temporary);
        partial.push(Partial {
            path: path.clone(),
            folder: Arc::clone(&parent),
            name: temporary.clone(),
            is_folder: true,
        });
        drop(partial);
        planted_pause();
        Ok(NewFolder {
            out: out.to_path_buf(),
            parent,
            name,
            temporary,
            path,
            committed: false,
        })
    }

    /// Where the folder is being filled.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Gives the folder its name: mode 0755, everything in it on the disk (one `syncfs`), renamed
    /// to `out`, and the rename made durable. On an error the temporary folder is removed.
    pub fn commit(mut self) -> Result<(), Error> {
        let parent = place::folder_as(&self.parent);
        let named = in_partial_folder(|| -> io::Result<()> {
            std::fs::set_permissions(&self.path, std::fs::Permissions::from_mode(0o755))?;
            sync_file_system(&self.path)?;
            place::rename_at(parent, &self.temporary, &self.name)?;
            place::sync_folder(parent);
            Ok(())
        });
        forget_partial(&self.path);
        match named {
            Ok(()) => {
                // Renamed: the folder is the output now, not a temporary one to remove.
                self.committed = true;
                Ok(())
            }
            Err(e) => Err(Error::output(&self.out, e)),
        }
    }
}

impl Drop for NewFolder {
    fn drop(&mut self) {
        // Uncommitted: the signal handler forgets it, and it is removed.
        if !self.committed {
            forget_partial(&self.path);
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// Everything written into `folder` reaches the disk before the folder takes its name: one
/// `syncfs` of its file system, rather than an fsync of each of its files (six per dataset group).
fn sync_file_system(folder: &Path) -> io::Result<()> {
    use std::os::fd::AsRawFd;
    let folder = File::open(folder)?;
    // SAFETY: syncfs only reads the descriptor, which `folder` keeps open for the call.
    match unsafe { libc::syncfs(folder.as_raw_fd()) } {
        0 => Ok(()),
        _ => Err(io::Error::last_os_error()),
    }
}

/// On SIGINT, SIGTERM or SIGHUP, every temporary file still being written is removed and the
/// process ends by that signal, as it would have without the cleanup: a shell reports 128 + its
/// number (130 for Ctrl-C, 143 for `kill`, 129 for a closed terminal), and a shell loop around
/// bvhview stops on Ctrl-C. A signal the process started with ignored (`nohup`, a background job
/// of a script) stays ignored.
#[cfg(feature = "cli")]
pub fn remove_partials_on_signal() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let wanted: Vec<i32> = [SIGINT, SIGTERM, SIGHUP]
        .into_iter()
        .filter(|&signal| !ignored_at_start(signal))
        .collect();
    let Ok(mut signals) = signal_hook::iterator::Signals::new(&wanted) else {
        return;
    };
    // The signals arrive on a thread of its own, so it may lock and remove files.
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            // Held to the end: no new temporary file can be made after the cleanup.
            let mut partial = partial();
            for made in partial.drain(..) {
                made.remove();
            }
            let what = match signal {
                SIGINT => "interrupted",
                SIGTERM => "terminated",
                _ => "hung up",
            };
            eprintln!("bvhview: {what}; no output was left half-written");
            // The default action, which ends the process at once: no exit handler runs (the GL
            // libraries' must not while the main thread may still be drawing with them).
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            // SAFETY: ends the process at once, should the default action not have.
            unsafe { libc::_exit(128 + signal) }
        }
    });
}

/// Whether `signal` was ignored when the process started (`nohup` ignores SIGHUP).
#[cfg(feature = "cli")]
fn ignored_at_start(signal: i32) -> bool {
    // SAFETY: sigaction with a null new action only reads the current one into `old`.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        libc::sigaction(signal, std::ptr::null(), &mut old) == 0
            && old.sa_sigaction == libc::SIG_IGN
    }
}

/// An output file being written; [`AtomicFile::commit`] finishes it.
pub struct AtomicFile {
    /// The path as the caller named it, for messages.
    path: PathBuf,
    writer: Option<Writer>,
}

enum Writer {
    /// A FIFO, a device or a link of /proc, opened at the first write: opening a FIFO waits
    /// for its reader, which should not stop a refusal that comes before.
    Pending {
        folder: OwnedFd,
        name: OsString,
        /// Through a link of /proc: followed, and a regular file there truncated (written in
        /// place, as `cp` does). Otherwise no link is followed.
        process_link: bool,
    },
    /// A regular file (or none yet): a temporary file beside it takes its name at the end.
    Replace {
        temporary: BufWriter<File>,
        /// The folder, held open: the temporary file is made, renamed and removed in it.
        folder: Arc<OwnedFd>,
        folder_path: PathBuf,
        temporary_name: OsString,
        name: OsString,
        /// Bytes handed to the file, and how many of them the disk has been asked to take.
        written: u64,
        flushing: u64,
        /// The file being replaced, whose mode and owner the new one keeps.
        old: Option<Status>,
    },
    /// A FIFO or a character device: there is nothing to replace, it is written to.
    Direct(BufWriter<File>),
}

impl AtomicFile {
    /// Writes `bytes` as the whole of `path`: the file takes its name only when complete.
    pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), Error> {
        use std::io::Write;
        let mut out = AtomicFile::create(path)?;
        out.write_all(bytes).map_err(|e| Error::output(path, e))?;
        out.commit()
    }

    /// Starts writing `path` (its folder must exist).
    pub fn create(path: &Path) -> Result<AtomicFile, Error> {
        let Place {
            folder,
            folder_path,
            name,
            found,
        } = place::walk(path, path)?;
        let old = match found {
            Found::ProcessLink | Found::Stream => {
                let process_link = matches!(found, Found::ProcessLink);
                return Ok(AtomicFile {
                    path: path.to_path_buf(),
                    writer: Some(Writer::Pending {
                        folder,
                        name,
                        process_link,
                    }),
                });
            }
            Found::Folder => {
                // As the OS says it (Python raises IsADirectoryError).
                let error = io::Error::new(io::ErrorKind::IsADirectory, "is a folder");
                return Err(Error::output(path, error));
            }
            Found::Other(what) => {
                return Err(Error::usage(format!(
                    "-o {}: is {what}; bvhview writes regular files, FIFOs and character devices",
                    path.display()
                )));
            }
            Found::File(old) => Some(old),
            Found::Nothing => None,
        };
        // A new file gets the mode any new file gets (0666 less the umask); one that replaces
        // another stays private until it takes the old one's mode.
        let mode = if old.is_some() { 0o600 } else { 0o666 };
        let folder = Arc::new(folder);
        // Held while the file is made and listed, so that a signal in between finds it listed
        // (the handler waits for the lock).
        let mut partial = partial();
        let (temporary_name, file) =
            place::make_unique(&temporary_prefix(Some(&name)), ".partial", |name| {
                place::open_at(
                    place::folder_as(&folder),
                    name,
                    libc::O_WRONLY | libc::O_CREAT | libc::O_EXCL | libc::O_NOFOLLOW,
                    mode,
                )
            })
            .map_err(|e| Error::output(path, e))?;
        // Made under the lock, and listed before it is let go.
        partial.push(Partial {
            path: folder_path.join(&temporary_name),
            folder: Arc::clone(&folder),
            name: temporary_name.clone(),
            is_folder: false,
        });
        drop(partial);
        planted_pause();
        Ok(AtomicFile {
            path: path.to_path_buf(),
            writer: Some(Writer::Replace {
                temporary: BufWriter::new(File::from(file)),
                folder,
                folder_path,
                temporary_name,
                name,
                written: 0,
                flushing: 0,
                old,
            }),
        })
    }

    /// The folder a regular file is written in (its temporary file's, beside the output), where
    /// a writer needing room for scratch data keeps it on the output's own disk; `None` for a
    /// FIFO or a device (whose folder, /dev, is no place for files).
    pub fn folder(&self) -> Option<&Path> {
        match &self.writer {
            Some(Writer::Replace { folder_path, .. }) => Some(folder_path),
            _ => None,
        }
    }

    /// Flushes the file and gives it its name (with the old file's mode and owner).
    pub fn commit(mut self) -> Result<(), Error> {
        let path = self.path.clone();
        let failed = |e: io::Error| Error::output(&path, e);
        // Nothing was written to a FIFO or device: opened and closed all the same, so that its
        // reader sees the (empty) output end.
        if matches!(self.writer, Some(Writer::Pending { .. })) {
            self.writer().map_err(&failed)?;
        }
        match self.writer.take().expect("committed once") {
            Writer::Pending { .. } => unreachable!("opened above"),
            Writer::Direct(mut writer) => writer.flush().map_err(failed),
            Writer::Replace {
                temporary,
                folder,
                folder_path,
                temporary_name,
                name,
                old,
                ..
            } => {
                let result = match temporary.into_inner() {
                    Ok(file) => finish(&file, &folder, &temporary_name, &name, old.as_ref()),
                    Err(e) => Err(e.into_error()),
                };
                if result.is_err() {
                    let _ = place::remove_at(place::folder_as(&folder), &temporary_name, 0);
                }
                forget_partial(&folder_path.join(&temporary_name));
                result.map_err(failed)
            }
        }
    }
}

/// The start of a temporary name beside an output named `name` (a file, or a dataset's folder):
/// `.NAME.`, the name cut to 200 bytes so that the whole temporary name (with six random
/// characters and a suffix) stays within the 255 bytes a name may have.
pub fn temporary_prefix(name: Option<&OsStr>) -> String {
    let name = name.map_or("out".into(), |n| n.to_string_lossy());
    let mut cut = name.len().min(200);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!(".{}.", &name[..cut])
}

/// Whether [`AtomicFile::create`] writes `path` where it is rather than replacing it: a FIFO, a
/// character device, or a link of /proc (`/dev/stdout`). Its name says nothing of its format.
#[cfg(feature = "cli")]
pub fn written_in_place(path: &Path) -> bool {
    place::walk(path, path)
        .is_ok_and(|place| matches!(place.found, Found::ProcessLink | Found::Stream))
}

/// Syncs, takes the old file's owner and mode, renames over the output and syncs its folder.
fn finish(
    file: &File,
    folder: &OwnedFd,
    temporary: &OsStr,
    name: &OsStr,
    old: Option<&Status>,
) -> io::Result<()> {
    use std::os::unix::fs::MetadataExt;
    file.sync_all()?;
    if let Some(old) = old {
        let ours = file.metadata()?;
        // The set-id bits are not kept: the new content is not the program they were set for.
        let mode = old.mode & 0o1777;
        if (ours.uid(), ours.gid()) != (old.uid, old.gid) {
            // Only root may give a file away; anyone else keeps what the file would get
            // anyway, as `sed -i` does.
            match std::os::unix::fs::fchown(file, Some(old.uid), Some(old.gid)) {
                Err(e) if e.kind() == io::ErrorKind::PermissionDenied => {}
                other => other?,
            }
        }
        // After the owner: a change of owner clears the set-id bits.
        file.set_permissions(std::fs::Permissions::from_mode(mode))?;
    }
    let folder = place::folder_as(folder);
    place::rename_at(folder, temporary, name)?;
    // The rename is durable once the folder is: a crash now leaves the old or the new file.
    place::sync_folder(folder);
    Ok(())
}

impl AtomicFile {
    /// The writer, a pending FIFO or device opened now.
    fn writer(&mut self) -> io::Result<&mut Writer> {
        let writer = self.writer.as_mut().expect("not committed");
        if let Writer::Pending {
            folder,
            name,
            process_link,
        } = writer
        {
            let follow = if *process_link { 0 } else { libc::O_NOFOLLOW };
            let file = File::from(place::open_at(
                place::folder_as(folder),
                name,
                libc::O_WRONLY | follow,
                0,
            )?);
            if *process_link && file.metadata()?.is_file() {
                file.set_len(0)?;
            }
            *writer = Writer::Direct(BufWriter::new(file));
        }
        Ok(writer)
    }
}

/// How much of a file being replaced is written before the disk is asked to take it.
const WRITEBACK_STEP: u64 = 8 << 20;

/// Asks the disk to take `range` of `file` now, without waiting: the `fsync` before the rename
/// then finds most of a large output on disk already, instead of writing all of it while the
/// program waits (a quarter of a second for the 228 MB of a big positions export).
pub(crate) fn start_writeback(file: &File, range: std::ops::Range<u64>) {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        // SAFETY: a hint on an open descriptor; it reads and writes no memory of ours. An
        // error changes nothing: the fsync writes whatever is left.
        unsafe {
            libc::sync_file_range(
                file.as_raw_fd(),
                range.start as i64,
                (range.end - range.start) as i64,
                libc::SYNC_FILE_RANGE_WRITE,
            )
        };
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (file, range);
}

impl Write for AtomicFile {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        match self.writer()? {
            Writer::Replace {
                temporary,
                written,
                flushing,
                ..
            } => {
                let n = temporary.write(bytes)?;
                *written += n as u64;
                if *written - *flushing >= WRITEBACK_STEP {
                    temporary.flush()?;
                    start_writeback(temporary.get_ref(), *flushing..*written);
                    *flushing = *written;
                }
                Ok(n)
            }
            Writer::Direct(writer) => writer.write(bytes),
            Writer::Pending { .. } => unreachable!("opened by writer()"),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self.writer()? {
            Writer::Replace { temporary, .. } => temporary.flush(),
            Writer::Direct(writer) => writer.flush(),
            Writer::Pending { .. } => unreachable!("opened by writer()"),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Uncommitted: the temporary file is removed.
        if let Some(Writer::Replace {
            folder,
            folder_path,
            temporary_name,
            ..
        }) = self.writer.take()
        {
            let _ = place::remove_at(place::folder_as(&folder), &temporary_name, 0);
            forget_partial(&folder_path.join(&temporary_name));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::place::my_uid;
    use std::os::unix::fs::{FileTypeExt, MetadataExt};

    fn folder(name: &str) -> PathBuf {
        // A folder of its own, kept: a process id comes round again, a tempfile name does not.
        tempfile::Builder::new()
            .prefix(&format!("bvhview-{name}-"))
            .tempdir()
            .unwrap()
            .keep()
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

    /// The old temporary name was `.NAME.PID.partial`, created by following whatever was there. A
    /// link planted under that name (or any name) is never written.
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
            Writer::Replace { temporary_name, .. } => temporary_name.clone(),
            Writer::Direct(_) | Writer::Pending { .. } => unreachable!(),
        };
        assert_ne!(names(&a), names(&b));
        drop((a, b));
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// The mode of the file replaced is kept; a link is written through.
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

    /// The owner of the file replaced is kept too: only root can check it (only root may give files
    /// away).
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

    /// A name of 240 bytes (`touch` makes it): the temporary name is cut to fit.
    #[test]
    fn a_long_output_name_is_written() {
        let dir = folder("long-name");
        let path = dir.join(format!("{}.csv", "a".repeat(240)));
        write(&path, b"long").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"long");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// In a sticky shared folder (/tmp), root does not replace a file another user planted (it
    /// would hand its output, set-id bits and all, to that user), nor follow a planted folder
    /// link; the set-id bits of a file it may replace are not kept.
    #[test]
    fn root_does_not_replace_what_another_user_planted_in_a_shared_folder() {
        if my_uid() != 0 {
            eprintln!("not root: another user's files need root to make");
            return;
        }
        let dir = folder("sticky");
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o1777)).unwrap();
        let planted = dir.join("theirs.csv");
        std::fs::write(&planted, b"theirs").unwrap();
        std::fs::set_permissions(&planted, std::fs::Permissions::from_mode(0o4755)).unwrap();
        std::os::unix::fs::chown(&planted, Some(1234), Some(1234)).unwrap();
        let error = write(&planted, b"root's").unwrap_err().to_string();
        assert!(
            error.contains("belongs to another user (uid 1234)"),
            "{error}"
        );
        assert_eq!(std::fs::read(&planted).unwrap(), b"theirs");
        let elsewhere = folder("sticky-target");
        let link = dir.join("dl");
        std::os::unix::fs::symlink(&elsewhere, &link).unwrap();
        std::os::unix::fs::lchown(&link, Some(1234), Some(1234)).unwrap();
        let error = write(&link.join("x.csv"), b"x").unwrap_err().to_string();
        assert!(
            error.contains("a symbolic link another user (uid 1234) made"),
            "{error}"
        );
        assert!(!elsewhere.join("x.csv").exists());
        // Root's own set-uid file: replaced, without the bit.
        let own = dir.join("own.csv");
        std::fs::write(&own, b"old").unwrap();
        std::fs::set_permissions(&own, std::fs::Permissions::from_mode(0o4755)).unwrap();
        write(&own, b"new").unwrap();
        assert_eq!(std::fs::metadata(&own).unwrap().mode() & 0o7777, 0o755);
        std::fs::remove_dir_all(dir).unwrap();
        std::fs::remove_dir_all(elsewhere).unwrap();
    }

    /// A character device is written to, not replaced.
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

    /// Saves of one path at once each leave a whole file.
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
