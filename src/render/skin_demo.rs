//! The skinning tutorial's demo: two bones of length 3, three quads of four vertices each (yellow,
//! green, blue, bottom to top). The bottom quad's lower edge follows bone 1, the top quad's upper
//! edge bone 2, and every other vertex is weighted half and half, so the middle quad bends
//! smoothly when bone 2 turns. Drawn as the demo draws it: line loops for the quads and a
//! wireframe shape per bone, over a blue-grey background, 15 units from the camera.

use crate::model::skin::{Skin, SkinVertex};
use crate::render::fixed::{
    FixedFunction, GL_COLOR_BUFFER_BIT, GL_DEPTH_BUFFER_BIT, GL_LINE_LOOP, GL_LINE_STRIP,
    GL_MODELVIEW, GL_PROJECTION,
};
use glam::{Mat4, Vec3};

/// The demo's window size.
pub const SIZE: (u32, u32) = (640, 480);

/// One of the seed's vertices: colour, position, (bone, weight) pairs.
type DemoVertex = ([f32; 3], Vec3, Vec<(usize, f32)>);

/// The 12 vertices, as in the seed.
fn quad_vertices() -> Vec<DemoVertex> {
    let half = vec![(0, 0.5), (1, 0.5)];
    let mut out = Vec::new();
    let colours = [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for (quad, colour) in colours.into_iter().enumerate() {
        let (bottom, top) = (2.0 * quad as f32, 2.0 * quad as f32 + 2.0);
        let bottom_weights = if quad == 0 {
            vec![(0, 1.0)]
        } else {
            half.clone()
        };
        let top_weights = if quad == 2 {
            vec![(1, 1.0)]
        } else {
            half.clone()
        };
        out.push((colour, Vec3::new(-1.0, bottom, 0.0), bottom_weights.clone()));
        out.push((colour, Vec3::new(1.0, bottom, 0.0), bottom_weights));
        out.push((colour, Vec3::new(1.0, top, 0.0), top_weights.clone()));
        out.push((colour, Vec3::new(-1.0, top, 0.0), top_weights));
    }
    out
}

/// The seed's wireframe bone, from (0, 0, 0) to (0, 3, 0).
const BONE_SHAPE: [[f32; 3]; 14] = [
    [0.0, 0.0, 0.0],
    [-0.2, 0.2, -0.2],
    [0.2, 0.2, -0.2],
    [0.0, 3.0, 0.0],
    [-0.2, 0.2, -0.2],
    [-0.2, 0.2, 0.2],
    [0.0, 0.0, 0.0],
    [0.2, 0.2, -0.2],
    [0.2, 0.2, 0.2],
    [0.0, 0.0, 0.0],
    [-0.2, 0.2, 0.2],
    [0.0, 3.0, 0.0],
    [0.2, 0.2, 0.2],
    [-0.2, 0.2, 0.2],
];

/// World matrices of the two bones: bone 1 at the origin, bone 2 at the end of bone 1 turned
/// by `Ry(bend.0) · Rz(bend.1)` (degrees; the seed's `rotate_y(spinY) * rotate_z(-spinX)`).
pub fn bone_worlds(bend: (f32, f32)) -> [Mat4; 2] {
    [
        Mat4::IDENTITY,
        Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
            * Mat4::from_rotation_y(bend.0.to_radians())
            * Mat4::from_rotation_z(bend.1.to_radians()),
    ]
}

/// The 12 skinned vertex positions for a bend.
pub fn skinned(bend: (f32, f32)) -> Vec<Vec3> {
    let vertices = quad_vertices()
        .into_iter()
        .map(|(_, p, w)| SkinVertex::new(p, Vec3::Z, &w))
        .collect();
    let skin = Skin::new(vertices, &bone_worlds((0.0, 0.0)));
    let (mut matrices, mut positions, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    skin.bone_matrices(&bone_worlds(bend), &mut matrices);
    skin.deform(&matrices, &mut positions, &mut normals);
    positions
}

/// The seed's `perspective(45, aspect, 0.1, 100)`, computed in floats as it does.
fn perspective(aspect: f32) -> [f32; 16] {
    let half = (45.0f32.to_radians() / 2.0).tan();
    let (near, far) = (0.1f32, 100.0f32);
    let mut m = [0.0f32; 16];
    m[0] = 1.0 / (aspect * half);
    m[5] = 1.0 / half;
    m[10] = -(far + near) / (far - near);
    m[11] = -1.0;
    m[14] = -(2.0 * far * near) / (far - near);
    m
}

/// Draws the demo for a bend of bone 2 into the current context.
pub fn draw<G: FixedFunction>(gl: &mut G, bend: (f32, f32), width: u32, height: u32) {
    gl.viewport(0, 0, width as i32, height as i32);
    gl.clear_color(0.35, 0.53, 0.7, 1.0);
    gl.clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.matrix_mode(GL_PROJECTION);
    gl.load_matrix(&perspective(width as f32 / height.max(1) as f32));
    gl.matrix_mode(GL_MODELVIEW);
    gl.load_identity();
    gl.translatef(0.0, 0.0, -15.0);
    let positions = skinned(bend);
    let colours: Vec<[f32; 3]> = quad_vertices().into_iter().map(|(c, _, _)| c).collect();
    for quad in 0..3 {
        gl.begin(GL_LINE_LOOP);
        for i in quad * 4..quad * 4 + 4 {
            let [r, g, b] = colours[i];
            gl.color3f(r, g, b);
            gl.vertex3f(positions[i].x, positions[i].y, positions[i].z);
        }
        gl.end();
    }
    for (bone, [r, g, b]) in bone_worlds(bend)
        .iter()
        .zip([[1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    {
        gl.push_matrix();
        gl.mult_matrixf(&bone.to_cols_array());
        gl.color3f(r, g, b);
        gl.begin(GL_LINE_STRIP);
        for [x, y, z] in BONE_SHAPE {
            gl.vertex3f(x, y, z);
        }
        gl.end();
        gl.pop_matrix();
    }
}

/// The demo offscreen, as a picture.
pub fn render(
    bend: (f32, f32),
    width: u32,
    height: u32,
) -> Result<crate::render::Image, crate::Error> {
    let mut context = crate::render::osmesa::OsMesa::new(width, height)?;
    draw(&mut context.gl, bend, width, height);
    Ok(crate::render::Image {
        width,
        height,
        rgb: context.read_rgb(),
    })
}
