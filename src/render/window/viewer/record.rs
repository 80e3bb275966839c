//! The window's recording (M, `--record OUT.mp4`): what the window shows, as it is shown, into an
//! MP4 ([`crate::render::video`]) at the rate the window plays when it starts (the take's rate
//! times the speed), at most 60 frames a second (a screen shows no more). A picture stays in the
//! video for as long as it stayed on the screen, so a pause, a turn of the camera or a step with W
//! plays back as it happened: one sample lasting as long as the picture stayed, not a copy per
//! frame (a long pause costs nothing to encode). Pictures are encoded on another thread while the
//! window goes on; the file is written when the recording stops (M again, or the window closing),
//! whole or not at all.

use crate::io::error::Error;
use crate::io::output::AtomicFile;
use crate::render::Image;
use crate::render::video::Mp4;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::thread::JoinHandle;
use std::time::Instant;

/// The most frames a second a recording takes.
pub(super) const MOST_FPS: f64 = 60.0;

pub(super) struct Recording {
    path: PathBuf,
    /// The file being written, made when the recording starts (a folder that is not there is
    /// said then, not when the window closes); the samples wait beside it.
    file: Option<AtomicFile>,
    size: (u32, u32),
    fps: f64,
    started: Instant,
    /// The picture shown now, and the frame of the video it started at: it goes to the encoder
    /// when the next one comes, with how long it lasted.
    last: Option<(Image, u64)>,
    /// Pictures handed to the encoder, and the frames they last together.
    pictures: u64,
    frames: u64,
    sender: Option<SyncSender<(Image, u64)>>,
    encoder: Option<JoinHandle<Result<Mp4, Error>>>,
}

impl Recording {
    /// Starts recording pictures of `size` into `path` at `fps` (at most [`MOST_FPS`]).
    pub(super) fn start(
        path: PathBuf,
        size: (u32, u32),
        fps: f64,
        now: Instant,
    ) -> Result<Recording, Error> {
        let fps = fps.min(MOST_FPS);
        crate::render::animation::check_video_size(size.0, size.1)?;
        let file = AtomicFile::create(&path)?;
        // One core for the encoder: the window keeps the other.
        let mut video = Mp4::new(size, fps, 1)?.spool_in(file.folder());
        // A few pictures in flight; when the encoder falls behind, the window waits for it.
        let (sender, pictures) = sync_channel::<(Image, u64)>(4);
        let encoder = std::thread::spawn(move || {
            for (picture, frames) in pictures {
                video.push_lasting(&picture, frames)?;
            }
            Ok(video)
        });
        Ok(Recording {
            path,
            file: Some(file),
            size,
            fps,
            started: now,
            last: None,
            pictures: 0,
            frames: 0,
            sender: Some(sender),
            encoder: Some(encoder),
        })
    }

    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    /// The frame of the video that `now` falls in.
    fn frame_at(&self, now: Instant) -> u64 {
        (now.saturating_duration_since(self.started).as_secs_f64() * self.fps) as u64
    }

    /// The window shows a new picture at `now`: the last one has lasted until then. Within the
    /// same frame of the video the new one takes the last one's place (the picture left on the
    /// screen before a pause is the one the video keeps).
    pub(super) fn capture(&mut self, now: Instant, picture: Image) -> Result<(), Error> {
        let frame = self.frame_at(now);
        if let Some((last, from)) = self.last.as_mut()
            && frame <= *from
        {
            *last = fitted(picture, self.size);
            return Ok(());
        }
        self.send_last(frame)?;
        self.last = Some((fitted(picture, self.size), frame));
        Ok(())
    }

    /// The picture shown until frame `until` to the encoder, lasting from its start to then.
    fn send_last(&mut self, until: u64) -> Result<(), Error> {
        let Some((picture, from)) = self.last.take() else {
            return Ok(());
        };
        let frames = until.saturating_sub(from).max(1);
        let sent = self
            .sender
            .as_ref()
            .is_some_and(|sender| sender.send((picture, frames)).is_ok());
        if !sent {
            // The encoder stopped: its error says why.
            return Err(self
                .join()
                .err()
                .unwrap_or_else(|| Error::usage("the recording's encoder stopped early")));
        }
        self.pictures += 1;
        self.frames += frames;
        Ok(())
    }

