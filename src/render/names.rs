//! Joint names beside the joints (N in the window, `snapshot --names`), drawn over whatever the
//! style drew, in the HUD's font at its own 8-pixel size. Not the article's.

use crate::pose::world_positions;
use crate::render::fixed::{FixedFunction, GL_DEPTH_TEST, GL_LIGHTING};
use crate::render::scene::Scene;
use crate::render::text;

/// Writes each joint's name (End Sites have none of their own) just right of where the joint is
/// drawn, under the modelview `scene::display` leaves (the camera's).
pub fn draw<G: FixedFunction>(gl: &mut G, scene: &Scene) {
    let stand = scene.up.to_y_up();
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
        let at = stand * point + glam::Vec3::from_array(scene.origin);
        gl.raster_pos(at.x, at.y, at.z);
        text::draw_small(gl, &format!(" {}", joint.name));
    }
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}

/// Writes `label` (a take's file name) just above the take's highest joint, in white, over
/// everything.
pub fn label<G: FixedFunction>(gl: &mut G, scene: &Scene, label: &str) {
    let stand = scene.up.to_y_up();
    let origin = glam::Vec3::from_array(scene.origin);
    let points = world_positions(
        scene.skeleton,
        scene.frame.unwrap_or(&[]),
        scene.offset_mode,
    );
    let Some(top) = points
        .into_iter()
        .map(|p| stand * p + origin)
        .max_by(|a, b| a.y.total_cmp(&b.y))
    else {
        return;
    };
    gl.disable(GL_LIGHTING);
    gl.disable(GL_DEPTH_TEST);
    gl.color3f(1.0, 1.0, 1.0);
    gl.raster_pos(top.x, top.y, top.z);
    // Centred on the joint: an empty bitmap moves the raster position back half the width.
    let half = (label.chars().count() * 8 / 2) as f32;
    gl.bitmap(0, 0, -half, &[]);
    text::draw_small(gl, label);
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}
