//! C++: main.cpp's `init`, `reshape` and `display`: the article's GL state, camera, light and
//! floor, drawn into whatever context is current (an OSMesa buffer or a window).
//!
//! The numbers are the article's and are computed at its precision, because the golden pictures
//! compare pixels: the eye is `(R·cos(angle), 20, R·sin(angle))` in single precision, GLU's
//! `gluLookAt` builds its matrix in floats and then calls `glTranslated`, and `gluPerspective`
//! builds its matrix in doubles for `glMultMatrixd`.

use crate::model::pose::OffsetMode;
use crate::model::skeleton::Skeleton;
use crate::render::draw::{self, Style};
use crate::render::fixed::{
    FixedFunction, GL_COLOR_BUFFER_BIT, GL_CULL_FACE, GL_DEPTH_BUFFER_BIT, GL_DEPTH_TEST,
    GL_LIGHT0, GL_LIGHTING, GL_MODELVIEW, GL_NORMALIZE, GL_POSITION, GL_PROJECTION, GL_QUADS,
};

/// C++: `float R = 200.0f`: the camera's distance from the point it looks at.
pub const R: f32 = 200.0;
/// C++: `float angle = 10`: the camera's start angle around the Y axis, in radians.
pub const START_ANGLE: f32 = 10.0;

/// C++: the globals `R` and `angle` of main.cpp, and the eye `display` computes from them: the
/// camera circles `target` at `distance`, at the target's height. A value rather than globals, so
/// `--fit` and the mouse can change it.
///
/// ```
/// use bvhview::render::scene::Camera;
///
/// let camera = Camera { angle: 0.0, ..Camera::default() }; // the article's, turned to angle 0
/// assert_eq!(camera.eye(), [200.0, 20.0, 0.0]); // R away along x, at the target's height
/// // One that sees a sphere of radius 100 around the origin.
/// let framing = Camera::framing([0.0; 3], 100.0, 0.0);
/// assert!(framing.distance > 100.0 / 22.5f32.to_radians().sin());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// C++: `angle`: where the eye is around the target, in radians about the Y axis.
    pub angle: f32,
    /// The point looked at.
    pub target: [f32; 3],
    /// C++: `R`: how far the eye is from the target.
    pub distance: f32,
    /// How far above the target's height the eye looks down, in radians; 0 is the article's
    /// level camera (the window's vertical drag tilts it).
    pub pitch: f32,
}

impl Default for Camera {
    /// The article's camera: 200 units from (0, 20, 0), angle 10.
    fn default() -> Camera {
        Camera {
            angle: START_ANGLE,
            target: [0.0, 20.0, 0.0],
            distance: R,
            pitch: 0.0,
        }
    }
}

impl Camera {
    /// The eye, as the article computes it: `R*cos(angle)` with a float `cos`.
    pub fn eye(&self) -> [f32; 3] {
        let [x, y, z] = self.target;
        if self.pitch == 0.0 {
            // Exactly the article's arithmetic, so its picture comes out pixel for pixel.
            return [
                x + self.distance * self.angle.cos(),
                y,
                z + self.distance * self.angle.sin(),
            ];
        }
        let (up, level) = self.pitch.sin_cos();
        [
            x + self.distance * level * self.angle.cos(),
            y + self.distance * up,
            z + self.distance * level * self.angle.sin(),
        ]
    }

    /// Moves the target across the view: `right` and `up` in units of the distance.
    pub fn pan(&mut self, right: f32, up: f32) {
        let (sin, cos) = self.angle.sin_cos();
        // The view's right is across the eye's direction (cos a, 0, sin a), in the ground plane.
        let step = self.distance;
        self.target[0] += -sin * right * step;
        self.target[2] += cos * right * step;
        self.target[1] += up * step;
    }

    /// A camera at `angle` that sees the whole sphere (`center`, `radius`) in the article's 45°
    /// field of view.
    pub fn framing(center: [f32; 3], radius: f32, angle: f32) -> Camera {
        let half_fov = 22.5f32.to_radians();
        Camera {
            angle,
            target: center,
            distance: (radius.max(1.0) / half_fov.sin()) * 1.1,
            pitch: 0.0,
        }
    }
}