    fn join(&mut self) -> Result<Mp4, Error> {
        self.sender = None;
        match self.encoder.take() {
            Some(encoder) => encoder
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            None => Err(Error::usage("the recording has ended")),
        }
    }

    /// Stops at `now` (the last picture shown until then) and writes the file: its path, the
    /// pictures and frames it holds, and its rate.
    pub(super) fn finish(mut self, now: Instant) -> Result<Written, Error> {
        // The picture on the screen lasts until now, and at least a frame.
        let end = self.frame_at(now);
        self.send_last(end)?;
        let video = self.join()?;
        let Some(mut file) = self.file.take() else {
            return Err(Error::usage("the recording has ended"));
        };
        video.finish_into(&mut file, &self.path)?;
        file.commit()?;
        Ok(Written {
            path: self.path.clone(),
            pictures: self.pictures,
            seconds: self.frames as f64 / self.fps,
        })
    }
}

/// What a recording wrote.
pub(super) struct Written {
    pub(super) path: PathBuf,
    pub(super) pictures: u64,
    pub(super) seconds: f64,
}

/// `picture` at `size`: a window resized while recording is cut, or filled with black, at its
/// right and bottom edges.
fn fitted(picture: Image, (width, height): (u32, u32)) -> Image {
    if (picture.width, picture.height) == (width, height) {
        return picture;
    }
    let mut rgb = vec![0; width as usize * height as usize * 3];
    let (keep_width, keep_height) = (
        picture.width.min(width) as usize,
        picture.height.min(height) as usize,
    );
    for y in 0..keep_height {
        let from = &picture.rgb[y * picture.width as usize * 3..][..keep_width * 3];
        rgb[y * width as usize * 3..][..keep_width * 3].copy_from_slice(from);
    }
    Image { width, height, rgb }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn grey(shade: u8, size: (u32, u32)) -> Image {
        Image {
            width: size.0,
            height: size.1,
            rgb: vec![shade; size.0 as usize * size.1 as usize * 3],
        }
    }

    /// A recording into a folder that is not there is refused when it starts, not after the
    /// whole session when the window closes.
    #[test]
    fn a_recording_into_a_missing_folder_is_refused_at_its_start() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("missing").join("take.mp4");
        let error = Recording::start(path, (16, 16), 30.0, Instant::now())
            .err()
            .expect("refused");
        assert!(error.to_string().contains("missing"), "{error}");
    }

    #[test]
    fn a_picture_stays_in_the_video_as_long_as_it_stayed_shown() {
        let folder = tempfile::tempdir().unwrap();
        let start = Instant::now();
        let path = folder.path().join("shown.mp4");
        let mut recording = Recording::start(path.clone(), (16, 16), 120.0, start).unwrap();
        // 120 frames a second asked: 60 taken. Shown at 0 s, then at 0.5 s, stopped at 1 s.
        recording.capture(start, grey(90, (16, 16))).unwrap();
        // Within the same frame, a new picture takes the last one's place.
        recording
            .capture(start + Duration::from_millis(5), grey(10, (16, 16)))
            .unwrap();
        recording
            .capture(start + Duration::from_millis(500), grey(200, (20, 12)))
            .unwrap();
        let written = recording.finish(start + Duration::from_secs(1)).unwrap();
        assert_eq!((written.path, written.pictures), (path.clone(), 2));
        assert!((written.seconds - 1.0).abs() < 1e-9, "{}", written.seconds);
        assert_eq!(&std::fs::read(&path).unwrap()[4..8], b"ftyp");
    }

    #[test]
    fn a_resized_window_is_cut_or_filled_to_the_video_s_size() {
        let bigger = fitted(grey(50, (4, 2)), (2, 3));
        assert_eq!((bigger.width, bigger.height), (2, 3));
        assert_eq!(bigger.rgb[..12], [50; 12]);
        assert_eq!(bigger.rgb[12..], [0; 6]);
    }
}
