//! Where an output goes, found one name at a time from an open folder, as the kernel walks a
//! path, with the rules a program that may run as root on a shared machine needs:
//!
//! - a symbolic link that another user made in a sticky shared folder (/tmp) is not followed,
//!   wherever it stands on the way and however the way is reached (through the user's own
//!   link, through `/proc/self/cwd`, by a relative path), as Linux's `fs.protected_symlinks`;
//! - a folder another user owns in a sticky shared folder is not written into, nor walked
//!   through: its owner could swap what is in it while bvhview writes;
//! - the folder found is held open ([`Place::folder`]): what is made there afterwards is made
//!   relative to it, with no link followed, whatever is renamed on the way meanwhile.
//!
//! std has no `openat`; the calls are libc's, each with its `SAFETY:` reason.

use crate::io::error::Error;
use std::ffi::{CString, OsStr, OsString};
use std::io;
use std::os::fd::{AsRawFd, BorrowedFd, FromRawFd, OwnedFd};
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::{Component, Path, PathBuf};

/// As many links as the kernel follows in one path (ELOOP past 40).
const MAX_LINKS: usize = 40;

/// Who owns a file and its mode bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Status {
    /// The owner's user id.
    pub uid: u32,
    /// The owner's group id.
    pub gid: u32,
    /// The type and permission bits (`st_mode`).
    pub mode: u32,
}

impl Status {
    fn kind(&self) -> u32 {
        self.mode & libc::S_IFMT
    }

    /// A sticky folder anyone may create files in (/tmp).
    fn sticky_and_shared(&self) -> bool {
        self.mode & 0o1002 == 0o1002
    }
}

/// What the output's name holds now.
#[derive(Debug)]
pub enum Found {
    /// Nothing: the output is new.
    Nothing,
    /// A regular file, replaced by the output.
    File(Status),
    /// A FIFO or a character device: written to, not replaced.
    Stream,
    /// A folder.
    Folder,
    /// A block device or a socket, named so in a message.
    Other(&'static str),
    /// A link of /proc (`/proc/self/fd/1`, where `/dev/stdout` leads), which names an open file
    /// rather than a path: opened as named, the kernel following it to whatever is open there.
    ProcessLink,
}

/// An output's place: its folder, held open, and its name in that folder.
#[derive(Debug)]
pub struct Place {
    /// The folder, opened with `O_PATH`: every file made for the output is made relative to it.
    pub folder: OwnedFd,
    /// The folder's path as walked (links replaced by where they lead), for messages and for
    /// work done by path inside a folder bvhview made itself.
    pub folder_path: PathBuf,
    /// The output's name in the folder.
    pub name: OsString,
    /// What the name holds now.
    pub found: Found,
}

enum Step {
    Root,
    Up,
    Name(OsString),
}

/// The steps of `path` in reverse, so that the next one is popped from the end.
fn steps_reversed(path: &Path) -> Vec<Step> {
    let mut steps: Vec<Step> = path
        .components()
        .filter_map(|c| match c {
            Component::RootDir | Component::Prefix(_) => Some(Step::Root),
            Component::CurDir => None,
            Component::ParentDir => Some(Step::Up),
            Component::Normal(name) => Some(Step::Name(name.to_os_string())),
        })
        .collect();
    steps.reverse();
    steps
}

fn c_name(name: &OsStr) -> io::Result<CString> {
    CString::new(name.as_bytes()).map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))
}

/// `openat(folder, name, flags)`, the descriptor closed on exec.
pub fn open_at(folder: BorrowedFd, name: &OsStr, flags: i32, mode: u32) -> io::Result<OwnedFd> {
    let name = c_name(name)?;
    // SAFETY: `name` is a NUL-terminated string alive for the call; `folder` is an open
    // descriptor borrowed for the call. The result is checked before it is owned.
    let fd = unsafe {
        libc::openat(
            folder.as_raw_fd(),
            name.as_ptr(),
            flags | libc::O_CLOEXEC,
            mode as libc::c_uint,
        )
    };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: `fd` was just returned by openat and is owned by nobody else.
    Ok(unsafe { OwnedFd::from_raw_fd(fd) })
}

fn open_root(absolute: bool) -> io::Result<OwnedFd> {
    let start = if absolute { c"/" } else { c"." };
    // SAFETY: a constant NUL-terminated path; the result is checked before it is owned.
    let fd = unsafe {
        libc::open(
            start.as_ptr(),
            libc::O_PATH | libc::O_DIRECTORY | libc::O_CLOEXEC,
        )
    };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: `fd` was just returned by open and is owned by nobody else.
    Ok(unsafe { OwnedFd::from_raw_fd(fd) })
}

