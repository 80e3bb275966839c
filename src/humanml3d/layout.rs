//! HumanML3D's fixed layout: the width of a vector and its parts, the 22 joints (their parents,
//! chains, rest directions and lengths), the rate, the joints that say the facing, the foot
//! points and their contact threshold.

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
/// spread ([`spread_by_part`](super::spread_by_part)) is one number per part.
pub const PARTS: [(&str, usize, usize); 7] = [
    ("root_turn", 0, 1),
    ("root_step", 1, 2),
    ("root_height", 3, 1),
    ("ric", 4, 63),
    ("rotations", 67, 126),
    ("velocities", 193, 66),
    ("contacts", 259, 4),
];
