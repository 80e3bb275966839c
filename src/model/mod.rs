//! The model every format reads into and every operation works on: the skeleton, the motion,
//! forward kinematics (`pose`), how a take stands (`stance`), the one exact Euler split, and
//! linear blend skinning; what a format's reader hands over, and a take built from world
//! transforms.

pub mod baked;
pub mod body;
pub mod bone_skin;
pub mod euler;
pub mod motion;
pub mod pose;
pub mod reading;
pub mod skeleton;
pub mod skin;
pub mod stance;
