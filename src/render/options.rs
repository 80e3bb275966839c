//! What a snapshot shows: its options and its look.

use super::draw::Style;
use super::scene;
use crate::model::pose::{OffsetMode, Up};

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
