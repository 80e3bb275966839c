//! Folder walks (`bvhview::info::batch::collect`, `info DIR`,
//! `dataset`) on folders with symbolic-link loops, links out, links to one file or folder twice,
//! FIFOs and broken links; CMU's ASF/AMC names; and `dataset -o`'s output rules (long names,
//! a folder that takes no new name, links planted in shared folders, numbers that overflow).
//! Every walk runs under a time limit, so that a walk that loops again fails instead of hanging.

use bvhview::info::batch::{self, Item, Walk};
use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

/// How long any walk or command here may take: they take well under a second.
const LIMIT: Duration = Duration::from_secs(60);

/// A small BVH take of the repository's, copied into test folders.
fn take() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bvh/bvhparser_simple.bvh")
}

/// `collect(dir)` on another thread, failing the test if it takes longer than [`LIMIT`].
fn collect(dir: &Path) -> Walk {
    let (send, receive) = std::sync::mpsc::channel();
    let dir = dir.to_path_buf();
    std::thread::spawn(move || {
        let _ = send.send(batch::collect(&dir).map_err(|e| e.to_string()));
    });
    receive
        .recv_timeout(LIMIT)
        .expect("the walk did not end: a loop?")
        .unwrap()
}

/// bvhview with `args`, killed and failed if it runs longer than [`LIMIT`].
fn bvhview_within_limit(args: &[&std::ffi::OsStr], dir: &Path) -> Output {
    let mut child = crate::common::bvhview_command()
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > LIMIT {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("bvhview {args:?} did not end within {LIMIT:?}: a loop?");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn os(text: &str) -> &std::ffi::OsStr {
    std::ffi::OsStr::new(text)
}

/// A folder of takes with every trap a folder walk can meet:
/// ```text
/// takes/a.bvh            takes/sub/b.bvh
/// takes/x -> .           takes/y -> .          (two links back up: exponential before)
/// takes/root -> /        takes/out -> ../elsewhere   (links out of the folder)
/// takes/zsub -> sub      (a second way to sub/)
/// takes/c.bvh -> a.bvh   (a second name of a.bvh)
/// takes/f.bvh            (a FIFO)
/// takes/broken.bvh -> missing.bvh
/// ```
fn trapped_folder(temp: &Path) -> PathBuf {
    let dir = temp.join("takes");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::create_dir_all(temp.join("elsewhere")).unwrap();
    std::fs::copy(take(), temp.join("elsewhere/outside.bvh")).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    std::fs::copy(take(), dir.join("sub/b.bvh")).unwrap();
    symlink(".", dir.join("x")).unwrap();
    symlink(".", dir.join("y")).unwrap();
    symlink("/", dir.join("root")).unwrap();
    symlink("../elsewhere", dir.join("out")).unwrap();
    symlink("sub", dir.join("zsub")).unwrap();
    symlink("a.bvh", dir.join("c.bvh")).unwrap();
    symlink("missing.bvh", dir.join("broken.bvh")).unwrap();
    let fifo =
        std::ffi::CString::new(dir.join("f.bvh").into_os_string().into_encoded_bytes()).unwrap();
    // SAFETY: mkfifo reads the NUL-terminated path `fifo` keeps alive for the call.
    assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o644) }, 0);
    dir
}

fn bvh(path: PathBuf) -> Item {
    Item { path, motion: None }
}

