//! ASF/AMC (Acclaim; the CMU motion database): an ASF file holds the skeleton, an AMC file the
//! frames. Both become the same [`Skeleton`](crate::Skeleton) + [`Motion`](crate::Motion) as a BVH
//! file, so every command that takes a BVH takes an ASF/AMC pair (as the ASF/AMC article reads
//! them):
//!
//! - the root is a joint at `:root position` with the channels of its `order`;
//! - every bone is a joint at the *start* of the bone, offset from its parent joint by the parent
//!   bone's `direction × length` (zero under the root), turning about its fixed `axis` C:
//!   local = T · C · M · C⁻¹, where M applies the `dof` rotations in the order listed (`rx ry rz`
//!   gives M = Rz · Ry · Rx, the ASF/AMC article's `cal_global_coord`);
//! - a bone without children ends in an End Site at its own `direction × length`.
//!
//! So the channels of a joint are the dof rotations in reverse (`Zrotation Yrotation Xrotation`
//! for `rx ry rz`), because a [`Skeleton`](crate::Skeleton)'s channels multiply in file order.

pub mod absolute;
pub mod amc;
pub mod asf;
mod rotation;
mod text;

pub use amc::load_amc;
pub use asf::{Asf, load_asf};
pub use rotation::axis_rotation;

/// CMU captures at 120 frames per second; AMC files do not say.
pub const DEFAULT_FRAME_TIME: f64 = 1.0 / 120.0;
