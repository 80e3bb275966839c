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
