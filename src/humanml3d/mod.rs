//! HumanML3D's motion representation, both ways: the 263 numbers per frame that text-to-motion
//! models train on (`dataset --features humanml3d`, [`features()`]) and back to joint positions
//! (`solve --from humanml3d`, [`recover_from_ric`]).
//!
//! The layout and the processing are those of HumanML3D's own pipeline
//! (`motion_representation.ipynb`, `common/skeleton.py` and `paramUtil.py` in
//! EricGuo5513/HumanML3D), written here anew. A vector holds, in order:
//!
//! | values | what |
//! |---|---|
//! | 1 | the root's turn about y to the next frame (half the angle, radians: see below) |
//! | 2 | the root's step to the next frame on x and z, in the next frame's facing |
//! | 1 | the root's height |
//! | 63 | the 21 other joints relative to the root on the floor, in the frame's facing ("ric") |
//! | 126 | the 21 joints' rotations in 6D (the first two columns of each matrix) |
//! | 66 | the 22 joints' steps to the next frame, in the frame's facing |
//! | 4 | foot contacts: left ankle, left foot, right ankle, right foot (0 or 1) |
//!
//! Where HumanML3D's processing has quirks, they are matched, so that vectors made here sit in
//! the same space as its published ones (and its `Mean.npy`/`Std.npy`, and the models trained
//! on them): the section below names each one.//!
//! # How the vectors are made
//!
//!
//! The steps, in its order: every bone set to the reference length along its own direction
//! (the root's path scaled by the legs: `uniform_skeleton`); the lowest point of the take put on
//! y = 0 and the root's first place at x = z = 0; the take turned about y to face +z at its
//! first frame (from the hips and the shoulders); foot contacts; each joint's rotation from its
//! bone's direction (its inverse kinematics); then the vector's parts from these.
//!
//! HumanML3D's quirks, kept so that vectors made here mean what its published ones mean:
//!
//! - **The facing its inverse kinematics reads is not the facing it turns the take by.** Its
//!   `inverse_kinematics_np` unpacks the four facing joints as *left* hip, right hip, right
//!   shoulder, left shoulder, while `process_file` passes right hip, left hip, …: the hips'
//!   vector is taken the other way round, so the root's facing comes from the shoulders' width
//!   *minus* the hips'. It still points forward on a human (shoulders are wider than hips), but
//!   it leans with the difference; the root's rotation, every vector's facing and the first
//!   bone of each chain carry it.
//! - **That facing is smoothed** along time (a Gaussian of 20 frames' spread, edges repeated,
//!   as SciPy's `gaussian_filter1d` with `mode='nearest'`), and **the first frame's root
//!   rotation is the identity** whatever the body faces.
//! - **The root's turn is stored as half its angle**: `arcsin` of the `y` part of the
//!   quaternion from one frame's root rotation to the next, which is `sin(angle / 2)`.
//! - **The root's step is turned by the next frame's rotation, the joints' by this frame's.**
//! - **Rotations are swings only**: each bone's rotation is the shortest turn from its rest
//!   direction to its direction now, relative to the chain's previous bone (not to its parent
//!   in the tree: the arms' chains start from the root's facing, not from the chest), so no
//!   bone carries a twist about itself.
//! - **Contacts are by speed alone**: a foot point is in contact when its squared step to the
//!   next frame is under 0.002 m² (its height is not read).
//!
//! Two cases HumanML3D does not survive (its numbers become NaN, and its mean and spread leave
//! the clip out) are decided here instead: a bone pointing exactly against its rest direction
//! turns half a turn about a perpendicular axis; a bone of zero length, or a first frame whose
//! facing is straight up, refuses the take with the frame and the joint.

mod features;
mod recover;

pub use features::{Features, features, joint_order, spread_by_part};
pub use recover::{read_vectors, recover_from_ric};

/// Values in one HumanML3D feature vector (22 joints).
pub const WIDTH: usize = 263;

/// Joints of the representation: SMPL's first 22 ([`crate::solve::SMPL22_ORDER`]).
pub const JOINTS: usize = 22;

/// The frame rate HumanML3D's vectors are made at.
pub const FPS: f64 = 20.0;

/// HumanML3D's kinematic chains (`t2m_kinematic_chain`): the right leg, the left leg, the spine
/// to the head, the right arm and the left arm from the chest (joint 9). Its inverse kinematics
/// turns each chain's bones from the root's facing, chain by chain.
pub const CHAINS: [&[usize]; 5] = [
    &[0, 2, 5, 8, 11],
    &[0, 1, 4, 7, 10],
    &[0, 3, 6, 9, 12, 15],
    &[9, 14, 17, 19, 21],
    &[9, 13, 16, 18, 20],
];

/// Each joint's parent along [`CHAINS`] (the root's is itself).
pub const PARENTS: [usize; JOINTS] = [
    0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19,
];

/// The direction of each joint's bone at rest (`t2m_raw_offsets`): y up, +z forward, the
/// body's left on +x. A joint's rotation turns this direction to its bone's.
pub const REST_DIRECTIONS: [[f64; 3]; JOINTS] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, 1.0],
    [0.0, 1.0, 0.0],
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, -1.0, 0.0],
];

/// The bone lengths (metres; the root's is 0) every take is made uniform to: HumanML3D's
/// reference skeleton, its AMASS clip `000021` at the first frame. That clip is not
/// redistributable; its lengths are read here from the published pair in `tests/humanml3d`,
/// whose every frame has them within 2e-6 m (a test holds this table to them).
pub const REFERENCE_LENGTHS: [f64; JOINTS] = [
    0.0, 0.103074, 0.109883, 0.131568, 0.393623, 0.390188, 0.143190, 0.432433, 0.425643, 0.057365,
    0.143382, 0.149419, 0.219360, 0.137487, 0.143383, 0.103039, 0.131614, 0.122984, 0.256840,
    0.263092, 0.266012, 0.269876,
];

/// The joints the facing is read from: right hip, left hip, right shoulder, left shoulder
/// (`face_joint_indx`).
pub const FACING_JOINTS: [usize; 4] = [2, 1, 17, 16];

/// The left foot's contact points (ankle, foot), then the right foot's (`fid_l`, `fid_r`).
pub const FOOT_POINTS: [[usize; 2]; 2] = [[7, 10], [8, 11]];

/// A foot point is in contact when its squared step to the next frame is under this (m², per
/// frame at 20 fps: under 4.5 cm a frame, 0.89 m/s): HumanML3D's `feet_thre`.
pub const CONTACT_THRESHOLD: f64 = 0.002;

/// Where each part starts in a vector, and its width: `(name, start, width)`. The normalising
/// spread ([`spread_by_part`]) is one number per part.
pub const PARTS: [(&str, usize, usize); 7] = [
    ("root_turn", 0, 1),
    ("root_step", 1, 2),
    ("root_height", 3, 1),
    ("ric", 4, 63),
    ("rotations", 67, 126),
    ("velocities", 193, 66),
    ("contacts", 259, 4),
];
