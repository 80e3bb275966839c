//! The SMPL family's model types: each one's joints, by name and in the order its pose
//! parameters list them, and its kinematic tree (the published layouts).

/// A body model of the SMPL family, as an AMASS file names it (`surface_model_type`).
///
/// ```
/// use bvhview::smpl::ModelType;
///
/// assert_eq!(ModelType::of_pose_width(156), Some(ModelType::Smplh));
/// assert_eq!(ModelType::Smplx.joint_names()[22], "jaw");
/// assert_eq!(ModelType::Smpl.parents()[15], Some(12)); // head under neck
/// assert_eq!(ModelType::named("smplx"), Some(ModelType::Smplx));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelType {
    /// SMPL: 24 joints (the body's 22 and a hand joint each side), poses of 72 values.
    Smpl,
    /// SMPL-H (SMPL+H): 52 joints (the body's 22 and fifteen finger joints a hand), 156 values.
    Smplh,
    /// SMPL-X: 55 joints (the body's 22, jaw, two eyes, fifteen finger joints a hand), 165.
    Smplx,
}

/// The 22 body joints every model type begins with, in SMPL's order (the solver's layout).
const BODY: [&str; 22] = crate::solve::positions::SMPL22_ORDER;

/// The parent of each of [`BODY`] (the root has none).
const BODY_PARENTS: [Option<usize>; 22] = [
    None,
    Some(0),
    Some(0),
    Some(0),
    Some(1),
    Some(2),
    Some(3),
    Some(4),
    Some(5),
    Some(6),
    Some(7),
    Some(8),
    Some(9),
    Some(9),
    Some(9),
    Some(12),
    Some(13),
    Some(14),
    Some(16),
    Some(17),
    Some(18),
    Some(19),
];

/// A hand's fingers in the order SMPL-H and SMPL-X list them, three joints each.
const FINGERS: [&str; 5] = ["index", "middle", "pinky", "ring", "thumb"];

/// The left and right wrists' indices in [`BODY`].
const WRISTS: [usize; 2] = [20, 21];

/// SMPL's head (the jaw's and eyes' parent in SMPL-X).
const HEAD: usize = 15;

impl ModelType {
    /// Every model type, smallest first.
    pub const ALL: [ModelType; 3] = [ModelType::Smpl, ModelType::Smplh, ModelType::Smplx];

    /// What messages call it: `SMPL`, `SMPL-H`, `SMPL-X`.
    pub fn label(self) -> &'static str {
        match self {
            ModelType::Smpl => "SMPL",
            ModelType::Smplh => "SMPL-H",
            ModelType::Smplx => "SMPL-X",
        }
    }

    /// The model type an AMASS file's `surface_model_type` names (`smpl`, `smplh`, `smplx`; case
    /// and a `+dmpl` suffix aside).
    pub fn named(name: &str) -> Option<ModelType> {
        let name = name.trim().to_ascii_lowercase();
        let name = name.split('+').next().unwrap_or("");
        match name.replace(['-', '_'], "").as_str() {
            "smpl" => Some(ModelType::Smpl),
            "smplh" => Some(ModelType::Smplh),
            "smplx" => Some(ModelType::Smplx),
            _ => None,
        }
    }

    /// The built-in skeleton with its joints (see [`crate::bvh::built_in::BUILT_IN`]).
    pub fn built_in(self) -> &'static str {
        match self {
            ModelType::Smpl => "smpl24",
            ModelType::Smplh => "smplh52",
            ModelType::Smplx => "smplx55",
        }
    }

    /// Its joints' names, in the order of its pose parameters.
    pub fn joint_names(self) -> Vec<String> {
        let mut names: Vec<String> = BODY.iter().map(|n| n.to_string()).collect();
        match self {
            ModelType::Smpl => names.extend(["left_hand".into(), "right_hand".into()]),
            ModelType::Smplh | ModelType::Smplx => {
                if self == ModelType::Smplx {
                    names.extend(["jaw", "left_eye_smplhf", "right_eye_smplhf"].map(String::from));
                }
                for side in ["left", "right"] {
                    for finger in FINGERS {
                        names.extend((1..=3).map(|k| format!("{side}_{finger}{k}")));
                    }
                }
            }
        }
        names
    }

    /// Each joint's parent, as an index into [`ModelType::joint_names`].
    pub fn parents(self) -> Vec<Option<usize>> {
        let mut parents = BODY_PARENTS.to_vec();
        match self {
            ModelType::Smpl => parents.extend(WRISTS.map(Some)),
            ModelType::Smplh | ModelType::Smplx => {
                if self == ModelType::Smplx {
                    parents.extend([Some(HEAD); 3]);
                }
                for wrist in WRISTS {
                    for _ in FINGERS {
                        let first = parents.len();
                        parents.extend([Some(wrist), Some(first), Some(first + 1)]);
                    }
                }
            }
        }
        parents
    }

    /// Its joints.
    pub fn joint_count(self) -> usize {
        match self {
            ModelType::Smpl => 24,
            ModelType::Smplh => 52,
            ModelType::Smplx => 55,
        }
    }

    /// The values of one frame's pose: three (an axis-angle) a joint.
    pub fn pose_width(self) -> usize {
        3 * self.joint_count()
    }

    /// The model type whose poses are `width` values a frame.
    pub fn of_pose_width(width: usize) -> Option<ModelType> {
        ModelType::ALL.into_iter().find(|m| m.pose_width() == width)
    }
}

#[cfg(test)]
mod tests {
    use super::ModelType;

    /// Each layout is a tree, parents before children, and its names are the built-in
    /// skeleton's joints.
    #[test]
    fn layouts_are_trees_and_their_built_ins_name_every_joint() {
        for model in ModelType::ALL {
            let (names, parents) = (model.joint_names(), model.parents());
            assert_eq!(names.len(), model.joint_count());
            assert_eq!(parents.len(), model.joint_count());
            for (j, parent) in parents.iter().enumerate() {
                assert!(parent.is_none_or(|p| p < j), "{model:?} {j}");
            }
            let (skeleton, _) = crate::bvh::built_in::built_in(model.built_in()).unwrap();
            let built: Vec<&str> = skeleton
                .joints
                .iter()
                .filter(|j| !j.end_site)
                .map(|j| j.name.as_str())
                .collect();
            for (j, name) in names.iter().enumerate() {
                let at = skeleton
                    .joints
                    .iter()
                    .position(|b| &b.name == name)
                    .unwrap();
                let parent = skeleton.joints[at]
                    .parent
                    .map(|p| skeleton.joints[p].name.clone());
                assert_eq!(parent, parents[j].map(|p| names[p].clone()), "{name}");
            }
            assert_eq!(built.len(), names.len());
        }
    }
}
