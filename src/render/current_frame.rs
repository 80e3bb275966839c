//! The frame a picture draws: C++'s `BVH::setCurrentFrame`, checked.

use crate::io::error::Error;
use crate::model::motion::Motion;

/// C++: `BVH::setCurrentFrame`: the MOTION row `index`. The article only `assert`s the range
/// (and its `draw` reads `frameData[0]` even when there are no frames); here an index out of
/// range is an error, and a take without frames draws its rest pose (`None`).
pub fn frame_values(motion: &Motion, index: usize) -> Result<Option<&[f32]>, Error> {
    if motion.frame_count() == 0 {
        return if index == 0 {
            Ok(None)
        } else {
            Err(Error::invalid(
                "frame",
                index.to_string(),
                "the file has no frames (only 0, the rest pose)",
            ))
        };
    }
    if index >= motion.frame_count() {
        return Err(Error::invalid(
            "frame",
            index.to_string(),
            format!("the file has frames 0 to {}", motion.frame_count() - 1),
        ));
    }
    Ok(Some(motion.frame(index)))
}