#[test]
fn a_folder_walk_follows_each_folder_once_and_lists_each_take_once() {
    let temp = tempfile::tempdir().unwrap();
    let dir = trapped_folder(temp.path());
    let walk = collect(&dir);
    assert_eq!(
        walk.items,
        vec![bvh(dir.join("a.bvh")), bvh(dir.join("sub/b.bvh"))]
    );
    let said: Vec<String> = walk.skipped.iter().map(ToString::to_string).collect();
    let reason = |name: &str| {
        let path = dir.join(name);
        walk.skipped
            .iter()
            .find(|s| s.path == path)
            .map(|s| s.reason.clone())
            .unwrap_or_else(|| panic!("{name} is not among the skipped: {said:#?}"))
    };
    assert!(reason("x").contains("(a loop)"), "{said:#?}");
    assert!(reason("y").contains("(a loop)"), "{said:#?}");
    assert!(reason("root").contains("a link to /, outside"), "{said:#?}");
    assert!(reason("out").contains("outside"), "{said:#?}");
    assert!(reason("zsub").contains("the folder"), "{said:#?}");
    assert!(reason("c.bvh").contains("again: listed once"), "{said:#?}");
    assert!(reason("f.bvh").contains("a FIFO"), "{said:#?}");
    assert!(reason("broken.bvh").contains("does not exist"), "{said:#?}");
    assert_eq!(walk.skipped.len(), 8, "{said:#?}");
}

/// One link back up gave 41 copies of every take before; deeper chains of links back up are
/// still one walk of each folder.
#[test]
fn a_self_link_duplicates_nothing_and_links_back_up_from_deep_do_not_loop() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    let deep = dir.join("one/two/three");
    std::fs::create_dir_all(&deep).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    std::fs::copy(take(), deep.join("d.bvh")).unwrap();
    symlink(".", dir.join("self")).unwrap();
    for (k, up) in ["..", "../..", "../../.."].iter().enumerate() {
        symlink(up, deep.join(format!("up{k}"))).unwrap();
        symlink(up, dir.join("one").join(format!("up{k}"))).unwrap();
    }
    let walk = collect(&dir);
    assert_eq!(
        walk.items,
        vec![bvh(dir.join("a.bvh")), bvh(deep.join("d.bvh"))]
    );
    assert!(!walk.skipped.is_empty());
    // The walk given the same folder through a link finds the same takes, under the link.
    let link = temp.path().join("link");
    symlink(&dir, &link).unwrap();
    assert_eq!(collect(&link).items.len(), 2);
}

/// Two links to one file inside the folder, and a hard link, are one take, kept at its first path.
#[test]
fn two_links_to_one_file_are_one_take_kept_at_its_first_path() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(dir.join("real")).unwrap();
    std::fs::copy(take(), dir.join("real/shared.bvh")).unwrap();
    symlink("real/shared.bvh", dir.join("one.bvh")).unwrap();
    symlink("real/shared.bvh", dir.join("two.bvh")).unwrap();
    std::fs::hard_link(dir.join("real/shared.bvh"), dir.join("zero.bvh")).unwrap();
    let walk = collect(&dir);
    assert_eq!(walk.items, vec![bvh(dir.join("one.bvh"))]);
    assert_eq!(walk.skipped.len(), 3, "{:?}", walk.skipped);
}

/// A link to a file outside the folder is not followed, by `info DIR` or `dataset`,
/// and nothing of that file reaches stderr or the dataset's manifest. Before, the link was
/// followed and the parse error quoted the private file's first line into `manifest.json`.
#[test]
fn a_link_to_a_file_outside_the_folder_is_skipped_and_never_quoted() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    std::fs::write(
        temp.path().join("secret.env"),
        "API_KEY=sk-private-0123456789\n",
    )
    .unwrap();
    std::fs::copy(take(), temp.path().join("outside.bvh")).unwrap();
    symlink("../secret.env", dir.join("leak.bvh")).unwrap();
    symlink("../outside.bvh", dir.join("other.bvh")).unwrap();
    let walk = collect(&dir);
    assert_eq!(walk.items, vec![bvh(dir.join("a.bvh"))]);
    for name in ["leak.bvh", "other.bvh"] {
        let skip = walk
            .skipped
            .iter()
            .find(|s| s.path == dir.join(name))
            .unwrap_or_else(|| panic!("{name}: {:?}", walk.skipped));
        assert!(skip.reason.contains("outside"), "{}", skip.reason);
    }
    let info = bvhview_within_limit(&[os("info"), os("takes")], temp.path());
    let dataset = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os("out.ds")],
        temp.path(),
    );
    assert!(
        dataset.status.success(),
        "{}",
        String::from_utf8_lossy(&dataset.stderr)
    );
    let manifest = std::fs::read_to_string(temp.path().join("out.ds/manifest.json")).unwrap();
    for printed in [
        String::from_utf8_lossy(&info.stdout).to_string(),
        String::from_utf8_lossy(&info.stderr).to_string(),
        String::from_utf8_lossy(&dataset.stderr).to_string(),
        manifest,
    ] {
        assert!(!printed.contains("sk-private"), "{printed}");
        assert!(!printed.contains("API_KEY"), "{printed}");
    }
    assert!(
        String::from_utf8_lossy(&info.stderr).contains("skipped takes/leak.bvh: a link to"),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
}

