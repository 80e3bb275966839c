//! Joint names beside the joints (N in the window, `snapshot --names`), drawn over whatever the
//! style drew, in the HUD's font at its own 8-pixel size. Not the article's.

use crate::model::pose::world_positions;
use crate::render::fixed::{FixedFunction, GL_DEPTH_TEST, GL_LIGHTING};
use crate::render::pixels::Rect;
use crate::render::scene::Scene;
use crate::render::{framing, text};

/// Writes each joint's name (End Sites have none of their own) just right of where the joint is
/// drawn, under the modelview `scene::display` leaves (the camera's).
pub fn draw<G: FixedFunction>(gl: &mut G, scene: &Scene) {
    let points = world_positions(
        scene.skeleton,
        scene.frame.unwrap_or(&[]),
        scene.offset_mode,
    );
    // The raster position takes the current colour only while lighting is off.
    gl.disable(GL_LIGHTING);
    gl.disable(GL_DEPTH_TEST);
    gl.color3f(1.0, 0.9, 0.3);
    for (joint, point) in scene.skeleton.joints.iter().zip(points) {
        if joint.end_site {
            continue;
        }
        let at = scene.place(point);
        gl.raster_pos(at.x, at.y, at.z);
        text::draw_small(gl, &format!(" {}", joint.name));
    }
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}

/// Writes each take's label (its file's name) centred just above its highest joint, in white,
/// over everything, where it covers no other text: not the HUD's lines or the timeline (`taken`,
/// in pixels from the bottom-left corner) nor another label. A label that would is moved down a
/// line at a time, no lower than `lowest`, then shortened in the middle to the room between its
/// neighbours; it always stays inside the picture.
pub fn labels<G: FixedFunction>(
    gl: &mut G,
    scenes: &[Scene],
    labels: &[String],
    (width, height): (u32, u32),
    (taken, lowest): (&[Rect], f32),
) {
    let Some(first) = scenes.first() else {
        return;
    };
    let matrix = framing::view_projection(&first.camera, width, height);
    // Each take's highest point, on the picture.
    let anchors: Vec<Option<(f32, f32)>> = scenes
        .iter()
        .map(|scene| {
            let top = world_positions(
                scene.skeleton,
                scene.frame.unwrap_or(&[]),
                scene.offset_mode,
            )
            .into_iter()
            .map(|p| scene.place(p))
            .filter(|p| p.is_finite())
            .max_by(|a, b| a.y.total_cmp(&b.y))?;
            framing::project(&matrix, top, width, height)
        })
        .collect();
    let mut placed: Vec<Rect> = taken.to_vec();
    let mut drawn: Vec<(i32, i32, String)> = Vec::new();
    for (index, (anchor, label)) in anchors.iter().zip(labels).enumerate() {
        let Some((x, y)) = *anchor else {
            continue;
        };
        // The nearest neighbour along x: a label as wide as twice that distance fits when the
        // two sit on different lines, one as wide as the distance always fits beside it.
        let nearest = anchors
            .iter()
            .enumerate()
            .filter(|&(other, _)| other != index)
            .filter_map(|(_, a)| a.map(|(ax, _)| (ax - x).abs()))
            .fold(width as f32, f32::min);
        let most = (width as usize / 8).saturating_sub(1).max(1);
        let wide = (((2.0 * nearest - 8.0) / 8.0).max(1.0) as usize).min(most);
        let narrow = (((nearest - 8.0) / 8.0).max(1.0) as usize).min(most);
        let spot = |columns: usize, drop: f32| -> (Rect, String) {
            let text = text::shorten_middle(label, columns);
            let across = (text.chars().count() * 8) as f32;
            let left = (x - across / 2.0).clamp(2.0, (width as f32 - across - 2.0).max(2.0));
            let bottom = ((y + 6.0).min(height as f32 - 10.0) - drop).max(lowest);
            let rect = Rect {
                left,
                right: left + across,
                bottom,
                top: bottom + 8.0,
            };
            (rect, text)
        };
        let free = |rect: &Rect| !placed.iter().any(|r| overlap(r, rect));
        let choice = [wide, narrow]
            .into_iter()
            .flat_map(|columns| (0..40).map(move |step| (columns, step as f32 * 10.0)))
            .map(|(columns, drop)| spot(columns, drop))
            .find(|(rect, _)| free(rect))
            .unwrap_or_else(|| spot(narrow, 0.0));
        placed.push(choice.0);
        drawn.push((choice.0.left as i32, choice.0.bottom as i32, choice.1));
    }
    gl.disable(GL_LIGHTING);
    gl.disable(GL_DEPTH_TEST);
    gl.color3f(1.0, 1.0, 1.0);
    for (left, bottom, text) in drawn {
        gl.window_pos(left, bottom);
        text::draw_small(gl, &text);
    }
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}

/// Whether two rectangles share any pixel.
fn overlap(a: &Rect, b: &Rect) -> bool {
    a.left < b.right && b.left < a.right && a.bottom < b.top && b.bottom < a.top
}
