//! bvhview: load, look at, snapshot and export motion capture (BVH, ASF/AMC, FBX, glTF).
//!
//! ```
//! use bvhview::Take;
//!
//! # fn main() -> Result<(), bvhview::Error> {
//! // Any format, by its extension: .bvh, .fbx, .gltf, .glb, .asf (+ .amc).
//! let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
//! println!("{} frames at {} fps", take.frame_count(), take.fps());
//!
//! // World positions of every joint and End Site at frame 10, named as exports name them.
//! let names = take.point_names();
//! let points = take.positions(10).expect("the take has a frame 10");
//! println!("{} is at {}", names[0], points[0]);
//!
//! // The first two seconds on the 22-joint SMPL skeleton, saved as glTF.
//! let smpl = bvhview::retarget::onto(&take.trim(0..240), "smpl22")?;
//! let folder = tempfile::tempdir().expect("a scratch folder");
//! # #[cfg(feature = "gltf")] // a build without glTF writes BVH only
//! smpl.save(folder.path().join("walk_on_smpl.glb"))?;
//! # Ok(())
//! # }
//! ```
//!
//! The heart is a port of a well-known C++/GLUT teaching program (a BVH loader with a byte cursor
//! and a brace stack, a recursive fixed-function draw). Its names and structure are kept so the
//! two can be read side by side: every item that ports an article function starts its docs with
//! `C++: …`. Start with the chapter [`teaching`] (TEACHING.md; in Traditional Chinese
//! [`teaching_zh_hant`]), which reads the article function by function beside [`bvh`] and
//! [`render`].
//!
//! # The map
//!
//! Data flows one way: bytes → a format's reader → [`Skeleton`] + [`Motion`] → forward
//! kinematics, drawing, a format's writer, world positions, edits, retargeting, datasets.
//!
//! - formats, one folder each: [`bvh`] (the article's loader, its row reader, the writer and
//!   the tree print), [`acclaim`] (ASF/AMC), [`fbx`], [`gltf`] (read and write);
//! - [`take`] ([`Take`]): any format opened by its extension, saved, edited (retargeted by
//!   [`retarget::onto`]); [`positions`]: world positions out as CSV
//!   or JSON; [`info`]: what a take holds, and a folder of takes summarised;
//! - [`model`]: the skeleton, the motion, forward kinematics ([`model::pose`]), how a take
//!   stands, the one exact Euler split, skinning;
//! - operations on motion: [`edit`], [`retarget`], [`dataset`];
//! - [`render`]: the article's fixed-function picture, its overlays, the window, offscreen;
//! - `io`: the plumbing (errors, bounded reads, atomic outputs, limits, cores), public for the
//!   command line, the Python package and the tests, and not part of the API: [`Error`] is
//!   re-exported here.

#![warn(missing_docs)]

pub mod acclaim;
pub mod bvh;
pub mod character;
// The command line, in the library so that its plumbing stays private; `src/main.rs` calls
// `cli::main`. Not part of the API.
#[doc(hidden)]
#[cfg(feature = "cli")]
pub mod cli;
pub mod dataset;
pub mod edit;
pub mod fbx;
pub mod gltf;
pub mod humanml3d;
pub mod info;
pub mod metrics;
// The plumbing (errors, bounded reads, atomic outputs, limits, cores): private to the crate.
pub(crate) mod io;
pub mod model;
#[doc(hidden)]
pub mod plumbing;
pub mod positions;
pub mod render;
pub mod retarget;
pub mod smpl;
pub mod solve;
pub mod take;

/// The article side by side with this crate: TEACHING.md.
#[doc = include_str!("../TEACHING.md")]
pub mod teaching {}

/// The same chapter in Traditional Chinese, the article's own language: TEACHING.zh-Hant.md.
#[doc = include_str!("../TEACHING.zh-Hant.md")]
pub mod teaching_zh_hant {}

pub use io::error::Error;
/// The limits every count, rate and size is held to (what bvhview refuses, and where).
pub use io::limits;
pub use io::message::{Argument, Message, RustSpelling, Spelling};
pub use model::motion::Motion;
pub use model::skeleton::{Channel, Joint, RotationOrder, Skeleton};
pub use take::bundled::{DEFAULT_MOTION, DEFAULT_MOTION_NAME};
pub use take::{OpenOptions, Take};