/// A file that is not motion, given by name, gets an error that shows none of its content.
#[test]
fn a_file_that_is_not_motion_is_not_quoted() {
    let temp = tempfile::tempdir().unwrap();
    for (name, content) in [
        ("a.bvh", &b"API_KEY=sk-private-0123456789\n"[..]),
        ("b.asf", &b"API_KEY=sk-private-0123456789\n"[..]),
        ("c.bvh", &b"\x7fELF\x02\x01\x01sk-private"[..]),
    ] {
        std::fs::write(temp.path().join(name), content).unwrap();
        let out = bvhview_within_limit(&[os("info"), os(name)], temp.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(":1:1: expected "), "{stderr}");
        assert!(!stderr.contains("sk-private"), "{stderr}");
        assert!(!stderr.contains("API_KEY"), "{stderr}");
    }
}

#[test]
fn an_unreadable_subfolder_is_skipped_and_said() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } == 0 {
        eprintln!("root reads every folder: nothing to test");
        return;
    }
    use std::os::unix::fs::PermissionsExt;
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(dir.join("locked")).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    std::fs::set_permissions(dir.join("locked"), std::fs::Permissions::from_mode(0o000)).unwrap();
    let walk = collect(&dir);
    std::fs::set_permissions(dir.join("locked"), std::fs::Permissions::from_mode(0o755)).unwrap();
    assert_eq!(walk.items.len(), 1);
    assert!(walk.skipped[0].reason.contains("permission denied"));
}

/// `info DIR` and `dataset DIR` on the trapped folder end, list each take once, and say on
/// stderr what the walk skipped.
#[test]
fn info_and_dataset_on_a_looping_folder_end_and_say_what_they_skipped() {
    let temp = tempfile::tempdir().unwrap();
    trapped_folder(temp.path());
    let out = bvhview_within_limit(&[os("info"), os("takes")], temp.path());
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("2 files: 2 ok, 0 failed"), "{stdout}");
    assert!(
        stderr.contains("skipped takes/x: a link back to takes"),
        "{stderr}"
    );
    assert!(
        stderr.contains("skipped takes/root: a link to /, outside takes: not followed"),
        "{stderr}"
    );
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with("skipped ")).count(),
        8
    );

    let out = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os("walk.ds")],
        temp.path(),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("skipped takes/c.bvh: the file takes/a.bvh again"));
    let manifest = std::fs::read_to_string(temp.path().join("walk.ds/manifest.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    assert_eq!(manifest["clips"].as_array().unwrap().len(), 2);
    // The walk's skips are not takes that failed: the manifest's list is the compile's.
    assert!(manifest["skipped"].as_array().unwrap().is_empty());
}

/// CMU's downloads name a subject's skeleton `cmu_07-walk.asf` and its takes
/// `cmu_07_05-walk.amc`.
#[test]
fn a_folder_pairs_asf_and_amc_as_cmu_downloads_name_them() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/asf_amc");
    std::fs::copy(data.join("heiden_12.asf"), dir.join("cmu_07-walk.asf")).unwrap();
    std::fs::copy(
        data.join("heiden_12_02_01.amc"),
        dir.join("cmu_07_05-walk.amc"),
    )
    .unwrap();
    std::fs::copy(data.join("heiden_12.asf"), dir.join("cmu_08-walk.asf")).unwrap();
    std::fs::copy(
        data.join("heiden_12_02_01.amc"),
        dir.join("cmu_08_01-walk.amc"),
    )
    .unwrap();
    let walk = collect(dir);
    let pair = |asf: &str, amc: &str| Item {
        path: dir.join(asf),
        motion: Some(dir.join(amc)),
    };
    assert_eq!(
        walk.items,
        vec![
            pair("cmu_07-walk.asf", "cmu_07_05-walk.amc"),
            pair("cmu_08-walk.asf", "cmu_08_01-walk.amc"),
        ]
    );
    let out = bvhview_within_limit(&[os("info"), dir.as_os_str()], dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("2 files: 2 ok"), "{stdout}");
}

