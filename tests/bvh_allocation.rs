//! A count read from the file never sizes an allocation beyond what the file could hold.
//! This test binary counts every byte it allocates.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static LARGEST: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

#[test]
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