/// The status of an open descriptor (an `O_PATH` one too, a link's included).
pub fn status_of(fd: BorrowedFd) -> io::Result<Status> {
    // SAFETY: fstat writes only into `stat`, a zeroed plain-data struct it fully owns.
    let mut stat: libc::stat = unsafe { std::mem::zeroed() };
    // SAFETY: `fd` is open for the call; `stat` is a valid place for the result.
    if unsafe { libc::fstat(fd.as_raw_fd(), &mut stat) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(Status {
        uid: stat.st_uid,
        gid: stat.st_gid,
        mode: stat.st_mode,
    })
}

/// What the link opened as `link` (with `O_PATH | O_NOFOLLOW`) says.
fn read_link(link: BorrowedFd) -> io::Result<PathBuf> {
    let mut buffer = vec![0u8; 256];
    loop {
        // SAFETY: `buffer` has `buffer.len()` writable bytes; the empty name reads the link
        // `link` itself is open on.
        let n = unsafe {
            libc::readlinkat(
                link.as_raw_fd(),
                c"".as_ptr(),
                buffer.as_mut_ptr().cast(),
                buffer.len(),
            )
        };
        if n < 0 {
            return Err(io::Error::last_os_error());
        }
        let n = n as usize;
        if n < buffer.len() {
            buffer.truncate(n);
            return Ok(PathBuf::from(OsString::from_vec(buffer)));
        }
        // Cut short: a longer buffer (a link holds at most PATH_MAX bytes).
        if buffer.len() >= 1 << 16 {
            return Err(io::Error::from_raw_os_error(libc::ENAMETOOLONG));
        }
        buffer.resize(buffer.len() * 4, 0);
    }
}

/// Whether `folder` is in /proc, whose links name open files rather than paths.
fn in_proc(folder: BorrowedFd) -> bool {
    // SAFETY: fstatfs writes only into `fs`, a zeroed plain-data struct it fully owns.
    let mut fs: libc::statfs = unsafe { std::mem::zeroed() };
    // SAFETY: `folder` is open for the call; `fs` is a valid place for the result.
    let read = unsafe { libc::fstatfs(folder.as_raw_fd(), &mut fs) } == 0;
    read && fs.f_type == libc::PROC_SUPER_MAGIC
}

pub(crate) fn my_uid() -> u32 {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() }
}

/// Whether a file of `owner` in a folder of status `folder` is another user's plant: the folder
/// is sticky and shared, and the file belongs to neither whoever writes nor the folder's owner.
pub fn planted(owner: u32, folder: &Status) -> bool {
    folder.sticky_and_shared() && owner != my_uid() && owner != folder.uid
}

/// Walks `path` to the output's place; `shown` is the path as the user named it, for messages.
/// Every folder on the way must exist.
pub fn walk(path: &Path, shown: &Path) -> Result<Place, Error> {
    let mut walker = Walker::start(path, shown)?;
    while let Some(step) = walker.todo.pop() {
        match step {
            Step::Root => walker.root()?,
            Step::Up => walker.up()?,
            Step::Name(name) => {
                if let Some(found) = walker.name(&name)? {
                    return Ok(walker.place(name, found));
                }
            }
        }
    }
    Err(not_a_name(shown))
}

/// Where the walk of an output's path is: the steps left (a link's target added as it is
/// met), the folder reached (open, with its status and its path as the user would write it),
/// the links followed so far, and the link the last name was reached through, for the message
/// when it leads nowhere.
struct Walker<'a> {
    shown: &'a Path,
    todo: Vec<Step>,
    folder: OwnedFd,
    folder_status: Status,
    folder_path: PathBuf,
    links: usize,
    last_link: Option<PathBuf>,
}

impl<'a> Walker<'a> {
    /// An I/O error on the way, said of the output.
    fn failed(&self, e: io::Error) -> Error {
        Error::output(self.shown, e)
    }