/// A 250-byte output name (valid: names have up to 255) makes a dataset: the temporary folder's
/// name is cut as file outputs cut theirs.
#[test]
fn a_dataset_with_a_250_byte_name_is_written() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    let name = format!("{}.ds", "n".repeat(247));
    assert_eq!(name.len(), 250);
    let out = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os(&name)],
        temp.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(temp.path().join(&name).join("manifest.json").is_file());
    let left: Vec<_> = std::fs::read_dir(temp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// `-o /proc/x.ds`: /proc exists but takes no new name; the message says so rather than that
/// it does not exist. A folder that really is missing is said as missing.
#[test]
fn a_dataset_that_cannot_be_made_says_the_real_cause() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    let run = |out: &str| {
        let out = bvhview_within_limit(
            &[os("dataset"), os("takes"), os("-o"), os(out)],
            temp.path(),
        );
        assert_eq!(out.status.code(), Some(1));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let said = run("/proc/x.ds");
    assert!(!said.contains("does not exist"), "{said}");
    assert!(said.contains("nothing can be created in /proc"), "{said}");
    let said = run("no/such/x.ds");
    assert!(said.contains("the folder no/such does not exist"), "{said}");
}

/// A link another user planted in a sticky shared folder (as in /tmp) on the way to OUT is not
/// followed, as file outputs refuse it. Only root can make another user's link.
#[test]
fn a_dataset_is_not_written_through_a_link_planted_in_a_shared_folder() {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        eprintln!("not root: another user's link needs root to make");
        return;
    }
    use std::os::unix::fs::PermissionsExt;
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(take(), dir.join("a.bvh")).unwrap();
    let shared = temp.path().join("shared");
    let victim = temp.path().join("victim");
    std::fs::create_dir_all(&shared).unwrap();
    std::fs::create_dir_all(&victim).unwrap();
    std::fs::set_permissions(&shared, std::fs::Permissions::from_mode(0o1777)).unwrap();
    let planted = shared.join("pl");
    symlink(&victim, &planted).unwrap();
    std::os::unix::fs::lchown(&planted, Some(1234), Some(1234)).unwrap();
    let out = bvhview_within_limit(
        &[
            os("dataset"),
            os("takes"),
            os("-o"),
            planted.join("x.ds").as_os_str(),
        ],
        temp.path(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("a symbolic link another user (uid 1234) made"),
        "{said}"
    );
    assert_eq!(std::fs::read_dir(&victim).unwrap().count(), 0);
    // The link is root's own: followed, as file outputs follow it.
    std::os::unix::fs::lchown(&planted, Some(0), Some(0)).unwrap();
    let out = bvhview_within_limit(
        &[
            os("dataset"),
            os("takes"),
            os("-o"),
            planted.join("x.ds").as_os_str(),
        ],
        temp.path(),
    );
    assert!(out.status.success());
    assert!(victim.join("x.ds/manifest.json").is_file());
}

/// `OFFSET 0 3e38 3e38` makes positions past float32's range: the take is skipped with the
/// array, frame and point that overflowed, and the rest of the folder is compiled; a folder of
/// nothing else writes nothing.
#[test]
fn a_take_whose_numbers_overflow_is_skipped_with_its_reason() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    let huge = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition \
                Zposition Zrotation Xrotation Yrotation\n  JOINT Chest\n  {\n    OFFSET 0 3e38 \
                3e38\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    JOINT Head\n    {\n      \
                OFFSET 0 3e38 3e38\n      CHANNELS 3 Zrotation Xrotation Yrotation\n      End \
                Site\n      {\n        OFFSET 0 1 0\n      }\n    }\n  }\n}\nMOTION\nFrames: 2\n\
                Frame Time: 0.0333333\n0 0 0 0 0 0 0 0 0 0 0 0\n1 0 0 0 0 0 0 0 0 0 0 0\n";
    std::fs::write(dir.join("huge.bvh"), huge).unwrap();
    let out = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os("alone.ds")],
        temp.path(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{said}");
    assert!(
        said.contains("takes/huge.bvh: positions overflow: inf at frame 0, point Head"),
        "{said}"
    );
    assert!(!temp.path().join("alone.ds").exists());

    std::fs::copy(take(), dir.join("ok.bvh")).unwrap();
    let out = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os("mixed.ds")],
        temp.path(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    let manifest = std::fs::read_to_string(temp.path().join("mixed.ds/manifest.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    assert_eq!(manifest["clips"].as_array().unwrap().len(), 1);
    let skipped = &manifest["skipped"][0];
    assert_eq!(skipped["path"], "huge.bvh");
    assert!(
        skipped["error"]
            .as_str()
            .unwrap()
            .starts_with("huge.bvh: positions overflow"),
        "{skipped}"
    );
    // Every array written is finite.
    let positions = std::fs::read(temp.path().join("mixed.ds/group_0/positions.npy")).unwrap();
    assert!(
        positions[128..]
            .chunks_exact(4)
            .all(|b| f32::from_le_bytes(b.try_into().unwrap()).is_finite())
    );
}

/// A folder whose only take is a link out of it said "no takes" and not
/// why; the refusal now says what the walk skipped, and counts the rest.
#[test]
fn a_folder_of_only_skipped_takes_says_why_there_are_none() {
    let temp = tempfile::tempdir().unwrap();
    let dir = temp.path().join("takes");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(take(), temp.path().join("outside.bvh")).unwrap();
    symlink("../outside.bvh", dir.join("walk.bvh")).unwrap();
    let outside = std::fs::canonicalize(temp.path().join("outside.bvh")).unwrap();
    let skipped = format!(
        "skipped takes/walk.bvh: a link to {}, outside takes: not followed",
        outside.display()
    );
    for command in [
        [os("dataset"), os("takes"), os("-o"), os("out.ds")],
        [os("convert"), os("takes"), os("--to"), os("bvh")],
    ] {
        let mut args = command.to_vec();
        if command[0] == "convert" {
            args.extend([os("-o"), os("out")]);
        }
        let out = bvhview_within_limit(&args, temp.path());
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            format!(
                "bvhview: takes: no takes (.bvh, .asf, .amc, .fbx, .gltf, .glb or .npz files): \
                 {skipped}\n"
            )
        );
    }
    symlink("../outside.bvh", dir.join("zwalk.bvh")).unwrap();
    let out = bvhview_within_limit(
        &[os("dataset"), os("takes"), os("-o"), os("out.ds")],
        temp.path(),
    );
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "bvhview: takes: no takes (.bvh, .asf, .amc, .fbx, .gltf, .glb or .npz files): {skipped}, \
             and 1 more\n"
        )
    );
}
