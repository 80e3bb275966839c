//! Edits that map a skeleton and its motion to new ones. Every edit whose arithmetic can leave
//! the 32-bit range (a scale, a difference, a turn of huge values) checks its result with
//! [`finite()`] and refuses it rather than hand on an infinity no file can hold.

mod angles;
mod canonical;
mod finite;
mod lock_feet;
mod mirror;
mod orient;
mod resample;
mod rest;
mod scale;
mod smooth;
#[cfg(test)]
mod testing;

pub use angles::{bake_axes, baked_for_bvh, channel_angles};
pub use canonical::{Canonical, canonical};
pub use finite::{finite, first_non_finite};
pub use lock_feet::{FeetLocked, FootLocked, LockFeet, NotHeld, lock_feet, lock_feet_when};
pub use mirror::{MirrorOptions, lateral_axis, mirror, mirror_partners};
pub use orient::{QuarterTurn, ground, in_place, reorient};
pub use resample::{Picks, Resampling, SAME_RATE, resample, resample_picks};
pub use rest::rest_tpose;
pub use scale::{scale, trim};
pub use smooth::{smooth, zero_phase};