/// What one `display()` draws.
///
/// ```
/// use bvhview::model::pose::{OffsetMode, Up};
/// use bvhview::render::{draw::Style, scene::{self, Camera, Scene}, trace::{Numbers, Recorder}};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let take = bvhview::Take::open("tests/oracle/inputs/tiny_crlf.bvh")?;
/// let view = Scene {
///     skeleton: &take.skeleton, frame: Some(take.motion.frame(0)), camera: Camera::default(),
///     style: Style::Points, offset_mode: OffsetMode::Replace, skin: None, shown: None,
///     sphere_radius: 1.0, up: Up::Y, origin: [0.0; 3], scale: 1.0, colours: None,
/// };
/// let mut gl = Recorder::new(Numbers::Apitrace);
/// scene::display(&mut gl, &view); // the article's `display`, traced
/// assert_eq!(gl.lines[0], "glClear(GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT);");
/// assert_eq!(gl.lines.iter().filter(|l| l.starts_with("glutSolidSphere")).count(), 12);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// The skeleton drawn.
    pub skeleton: &'a Skeleton,
    /// The MOTION row to draw; `None` draws the rest pose.
    pub frame: Option<&'a [f32]>,
    /// Where the eye is and what it looks at.
    pub camera: Camera,
    /// Spheres, sticks or both.
    pub style: Style,
    /// How position channels meet the OFFSET.
    pub offset_mode: OffsetMode,
    /// A skin posed for this frame, drawn lit before the skeleton (`--skin`; not the article's).
    pub skin: Option<&'a crate::model::bone_skin::PosedBody>,
    /// Only the first joints in drawing order, the last highlighted (the step view; not the
    /// article's). `None`: the whole skeleton.
    pub shown: Option<usize>,
    /// The spheres' radius (the article's 1; see [`sphere_radius`]).
    pub sphere_radius: f64,
    /// The file's up axis; a Z-up file is turned to stand (the floor stays where it is).
    pub up: crate::model::pose::Up,
    /// Where the take stands: moved along x beside the others when several are shown.
    pub origin: [f32; 3],
    /// How much larger the take is drawn than written (several takes to one height); 1 alone.
    pub scale: f32,
    /// A colour per joint (the studio look's sides); `None` draws without colour calls.
    pub colours: Option<&'a [[f32; 3]]>,
}

impl Scene<'_> {
    /// Where a point of the take (as the file places it) is drawn (see [`place`]).
    pub fn place(&self, point: glam::Vec3) -> glam::Vec3 {
        place(
            self.up,
            self.scale,
            glam::Vec3::from_array(self.origin),
            point,
        )
    }
}

/// Where a point of a take (as the file places it) is drawn: stood up, scaled, moved to the
/// take's place.
pub fn place(
    up: crate::model::pose::Up,
    scale: f32,
    origin: glam::Vec3,
    point: glam::Vec3,
) -> glam::Vec3 {
    up.to_y_up() * point * scale + origin
}

/// Scales the modelview by `scale` (several takes at one height), with normals kept unit length
/// for the lighting; nothing for 1.
pub fn scale_take<G: FixedFunction>(gl: &mut G, scale: f32) {
    if scale != 1.0 {
        #[rustfmt::skip]
        let m = [
            scale, 0.0, 0.0, 0.0,
            0.0, scale, 0.0, 0.0,
            0.0, 0.0, scale, 0.0,
            0.0, 0.0, 0.0, 1.0,
        ];
        gl.mult_matrixf(&m);
        gl.enable(GL_NORMALIZE);
    }
}

/// The spheres' radius for a view: the article's 1 at its own camera; in a view that frames the
/// skeleton, in proportion to it, as 1 is to a 170-unit figure 200 units away, so that a rig in
/// metres is not one blob and one in CMU's units not big balls.
pub fn sphere_radius(camera: &Camera, framed: bool) -> f64 {
    if framed {
        f64::from(camera.distance) * 0.0042
    } else {
        1.0
    }
}

