//! Drawing: the article's fixed-function renderer, offscreen (OSMesa) and in a window.
//!
//! The article's picture is [`scene`] and [`draw`]; [`snapshot`] draws it offscreen. The
//! layers drawn on top (names, the step view), the offscreen context and the window are
//! private to the crate; the HUD, timeline, studio look and paint are public for the tests
//! only, and left out of these docs.

pub mod animation;
pub mod draw;
#[doc(hidden)] // the GL state machine the picture is traced and checked with, for the tests
pub mod fixed;
pub mod framing;
#[doc(hidden)]
pub mod hud;
pub(crate) mod names;
pub(crate) mod osmesa;
#[doc(hidden)]
pub mod paint;
pub(crate) mod pixels;
pub mod scene;
#[doc(hidden)]
pub mod skin_demo;
pub mod sphere;
pub(crate) mod step;
#[doc(hidden)]
pub mod studio;
#[doc(hidden)]
pub mod text;
#[doc(hidden)]
pub mod timeline;
pub mod trace;
#[cfg(feature = "video")]
pub mod video;
#[cfg(feature = "window")]
pub(crate) mod window;

/// What draws the viewer's pictures without a display, for the messages.
pub const VIEWER_OFFSCREEN: &str = "`bvhview snapshot FILE -o out.png`";
/// What draws the skinning demo without a display.
pub const SKIN_DEMO_OFFSCREEN: &str = "`bvhview skin-demo -o out.png`";

/// Why a build without the window feature opens none, and what draws without one.
pub fn without_window(offscreen: &str) -> Error {
    Error::Environment(format!(
        "this bvhview was built without its window (cargo feature `window`). {offscreen} draws \
         without one"
    ))
}

use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up};
use crate::model::skeleton::Skeleton;
use draw::Style;
use scene::{Camera, Scene};
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

/// A picture as GL draws it: RGBA rows from the bottom up (see [`Renderer::render_frame`]).
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

/// What a snapshot shows.
///
/// ```
/// use bvhview::{Take, render::{SnapshotOptions, draw::Style, snapshot}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// // Frame 10 as a stick figure, framed by the camera, 80 × 60.
/// let options = SnapshotOptions {
///     frame: 10, style: Style::Sticks, fit: true, width: 80, height: 60,
///     ..SnapshotOptions::default()
/// };
/// let image = snapshot(&take.skeleton, &take.motion, &options)?;
/// assert_eq!((image.width, image.height), (80, 60));
/// // Past the last frame is an error, not a picture.
/// let past = SnapshotOptions { frame: 344, ..options };
/// assert!(snapshot(&take.skeleton, &take.motion, &past).is_err());
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SnapshotOptions {
    /// The MOTION row drawn (0 for a take without frames: its rest pose).
    pub frame: usize,
    /// Camera angle in radians (the article's `angle`; it starts at 10).
    pub angle: f32,
    /// The picture's width in pixels.
    pub width: u32,
    /// The picture's height in pixels.
    pub height: u32,
    /// Spheres, sticks or both.
    pub style: Style,
    /// Frame the skeleton instead of the article's fixed camera.
    pub fit: bool,
    /// How position channels meet the OFFSET.
    pub offset_mode: OffsetMode,
    /// Draw a generated skin around the bones (not the article's picture).
    pub skin: bool,
    /// Only the first joints in drawing order, the last highlighted, with the step overlay
    /// (the window's J key; not the article's picture).
    pub step: Option<usize>,
    /// The file's up axis: Z stands the skeleton up (`--up`; the article draws files as written).
    pub up: Up,
    /// The article's look or the studio's (`--look studio`).
    pub look: Look,
    /// In the studio look, the camera follows the root (the window's T).
    pub follow: bool,
    /// A framed view (`--fit`, the studio look) keeps every frame of the take in view from a
    /// camera that stays put (`--fit=take`), instead of following the pose shown.
    pub whole_take: bool,
    /// Several takes at their true sizes (by the units guessed for each) instead of scaled to
    /// the first one's height.
    pub true_scale: bool,
    /// Several takes drawn one over the other (each where its file puts it, on the first one's
    /// floor) instead of side by side, so that one camera sees each
    /// from the same side: the first in its colours, each other one paler.
    pub overlaid: bool,
}

/// How the picture looks: the article's (the default) or the studio's, opt-in.
///
/// ```
/// use bvhview::{Take, render::{Look, SnapshotOptions, snapshot}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let article = SnapshotOptions { width: 64, height: 64, ..SnapshotOptions::default() };
/// assert_eq!(article.look, Look::Article);
/// let studio = SnapshotOptions { look: Look::Studio, ..article };
/// let a = snapshot(&take.skeleton, &take.motion, &article)?;
/// let s = snapshot(&take.skeleton, &take.motion, &studio)?;
/// assert!(a.differing_pixels(&s) > 0);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Look {
    /// The article's picture: its fixed camera, light and floor.
    #[default]
    Article,
    /// A framed figure on a studio floor, its sides in colours (`--look studio`).
    Studio,
}

