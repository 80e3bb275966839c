//! Outputs land only where the user points: on a shared machine, a link or a folder another user
//! controls on the way to an output is never followed or written into, however the way is
//! reached. Each test makes a sticky, world-writable folder (as /tmp is) in a temporary folder,
//! plants there what another user (`nobody`, uid 65534) would, and aims bvhview at it; the
//! victims are files the test made. Only root can give a file to another user, so the tests
//! need root (CI runs as root) and say so otherwise.

use std::os::unix::fs::{PermissionsExt, symlink};
use std::path::{Path, PathBuf};
use std::process::Output;

const NOBODY: u32 = 65534;

fn root() -> bool {
    // SAFETY: geteuid has no preconditions and cannot fail.
    let root = unsafe { libc::geteuid() } == 0;
    if !root {
        eprintln!("not root: another user's files need root to make");
    }
    root
}

fn take() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/walk.bvh")
        .display()
        .to_string()
}

fn bvhview_in(folder: &Path, args: &[&str]) -> Output {
    crate::common::bvhview_command()
        .args(args)
        .current_dir(folder)
        .output()
        .unwrap()
}

/// `positions TAKE -o OUT`, run in `folder`.
fn positions(folder: &Path, out: &str) -> Output {
    bvhview_in(folder, &["positions", &take(), "-o", out])
}

/// A temporary folder holding `shared`, sticky and world-writable, and `elsewhere`, a folder of
/// root's that a planted link leads to.
struct Machine {
    _temp: tempfile::TempDir,
    shared: PathBuf,
    elsewhere: PathBuf,
}

fn machine() -> Machine {
    let temp = tempfile::tempdir().unwrap();
    let shared = temp.path().join("shared");
    let elsewhere = temp.path().join("elsewhere");
    std::fs::create_dir(&shared).unwrap();
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::set_permissions(&shared, std::fs::Permissions::from_mode(0o1777)).unwrap();
    Machine {
        _temp: temp,
        shared,
        elsewhere,
    }
}

/// A link at `link` to `target`, owned by nobody.
fn plant_link(target: &Path, link: &Path) {
    symlink(target, link).unwrap();
    std::os::unix::fs::lchown(link, Some(NOBODY), Some(NOBODY)).unwrap();
}

fn refused_saying(out: &Output, want: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains(want), "{stderr}");
}

fn files_in(folder: &Path) -> usize {
    std::fs::read_dir(folder).unwrap().count()
}

/// `snapshot --frames -o DIR/` into an empty folder another user owns in a shared folder: that
/// user could plant links in it while the pictures are written (a file outside was replaced by
/// a PNG). Refused; one's own empty folder there takes the pictures.
#[test]
fn a_pictures_folder_another_user_owns_in_a_shared_folder_is_refused() {
    if !root() {
        return;
    }
    let m = machine();
    let theirs = m.shared.join("theirs");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::set_permissions(&theirs, std::fs::Permissions::from_mode(0o777)).unwrap();
    std::os::unix::fs::chown(&theirs, Some(NOBODY), Some(NOBODY)).unwrap();
    let snapshot = |out: &str| {
        bvhview_in(
            &m.shared,
            &[
                "snapshot",
                &take(),
                "--frames",
                "0..3",
                "--size",
                "32x32",
                "-o",
                out,
            ],
        )
    };
    let out = snapshot("theirs/");
    refused_saying(
        &out,
        "theirs is a folder another user (uid 65534) owns in a shared folder; not written into",
    );
    assert_eq!(files_in(&theirs), 0);
    // A file output into that folder is refused the same way.
    refused_saying(
        &positions(&m.shared, "theirs/p.csv"),
        "another user (uid 65534) owns in a shared folder",
    );
    assert_eq!(files_in(&theirs), 0);
    let mine = m.shared.join("mine");
    std::fs::create_dir(&mine).unwrap();
    let out = snapshot("mine/");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(files_in(&mine), 3);
}

