//! H.264 video in an MP4 file (`snapshot --frames A..B -o OUT.mp4`, the window's recording):
//! OpenH264 (Cisco's encoder, compiled from its source by the `openh264` crate) encodes each
//! picture and the `mp4` crate writes the container. Nothing is downloaded at build time and
//! nothing outside the program runs: no ffmpeg, no system codec.
//!
//! H.264 as players expect it (4:2:0 colour) needs even sides: a picture of an odd width or
//! height is encoded one pixel wider or higher, its last column or row repeated
//! ([`crate::render::animation::encoded_size`]). Colours are BT.601 limited range, as the
//! stream's VUI says, converted here rather than by OpenH264's converter: each 2 × 2 block's
//! shared colour is its mean, and each pixel's brightness the one that comes nearest its own
//! red, green and blue with that colour. On the studio look's thin coloured lines that is 35.2
//! dB from the PNG where colour taken level with the left column ([1 2 1]) gave 34.6, at the
//! same quantiser. A key frame every two seconds' worth of pictures lets a player seek (in a
//! window's recording, where a picture can last long, every 2 × fps pictures).

use crate::io::error::Error;
use crate::render::Image;
use crate::render::video_size::{check_video_size, encoded_size};
use openh264::OpenH264API;
use openh264::encoder::{
    Encoder, EncoderConfig, FrameRate, FrameType, IntraFramePeriod, QpRange, RateControlMode,
    VuiConfig,
};
use openh264::formats::YUVSource;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// The quantiser frames are encoded with (H.264's 0–51, lower is finer; OpenH264's rate control
/// may raise it a step or two at a change of scene). At 12 the colour's half resolution is all
/// that separates a frame from its PNG: a finer one measured the same (GUIDE, Video).
const QUANTISER: u8 = 12;

/// An MP4 being written: pictures in, one H.264 sample each, the file's bytes at the end. The
/// samples wait in an unnamed temporary file (MP4's index goes after them and points back
/// into them), so a long recording costs disk, not memory: in the output's own folder when
/// [`Mp4::spool_in`] names it (the system's temporary folder may be in memory), else there.
///
/// ```
/// use bvhview::render::{Image, video::Mp4};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// // Ten grey 33 × 17 pictures at 25 frames per second, growing lighter.
/// let mut video = Mp4::new((33, 17), 25.0, 1)?;
/// for shade in 0..10u8 {
///     video.push(&Image { width: 33, height: 17, rgb: vec![shade * 20; 33 * 17 * 3] })?;
/// }
/// let bytes = video.finish()?;
/// assert_eq!(&bytes[4..8], b"ftyp");
/// # Ok(())
/// # }
/// ```
pub struct Mp4 {
    encoder: Encoder,
    /// The pictures' size, and the encoded (even) one.
    size: (u32, u32),
    even: (u32, u32),
    /// The picture in YUV, kept from frame to frame.
    yuv: Planes,
    /// Started at the first frame, which carries the parameter sets the header needs.
    writer: Option<mp4::Mp4Writer<BufWriter<File>>>,
    /// Where the samples wait; `None`: the system's temporary folder.
    spool: Option<PathBuf>,
    /// Ticks per second of the track and ticks per frame: a frame lasts exactly `1 / fps`.
    timescale: u32,
    ticks: u32,
    /// Pictures in, and the frames they last together.
    pictures: u64,
    frames: u64,
}

/// Most ticks a frame lasts, and most ticks a second, of an MP4's track.
const MOST_TICKS: u32 = 100_000;
const MOST_TIMESCALE: u32 = 1_000_000;

