//! The timeline, shown with the HUD: a bar along the bottom of the picture, filled up to the frame
//! shown, with a mark at it. In the window a click or a drag on the bar seeks. Not the article's.

use crate::render::fixed::FixedFunction;
use crate::render::pixels::{self, Rect};

/// Pixels of slack above and below the bar that still count as a click on it.
const SLACK: f32 = 8.0;

/// The bar's place, in pixels from the picture's bottom-left corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    pub left: f32,
    pub right: f32,
    pub bottom: f32,
    pub top: f32,
}

impl Bar {
    /// The bar on a picture `width` pixels wide: 12 pixels in from each side, 10 up from the
    /// bottom, 12 high.
    pub fn new(width: u32) -> Bar {
        let left = 12.0;
        Bar {
            left,
            right: (width as f32 - 12.0).max(left + 1.0),
            bottom: 10.0,
            top: 22.0,
        }
    }

    /// The bar on a `width × height` picture: [`Bar::new`]'s, or on a picture that takes the
    /// HUD's small font (see `text::Font::for_picture`), a thinner one lower down, 6 pixels
    /// high and 6 up, so that the figure keeps its room.
    pub fn for_picture(width: u32, height: u32) -> Bar {
        let bar = Bar::new(width);
        if crate::render::text::Font::for_picture(width, height) == crate::render::text::Font::BIG {
            bar
        } else {
            Bar {
                left: 6.0,
                right: (width as f32 - 6.0).max(7.0),
                bottom: 6.0,
                top: 12.0,
            }
        }
    }

    /// Pixels along the bottom the bar and its mark cover, with a gap above.
    pub fn room(&self) -> f32 {
        self.top + 8.0
    }

    /// Where frame `frame` of `frames` sits along the bar: the first at the left end, the last at
    /// the right.
    pub fn x_of(&self, frame: usize, frames: usize) -> f32 {
        if frames <= 1 {
            return self.left;
        }
        let at = frame.min(frames - 1) as f64 / (frames - 1) as f64;
        self.left + (self.right - self.left) * at as f32
    }

    /// The frame nearest to `x` (pixels from the left), clamped to the bar's ends: a drag that
    /// leaves the bar keeps seeking.
    pub fn frame_along(&self, x: f64, frames: usize) -> usize {
        if frames <= 1 {
            return 0;
        }
        let at = ((x - f64::from(self.left)) / f64::from(self.right - self.left)).clamp(0.0, 1.0);
        (at * (frames - 1) as f64).round() as usize
    }

    /// The frame a click at (`x`, `y`) picks, `y` in pixels from the top as the mouse counts it
    /// on a picture `height` pixels high; `None` off the bar.
    pub fn frame_at(&self, x: f64, y: f64, height: u32, frames: usize) -> Option<usize> {
        let up = f64::from(height) - y;
        let inside = up >= f64::from(self.bottom - SLACK)
            && up <= f64::from(self.top + SLACK)
            && x >= f64::from(self.left - SLACK)
            && x <= f64::from(self.right + SLACK);
        inside.then(|| self.frame_along(x, frames))
    }
}

/// Draws the bar for frame `frame` of `frames` on a picture `width × height`, unlit and over
/// everything (see `pixels::fill`).
pub fn draw<G: FixedFunction>(gl: &mut G, width: u32, height: u32, frame: usize, frames: usize) {
    let bar = Bar::for_picture(width, height);
    let mark = bar.x_of(frame, frames);
    let rect = |left, right, bottom, top| Rect {
        left,
        right,
        bottom,
        top,
    };
    pixels::fill(
        gl,
        (width, height),
        &[
            (
                [0.25, 0.25, 0.28],
                rect(bar.left, bar.right, bar.bottom, bar.top),
            ),
            (
                [0.45, 0.55, 0.75],
                rect(bar.left, mark, bar.bottom, bar.top),
            ),
            (
                [1.0, 1.0, 1.0],
                rect(mark - 2.0, mark + 2.0, bar.bottom - 4.0, bar.top + 4.0),
            ),
        ],
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_of_the_bar_are_the_first_and_last_frames() {
        let bar = Bar::new(600);
        assert_eq!((bar.left, bar.right), (12.0, 588.0));
        assert_eq!(bar.x_of(0, 41), 12.0);
        assert_eq!(bar.x_of(40, 41), 588.0);
        assert_eq!(bar.x_of(20, 41), 300.0);
        assert_eq!(bar.frame_along(300.0, 41), 20);
        assert_eq!(bar.frame_along(-50.0, 41), 0);
        assert_eq!(bar.frame_along(9999.0, 41), 40);
        // Nothing to seek in a rest pose or a single frame.
        assert_eq!(bar.frame_along(300.0, 1), 0);
        assert_eq!(bar.x_of(0, 0), 12.0);
    }

    #[test]
    fn a_click_counts_on_the_bar_only() {
        let bar = Bar::new(600);
        // The bar is 10 to 22 pixels up from the bottom of a 600-pixel picture: y 578 to 590
        // from the top, with 8 pixels of slack.
        assert_eq!(bar.frame_at(300.0, 584.0, 600, 41), Some(20));
        assert_eq!(bar.frame_at(12.0, 597.0, 600, 41), Some(0));
        assert_eq!(bar.frame_at(12.0, 599.0, 600, 41), None);
        assert_eq!(bar.frame_at(300.0, 560.0, 600, 41), None);
        assert_eq!(bar.frame_at(300.0, 100.0, 600, 41), None);
        assert_eq!(bar.frame_at(597.0, 584.0, 600, 41), None);
    }
}
