//! bvhview: load, look at, snapshot and export BVH motion capture.
//!
//! The heart is a port of a well-known C++/GLUT teaching program (a BVH loader with a byte cursor
//! and a brace stack, a recursive fixed-function draw). Its names and structure are kept so the
//! two can be read side by side: every item that ports an article function starts its docs with
//! `C++: …`.
//!
//! Data flows one way: bytes → [`bvh::loader`] (or [`acclaim`] for ASF/AMC) → [`Skeleton`] +
//! [`Motion`] → [`pose`] (forward kinematics) → [`render`], [`export`], [`bvh::print`] or
//! [`bvh::writer`].
//!
//! Start with the chapter [`teaching`] (TEACHING.md; in Traditional Chinese [`teaching_zh_hant`],
//! TEACHING.zh-Hant.md), which reads the article function by function beside the items here.

pub mod acclaim;
pub mod baked;
pub mod batch;
pub mod bvh;
pub mod dataset;
pub mod edit;
pub mod error;
pub mod euler;
pub mod export;
pub mod fbx;
pub mod gltf;
pub mod gltf_in;
pub mod info;
pub mod input;
pub mod limits;
pub mod lines;
pub mod motion;
pub mod output;
pub mod parallel;
pub mod pose;
pub mod read;
pub mod render;
pub mod retarget;
pub mod skeleton;
pub mod skin;
pub mod stance;

/// The article side by side with this crate: TEACHING.md.
#[doc = include_str!("../TEACHING.md")]
pub mod teaching {}

/// The same chapter in Traditional Chinese, the article's own language: TEACHING.zh-Hant.md.
#[doc = include_str!("../TEACHING.zh-Hant.md")]
pub mod teaching_zh_hant {}

pub use error::Error;
pub use motion::Motion;
pub use skeleton::{Channel, Joint, RotationOrder, Skeleton};

/// The default motion shown when no file is given: a short walk on the skeleton printed in the
/// article's companion text about MOTION rows, made by `examples/make_walk.rs`.
pub const DEFAULT_MOTION: &[u8] = include_bytes!("../assets/walk.bvh");

/// Threads to parse and export with: the machine's cores, asked once (the answer comes from
/// cgroup files, too slow to read for every small file). Kept in an atomic, not a `OnceLock`: a
/// child forked while another thread was asking would wait for that thread's answer for good.
pub fn cores() -> usize {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static CORES: AtomicUsize = AtomicUsize::new(0);
    match CORES.load(Ordering::Relaxed) {
        0 => {
            // Two threads asking at once both ask; they get the same answer.
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            CORES.store(cores, Ordering::Relaxed);
            cores
        }
        known => known,
    }
}

/// How the default motion is named in messages: it is built into the binary, so no path names
/// it (assets/walk.bvh exists only in the source).
pub const DEFAULT_MOTION_NAME: &str = "the bundled walk";
