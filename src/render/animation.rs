//! A take as one animated picture: GIF (the gif crate), APNG (the png crate) or MP4 video
//! ([`crate::render::video`]), frames drawn by the same offscreen renderer as `snapshot`, written
//! whole or not at all (`io::output`).

use crate::io::error::Error;
use crate::limits::GIF_MAX_FPS;
pub use crate::render::video_size::{check_video_size, encoded_size};
use crate::render::{Frame, Image};
use std::ops::Range;
use std::path::Path;

/// The animated formats `snapshot --frames` writes.
///
/// ```
/// use bvhview::render::{Image, animation::{AnimationFormat, default_fps, write}};
/// use std::path::Path;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// assert_eq!(AnimationFormat::of(Path::new("walk.gif")), Some(AnimationFormat::Gif));
/// assert_eq!(AnimationFormat::of(Path::new("walk.jpg")), None);
/// assert_eq!(default_fps(1.0 / 120.0, AnimationFormat::Gif), 50.0); // a GIF plays at most this fast
/// // Two 1 × 1 pictures, black then white, as a GIF at 10 fps.
/// let pictures = [0, 255].map(|shade| Ok(Image { width: 1, height: 1, rgb: vec![shade; 3] }));
/// let folder = tempfile::tempdir().unwrap();
/// let path = folder.path().join("blink.gif");
/// write(&path, AnimationFormat::Gif, (1, 1), 10.0, pictures.into_iter(), 2)?;
/// assert!(std::fs::read(&path).unwrap().starts_with(b"GIF89a"));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimationFormat {
    /// GIF (`.gif`): 256 colours a frame, delays in hundredths of a second.
    Gif,
    /// Animated PNG (`.apng`, or `.png` with `--frames`).
    Apng,
    /// H.264 video in an MP4 file (`.mp4`; the cargo feature `video`).
    Mp4,
}

impl AnimationFormat {
    /// The format an output name asks for, if animated.
    pub fn of(path: &Path) -> Option<AnimationFormat> {
        match crate::take::extension(path).as_str() {
            "gif" => Some(AnimationFormat::Gif),
            "apng" | "png" => Some(AnimationFormat::Apng),
            "mp4" => Some(AnimationFormat::Mp4),
            _ => None,
        }
    }
}

/// The rate an animation plays at when none is asked for: the file's own (30 when the file has
/// no frame time), at most [`GIF_MAX_FPS`] for a GIF.
pub fn default_fps(frame_time: f64, format: AnimationFormat) -> f64 {
    let rate = if frame_time > 0.0 && frame_time.is_finite() {
        1.0 / frame_time
    } else {
        30.0
    };
    // Within what `--fps` takes: an hour-long frame plays for 100 s.
    match format {
        AnimationFormat::Gif => rate.clamp(crate::limits::MIN_FPS, GIF_MAX_FPS),
        AnimationFormat::Apng | AnimationFormat::Mp4 => {
            rate.clamp(crate::limits::MIN_FPS, crate::limits::MAX_FPS)
        }
    }
}

/// The take's frames an animation at `fps` shows: for each of its ticks from the start of
/// `range`, the frame at that time (so a slower rate skips frames, a faster one repeats them).
/// Refused past [`crate::limits::MAX_ANIMATION_FRAMES`].
pub fn sampled_frames(range: Range<usize>, frame_time: f64, fps: f64) -> Result<Vec<usize>, Error> {
    if range.is_empty() {
        return Ok(Vec::new());
    }
    if !(frame_time > 0.0 && frame_time.is_finite() && fps > 0.0) {
        crate::limits::animation_frames(range.len(), 1.0, 1.0)?;
        return Ok(range.collect());
    }
    let ticks = crate::limits::animation_frames(range.len(), frame_time, fps)?;
    Ok((0..ticks)
        .map(|tick| {
            let offset = (tick as f64 / fps / frame_time + 1e-9).floor() as usize;
            (range.start + offset).min(range.end - 1)
        })
        .collect())
}

