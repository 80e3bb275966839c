//! Drawing: the article's fixed-function renderer, offscreen (OSMesa) and in a window.
//!
//! The article's picture is [`scene`] and [`draw`]; [`snapshot`] draws it offscreen. The
//! layers drawn on top (names, the step view), the offscreen context and the window are
//! private to the crate; the HUD, timeline, studio look and paint are public for the tests
//! only, and left out of these docs.

pub mod animation;
mod current_frame;
pub mod draw;
#[doc(hidden)] // the GL state machine the picture is traced and checked with, for the tests
pub mod fixed;
pub mod framing;
#[doc(hidden)]
pub mod hud;
mod image;
pub(crate) mod names;
mod options;
pub(crate) mod osmesa;
mod overlay;
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
mod video_size;
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
use crate::model::skeleton::Skeleton;
pub use current_frame::frame_values;
pub use image::{Frame, Image};
pub use options::{Look, SnapshotOptions};
pub use overlay::{Overlay, draw_overlay};
use scene::Camera;

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
