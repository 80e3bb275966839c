//! A process forked while other threads of its parent load files (Python's multiprocessing forks
//! by default on Linux, and the loader releases the GIL) has only the forking thread: a lock one
//! of the others held at that moment stays locked in the child for good. The child must still
//! load, on threads of its own, and not wait for ever.
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/bvh")
        .join(name)
}

/// Streams `path` through chunk buffers (kept between loads) on two threads (kept helpers).
fn load_streamed(path: &Path) -> Vec<f32> {
    bvhview::bvh::load_file(
        path,
        bvhview::bvh::loader::Settings {
            threads: 2,
            first_read: 1,
            ..Default::default()
        },
    )
    .expect("loads")
    .motion
    .data
}

#[test]
fn a_child_forked_while_other_threads_load_still_loads() {
    // 260 KB: four 64 KB chunks, so a load takes two threads and two chunk buffers.
    let file = data("bvhparser_walk_01.bvh");
    let want = load_streamed(&file);
    static STOP: AtomicBool = AtomicBool::new(false);
    let busy: Vec<_> = [0, 1]
        .into_iter()
        .map(|kind| {
            let file = file.clone();
            std::thread::spawn(move || {
                while !STOP.load(Ordering::Relaxed) {
                    if kind == 0 {
                        // Short calls: the helper pool's lock is taken and released all the time.
                        bvhview::plumbing::on_threads(2, || {});
                    } else {
                        load_streamed(&file);
                    }
                }
            })
        })
        .collect();

    let children = 100;
    let (mut forked, mut hung, mut wrong) = (0, 0, 0);
    // One hung child is enough to fail: no need to wait for more.
    while forked < children && hung == 0 {
        forked += 1;
        // SAFETY: the child calls only the loader, then `_exit`; an alarm ends it if it hangs.
        let child = unsafe { libc::fork() };
        assert!(child >= 0, "fork failed");
        if child == 0 {
            // SAFETY: alarm has no preconditions.
            unsafe { libc::alarm(10) };
            let same = load_streamed(&file) == want;
            // SAFETY: ends the child at once, running nothing of the parent's.
            unsafe { libc::_exit(if same { 0 } else { 1 }) };
        }
        let mut status = 0;
        // SAFETY: waits for the child forked above; `status` is a valid int to write.
        assert_eq!(unsafe { libc::waitpid(child, &mut status, 0) }, child);
        if libc::WIFSIGNALED(status) {
            hung += 1;
        } else if libc::WEXITSTATUS(status) != 0 {
            wrong += 1;
        }
    }
    STOP.store(true, Ordering::Relaxed);
    for thread in busy {
        thread.join().unwrap();
    }
    assert_eq!(
        (hung, wrong),
        (0, 0),
        "of {forked} forked children, (hung, loaded other values)"
    );
}
