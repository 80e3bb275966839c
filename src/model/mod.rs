//! The model every format reads into and every operation works on: the skeleton, the motion,
//! forward kinematics (`pose`), how a take stands (`stance`), the one exact Euler split, and
//! linear blend skinning; what a format's reader hands over, and a take built from world
//! transforms.

#[cfg(any(feature = "fbx", feature = "gltf"))]
pub(crate) mod baked;
pub mod body;
#[doc(hidden)] // the generated skin the `body` look draws, for the tests
pub mod bone_skin;
pub mod euler;
pub mod mesh;
pub mod motion;
pub mod pose;
pub mod reading;
pub mod skeleton;
pub mod skin;
pub mod stance;