/// The track's ticks a second and ticks a frame for `fps`: thousandths of a frame a second
/// when they say it within 10 parts in a million (120 fps: 120,000 ticks a second, 1,000 a
/// frame; a BVH's `Frame Time: 0.0083333`, 120.0005 fps, is the 120 it was written for), else
/// the whole ticks whose ratio is nearest `fps` (0.0137: 137 a second, 10,000 a frame;
/// thousandths wrote it as 0.014, 2% off).
fn rate_ticks(fps: f64) -> (u32, u32) {
    let thousandths = (fps * 1000.0).round();
    if (thousandths / 1000.0 - fps).abs() <= 1e-5 * fps {
        return (
            thousandths.clamp(1.0, f64::from(MOST_TIMESCALE)) as u32,
            1000,
        );
    }
    let mut best = (
        thousandths.clamp(1.0, f64::from(MOST_TIMESCALE)) as u32,
        1000,
    );
    let mut error = (f64::from(best.0) / 1000.0 - fps).abs();
    for ticks in 1..=MOST_TICKS {
        let timescale = (fps * f64::from(ticks)).round();
        if !(1.0..=f64::from(MOST_TIMESCALE)).contains(&timescale) {
            continue;
        }
        let off = (timescale / f64::from(ticks) - fps).abs();
        if off < error {
            (best, error) = ((timescale as u32, ticks), off);
        }
        if off == 0.0 {
            break;
        }
    }
    best
}

/// The rate an MP4 asked for at `fps` is written at (its track's whole ticks a second over
/// whole ticks a frame): `fps` itself, or the nearest such ratio.
pub fn written_rate(fps: f64) -> f64 {
    let (timescale, ticks) = rate_ticks(fps);
    f64::from(timescale) / f64::from(ticks)
}

