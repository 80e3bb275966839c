//! The reading of the body: which joints are the hips, the spine, the neck and head, and per
//! side the limbs, from joint names ([`names`], [`sides`]) and from the tree ([`roles`]), and
//! the joint that carries the travel ([`travel`]), the foot points and legs' length ([`feet`]),
//! when a foot is planted ([`contact`]), and what the reading is sure of ([`verdict`]). Every
//! part of bvhview that asks what a joint is (retargeting, mirroring, `info`, the viewer's
//! names) asks here.

pub mod contact;
pub mod feet;
pub mod fingers;
mod geometry;
mod legs;
pub mod names;
pub mod roles;
pub mod sides;
pub mod travel;
pub mod verdict;

pub(crate) use legs::count_word;
pub use names::FINGERS;
pub use names::{Limb, Role};
pub use roles::Body;
pub(crate) use roles::{is_ancestor, path_between};
pub use sides::{Side, mirrored_name, name_side};
pub use travel::{travel_candidates, travel_joint, travel_joint_of_take};
pub use verdict::Doubt;
