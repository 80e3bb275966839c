//! What the writer targets share: the first byte of an input picks an edit, the rest is a BVH
//! file for the loader.

use bvhview::{Motion, Skeleton};

/// What the writer targets start from: the choice byte, and the take the BVH loader makes of
/// the rest after the edits it picks; `None` when the loader or an edit refuses.
pub fn edited_take(data: &[u8]) -> Option<(u8, Skeleton, Motion)> {
    let (choice, bytes) = split(data);
    let bvh = bvhview::bvh::load_bytes(bytes, "fuzz.bvh").ok()?;
    let (skeleton, motion) = edited(choice, bvh.skeleton, bvh.motion)?;
    Some((choice, skeleton, motion))
}

/// The choice byte and the file's bytes.
pub fn split(data: &[u8]) -> (u8, &[u8]) {
    match data.split_first() {
        Some((&choice, rest)) => (choice, rest),
        None => (0, data),
    }
}

/// The take after the edits `choice` picks (bits 0-3: scale by a large, a tiny or a negative
/// factor, resample, mirror, turn to Z up), as `convert` applies them; `None` when an edit
/// refuses the take (that refusal is the edit's own answer, checked elsewhere).
pub fn edited(choice: u8, skeleton: Skeleton, motion: Motion) -> Option<(Skeleton, Motion)> {
    let (mut skeleton, mut motion) = (skeleton, motion);
    if choice & 1 != 0 {
        let factor = [1e38f32, 1e-30, -3.5, 1e20][usize::from(choice >> 4) % 4];
        (skeleton, motion) = bvhview::edit::scale(&skeleton, &motion, factor).ok()?;
    }
    // Resampled only where that makes few frames: an hour-long frame time at 7.5 per second
    // makes tens of thousands, which is right but slow (the limits are tested elsewhere).
    let duration = motion.frame_count() as f64 * motion.frame_time;
    if choice & 2 != 0 && duration * 7.5 < 2000.0 {
        motion = bvhview::edit::resample(&skeleton, &motion, 7.5).ok()?;
    }
    if choice & 4 != 0 {
        let options = bvhview::edit::MirrorOptions {
            rename: choice & 64 != 0,
            ..Default::default()
        };
        (skeleton, motion) = bvhview::edit::mirror(&skeleton, &motion, &options).ok()?;
    }
    if choice & 8 != 0 {
        use bvhview::model::pose::Up;
        (skeleton, motion) = bvhview::edit::reorient(&skeleton, &motion, Up::Y, Up::Z).ok()?;
    }
    Some((skeleton, motion))
}