impl Mp4 {
    /// A video of pictures `width × height` at `fps` frames per second (from
    /// [`crate::limits::MIN_FPS`] to [`crate::limits::MAX_FPS`]); `threads`: OpenH264's
    /// (in one slice a picture, a second thread measured no faster: `bvhview-bench --encoders`).
    pub fn new((width, height): (u32, u32), fps: f64, threads: usize) -> Result<Mp4, Error> {
        check_video_size(width, height)?;
        let fps = crate::limits::fps(fps, false)?;
        let even = encoded_size(width, height);
        let (timescale, ticks) = rate_ticks(fps);
        let config = EncoderConfig::new()
            // The quantiser's range is one value, so every frame has the same quality and none
            // is dropped to meet a bit rate. (Buffer-based: the modes that aim at a bit rate
            // print a warning when frames may not be dropped.)
            .rate_control_mode(RateControlMode::Bufferbased)
            .qp(QpRange::new(QUANTISER, QUANTISER))
            .skip_frames(false)
            .max_frame_rate(FrameRate::from_hz(fps as f32))
            .intra_frame_period(IntraFramePeriod::from_num_frames(
                (2.0 * fps).round().clamp(1.0, 600.0) as u32,
            ))
            .num_threads(threads.clamp(1, 4) as u16)
            .vui(VuiConfig::bt601());
        let encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| encoder_error(&e))?;
        Ok(Mp4 {
            encoder,
            size: (width, height),
            even,
            yuv: Planes::new(even.0 as usize, even.1 as usize),
            writer: None,
            spool: None,
            timescale,
            ticks,
            pictures: 0,
            frames: 0,
        })
    }

    /// Keeps the samples in `folder` until the end (the output's folder, so that they take room
    /// on its disk and not in a temporary folder held in memory); `None` leaves them in the
    /// system's temporary folder.
    pub fn spool_in(mut self, folder: Option<&Path>) -> Mp4 {
        self.spool = folder.map(Path::to_path_buf);
        self
    }

    /// Encodes the next picture (of the size given to [`Mp4::new`]), one frame long.
    pub fn push(&mut self, image: &Image) -> Result<(), Error> {
        self.push_lasting(image, 1)
    }

    /// Encodes the next picture, shown for `frames` frames (at least 1): one sample in the
    /// file however long it lasts (the window's recording holds a still picture this way), or
    /// as many as a sample's 32-bit duration needs for a still of days.
    pub fn push_lasting(&mut self, image: &Image, frames: u64) -> Result<(), Error> {
        // The muxer adds a sample's duration to the chunk's, kept in 32 bits, which holds up to
        // a second before the chunk is written: a sample leaves that second free.
        let most = u64::from((u32::MAX - self.timescale) / self.ticks);
        let mut left = frames.max(1);
        while left > 0 {
            let now = left.min(most);
            self.push_sample(image, now as u32)?;
            left -= now;
        }
        self.pictures += 1;
        Ok(())
    }

    /// One picture, one sample `frames` frames long (no more than its duration holds).
    fn push_sample(&mut self, image: &Image, frames: u32) -> Result<(), Error> {
        let duration = self.ticks * frames;
        if (image.width, image.height) != self.size
            || image.rgb.len() != image.width as usize * image.height as usize * 3
        {
            return Err(Error::usage(format!(
                "a {}x{} picture in a {}x{} video",
                image.width, image.height, self.size.0, self.size.1
            )));
        }
        self.yuv.fill(image);
        let encoded = self
            .encoder
            .encode(&self.yuv)
            .map_err(|e| encoder_error(&e))?;
        let key = encoded.frame_type() == FrameType::IDR;
        let (mut sample, mut sps, mut pps) = (Vec::new(), None, None);
        for layer in (0..encoded.num_layers()).filter_map(|i| encoded.layer(i)) {
            for nal in (0..layer.nal_count()).filter_map(|i| layer.nal_unit(i)) {
                let nal = without_start_code(nal);
                match nal.first().map(|byte| byte & 0x1f) {
                    None => {}
                    Some(7) => sps = Some(nal.to_vec()),
                    Some(8) => pps = Some(nal.to_vec()),
                    // Each NAL unit in the sample after its length (MP4's `avcC` layout).
                    Some(_) => {
                        let length = u32::try_from(nal.len())
                            .map_err(|_| encoder_error(&"a NAL unit over 4 GB"))?;
                        sample.extend_from_slice(&length.to_be_bytes());
                        sample.extend_from_slice(nal);
                    }
                }
            }
        }
        if sample.is_empty() {
            return Err(encoder_error(&format_args!(
                "picture {} came out empty",
                self.pictures
            )));
        }
        if self.writer.is_none() {
            let (Some(sps), Some(pps)) = (sps, pps) else {
                return Err(encoder_error(&"the first frame has no parameter sets"));
            };
            let samples = match &self.spool {
                Some(folder) => tempfile::tempfile_in(folder),
                None => tempfile::tempfile(),
            }
            .map_err(|e| Error::output(&self.spool_folder(), e))?;
            let started = self.start(BufWriter::new(samples), sps, pps);
            self.writer = Some(started.map_err(|e| self.muxer_error(e))?);
        }
        let writer = self.writer.as_mut().expect("started above");
        let written = writer.write_sample(
            1,
            &mp4::Mp4Sample {
                start_time: self.frames * u64::from(self.ticks),
                duration,
                rendering_offset: 0,
                is_sync: key,
                bytes: sample.into(),
            },
        );
        written.map_err(|e| self.muxer_error(e))?;
        self.frames += u64::from(frames);
        Ok(())
    }

    fn start(
        &self,
        samples: BufWriter<File>,
        sps: Vec<u8>,
        pps: Vec<u8>,
    ) -> mp4::Result<mp4::Mp4Writer<BufWriter<File>>> {
        let brand = |name: &[u8; 4]| mp4::FourCC::from(*name);
        let config = mp4::Mp4Config {
            major_brand: brand(b"isom"),
            minor_version: 512,
            compatible_brands: vec![
                brand(b"isom"),
                brand(b"iso2"),
                brand(b"avc1"),
                brand(b"mp41"),
            ],
            // The track's own: a movie in milliseconds rounded each frame down (1–4 % short).
            timescale: self.timescale,
        };
        let mut writer = mp4::Mp4Writer::write_start(samples, &config)?;
        writer.add_track(&mp4::TrackConfig {
            track_type: mp4::TrackType::Video,
            timescale: self.timescale,
            language: "und".to_string(),
            media_conf: mp4::MediaConfig::AvcConfig(mp4::AvcConfig {
                width: self.even.0 as u16,
                height: self.even.1 as u16,
                seq_param_set: sps,
                pic_param_set: pps,
            }),
        })?;
        Ok(writer)
    }

    /// The folder the samples wait in.
    fn spool_folder(&self) -> PathBuf {
        self.spool.clone().unwrap_or_else(std::env::temp_dir)
    }

    /// The muxer's error: a file that could not be written names the folder the samples wait
    /// in (a full disk is not the input's fault); anything else is the muxer's.
    fn muxer_error(&self, e: mp4::Error) -> Error {
        match e {
            mp4::Error::IoError(e) => Error::output(&self.spool_folder(), e),
            other => Error::usage(format!("the MP4 writer: {other}")),
        }
    }

    /// How many pictures are in, and the frames they last together.
    pub fn length(&self) -> (u64, u64) {
        (self.pictures, self.frames)
    }

    /// The whole file in memory: refused with no picture in it.
    pub fn finish(self) -> Result<Vec<u8>, Error> {
        let mut bytes = Vec::new();
        self.finish_into(&mut bytes, Path::new("the video in memory"))?;
        Ok(bytes)
    }

    /// The whole file written to `out` (`path` names it in an error): refused with no
    /// picture in it.
    pub fn finish_into(mut self, out: &mut dyn Write, path: &Path) -> Result<(), Error> {
        let Some(mut writer) = self.writer.take() else {
            return Err(Error::usage("a video needs one frame or more"));
        };
        writer.write_end().map_err(|e| self.muxer_error(e))?;
        // The samples' last bytes reach their file here.
        let mut file = writer
            .into_writer()
            .into_inner()
            .map_err(|e| Error::output(&self.spool_folder(), e.into_error()))?;
        file.seek(SeekFrom::Start(0))
            .and_then(|_| std::io::copy(&mut file, out))
            .map_err(|e| Error::output(path, e))?;
        Ok(())
    }
}

