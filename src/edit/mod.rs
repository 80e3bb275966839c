//! Edits that map a skeleton and its motion to new ones. Every edit whose arithmetic can leave
//! the 32-bit range (a scale, a difference, a turn of huge values) checks its result with
//! [`finite()`] and refuses it rather than hand on an infinity no file can hold.

mod angles;
mod finite;
mod lock_feet;
mod mirror;
mod orient;
mod resample;
mod scale;
mod smooth;
#[cfg(test)]
mod testing;

pub use angles::*;
pub use finite::*;
pub use lock_feet::*;
pub use mirror::*;
pub use orient::*;
pub use resample::*;
pub use scale::*;
pub use smooth::*;
