//! What is drawn over the scene (names, labels, the step view, the HUD's lines, the timeline),
//! in the order the window and `snapshot` share.

use super::fixed::FixedFunction;
use super::scene::Scene;
use super::{hud, names, pixels, step, text, timeline};

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
pub fn draw_overlay<G: FixedFunction>(
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