/// A picture in H.264's 4:2:0 YUV: full-size luma, colour at half size each way.
struct Planes {
    width: usize,
    height: usize,
    y: Vec<u8>,
    u: Vec<u8>,
    v: Vec<u8>,
    /// A picture of an odd side, made even.
    padded: Vec<u8>,
}

impl Planes {
    fn new(width: usize, height: usize) -> Planes {
        let chroma = (width / 2) * (height / 2);
        Planes {
            width,
            height,
            y: vec![0; width * height],
            u: vec![0; chroma],
            v: vec![0; chroma],
            padded: Vec::new(),
        }
    }

    /// `image` (at most one pixel smaller each way: its edge repeats) in BT.601 limited range.
    ///
    /// Each 2 × 2 block shares one colour, the mean of its four pixels. Each pixel's brightness
    /// is then the one that, with that shared colour, comes nearest its red, green and blue
    /// together (libwebp's "sharp YUV" idea, in one step): where a thin coloured line shares a
    /// block with the background, the shared colour's error is not doubled by a brightness
    /// computed apart from it.
    fn fill(&mut self, image: &Image) {
        let (width, height) = (image.width as usize, image.height as usize);
        let rgb = if (width, height) == (self.width, self.height) {
            &image.rgb
        } else {
            // One pixel short each way at most: the last column and row repeated.
            self.padded.resize(self.width * self.height * 3, 0);
            for (y, row) in self.padded.chunks_exact_mut(self.width * 3).enumerate() {
                let from = &image.rgb[y.min(height - 1) * width * 3..][..width * 3];
                row[..width * 3].copy_from_slice(from);
                row.copy_within((width - 1) * 3..width * 3, (self.width - 1) * 3);
            }
            &self.padded
        };
        // In whole numbers with 16 bits after the point; the coefficients are BT.601's (limited
        // range) times 2^16, over 4 where they take the sum of a block's four pixels.
        let byte = |fixed: i64| ((fixed + 0x8000) >> 16).clamp(0, 255) as u8;
        let rows = rgb.chunks_exact(self.width * 6);
        let luma = self.y.chunks_exact_mut(self.width * 2);
        let colours = self
            .u
            .chunks_exact_mut(self.width / 2)
            .zip(self.v.chunks_exact_mut(self.width / 2));
        for ((pair, luma), (u_row, v_row)) in rows.zip(luma).zip(colours) {
            let (top, bottom) = pair.split_at(self.width * 3);
            let (luma_top, luma_bottom) = luma.split_at_mut(self.width);
            let pixels = top.chunks_exact(6).zip(bottom.chunks_exact(6));
            let outputs = luma_top
                .chunks_exact_mut(2)
                .zip(luma_bottom.chunks_exact_mut(2));
            for (((top, bottom), (y_top, y_bottom)), (u, v)) in pixels
                .zip(outputs)
                .zip(u_row.iter_mut().zip(v_row.iter_mut()))
            {
                let block = [&top[..3], &top[3..], &bottom[..3], &bottom[3..]];
                let mut totals = [0i64; 4];
                let mut sum = [0i64; 3];
                for (total, pixel) in totals.iter_mut().zip(block) {
                    let [r, g, b] = [pixel[0], pixel[1], pixel[2]].map(i64::from);
                    *total = r + g + b;
                    sum = [sum[0] + r, sum[1] + g, sum[2] + b];
                }
                let [r, g, b] = sum;
                // U = 128 - 0.148223 R - 0.290993 G + 0.439216 B, V = 128 + 0.439216 R
                // - 0.367788 G - 0.071427 B, of the block's mean colour.
                *u = byte((128 << 16) - 2429 * r - 4768 * g + 7196 * b);
                *v = byte((128 << 16) + 7196 * r - 6026 * g - 1170 * b);
                // What the colour adds to red, green and blue together when decoded (1.596 V to
                // red, -0.392 U - 0.813 V to green, 2.017 U to blue: 1.625470 U + 0.783059 V),
                // beside brightness's 1.164383 to each (3.493149 together: 18761 / 2^16 is its
                // inverse).
                let colour = 106_527 * (i64::from(*u) - 128) + 51_318 * (i64::from(*v) - 128);
                let bright =
                    |total: i64| byte((16 << 16) + ((((total << 16) - colour) * 18_761) >> 16));
                (y_top[0], y_top[1]) = (bright(totals[0]), bright(totals[1]));
                (y_bottom[0], y_bottom[1]) = (bright(totals[2]), bright(totals[3]));
            }
        }
    }
}

