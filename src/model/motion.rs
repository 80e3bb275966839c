//! The MOTION section: a frame time and one flat array of values, `frames × channels`.
//!
//! C++: `float **frameData` (one heap array per frame) and `frameTime`. One flat `Vec<f32>` keeps
//! the rows contiguous and costs one allocation.

/// C++: `BVH::frameData`, `frameCount` and `frameTime`: the rows of the MOTION section.
///
/// ```
/// use bvhview::Motion;
///
/// // Two frames of three channels, at 30 frames per second.
/// let motion = Motion::new(1.0 / 30.0, 3, 2, vec![0.0, 1.0, 2.0, 10.0, 11.0, 12.0]);
/// assert_eq!(motion.get(1), Some(&[10.0, 11.0, 12.0][..]));
/// assert_eq!(motion.get(2), None);
/// assert_eq!(motion.next_frame(1), 0, "the article's W wraps to the first frame");
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    /// Seconds per frame, as the file's `Frame Time:` says.
    pub frame_time: f64,
    /// Values per frame (the skeleton's channel count).
    pub channels: usize,
    /// `frame_count() * channels` values, row after row.
    pub data: Vec<f32>,
    frames: usize,
}

impl Motion {
    /// `frames` rows of `channels` values, row after row in `data`, `frame_time` seconds apart.
    pub fn new(frame_time: f64, channels: usize, frames: usize, data: Vec<f32>) -> Motion {
        debug_assert_eq!(data.len(), frames * channels);
        Motion {
            frame_time,
            channels,
            data,
            frames,
        }
    }

    /// C++: `BVH::getFrameCount`.
    pub fn frame_count(&self) -> usize {
        self.frames
    }

    /// The values of frame `index` (C++: `frameData[index]`). Panics if `index` is out of range.
    pub fn frame(&self, index: usize) -> &[f32] {
        &self.data[index * self.channels..(index + 1) * self.channels]
    }

    /// The values of frame `index`, or `None` past the last frame.
    pub fn get(&self, index: usize) -> Option<&[f32]> {
        (index < self.frames).then(|| self.frame(index))
    }

    /// C++: `BVH::addFrame`: the frame after `current`, back to 0 after the last (the article
    /// keeps the current frame inside the class; here the caller does).
    pub fn next_frame(&self, current: usize) -> usize {
        (current + 1) % self.frames.max(1)
    }

    /// The frame before `current`, wrapping to the last (the S key; the article has none).
    pub fn previous_frame(&self, current: usize) -> usize {
        let count = self.frames.max(1);
        (current + count - 1) % count
    }

    /// Length of the take in seconds.
    pub fn duration(&self) -> f64 {
        self.frames as f64 * self.frame_time
    }
}
