//! A count read from the file never sizes an allocation beyond what the file could hold, and a
//! long take costs memory in proportion to its size. This test binary counts every byte it
//! allocates, from any thread, so it holds one test that runs its checks in turn: a second test
//! ending beside a check, or a loader's worker pool left from an earlier check starting up, would
//! count for it (CI saw a 9680-byte allocation that way).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
/// The largest single allocation, the bytes allocated now, and the most at any one time.
static LARGEST: AtomicUsize = AtomicUsize::new(0);
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(bytes: usize) {
    let live = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

// SAFETY: every call is passed on to the system allocator unchanged; only counts are kept.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        grow(layout.size());
        // SAFETY: the caller's layout, as GlobalAlloc::alloc requires.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` came from System.alloc with this layout (every allocation goes there).
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        grow(new_size);
        // SAFETY: `ptr` came from System with `layout`; the caller's new size.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The checks in turn: the one that must see no big allocation first, before any worker pool
/// exists.
#[test]
fn allocations_follow_the_file_not_its_counts() {
    a_huge_frames_count_allocates_nothing_big();
    a_long_amc_take_needs_at_most_twice_its_size();
}

fn a_huge_frames_count_allocates_nothing_big() {
    let text = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition \
                Zrotation Xrotation Yrotation\n}\nMOTION\nFrames: 999999999999\nFrame Time: 0.1\n\
                1 2 3 4 5 6\n";
    LARGEST.store(0, Ordering::Relaxed);
    let error = bvhview::bvh::load_bytes(text.as_bytes(), "big.bvh").unwrap_err();
    let largest = LARGEST.load(Ordering::Relaxed);
    assert!(
        error.to_string().contains("expected 999999999999 frames"),
        "{error}"
    );
    assert!(
        largest < 4096,
        "largest allocation {largest} bytes for a {}-byte file",
        text.len()
    );
}

/// A long AMC take (4 MB here) is read without holding more than twice its size: the text once,
/// the values, and one line's words at a time.
fn a_long_amc_take_needs_at_most_twice_its_size() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/asf_amc");
    let take = std::fs::read_to_string(data.join("heiden_12_02_01.amc")).unwrap();
    // The take's frames, numbered on from the last, until the text passes 4 MB.
    let first = take.find("\r\n1\r\n").unwrap() + 2;
    let mut text = take[..first].to_string();
    let body: Vec<&str> = take[first..].split("\r\n").collect();
    let mut number = 0;
    while text.len() < 4 << 20 {
        for line in &body {
            if line.trim().parse::<u32>().is_ok() {
                number += 1;
                text.push_str(&format!("{number}\r\n"));
            } else if !line.is_empty() {
                text.push_str(line);
                text.push_str("\r\n");
            }
        }
    }
    let amc = tempfile::Builder::new()
        .prefix("bvhview-long-")
        .tempdir()
        .unwrap()
        .keep()
        .join("long.amc");
    std::fs::write(&amc, &text).unwrap();
    drop(text);
    let size = std::fs::metadata(&amc).unwrap().len() as usize;
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let loaded = bvhview::take::OpenOptions::new()
        .motion(&amc)
        .open(data.join("heiden_12.asf"))
        .unwrap();
    let peak = PEAK.load(Ordering::Relaxed) - before;
    std::fs::remove_file(&amc).unwrap();
    assert_eq!(loaded.motion.frame_count(), number);
    assert!(
        peak <= 2 * size,
        "{peak} bytes at most for a {size}-byte take ({:.2}×)",
        peak as f64 / size as f64
    );
}
