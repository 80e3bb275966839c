//! The retarget itself: the source's frames on the target's skeleton, the fast pass and the
//! plain one it is held to, and the source's feet locked on the result.

use crate::io::error::Error;
use crate::model::body::Body;
use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use crate::retarget::align::{Ups, source_offset_mode};
use crate::retarget::fast;
use crate::retarget::map::Map;
use crate::retarget::plain::{Setup, plain_frames};
use crate::take::Take;

/// The source's motion on the target skeleton: a take with the target's joints, offsets and
/// channels, and the source's frames and frame time, computed on up to `threads` threads (the
/// same values on any number). See the module's docs for the steps.
///
/// The fast path (eight frames at a time, src/retarget/fast/); [`retarget_plain`] is the same
/// work a joint and a frame at a time, which a test holds it to.
pub fn retarget(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
) -> Result<(Skeleton, Motion), Error> {
    retarget_posed(source, motion, target, None, map, ups, threads)
}

/// [`retarget`] onto a target that comes with poses of its own take (a [`Target`](crate::retarget::Target)'s): where
/// its rest pose cannot say which way its body faces (Blender's FBX rest, every bone along +y),
/// rest alignment reads its bones in one of those poses instead.
pub(crate) fn retarget_posed(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    target_poses: Option<&Motion>,
    map: &Map,
    ups: Ups,
    threads: usize,
) -> Result<(Skeleton, Motion), Error> {
    within_limits(source, motion, target)?;
    let setup = Setup::new(source, motion, target, map, ups, target_poses);
    let (data, finite) = fast::frames(&setup, source, motion, target, map, threads);
    if finite && target.joints.iter().all(|j| j.offset.is_finite()) {
        // What `finish` checks, checked already on the cores.
        let motion = Motion::new(
            motion.frame_time,
            target.channel_count(),
            motion.frame_count(),
            data,
        );
        return Ok((target.clone(), motion));
    }
    finish(target, motion, data)
}

/// The values a retarget makes, held to the limits: checked again here for callers that come
/// without a Target (its message names them).
fn within_limits(source: &Skeleton, motion: &Motion, target: &Skeleton) -> Result<(), Error> {
    crate::limits::retarget_values(
        "the retarget",
        motion.frame_count(),
        source.channel_count(),
        target.joints.len(),
        target.channel_count(),
    )
}

/// [`retarget`] done plainly: glam's 64-bit quaternions and libm's `sin`, `cos` and `atan2`, a
/// joint and a frame at a time. What the fast path is checked against.
pub fn retarget_plain(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
) -> Result<(Skeleton, Motion), Error> {
    within_limits(source, motion, target)?;
    let setup = Setup::new(source, motion, target, map, ups, None);
    let values = plain_frames(&setup, source, motion, target, map, threads);
    finish(target, motion, values.iter().map(|&v| v as f32).collect())
}

/// The channel values [`retarget`] (`fast`) or [`retarget_plain`] computes, before they are
/// rounded to 32 bits: for the test that holds the two together.
#[doc(hidden)]
pub fn retargeted_values(
    source: &Skeleton,
    motion: &Motion,
    target: &Skeleton,
    map: &Map,
    ups: Ups,
    threads: usize,
    fast: bool,
) -> Vec<f64> {
    let setup = Setup::new(source, motion, target, map, ups, None);
    match fast {
        true => fast::frames(&setup, source, motion, target, map, threads).0,
        false => plain_frames(&setup, source, motion, target, map, threads),
    }
}

/// `out` (`source` retargeted onto `target`) with its planted feet locked (`--lock-feet`,
/// [`crate::edit::lock_feet`]) during the contacts of the source's ankles
/// ([`Body::planted_ankles`]), not its own: the source says when a foot is planted, while the
/// retargeted feet, on legs of other proportions, may slide enough that their own reading
/// misses the contact. Each take stands as [`Take::stance`] reads it (up, metres per unit): the
/// result `out` (the take on the target) with what the user said of the target, if anything
/// ([`Target::state_on`](crate::retarget::Target::state_on)).
///
/// ```
/// use bvhview::Take;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let source = Take::open("tests/data/bvh/bvh11_131_01.bvh")?;
/// let smpl = bvhview::retarget::onto(&source, "smpl22")?;
/// let (locked, report) = bvhview::retarget::lock_feet_from_source(&source, &smpl)?;
/// assert_eq!(locked.frame_count(), source.frame_count());
/// // Every contact of the source's ankles is held on the target or named with why.
/// assert!(report.feet.iter().all(|foot| foot.held + foot.not_held.len() == foot.contacts));
/// # Ok(())
/// # }
/// ```
pub fn lock_feet_from_source(
    source: &Take,
    out: &Take,
) -> Result<(Motion, crate::edit::FeetLocked), Error> {
    let source_mode = source_offset_mode(&source.skeleton, &source.motion);
    let source_stance = source.stance(source_mode);
    let planted = Body::of(&source.skeleton).planted_ankles(
        &source.skeleton,
        &source.motion,
        source_mode,
        (source_stance.up, f64::from(source_stance.units.metres)),
        &crate::edit::LockFeet::default().planting,
    );
    let target_stance = out.stance(OffsetMode::Replace);
    crate::edit::lock_feet_when(
        &out.skeleton,
        &out.motion,
        OffsetMode::Replace,
        (target_stance.up, f64::from(target_stance.units.metres)),
        &crate::edit::LockFeet::default(),
        Some(&planted),
    )
}

/// The take, refused when a value is not finite (too large for a 32-bit float).
fn finish(target: &Skeleton, motion: &Motion, data: Vec<f32>) -> Result<(Skeleton, Motion), Error> {
    crate::edit::finite(
        "retargeting",
        target.clone(),
        Motion::new(
            motion.frame_time,
            target.channel_count(),
            motion.frame_count(),
            data,
        ),
    )
}
