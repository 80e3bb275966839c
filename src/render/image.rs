//! Pictures: an RGB image (PNG in and out, compared pixel by pixel) and a frame as GL leaves it.

use crate::io::error::Error;
use std::path::Path;

/// An RGB picture, rows from the top down.
///
/// ```
/// use bvhview::{Take, render::{Image, SnapshotOptions, snapshot}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = SnapshotOptions { width: 64, height: 48, ..SnapshotOptions::default() };
/// let image = snapshot(&take.skeleton, &take.motion, &options)?;
/// assert_eq!((image.width, image.height, image.rgb.len()), (64, 48, 64 * 48 * 3));
/// let folder = tempfile::tempdir().unwrap();
/// let path = folder.path().join("tiny.png");
/// image.write_png(&path)?;
/// assert_eq!(Image::read_png(&path)?, image);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Red, green, blue per pixel, a byte each, row after row from the top.
    pub rgb: Vec<u8>,
}

impl Image {
    /// Writes the picture as PNG, whole or not at all, compressed as small as the default
    /// level makes it.
    pub fn write_png(&self, path: &Path) -> Result<(), Error> {
        self.write_png_at(path, png::Compression::Balanced)
    }

    /// A picture of a sequence (`snapshot --frames` into a folder) as PNG bytes: fdeflate's
    /// fast level, some three times quicker than [`Image::write_png`]'s, files two to four
    /// times larger, the same pixels. `path` names the output in a message.
    pub fn png_fast(&self, path: &Path) -> Result<Vec<u8>, Error> {
        let mut bytes = Vec::new();
        self.encode_png(&mut bytes, png::Compression::Fast, path)?;
        Ok(bytes)
    }

    fn write_png_at(&self, path: &Path, compression: png::Compression) -> Result<(), Error> {
        let mut file = crate::io::output::AtomicFile::create(path)?;
        self.encode_png(&mut file, compression, path)?;
        file.commit()
    }

    fn encode_png(
        &self,
        out: &mut impl std::io::Write,
        compression: png::Compression,
        path: &Path,
    ) -> Result<(), Error> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(compression);
        // Whatever goes wrong while encoding is a failure to write the output (exit code 1).
        let io_error = |e: png::EncodingError| match e {
            png::EncodingError::IoError(e) => Error::output(path, e),
            other => Error::output(path, std::io::Error::other(other.to_string())),
        };
        let mut writer = encoder.write_header().map_err(io_error)?;
        writer.write_image_data(&self.rgb).map_err(io_error)?;
        writer.finish().map_err(io_error)
    }

    /// Reads a PNG file of any colour type as RGB (grey repeated, alpha dropped, 16 bits cut
    /// to 8).
    pub fn read_png(path: &Path) -> Result<Image, Error> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let bad = |e: png::DecodingError| Error::usage(format!("{}: {e}", path.display()));
        let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().map_err(bad)?;
        let mut data = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader.next_frame(&mut data).map_err(bad)?;
        data.truncate(info.buffer_size());
        // 8 bits per sample after the transformations: grey, grey + alpha, RGB or RGBA.
        let rgb = match info.color_type.samples() {
            1 => data.iter().flat_map(|&g| [g, g, g]).collect(),
            2 => data
                .chunks_exact(2)
                .flat_map(|p| [p[0], p[0], p[0]])
                .collect(),
            3 => data,
            _ => data
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect(),
        };
        Ok(Image {
            width: info.width,
            height: info.height,
            rgb,
        })
    }

    /// A picture from GL's RGBA rows, which run from the bottom up.
    pub fn from_rgba_bottom_up(width: u32, height: u32, rgba: &[u8]) -> Image {
        let row_in = width.max(1) as usize * 4;
        let rows = (rgba.len() / row_in).min(height as usize);
        let mut rgb = vec![0; rows * width as usize * 3];
        // Row by row into a picture already the right size, four pixels at a time: sixteen
        // bytes of RGBA in three 32-bit words, twelve bytes of RGB out (a sequence turns every
        // frame's 1.4 MB this way).
        for (out, row) in rgb
            .chunks_exact_mut(width.max(1) as usize * 3)
            .zip(rgba.chunks_exact(row_in).take(rows).rev())
        {
            let mut to = out.chunks_exact_mut(12);
            let mut from = row.chunks_exact(16);
            for (to, from) in (&mut to).zip(&mut from) {
                let word =
                    |i: usize| u32::from_le_bytes([from[i], from[i + 1], from[i + 2], from[i + 3]]);
                let (p0, p1, p2, p3) = (word(0), word(4), word(8), word(12));
                to[0..4].copy_from_slice(&(p0 & 0xFF_FFFF | p1 << 24).to_le_bytes());
                to[4..8].copy_from_slice(&((p1 >> 8) & 0xFFFF | p2 << 16).to_le_bytes());
                to[8..12].copy_from_slice(&((p2 >> 16) & 0xFF | p3 << 8).to_le_bytes());
            }
            for (to, pixel) in to
                .into_remainder()
                .chunks_exact_mut(3)
                .zip(from.remainder().chunks_exact(4))
            {
                to.copy_from_slice(&pixel[..3]);
            }
        }
        Image { width, height, rgb }
    }

    /// A picture of where two pictures differ: differing pixels red, the others a dim copy.
    pub fn difference(&self, other: &Image) -> Image {
        let mut rgb = Vec::with_capacity(self.rgb.len());
        for (a, b) in self.rgb.chunks_exact(3).zip(other.rgb.chunks_exact(3)) {
            if a == b {
                rgb.extend(a.iter().map(|&c| c / 4));
            } else {
                rgb.extend([255, 0, 0]);
            }
        }
        Image {
            width: self.width,
            height: self.height,
            rgb,
        }
    }

    /// Pixels whose RGB differ from `other`'s (the sizes must match).
    pub fn differing_pixels(&self, other: &Image) -> usize {
        assert_eq!(
            (self.width, self.height),
            (other.width, other.height),
            "picture sizes differ"
        );
        self.rgb
            .chunks_exact(3)
            .zip(other.rgb.chunks_exact(3))
            .filter(|(a, b)| a != b)
            .count()
    }
}

/// A picture as GL draws it: RGBA rows from the bottom up (see [`Renderer::render_frame`](super::Renderer::render_frame)).
///
/// ```
/// use bvhview::{Take, render::{Overlay, Renderer, SnapshotOptions, paint::Shown}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = SnapshotOptions { width: 32, height: 32, ..SnapshotOptions::default() };
/// let shown = Shown::of(&take.skeleton, &take.motion, options.up, options.offset_mode, false);
/// let mut renderer = Renderer::new(32, 32)?;
/// let frame = renderer.render_frame(&[shown], &options, &Overlay::default(), None)?;
/// assert_eq!(frame.rgba.len(), 32 * 32 * 4);
/// let (image, spare) = frame.into_image(); // the buffer back, for the next frame
/// assert_eq!(image, renderer.render(&take.skeleton, &take.motion, &options)?);
/// assert_eq!(spare.len(), 32 * 32 * 4);
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Frame {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Red, green, blue, alpha per pixel, row after row from the bottom.
    pub rgba: Vec<u8>,
}

impl Frame {
    /// The picture, and the buffer back for the next frame to be drawn into.
    pub fn into_image(self) -> (Image, Vec<u8>) {
        let image = Image::from_rgba_bottom_up(self.width, self.height, &self.rgba);
        (image, self.rgba)
    }
}