/// What is drawn over the scene; none of it is the article's picture.
///
/// ```
/// use bvhview::{Take, render::{Overlay, Renderer, SnapshotOptions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let options = SnapshotOptions { width: 200, height: 100, ..SnapshotOptions::default() };
/// let mut renderer = Renderer::new(200, 100)?;
/// let plain = renderer.render(&take.skeleton, &take.motion, &options)?;
/// let lines = vec!["frame 0".to_string()];
/// let overlay = Overlay { lines, timeline: Some((0, 3)), ..Overlay::default() };
/// let hud = renderer.render_with_overlay(&take.skeleton, &take.motion, &options, &overlay)?;
/// assert!(hud.differing_pixels(&plain) > 0);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    /// Lines of text bottom left above the timeline (top left in the step view): the HUD's, or
    /// the help's.
    pub lines: Vec<String>,
    /// The timeline along the bottom (with the HUD): the frame shown, and how many there are.
    pub timeline: Option<(usize, usize)>,
    /// Each joint's name beside it (N).
    pub names: bool,
    /// A label over each take (its file's name, with the HUD when several are shown).
    pub labels: Vec<String>,
}

/// Draws `overlay` and the step view's text over scenes just displayed, in the order the window
/// and `snapshot` share: names, labels, the step view (the first take's), the top-left lines, the
/// timeline (not in the step view, whose text takes the bottom).
pub fn draw_overlay<G: fixed::FixedFunction>(
    gl: &mut G,
    scenes: &[Scene],
    (width, height): (u32, u32),
    overlay: &Overlay,
) {
    if overlay.names {
        for scene in scenes {
            names::draw(gl, scene);
        }
    }
    let stepping = scenes.first().is_some_and(|s| s.shown.is_some());
    let place = hud::Place::for_picture((width, height), overlay.timeline.is_some(), stepping);
    if !overlay.labels.is_empty() {
        // Labels keep clear of the HUD's lines and stay above the timeline.
        let mut taken = hud::bands((width, height), &overlay.lines, place);
        let mut lowest = 2.0;
        if overlay.timeline.is_some() && !stepping {
            let bar = timeline::Bar::for_picture(width, height);
            lowest = bar.room();
            taken.push(pixels::Rect {
                left: 0.0,
                right: width as f32,
                bottom: 0.0,
                top: bar.room(),
            });
        }
        names::labels(
            gl,
            scenes,
            &overlay.labels,
            (width, height),
            (&taken, lowest),
        );
    }
    if let Some(scene) = scenes.first()
        && let Some(shown) = scene.shown
    {
        // At 300x300 the big glyphs once ran off the right and covered two thirds of it.
        let font = text::Font::for_picture(width, height);
        let lines = step::lines(
            scene.skeleton,
            scene.frame,
            (scene.style, scene.offset_mode),
            scene.sphere_radius,
            shown,
            step::columns(width, font),
        );
        step::draw_overlay(gl, &lines, font);
    }
    if !overlay.lines.is_empty() {
        hud::draw(gl, (width, height), &overlay.lines, place);
    }
    if let (Some((frame, frames)), false) = (overlay.timeline, stepping) {
        timeline::draw(gl, width, height, frame, frames);
    }
}

impl Default for SnapshotOptions {
    fn default() -> SnapshotOptions {
        SnapshotOptions {
            frame: 0,
            angle: scene::START_ANGLE,
            width: 600,
            height: 600,
            style: Style::Points,
            fit: false,
            offset_mode: OffsetMode::Replace,
            skin: false,
            step: None,
            up: Up::Y,
            look: Look::Article,
            follow: false,
            whole_take: false,
            true_scale: false,
            overlaid: false,
        }
    }
}

/// The camera `snapshot` draws one take with for `options` (no overlay): the article's, or one
/// that frames the figure; `stance` is the take's (`Take::stance`, which knows an ASF's units).
pub fn camera_for(
    skeleton: &Skeleton,
    motion: &Motion,
    stance: crate::model::stance::Stance,
    options: &SnapshotOptions,
) -> Result<Camera, Error> {
    let take = paint::Shown {
        skeleton,
        motion,
        up: options.up,
        stance,
        mesh: None,
    };
    paint::Painter::default().camera(&[take], options, &Overlay::default(), None)
}

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

/// Renders frames offscreen with one context, reused for every picture.
///
/// ```
/// use bvhview::{Take, render::{Renderer, SnapshotOptions}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let mut renderer = Renderer::new(64, 64)?; // one context for every frame
/// let options = SnapshotOptions { width: 64, height: 64, ..SnapshotOptions::default() };
/// let first = renderer.render(&take.skeleton, &take.motion, &options)?;
/// let options = SnapshotOptions { frame: 100, ..options };
/// let later = renderer.render(&take.skeleton, &take.motion, &options)?;
/// assert!(first.differing_pixels(&later) > 0, "the figure moved");
/// // It draws at the size it was made with.
/// assert!(renderer.render(&take.skeleton, &take.motion, &SnapshotOptions::default()).is_err());
/// # Ok(())
/// # }
/// ```
pub struct Renderer {
    context: osmesa::OsMesa,
    painter: paint::Painter,
}

