//! Retargeting: one take's motion on another skeleton (its names, hierarchy, bone lengths,
//! channel orders and rest pose).
//!
//! Three steps, each usable alone:
//! 1. **Roles.** [`Body::of`](crate::model::body::Body::of) reads which joint of a skeleton is the hips, the spine chain, the
//!    neck, the head and, per side, the clavicle, upper arm, forearm, hand, thigh, shin, foot and
//!    toe, from the names every common family uses (CMU, Mixamo `mixamorig:`, LaFAN1, Xsens/MVN,
//!    Bandai `UpperLeg_L`, MakeHuman, Daz/Poser/Second Life `lThigh`/`lShldr`, Rokoko,
//!    Perception Neuron, OptiTrack `LUArm`, SMPL `left_hip`, Rigify `thigh.L`), prefixes and case
//!    ignored, and from the tree where names say less (the hips are where legs and spine part).
//! 2. **A map.** [`Map::guess`] pairs target joints with source joints by role (spine chains of
//!    different lengths spread end to end), then by equal names for what has no role (fingers);
//!    [`Map::apply`] overrides it with `SRC = DST` pairs.
//! 3. **Rest alignment.** [`retarget`] gives each mapped target joint the source joint's world
//!    rotation relative to its rest pose, `W_t = W_s · W_s,rest⁻¹ · A · W_t,rest`, where A turns the
//!    target's rest bones onto the source's (so a T-pose take drives an A-pose rig with the arms
//!    where the source has them), then writes it into the target's own channels and orders.
//!    Unmapped joints keep their rest rotation; the hips' path is scaled by the ratio of hip
//!    heights and the feet are kept on the source's floor.
//!
//! Rotations are carried in 64-bit floats (see [`crate::model::pose::world_transforms_f64`]), so a take
//! retargeted onto its own skeleton gives back its own values. [`retarget`] runs eight frames side
//! by side (src/retarget/fast/); [`retarget_plain`] is the same work a joint and a frame at a
//! time, which a test holds it to (tests/motion/retarget_fast_and_plain_agree.rs).

mod align;
mod check;
mod fast;
mod hinge;
mod map;
mod map_file;
mod measure;
mod names;
mod plain;
mod run;
mod target;

pub use crate::bvh::built_in::{BUILT_IN, BUILT_IN_ABOUT, built_in};
pub use align::{NO_WIDTH, Ups, bones};
pub use check::{Across, COLLAPSED, Check, check};
pub(crate) use hinge::{limited_angles, limited_angles_by};
pub use map::{How, Map, REQUIRED};
pub use map_file::{MapPairs, Stated, parse_map, parse_map_pairs, parse_pair};
pub use measure::{Standing, direction_errors, followable_errors, quantile, standing};
pub use names::names_of_family;
pub use run::{lock_feet_from_source, retarget, retarget_plain, retargeted_values};
pub use target::{Insist, Retargeted, Target, onto};