/// C++: `init()`: black clear colour, depth test, `GL_LIGHT0` at (0, 0, 1, 1) while the modelview
/// matrix is the identity (so the light sits at the eye and moves with it), lighting on, line
/// width 3, colour green (which lighting then ignores: the article's spheres are grey). The
/// article also loads its file and prints it here; the port loads before it makes a context.
pub fn init<G: FixedFunction>(gl: &mut G) {
    gl.clear_color(0.0, 0.0, 0.0, 0.0);
    gl.enable(GL_DEPTH_TEST);
    gl.lightfv(GL_LIGHT0, GL_POSITION, [0.0, 0.0, 1.0, 1.0]);
    gl.enable(GL_LIGHTING);
    gl.enable(GL_LIGHT0);
    gl.line_width(3.0);
    gl.color3f(0.0, 1.0, 0.0);
}

/// C++: `reshape(w, h)`: viewport, a 45° perspective from 1 to 1000, and a modelview that
/// `display` replaces at once (the article looks at the origin here; kept so the calls match).
/// What changed: a camera more than 200 units away or less than 20 widens the planes with it.
pub fn reshape<G: FixedFunction>(gl: &mut G, width: u32, height: u32, camera: &Camera) {
    gl.viewport(0, 0, width as i32, height as i32);
    gl.matrix_mode(GL_PROJECTION);
    gl.load_identity();
    // The article's planes around its camera (200 away); a camera framing a rig in millimetres
    // stands thousands of units away and one in metres a few, so their planes follow it.
    let distance = f64::from(camera.distance);
    let (near, far) = (1.0f64.min(distance / 20.0), 1000.0f64.max(distance * 5.0));
    perspective(gl, 45.0, width as f64 / height.max(1) as f64, near, far);
    gl.matrix_mode(GL_MODELVIEW);
    gl.load_identity();
    let [x, _, z] = camera.eye();
    let [tx, _, tz] = camera.target;
    look_at(gl, [x, 0.0, z], [tx, 0.0, tz], [0.0, 1.0, 0.0]);
}

/// C++: `display()` without `glutSwapBuffers` (the caller presents): clear, look at the target,
/// draw the skeleton, then the floor quad at y = −10, which has no `glNormal` and so is lit with
/// the current normal like a wall facing +Z.
pub fn display<G: FixedFunction>(gl: &mut G, scene: &Scene) {
    display_all(gl, std::slice::from_ref(scene));
}

/// [`display`] for several takes side by side, each scene one take, under the first one's
/// camera: the article's calls for each take in turn, then its floor once. (The studio look is
/// `studio::display`; the painter picks one or the other.)
pub fn display_all<G: FixedFunction>(gl: &mut G, scenes: &[Scene]) {
    let Some(first) = scenes.first() else {
        return;
    };
    gl.clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.load_identity();
    look_at(gl, first.camera.eye(), first.camera.target, [0.0, 1.0, 0.0]);
    for scene in scenes {
        draw_take(gl, scene);
    }
    gl.begin(GL_QUADS);
    gl.vertex3f(-100.0, -10.0, 100.0);
    gl.vertex3f(100.0, -10.0, 100.0);
    gl.vertex3f(100.0, -10.0, -100.0);
    gl.vertex3f(-100.0, -10.0, -100.0);
    gl.end();
}