/// A link another user planted in a shared folder was refused when it led to a regular file,
/// but followed when it led to a FIFO (1,555 bytes written into it) or a character device.
#[test]
fn a_planted_link_to_a_fifo_or_a_device_is_not_followed() {
    if !root() {
        return;
    }
    let m = machine();
    let fifo = m.elsewhere.join("pipe");
    let name = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: a NUL-terminated path alive for the call.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o666) }, 0);
    // Held open for reading without waiting, so that a writer would not block the test: what
    // it wrote would be read below.
    let reader = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(&fifo)
        .unwrap();
    plant_link(&fifo, &m.shared.join("pn.csv"));
    refused_saying(
        &positions(&m.shared, "pn.csv"),
        "is a symbolic link another user (uid 65534) made in a shared folder; not followed",
    );
    let mut read = Vec::new();
    let _ = std::io::Read::read_to_end(&mut &reader, &mut read);
    assert!(read.is_empty(), "{} bytes reached the FIFO", read.len());
    // A character device of the test's own (the null device's numbers), never the machine's.
    let device = m.elsewhere.join("null");
    let name = std::ffi::CString::new(device.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: a NUL-terminated path alive for the call.
    let made = unsafe { libc::mknod(name.as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 3)) };
    assert_eq!(made, 0, "{}", std::io::Error::last_os_error());
    plant_link(&device, &m.shared.join("dev.csv"));
    refused_saying(
        &positions(&m.shared, "dev.csv"),
        "is a symbolic link another user (uid 65534) made in a shared folder; not followed",
    );
    // A FIFO another user made in the shared folder itself is not written to either (as
    // Linux's fs.protected_fifos refuses it).
    let their_fifo = m.shared.join("their.csv");
    let name = std::ffi::CString::new(their_fifo.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: a NUL-terminated path alive for the call.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o666) }, 0);
    std::os::unix::fs::chown(&their_fifo, Some(NOBODY), Some(NOBODY)).unwrap();
    refused_saying(
        &positions(&m.shared, "their.csv"),
        "belongs to another user (uid 65534) in a shared folder; not replaced",
    );
}

use std::os::unix::fs::OpenOptionsExt;

/// `-o mylink.csv`, the user's own link, leading to `shared/theirdir/d.csv` where `theirdir`
/// is another user's link: naming that path directly was refused, reaching it through one's own
/// link overwrote the file the planted link led to.
#[test]
fn a_planted_link_reached_through_ones_own_link_is_not_followed() {
    if !root() {
        return;
    }
    let m = machine();
    let victim = m.elsewhere.join("d.csv");
    std::fs::write(&victim, "precious").unwrap();
    plant_link(&m.elsewhere, &m.shared.join("theirdir"));
    let home = m.shared.parent().unwrap().join("home");
    std::fs::create_dir(&home).unwrap();
    symlink(m.shared.join("theirdir/d.csv"), home.join("mylink.csv")).unwrap();
    refused_saying(
        &positions(&home, "mylink.csv"),
        "theirdir is a symbolic link another user (uid 65534) made in a shared folder",
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    // A relative way round to the same link is refused the same way.
    refused_saying(
        &positions(&home, "../shared/theirdir/d.csv"),
        "a symbolic link another user (uid 65534) made",
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
}

/// Paths through `/proc/self/cwd/…` skipped the planted-link and planted-file checks.
#[test]
fn paths_through_proc_self_cwd_are_checked_as_any_path() {
    if !root() {
        return;
    }
    let m = machine();
    let victim = m.elsewhere.join("victim.csv");
    std::fs::write(&victim, "precious").unwrap();
    plant_link(&victim, &m.shared.join("planted.csv"));
    refused_saying(
        &positions(&m.shared, "/proc/self/cwd/planted.csv"),
        "a symbolic link another user (uid 65534) made",
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    let theirs = m.shared.join("theirs.csv");
    std::fs::write(&theirs, "theirs").unwrap();
    std::os::unix::fs::chown(&theirs, Some(NOBODY), Some(NOBODY)).unwrap();
    refused_saying(
        &positions(&m.shared, "/proc/self/cwd/theirs.csv"),
        "belongs to another user (uid 65534) in a shared folder; not replaced",
    );
    assert_eq!(std::fs::read_to_string(&theirs).unwrap(), "theirs");
    // One's own new file there is written, whole.
    let out = positions(&m.shared, "/proc/self/cwd/mine.csv");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(m.shared.join("mine.csv")).unwrap();
    assert!(text.starts_with("frame,"), "{text}");
}
