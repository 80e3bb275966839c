//! The picture sizes an MP4 takes: sides rounded up to even, and the sizes OpenH264 encodes.

use crate::io::error::Error;

/// The size an MP4 of pictures `width × height` is encoded at: each side rounded up to even
/// (H.264's 4:2:0 pictures have even sides; the last column or row repeats).
///
/// ```
/// use bvhview::render::animation::encoded_size;
///
/// assert_eq!(encoded_size(640, 480), (640, 480));
/// assert_eq!(encoded_size(641, 481), (642, 482));
/// ```
pub fn encoded_size(width: u32, height: u32) -> (u32, u32) {
    (width + width % 2, height + height % 2)
}

/// Refuses a video size OpenH264 cannot encode: it takes sides of 16 pixels and more, and stops
/// at H.264's level 5.2, 3840 × 2160 either way up.
pub fn check_video_size(width: u32, height: u32) -> Result<(), Error> {
    if width < 16 || height < 16 {
        return Err(Error::usage(format!(
            "an MP4 of {width}x{height}: the H.264 encoder (OpenH264) takes pictures of 16x16 \
             and more"
        )));
    }
    if width.max(height) > 3840 || width.min(height) > 2160 {
        return Err(Error::usage(format!(
            "an MP4 of {width}x{height}: the H.264 encoder (OpenH264) takes pictures up to \
             3840x2160 (or 2160x3840)"
        )));
    }
    Ok(())
}