    /// At the start of `path`: `/` for an absolute path, else the current folder.
    fn start(path: &Path, shown: &'a Path) -> Result<Walker<'a>, Error> {
        let failed = |e: io::Error| Error::output(shown, e);
        let absolute = path.is_absolute();
        let folder = open_root(absolute).map_err(failed)?;
        let folder_status = status_of(folder_as(&folder)).map_err(failed)?;
        Ok(Walker {
            shown,
            todo: steps_reversed(path),
            folder,
            folder_status,
            folder_path: PathBuf::from(if absolute { "/" } else { "" }),
            links: 0,
            last_link: None,
        })
    }

    /// A step to `/` (a link's absolute target).
    fn root(&mut self) -> Result<(), Error> {
        self.folder = open_root(true).map_err(|e| self.failed(e))?;
        self.folder_status = status_of(folder_as(&self.folder)).map_err(|e| self.failed(e))?;
        self.folder_path = PathBuf::from("/");
        Ok(())
    }

    /// A step up, `..`, to the folder's parent.
    fn up(&mut self) -> Result<(), Error> {
        self.folder = open_at(
            folder_as(&self.folder),
            OsStr::new(".."),
            libc::O_PATH | libc::O_DIRECTORY,
            0,
        )
        .map_err(|e| self.failed(e))?;
        self.folder_status = status_of(folder_as(&self.folder)).map_err(|e| self.failed(e))?;
        match self.folder_path.components().next_back() {
            Some(Component::Normal(_)) => {
                self.folder_path.pop();
            }
            Some(Component::RootDir) => {}
            _ => self.folder_path.push(".."),
        }
        Ok(())
    }

    /// A step to `name` in the folder reached: a link is followed (its target's steps added),
    /// a folder entered; the last name is what the walk finds (`Some`), unless it is a link.
    /// Nothing another user controls in a shared folder is followed, entered or replaced.
    fn name(&mut self, name: &OsStr) -> Result<Option<Found>, Error> {
        let shown = self.shown;
        let last = self.todo.is_empty();
        let here = self.folder_path.join(name);
        let opened = open_at(
            folder_as(&self.folder),
            name,
            libc::O_PATH | libc::O_NOFOLLOW,
            0,
        );
        let entry = match opened {
            Err(e) if e.kind() == io::ErrorKind::NotFound && last => {
                if let Some(link) = &self.last_link {
                    return Err(Error::usage(format!(
                        "-o {}: is a symbolic link to {}, which does not exist",
                        shown.display(),
                        link.display()
                    )));
                }
                return Ok(Some(Found::Nothing));
            }
            Err(e) => return Err(self.failed(e)),
            Ok(entry) => entry,
        };
        let status = status_of(folder_as(&entry)).map_err(|e| self.failed(e))?;
        match status.kind() {
            libc::S_IFLNK => {
                if last && in_proc(folder_as(&self.folder)) {
                    return Ok(Some(Found::ProcessLink));
                }
                self.link(&entry, &status, &here, last)?;
                Ok(None)
            }
            libc::S_IFDIR => {
                if planted(status.uid, &self.folder_status) {
                    return Err(Error::usage(format!(
                        "-o {}: {} is a folder another user (uid {}) owns in a shared folder; \
                         not written into",
                        shown.display(),
                        here.display(),
                        status.uid
                    )));
                }
                if last {
                    return Ok(Some(Found::Folder));
                }
                self.folder = entry;
                self.folder_status = status;
                self.folder_path = here;
                Ok(None)
            }
            kind if last => {
                let found = match kind {
                    libc::S_IFREG => Found::File(status),
                    libc::S_IFIFO | libc::S_IFCHR => Found::Stream,
                    libc::S_IFBLK => Found::Other("a block device"),
                    _ => Found::Other("a socket"),
                };
                if matches!(found, Found::File(_) | Found::Stream)
                    && planted(status.uid, &self.folder_status)
                {
                    return Err(Error::usage(format!(
                        "-o {}: belongs to another user (uid {}) in a shared folder; not replaced",
                        shown.display(),
                        status.uid
                    )));
                }
                Ok(Some(found))
            }
            _ => Err(self.failed(io::Error::from_raw_os_error(libc::ENOTDIR))),
        }
    }

    /// A symbolic link met at `here` (`entry`, of `status`): followed, its target's steps next,
    /// unless another user planted it in a shared folder or there are too many levels.
    fn link(
        &mut self,
        entry: &OwnedFd,
        status: &Status,
        here: &Path,
        last: bool,
    ) -> Result<(), Error> {
        let shown = self.shown;
        if planted(status.uid, &self.folder_status) {
            return Err(Error::usage(format!(
                "-o {}: {} is a symbolic link another user (uid {}) made in a shared \
                 folder; not followed",
                shown.display(),
                here.display(),
                status.uid
            )));
        }
        self.links += 1;
        if self.links > MAX_LINKS {
            return Err(Error::usage(format!(
                "-o {}: too many levels of symbolic links",
                shown.display()
            )));
        }
        let target = read_link(folder_as(entry)).map_err(|e| self.failed(e))?;
        if last {
            self.last_link = Some(self.folder_path.join(&target));
        }
        self.todo.extend(steps_reversed(&target));
        // A link to "." or "/" leaves no name: the folder it leads to is the last step.
        if last && self.todo.is_empty() {
            return Err(not_a_name(shown));
        }
        Ok(())
    }

    /// The walk's end: `name` in the folder reached, and what it is.
    fn place(self, name: OsString, found: Found) -> Place {
        Place {
            folder: self.folder,
            folder_path: dot_if_empty(self.folder_path),
            name,
            found,
        }
    }
}

fn not_a_name(shown: &Path) -> Error {
    Error::usage(format!(
        "-o {}: names a folder, not a file or folder to make in it",
        shown.display()
    ))
}

fn dot_if_empty(path: PathBuf) -> PathBuf {
    if path.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        path
    }
}

