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
mod layout;
mod recover;

pub use features::{Features, features, joint_order, spread_by_part};
pub use layout::{
    CHAINS, CONTACT_THRESHOLD, FACING_JOINTS, FOOT_POINTS, FPS, JOINTS, PARENTS, PARTS,
    REFERENCE_LENGTHS, REST_DIRECTIONS, WIDTH,
};
pub use recover::{read_vectors, recover_from_ric};