/// Writes the pictures `frames` yields as one animation at `fps`, looping.
/// Draws `count` pictures on this thread (the GL context's) while another thread encodes and
/// writes them (`write`, given the pictures in order): the two overlap, so a sequence costs
/// about the larger of drawing and encoding per frame, not their sum. The first error either
/// side meets ends both.
pub fn overlapped<P: Send, T: Send>(
    count: usize,
    mut draw: impl FnMut(usize) -> Result<P, Error>,
    write: impl FnOnce(std::sync::mpsc::IntoIter<Result<P, Error>>) -> Result<T, Error> + Send,
) -> Result<T, Error> {
    // Two pictures in flight: enough to keep both threads busy, little memory.
    let (sender, receiver) = std::sync::mpsc::sync_channel::<Result<P, Error>>(2);
    std::thread::scope(|scope| {
        let writer = scope.spawn(move || write(receiver.into_iter()));
        for index in 0..count {
            let picture = draw(index);
            let failed = picture.is_err();
            // A writer that stopped (an error of its own) no longer listens: its error counts.
            if sender.send(picture).is_err() || failed {
                break;
            }
        }
        drop(sender);
        writer
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// [`overlapped`] for pictures drawn by [`crate::render::Renderer::render_frame`]: each is
/// turned into an [`Image`] (flipped, alpha dropped) on the writing thread, which then hands its
/// buffer back for a later frame to be drawn into; `draw` gets that buffer when one is back.
pub fn drawn_and_written<T: Send>(
    count: usize,
    mut draw: impl FnMut(usize, Option<Vec<u8>>) -> Result<Frame, Error>,
    write: impl FnOnce(&mut dyn Iterator<Item = Result<Image, Error>>) -> Result<T, Error> + Send,
) -> Result<T, Error> {
    let (spares, recycled) = std::sync::mpsc::channel();
    overlapped(
        count,
        |index| draw(index, recycled.try_recv().ok()),
        move |frames| {
            let mut pictures = frames.map(|frame| {
                let (image, buffer) = frame?.into_image();
                // The drawing thread may have ended: then the buffer is simply dropped.
                let _ = spares.send(buffer);
                Ok(image)
            });
            write(&mut pictures)
        },
    )
}

/// Writes `count` pictures of `width × height` from `frames` to `path` as one looping
/// animation in `format` at `fps`, whole or not at all.
pub fn write(
    path: &Path,
    format: AnimationFormat,
    (width, height): (u32, u32),
    fps: f64,
    frames: impl Iterator<Item = Result<Image, Error>>,
    count: usize,
) -> Result<(), Error> {
    let mut file = crate::io::output::AtomicFile::create(path)?;
    let out = &mut file;
    let encoding =
        |e: &dyn std::fmt::Display| Error::output(path, std::io::Error::other(e.to_string()));
    match format {
        AnimationFormat::Gif => {
            let (w, h) = (
                u16::try_from(width).map_err(|_| {
                    Error::limit(
                        "pixels wide",
                        65535,
                        width.into(),
                        "a GIF is at most 65535 wide",
                    )
                })?,
                u16::try_from(height).map_err(|_| {
                    Error::limit(
                        "pixels high",
                        65535,
                        height.into(),
                        "a GIF is at most 65535 high",
                    )
                })?,
            );
            let mut encoder = gif::Encoder::new(out, w, h, &[]).map_err(|e| encoding(&e))?;
            encoder
                .set_repeat(gif::Repeat::Infinite)
                .map_err(|e| encoding(&e))?;
            // GIF counts delays in hundredths of a second.
            let delay = (100.0 / fps).round().clamp(2.0, 65535.0) as u16;
            for image in frames {
                let image = image?;
                let mut frame = gif::Frame::from_rgb_speed(w, h, &image.rgb, 10);
                frame.delay = delay;
                encoder.write_frame(&frame).map_err(|e| encoding(&e))?;
            }
            encoder.into_inner().map_err(|e| encoding(&e))?;
        }
        AnimationFormat::Apng => {
            let mut encoder = png::Encoder::new(out, width, height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            // As for a sequence of PNGs: fdeflate's fast level, the same pixels.
            encoder.set_compression(png::Compression::Fast);
            let count = u32::try_from(count.max(1)).unwrap_or(u32::MAX);
            encoder.set_animated(count, 0).map_err(|e| encoding(&e))?;
            // The delay as a fraction of a second: 1000 / (1000 · fps).
            // Thousandths of a second where they fit (65.5 s), whole seconds for slower rates.
            let (delay, unit) = if 1000.0 / fps <= 65535.0 {
                ((1000.0 / fps).round().max(1.0) as u16, 1000)
            } else {
                ((1.0 / fps).round().clamp(1.0, 65535.0) as u16, 1)
            };
            encoder
                .set_frame_delay(delay, unit)
                .map_err(|e| encoding(&e))?;
            let mut writer = encoder.write_header().map_err(|e| encoding(&e))?;
            for image in frames {
                let image = image?;
                writer
                    .write_image_data(&image.rgb)
                    .map_err(|e| encoding(&e))?;
            }
            writer.finish().map_err(|e| encoding(&e))?;
        }
        #[cfg(feature = "video")]
        AnimationFormat::Mp4 => {
            let folder = out.folder().map(Path::to_path_buf);
            let mut video =
                crate::render::video::Mp4::new((width, height), fps, crate::io::parallel::cores())?
                    .spool_in(folder.as_deref());
            for image in frames {
                video.push(&image?)?;
            }
            video.finish_into(out, path)?;
        }
        #[cfg(not(feature = "video"))]
        AnimationFormat::Mp4 => {
            drop(frames);
            return Err(crate::io::absent::without(
                "video",
                "MP4 video",
                &path.display().to_string(),
            ));
        }
    }
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(shade: u8) -> Image {
        Image {
            width: 1,
            height: 1,
            rgb: vec![shade; 3],
        }
    }

    #[test]
    fn overlapped_writes_every_picture_in_order_and_stops_at_the_first_error() {
        // In order, all of them.
        let shades = overlapped(
            50,
            |i| Ok(picture(i as u8)),
            |pictures| {
                pictures
                    .map(|p| p.map(|p| p.rgb[0]))
                    .collect::<Result<Vec<_>, _>>()
            },
        )
        .unwrap();
        assert_eq!(shades, (0..50).collect::<Vec<u8>>());
        // A drawing error ends the sequence and is the result; nothing is drawn after it.
        let mut drawn = 0;
        let error = overlapped(
            50,
            |i| {
                drawn += 1;
                if i == 7 {
                    Err(Error::usage("frame 7"))
                } else {
                    Ok(picture(0))
                }
            },
            |pictures| {
                pictures
                    .map(|p| p.map(|_| ()))
                    .collect::<Result<Vec<_>, _>>()
            },
        )
        .unwrap_err();
        assert_eq!(error.to_string(), "frame 7");
        assert_eq!(drawn, 8);
        // A writing error stops the drawing soon after (two pictures in flight at most).
        let mut drawn = 0;
        let error = overlapped(
            1000,
            |_| {
                drawn += 1;
                Ok(picture(0))
            },
            |mut pictures| -> Result<(), Error> {
                pictures.next();
                Err(Error::usage("disk full"))
            },
        )
        .unwrap_err();
        assert_eq!(error.to_string(), "disk full");
        assert!(drawn < 1000, "{drawn}");
    }

    #[test]
    fn frames_are_sampled_by_time() {
        // 120 fps shown at 30: every fourth frame.
        assert_eq!(
            sampled_frames(0..12, 1.0 / 120.0, 30.0).unwrap(),
            vec![0, 4, 8]
        );
        // 30 fps shown at 60: each frame twice.
        assert_eq!(
            sampled_frames(2..4, 1.0 / 30.0, 60.0).unwrap(),
            vec![2, 2, 3, 3]
        );
        // The file's own rate: every frame.
        assert_eq!(
            sampled_frames(0..5, 0.04, 25.0).unwrap(),
            vec![0, 1, 2, 3, 4]
        );
        assert_eq!(default_fps(1.0 / 120.0, AnimationFormat::Gif), GIF_MAX_FPS);
        assert_eq!(default_fps(1.0 / 120.0, AnimationFormat::Apng), 120.0);
    }
}