impl Renderer {
    /// An offscreen context (OSMesa) drawing `width × height` pictures, set up as the
    /// article's `init` sets its window.
    pub fn new(width: u32, height: u32) -> Result<Renderer, Error> {
        let mut context = osmesa::OsMesa::new(width, height)?;
        scene::init(&mut context.gl);
        Ok(Renderer {
            context,
            painter: paint::Painter::default(),
        })
    }

    /// The article's `reshape` then `display` for one frame, read back.
    pub fn render(
        &mut self,
        skeleton: &Skeleton,
        motion: &Motion,
        options: &SnapshotOptions,
    ) -> Result<Image, Error> {
        self.render_with_overlay(skeleton, motion, options, &Overlay::default())
    }

    /// [`Renderer::render`] with `overlay` on top (an empty one draws the picture
    /// [`Renderer::render`] draws). The take's units are guessed from its figure; for an ASF's
    /// stated units, call [`Renderer::render_all`] with its `Take::stance`.
    pub fn render_with_overlay(
        &mut self,
        skeleton: &Skeleton,
        motion: &Motion,
        options: &SnapshotOptions,
        overlay: &Overlay,
    ) -> Result<Image, Error> {
        let framed = options.fit || options.look == Look::Studio;
        let take = paint::Shown::of(skeleton, motion, options.up, options.offset_mode, framed);
        self.render_all(&[take], options, overlay)
    }

    /// Several takes side by side on one timeline (`options.frame` is its tick, see
    /// [`paint::Clock`]), with `overlay` on top; one take is [`Renderer::render_with_overlay`].
    pub fn render_all(
        &mut self,
        takes: &[paint::Shown],
        options: &SnapshotOptions,
        overlay: &Overlay,
    ) -> Result<Image, Error> {
        self.paint(takes, options, overlay)?;
        let (width, height) = self.context.size();
        Ok(Image {
            width,
            height,
            rgb: self.context.read_rgb(),
        })
    }

    /// [`Renderer::render_all`] for a sequence: the picture as GL left it ([`Frame`], turned
    /// into an [`Image`] by whoever encodes it, on another thread), drawn into `spare` (a buffer
    /// an earlier frame handed back, or a new one) so that the next frame need not wait for it.
    pub fn render_frame(
        &mut self,
        takes: &[paint::Shown],
        options: &SnapshotOptions,
        overlay: &Overlay,
        spare: Option<Vec<u8>>,
    ) -> Result<Frame, Error> {
        self.paint(takes, options, overlay)?;
        let (width, height) = self.context.size();
        let spare = match spare {
            Some(spare) => spare,
            None => {
                crate::limits::zeroed_bytes(width as usize * height as usize * 4, "the picture")?
            }
        };
        Ok(Frame {
            width,
            height,
            rgba: self.context.swap_buffer(spare)?,
        })
    }

    fn paint(
        &mut self,
        takes: &[paint::Shown],
        options: &SnapshotOptions,
        overlay: &Overlay,
    ) -> Result<(), Error> {
        let (width, height) = self.context.size();
        if (options.width, options.height) != (width, height) {
            return Err(Error::usage(
                "a renderer draws at the size it was made with",
            ));
        }
        self.context.make_current()?;
        self.painter
            .paint(&mut self.context.gl, takes, options, overlay, None)
    }

    /// The GL context, for tests that query its state.
    pub fn context(&mut self) -> &mut osmesa::OsMesa {
        &mut self.context
    }
}

/// One picture of one frame, offscreen.
pub fn snapshot(
    skeleton: &Skeleton,
    motion: &Motion,
    options: &SnapshotOptions,
) -> Result<Image, Error> {
    frame_values(motion, options.frame)?;
    Renderer::new(options.width, options.height)?.render(skeleton, motion, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four pixels at a time gives what one pixel at a time gives, rows flipped, alpha dropped,
    /// for every width's remainder.
    #[test]
    fn rgba_rows_turn_into_rgb_top_down() {
        let mut seed = 7u32;
        for width in 1..=11u32 {
            for height in 1..=3u32 {
                let rgba: Vec<u8> = (0..width * height * 4)
                    .map(|_| {
                        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                        (seed >> 24) as u8
                    })
                    .collect();
                let mut want = Vec::new();
                for row in rgba.chunks_exact(width as usize * 4).rev() {
                    for pixel in row.chunks_exact(4) {
                        want.extend_from_slice(&pixel[..3]);
                    }
                }
                assert_eq!(Image::from_rgba_bottom_up(width, height, &rgba).rgb, want);
            }
        }
    }
}
