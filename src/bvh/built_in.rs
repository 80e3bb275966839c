//! The built-in skeletons: BVH files inside the program, read by name wherever a take or a
//! target is (`bvhview info smpl22`, `retarget --onto smpl22`).

use crate::model::motion::Motion;
use crate::model::skeleton::Skeleton;

/// The built-in target skeletons: `smpl22`, the 22 body joints of SMPL in the layout of
/// HumanML3D, AMASS and most text-to-motion models, and the whole joint sets of the SMPL family's
/// three model types (`smpl24`, `smplh52`, `smplx55`, made by `scripts/make_smpl_builtins.py`),
/// in centimetres, T-pose, Y up, facing +z.
pub const BUILT_IN: &[(&str, &[u8])] = &[
    ("smpl22", include_bytes!("../../assets/smpl22.bvh")),
    ("smpl24", include_bytes!("../../assets/smpl24.bvh")),
    ("smplh52", include_bytes!("../../assets/smplh52.bvh")),
    ("smplx55", include_bytes!("../../assets/smplx55.bvh")),
];

/// What each built-in skeleton is and where it comes from (`bvhview info --list-skeletons`).
pub const BUILT_IN_ABOUT: &[(&str, &str)] = &[
    (
        "smpl22",
        "the 22 body joints of SMPL (its kinematic tree and joint names) in the layout of \
         HumanML3D, AMASS and most text-to-motion models, a T-pose facing +z; lengths of \
         bvhview's own adult figure (no SMPL model file is shipped)",
    ),
    (
        "smpl24",
        "SMPL's 24 joints (smpl22 and a joint in each hand), as an AMASS SMPL file poses them; \
         lengths of bvhview's own adult figure",
    ),
    (
        "smplh52",
        "SMPL-H's 52 joints (smpl22 and fifteen finger joints a hand), as AMASS's SMPL-H files \
         pose them; lengths of bvhview's own adult figure, hands measured on no model",
    ),
    (
        "smplx55",
        "SMPL-X's 55 joints (smpl22, jaw, two eyes and fifteen finger joints a hand), as \
         AMASS's SMPL-X files pose them; lengths of bvhview's own adult figure, hands and face \
         measured on no model",
    ),
];

/// Other names of built-in skeletons: a model type's name for its whole joint set, as AMASS's
/// `surface_model_type` and `--onto smplh` say it.
pub const ALIASES: &[(&str, &str)] = &[
    ("smpl", "smpl24"),
    ("smplh", "smplh52"),
    ("smplx", "smplx55"),
];

/// The built-in skeleton `name` (or one of its [`ALIASES`]) names, case aside.
///
/// ```
/// use bvhview::bvh::built_in::name_of;
///
/// assert_eq!(name_of("SMPLH"), Some("smplh52"));
/// assert_eq!(name_of("smpl22"), Some("smpl22"));
/// assert_eq!(name_of("walk"), None);
/// ```
pub fn name_of(name: &str) -> Option<&'static str> {
    let alias = ALIASES
        .iter()
        .find(|(alias, _)| alias.eq_ignore_ascii_case(name))
        .map(|(_, built_in)| *built_in);
    alias.or_else(|| {
        BUILT_IN
            .iter()
            .map(|(built_in, _)| *built_in)
            .find(|built_in| built_in.eq_ignore_ascii_case(name))
    })
}

/// A built-in skeleton by name (see [`BUILT_IN`] and [`ALIASES`]), with its one rest frame.
pub fn built_in(name: &str) -> Option<(Skeleton, Motion)> {
    let name = name_of(name)?;
    let (_, bytes) = BUILT_IN.iter().find(|(n, _)| *n == name)?;
    let file = crate::bvh::load_bytes(bytes, name).ok()?;
    Some((file.skeleton, file.motion))
}
