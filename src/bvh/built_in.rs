//! The built-in skeletons: BVH files inside the program, read by name wherever a take or a
//! target is (`bvhview info smpl22`, `retarget --onto smpl22`).

use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// The built-in target skeletons: `smpl22`, the 22 body joints of SMPL in the layout of
/// HumanML3D, AMASS and most text-to-motion models, in centimetres, T-pose, Y up, facing +z.
pub const BUILT_IN: &[(&str, &[u8])] = &[("smpl22", include_bytes!("../../assets/smpl22.bvh"))];

/// What each built-in skeleton is and where it comes from (`bvhview info --list-skeletons`).
pub const BUILT_IN_ABOUT: &[(&str, &str)] = &[(
    "smpl22",
    "the 22 body joints of SMPL (its kinematic tree and joint names) in the layout of \
     HumanML3D, AMASS and most text-to-motion models, a T-pose facing +z; lengths of bvhview's \
     own adult figure (no SMPL model file is shipped)",
)];

/// A built-in skeleton by name (see [`BUILT_IN`]), with its one rest frame.
pub fn built_in(name: &str) -> Option<(Skeleton, Motion)> {
    let (_, bytes) = BUILT_IN
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))?;
    let file = crate::bvh::load_bytes(bytes, name).ok()?;
    Some((file.skeleton, file.motion))
}
