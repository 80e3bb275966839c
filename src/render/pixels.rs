//! Flat rectangles over the picture, placed in pixels from its bottom-left corner: the timeline's
//! bar and the backing behind the HUD's lines. Not the article's.

use crate::render::fixed::{
    FixedFunction, GL_DEPTH_TEST, GL_LIGHTING, GL_MODELVIEW, GL_PROJECTION, GL_QUADS,
};

/// A rectangle in pixels from the picture's bottom-left corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub left: f32,
    pub right: f32,
    pub bottom: f32,
    pub top: f32,
}

/// Fills each of `rects` with its colour on a picture `width × height`, unlit and over
/// everything; leaves the GL state as the scene expects it (lit, depth-tested, the article's
/// green, the projection and modelview as they were).
pub fn fill<G: FixedFunction>(gl: &mut G, (width, height): (u32, u32), rects: &[([f32; 3], Rect)]) {
    gl.disable(GL_LIGHTING);
    gl.disable(GL_DEPTH_TEST);
    gl.matrix_mode(GL_PROJECTION);
    gl.push_matrix();
    gl.load_identity();
    // glOrtho(0, width, 0, height, -1, 1): one unit per pixel from the bottom-left corner.
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    #[rustfmt::skip]
    let ortho = [
        2.0 / w, 0.0, 0.0, 0.0,
        0.0, 2.0 / h, 0.0, 0.0,
        0.0, 0.0, -1.0, 0.0,
        -1.0, -1.0, 0.0, 1.0,
    ];
    gl.mult_matrixd(&ortho);
    gl.matrix_mode(GL_MODELVIEW);
    gl.push_matrix();
    gl.load_identity();
    for (colour, rect) in rects {
        gl.color3f(colour[0], colour[1], colour[2]);
        gl.begin(GL_QUADS);
        gl.vertex3f(rect.left, rect.bottom, 0.0);
        gl.vertex3f(rect.right, rect.bottom, 0.0);
        gl.vertex3f(rect.right, rect.top, 0.0);
        gl.vertex3f(rect.left, rect.top, 0.0);
        gl.end();
    }
    gl.pop_matrix();
    gl.matrix_mode(GL_PROJECTION);
    gl.pop_matrix();
    gl.matrix_mode(GL_MODELVIEW);
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.enable(GL_LIGHTING);
}