/// Borrows an owned descriptor (a shorthand).
pub fn folder_as(fd: &OwnedFd) -> BorrowedFd<'_> {
    use std::os::fd::AsFd;
    fd.as_fd()
}

/// A name no file in the folder has yet: `prefix`, six random letters and digits, `suffix`.
pub fn random_name(prefix: &str, suffix: &str) -> OsString {
    const LETTERS: &[u8] = b"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    let random: String = (0..6)
        .map(|_| LETTERS[fastrand::usize(..LETTERS.len())] as char)
        .collect();
    OsString::from(format!("{prefix}{random}{suffix}"))
}

/// Makes a file or folder under a random name in `folder` with `make` (which fails with
/// `AlreadyExists` when the name is taken), trying new names until one is free.
pub fn make_unique<T>(
    prefix: &str,
    suffix: &str,
    mut make: impl FnMut(&OsStr) -> io::Result<T>,
) -> io::Result<(OsString, T)> {
    let mut last = io::Error::from(io::ErrorKind::AlreadyExists);
    for _ in 0..1000 {
        let name = random_name(prefix, suffix);
        match make(&name) {
            Ok(made) => return Ok((name, made)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// `renameat(folder, from, folder, to)`.
pub fn rename_at(folder: BorrowedFd, from: &OsStr, to: &OsStr) -> io::Result<()> {
    let (from, to) = (c_name(from)?, c_name(to)?);
    // SAFETY: both names are NUL-terminated strings alive for the call; `folder` is open.
    let done = unsafe {
        libc::renameat(
            folder.as_raw_fd(),
            from.as_ptr(),
            folder.as_raw_fd(),
            to.as_ptr(),
        )
    };
    if done != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(())
}

/// `unlinkat(folder, name, flags)`: a file (`0`) or an empty folder (`AT_REMOVEDIR`).
pub fn remove_at(folder: BorrowedFd, name: &OsStr, flags: i32) -> io::Result<()> {
    let name = c_name(name)?;
    // SAFETY: `name` is a NUL-terminated string alive for the call; `folder` is open.
    if unsafe { libc::unlinkat(folder.as_raw_fd(), name.as_ptr(), flags) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(())
}

/// `mkdirat(folder, name, mode)`.
pub fn make_folder_at(folder: BorrowedFd, name: &OsStr, mode: u32) -> io::Result<()> {
    let name = c_name(name)?;
    // SAFETY: `name` is a NUL-terminated string alive for the call; `folder` is open.
    if unsafe { libc::mkdirat(folder.as_raw_fd(), name.as_ptr(), mode as libc::mode_t) } != 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(())
}

/// Asks the disk to keep the folder's names (after a rename in it). `folder` may be an `O_PATH`
/// descriptor, which cannot be synced: the folder is opened again for reading; a folder that
/// cannot be read is left to the kernel's own writeback.
pub fn sync_folder(folder: BorrowedFd) {
    if let Ok(readable) = open_at(
        folder,
        OsStr::new("."),
        libc::O_RDONLY | libc::O_DIRECTORY,
        0,
    ) {
        let _ = std::fs::File::from(readable).sync_all();
    }
}