impl YUVSource for Planes {
    fn dimensions(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    fn strides(&self) -> (usize, usize, usize) {
        (self.width, self.width / 2, self.width / 2)
    }

    fn y(&self) -> &[u8] {
        &self.y
    }

    fn u(&self) -> &[u8] {
        &self.u
    }

    fn v(&self) -> &[u8] {
        &self.v
    }
}

/// A NAL unit as OpenH264 gives it, its Annex B start code (`00 00 01` or `00 00 00 01`) left
/// out.
fn without_start_code(nal: &[u8]) -> &[u8] {
    let zeros = nal.iter().take_while(|&&byte| byte == 0).count();
    match nal.get(zeros) {
        Some(1) if zeros >= 2 => &nal[zeros + 1..],
        _ => nal,
    }
}

fn encoder_error(e: &dyn std::fmt::Display) -> Error {
    Error::usage(format!("the H.264 encoder (OpenH264): {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_codes_of_both_lengths_are_left_out() {
        assert_eq!(without_start_code(&[0, 0, 0, 1, 0x67, 9]), &[0x67, 9]);
        assert_eq!(without_start_code(&[0, 0, 1, 0x68]), &[0x68]);
        assert_eq!(without_start_code(&[0x65, 1]), &[0x65, 1]);
    }

    #[test]
    fn a_picture_of_another_size_is_refused() {
        let mut video = Mp4::new((16, 16), 30.0, 1).unwrap();
        let wrong = Image {
            width: 2,
            height: 4,
            rgb: vec![0; 24],
        };
        assert!(video.push(&wrong).unwrap_err().to_string().contains("2x4"));
        assert!(Mp4::new((0, 4), 30.0, 1).is_err());
        assert!(
            Mp4::new((15, 16), 30.0, 1).is_err(),
            "OpenH264 takes 16 pixels a side and more"
        );
        assert!(Mp4::new((16, 16), 30.0, 1).unwrap().finish().is_err());
    }

    /// 0.0137 frames per second was once written as 0.014 (thousandths of a frame a
    /// second); now as 137 ticks a second over 10,000 a frame, exactly the rate asked, and a
    /// rate of thousandths keeps its old ticks (outputs stay byte for byte).
    #[test]
    fn a_rate_is_written_as_asked_to_the_ticks_the_track_holds() {
        assert_eq!(rate_ticks(0.0137), (137, 10_000));
        assert_eq!(written_rate(0.0137), 0.0137);
        assert_eq!(rate_ticks(120.0), (120_000, 1000));
        assert_eq!(rate_ticks(29.97), (29_970, 1000));
        // A frame time written to seven decimals is the rate it was written for.
        assert_eq!(rate_ticks(1.0 / 0.0083333), (120_000, 1000));
        assert_eq!(rate_ticks(1000.0), (1_000_000, 1000));
        // A third of a frame a second is no decimal: the nearest ratio of whole ticks.
        assert_eq!(rate_ticks(1.0 / 3.0), (1, 3));
        let mut video = Mp4::new((16, 16), 0.0137, 1).unwrap();
        let grey = Image {
            width: 16,
            height: 16,
            rgb: vec![128; 16 * 16 * 3],
        };
        video.push(&grey).unwrap();
        video.push(&grey).unwrap();
        let bytes = video.finish().unwrap();
        let size = bytes.len() as u64;
        let file = mp4::Mp4Reader::read_header(std::io::Cursor::new(bytes), size).unwrap();
        let track = file.tracks().get(&1).unwrap();
        assert_eq!(track.timescale(), 137);
        // Two frames of 10,000 ticks: 146 s, as 2 / 0.0137 is.
        assert_eq!(track.trak.mdia.mdhd.duration, 20_000);
    }

    /// A still longer than one sample's 32-bit duration (4,294,847 frames at 1,000 ticks a
    /// frame and 120,000 a second: the muxer keeps a second of room in its 32-bit chunk
    /// length; 9.9 hours at 120 fps) is split into samples of the same picture, lasting as long
    /// together; a frame before it (in the same chunk) is what overflowed the muxer's sum. The
    /// samples wait in the folder named, and nothing is left there.
    #[test]
    fn a_still_of_days_is_split_into_samples() {
        let folder = tempfile::tempdir().unwrap();
        let mut video = Mp4::new((16, 16), 120.0, 1)
            .unwrap()
            .spool_in(Some(folder.path()));
        let grey = Image {
            width: 16,
            height: 16,
            rgb: vec![128; 16 * 16 * 3],
        };
        let most = u64::from((u32::MAX - 120_000) / 1000);
        let long = 2 * most + 7;
        video.push(&grey).unwrap();
        video.push_lasting(&grey, long).unwrap();
        video.push(&grey).unwrap();
        assert_eq!(video.length(), (3, long + 2));
        let bytes = video.finish().unwrap();
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
        let size = bytes.len() as u64;
        let file = mp4::Mp4Reader::read_header(std::io::Cursor::new(bytes), size).unwrap();
        let track = file.tracks().get(&1).unwrap();
        assert_eq!(track.sample_count(), 5);
        let seconds = (long + 2) as f64 / 120.0;
        assert!((track.duration().as_secs_f64() - seconds).abs() < 1e-3);
    }
}
