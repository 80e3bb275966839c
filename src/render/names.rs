//! Joint names beside the joints (N in the window, `snapshot --names`), drawn over whatever the
//! style drew, in the HUD's font at its own 8-pixel size. Not the article's.

use crate::pose::world_positions;
use crate::render::fixed::{FixedFunction, GL_DEPTH_TEST, GL_LIGHTING};
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
/// over everything: shortened in the middle to the room between its neighbours, and kept under
/// `below` (pixels from the bottom: the HUD's lowest line) and inside the picture, so that no
/// label covers other text.
pub fn labels<G: FixedFunction>(
    gl: &mut G,
    scenes: &[Scene],
    labels: &[String],
    (width, height): (u32, u32),
    below: f32,
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
    gl.disable(GL_LIGHTING);
    gl.disable(GL_DEPTH_TEST);
    gl.color3f(1.0, 1.0, 1.0);
    for (index, (anchor, label)) in anchors.iter().zip(labels).enumerate() {
        let Some((x, y)) = *anchor else {
            continue;
        };
        // The room: up to half-way to the nearest neighbour on either side, less a gap.
        let room = anchors
            .iter()
            .enumerate()
            .filter(|&(other, a)| other != index && a.is_some())
            .map(|(_, a)| (a.map_or(f32::MAX, |(ax, _)| (ax - x).abs()) - 8.0).max(8.0))
            .fold(width as f32, f32::min);
        let columns = ((room / 8.0) as usize).clamp(1, (width as usize / 8).max(1));
        let text = text::shorten_middle(label, columns);
        let wide = (text.chars().count() * 8) as f32;
        let left = (x - wide / 2.0).clamp(2.0, (width as f32 - wide - 2.0).max(2.0));
        let bottom = (y + 6.0).min(below - 10.0).max(2.0);
        gl.window_pos(left as i32, bottom as i32);
        text::draw_small(gl, &text);
    }
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}
