//! Operations on motion and the model under them: the generated skin, the reading of the body,
//! stance (up axis and units), retargeting, solving positions into rotations, smoothing,
//! mirroring, foot locking, the travel joint, the positions export and skinned characters.
//! One test binary; `cargo test --test motion MODULE` runs one file's tests.

#[path = "../common/mod.rs"]
mod common;

mod body_reading;
mod canonical_layout;
mod character_skinning;
mod generated_skin;
mod keypoint_layouts;
mod lock_feet;
mod mirror_left_right;
mod plausibility_metrics;
mod positions_fast_and_plain_agree;
mod retarget;
mod retarget_every_family;
mod retarget_fast_and_plain_agree;
mod smooth_jitter;
mod solve_positions_to_rotations;
mod stance_up_axis_and_units;
mod travel_joint;