/// The figure of `display`, under the camera already set: the skin and the style asked for, at
/// the take's place (no calls at all for the article's one take at the origin).
pub fn draw_take<G: FixedFunction>(gl: &mut G, scene: &Scene) {
    let moved = scene.origin != [0.0; 3] || scene.scale != 1.0;
    if moved {
        gl.push_matrix();
        gl.translatef(scene.origin[0], scene.origin[1], scene.origin[2]);
        scale_take(gl, scene.scale);
    }
    // With a skin, the skin takes the spheres' place (the stick figure, if asked for, stays).
    let style = match (scene.skin, scene.style) {
        (None, style) => Some(style),
        (Some(_), Style::Points) => None,
        (Some(_), _) => Some(Style::Sticks),
    };
    // A Z-up file turned to stand in the article's Y-up world; nothing changes for Y-up files.
    let stand_up = scene.up == crate::model::pose::Up::Z;
    if stand_up {
        gl.push_matrix();
        gl.rotatef(-90.0, 1.0, 0.0, 0.0);
    }
    if let Some(skin) = scene.skin {
        draw_skin(gl, skin, skin.single_sided);
    }
    if let Some(style) = style {
        let pass = draw::Pass {
            shown: scene.shown,
            sphere_radius: scene.sphere_radius,
            ..draw::Pass::whole(scene.skeleton, scene.frame, style, scene.offset_mode)
        };
        draw::draw_pass(gl, &pass);
    }
    if stand_up {
        gl.pop_matrix();
    }
    if moved {
        gl.pop_matrix();
        gl.disable(GL_NORMALIZE);
    }
}

/// A posed skin's triangles, its back faces culled when `cull` (a skin whose file hides them:
/// a glTF material that is not double-sided; what a glTF viewer draws, at half the triangles).
pub fn draw_skin<G: FixedFunction>(
    gl: &mut G,
    skin: &crate::model::bone_skin::PosedBody,
    cull: bool,
) {
    if cull {
        gl.enable(GL_CULL_FACE);
    }
    gl.draw_triangles(&skin.positions, &skin.normals, &skin.indices);
    if cull {
        gl.disable(GL_CULL_FACE);
    }
}

fn normalize(v: &mut [f32; 3]) {
    // GLU: the sum in floats, the root rounded to a float.
    let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if r == 0.0 {
        return;
    }
    for c in v.iter_mut() {
        *c /= r;
    }
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// C++: `gluLookAt` (SGI's libGLU, as Mesa ships it). Its arguments are doubles; the article
/// passes floats. The direction is computed in doubles and stored in floats, the basis is built
/// in floats and multiplied with `glMultMatrixf`, then `glTranslated(-eye)`.
pub fn look_at<G: FixedFunction>(gl: &mut G, eye: [f32; 3], center: [f32; 3], up: [f32; 3]) {
    let eye = eye.map(f64::from);
    let center = center.map(f64::from);
    let mut forward = [
        (center[0] - eye[0]) as f32,
        (center[1] - eye[1]) as f32,
        (center[2] - eye[2]) as f32,
    ];
    normalize(&mut forward);
    let mut side = cross(forward, up);
    normalize(&mut side);
    let up = cross(side, forward);
    #[rustfmt::skip]
    let m = [
        side[0], up[0], -forward[0], 0.0,
        side[1], up[1], -forward[1], 0.0,
        side[2], up[2], -forward[2], 0.0,
        0.0, 0.0, 0.0, 1.0,
    ];
    gl.mult_matrixf(&m);
    gl.translated(-eye[0], -eye[1], -eye[2]);
}

/// C++: `gluPerspective`: the matrix in doubles, multiplied with `glMultMatrixd`.
pub fn perspective<G: FixedFunction>(gl: &mut G, fovy: f64, aspect: f64, near: f64, far: f64) {
    let radians = fovy / 2.0 * std::f64::consts::PI / 180.0;
    let delta_z = far - near;
    let sine = radians.sin();
    if delta_z == 0.0 || sine == 0.0 || aspect == 0.0 {
        return;
    }
    let cotangent = radians.cos() / sine;
    #[rustfmt::skip]
    let m = [
        cotangent / aspect, 0.0, 0.0, 0.0,
        0.0, cotangent, 0.0, 0.0,
        0.0, 0.0, -(far + near) / delta_z, -1.0,
        0.0, 0.0, -2.0 * near * far / delta_z, 0.0,
    ];
    gl.mult_matrixd(&m);
}
