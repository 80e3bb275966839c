//! A recording implementation of the GL table: the scene and draw code run unchanged and every
//! call becomes one line of C. The window and the snapshots run the same code against real GL,
//! so what the trace shows is what they draw.

use crate::render::fixed::*;

/// How numbers are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    /// As apitrace dumps them: `%.7g` for floats, `%.16g` for doubles (tests/oracle/trace).
    Apitrace,
    /// As C's `printf("%f")`: six decimals (`glTranslatef(0.000000, 84.730759, 0.000000)`).
    Printf,
}

/// Collects the calls as lines, and follows the modelview matrix (so that a draw that saves it,
/// for skeletons deeper than the GL matrix stack, records the right values).
pub struct Recorder {
    pub numbers: Numbers,
    pub lines: Vec<String>,
    modelview: Vec<glam::DMat4>,
    in_modelview: bool,
}

impl Recorder {
    pub fn new(numbers: Numbers) -> Recorder {
        Recorder {
            numbers,
            lines: Vec::new(),
            modelview: vec![glam::DMat4::IDENTITY],
            in_modelview: true,
        }
    }

    /// All lines, each ending in a newline.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for line in &self.lines {
            out.push_str(line);
            out.push('\n');
        }
        out
    }

    fn float(&self, value: f32) -> String {
        match self.numbers {
            Numbers::Apitrace => format_g(value as f64, 7),
            Numbers::Printf => format!("{:.6}", value as f64),
        }
    }

    fn double(&self, value: f64) -> String {
        match self.numbers {
            Numbers::Apitrace => format_g(value, 16),
            Numbers::Printf => format!("{value:.6}"),
        }
    }

    fn floats(&self, values: &[f32]) -> String {
        values
            .iter()
            .map(|&v| self.float(v))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn doubles(&self, values: &[f64]) -> String {
        values
            .iter()
            .map(|&v| self.double(v))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn call(&mut self, name: &str, arguments: &str) {
        self.lines.push(format!("{name}({arguments});"));
    }

    /// Applies `m` to the current modelview matrix, if modelview is the current mode.
    fn multiply(&mut self, m: glam::DMat4) {
        if self.in_modelview {
            let top = self.modelview.last_mut().expect("the stack is never empty");
            *top *= m;
        }
    }
}

/// C's `%.{precision}g`: `precision` significant digits, trailing zeros dropped, scientific
/// notation when the exponent is below −4 or at least `precision`.
pub fn format_g(value: f64, precision: usize) -> String {
    if value == 0.0 {
        return if value.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    if !value.is_finite() {
        return format!("{value}");
    }
    let scientific = format!("{:.*e}", precision - 1, value);
    let (mantissa, exponent) = scientific.split_once('e').expect("{:e} has an exponent");
    let exponent: i32 = exponent.parse().expect("{:e} writes an integer exponent");
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if exponent < -4 || exponent >= precision as i32 {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), exponent.abs())
    } else {
        let decimals = (precision as i32 - 1 - exponent).max(0) as usize;
        trim(&format!("{value:.decimals$}"))
    }
}

fn enum_name(value: u32, names: &[(u32, &'static str)]) -> String {
    names
        .iter()
        .find(|(v, _)| *v == value)
        .map_or_else(|| format!("0x{value:04X}"), |(_, n)| n.to_string())
}

const CAPS: &[(u32, &str)] = &[
    (GL_DEPTH_TEST, "GL_DEPTH_TEST"),
    (GL_LIGHTING, "GL_LIGHTING"),
    (GL_LIGHT0, "GL_LIGHT0"),
];
const MODES: &[(u32, &str)] = &[
    (GL_QUADS, "GL_QUADS"),
    (GL_LINES, "GL_LINES"),
    (GL_LINE_LOOP, "GL_LINE_LOOP"),
    (GL_LINE_STRIP, "GL_LINE_STRIP"),
    (GL_TRIANGLE_STRIP, "GL_TRIANGLE_STRIP"),
];
const MATRICES: &[(u32, &str)] = &[
    (GL_MODELVIEW, "GL_MODELVIEW"),
    (GL_PROJECTION, "GL_PROJECTION"),
];

impl FixedFunction for Recorder {
    fn clear_color(&mut self, r: f32, g: f32, b: f32, a: f32) {
        let args = self.floats(&[r, g, b, a]);
        self.call("glClearColor", &args);
    }
    fn clear(&mut self, mask: u32) {
        let mut bits = Vec::new();
        if mask & GL_DEPTH_BUFFER_BIT != 0 {
            bits.push("GL_DEPTH_BUFFER_BIT");
        }
        if mask & GL_COLOR_BUFFER_BIT != 0 {
            bits.push("GL_COLOR_BUFFER_BIT");
        }
        self.call("glClear", &bits.join(" | "));
    }
    fn enable(&mut self, cap: u32) {
        self.call("glEnable", &enum_name(cap, CAPS));
    }
    fn disable(&mut self, cap: u32) {
        self.call("glDisable", &enum_name(cap, CAPS));
    }
    fn lightfv(&mut self, light: u32, pname: u32, params: [f32; 4]) {
        let pname = if pname == GL_POSITION {
            "GL_POSITION".to_string()
        } else {
            format!("0x{pname:04X}")
        };
        let args = format!(
            "{}, {pname}, {{{}}}",
            enum_name(light, CAPS),
            self.floats(&params)
        );
        self.call("glLightfv", &args);
    }
    fn line_width(&mut self, width: f32) {
        let args = self.float(width);
        self.call("glLineWidth", &args);
    }
    fn color3f(&mut self, r: f32, g: f32, b: f32) {
        let args = self.floats(&[r, g, b]);
        self.call("glColor3f", &args);
    }
    fn viewport(&mut self, x: i32, y: i32, width: i32, height: i32) {
        self.call("glViewport", &format!("{x}, {y}, {width}, {height}"));
    }
    fn matrix_mode(&mut self, mode: u32) {
        self.in_modelview = mode == GL_MODELVIEW;
        self.call("glMatrixMode", &enum_name(mode, MATRICES));
    }
    fn load_identity(&mut self) {
        if self.in_modelview {
            *self.modelview.last_mut().expect("never empty") = glam::DMat4::IDENTITY;
        }
        self.call("glLoadIdentity", "");
    }
    fn mult_matrixf(&mut self, m: &[f32; 16]) {
        self.multiply(glam::Mat4::from_cols_array(m).as_dmat4());
        let args = format!("{{{}}}", self.floats(m));
        self.call("glMultMatrixf", &args);
    }
    fn mult_matrixd(&mut self, m: &[f64; 16]) {
        self.multiply(glam::DMat4::from_cols_array(m));
        let args = format!("{{{}}}", self.doubles(m));
        self.call("glMultMatrixd", &args);
    }
    fn push_matrix(&mut self) {
        if self.in_modelview {
            let top = *self.modelview.last().expect("never empty");
            self.modelview.push(top);
        }
        self.call("glPushMatrix", "");
    }
    fn pop_matrix(&mut self) {
        if self.in_modelview && self.modelview.len() > 1 {
            self.modelview.pop();
        }
        self.call("glPopMatrix", "");
    }
    fn translatef(&mut self, x: f32, y: f32, z: f32) {
        self.multiply(glam::DMat4::from_translation(glam::DVec3::new(
            x.into(),
            y.into(),
            z.into(),
        )));
        let args = self.floats(&[x, y, z]);
        self.call("glTranslatef", &args);
    }
    fn translated(&mut self, x: f64, y: f64, z: f64) {
        self.multiply(glam::DMat4::from_translation(glam::DVec3::new(x, y, z)));
        let args = self.doubles(&[x, y, z]);
        self.call("glTranslated", &args);
    }
    fn rotatef(&mut self, angle: f32, x: f32, y: f32, z: f32) {
        let axis = glam::DVec3::new(x.into(), y.into(), z.into());
        if axis.length_squared() > 0.0 {
            self.multiply(glam::DMat4::from_axis_angle(
                axis.normalize(),
                f64::from(angle).to_radians(),
            ));
        }
        let args = self.floats(&[angle, x, y, z]);
        self.call("glRotatef", &args);
    }
    fn draw_triangles(
        &mut self,
        positions: &[glam::Vec3],
        _normals: &[glam::Vec3],
        indices: &[u32],
    ) {
        let args = format!(
            "GL_TRIANGLES, {}, GL_UNSIGNED_INT, skin /* {} vertices */",
            indices.len(),
            positions.len()
        );
        self.call("glDrawElements", &args);
    }
    fn get_modelview(&mut self) -> [f32; 16] {
        self.call("glGetFloatv", "GL_MODELVIEW_MATRIX, m");
        self.modelview
            .last()
            .expect("never empty")
            .as_mat4()
            .to_cols_array()
    }
    fn load_matrix(&mut self, m: &[f32; 16]) {
        if self.in_modelview {
            *self.modelview.last_mut().expect("never empty") =
                glam::Mat4::from_cols_array(m).as_dmat4();
        }
        let args = format!("{{{}}}", self.floats(m));
        self.call("glLoadMatrixf", &args);
    }
    fn begin(&mut self, mode: u32) {
        self.call("glBegin", &enum_name(mode, MODES));
    }
    fn end(&mut self) {
        self.call("glEnd", "");
    }
    fn vertex3f(&mut self, x: f32, y: f32, z: f32) {
        let args = self.floats(&[x, y, z]);
        self.call("glVertex3f", &args);
    }
    fn normal3f(&mut self, x: f32, y: f32, z: f32) {
        let args = self.floats(&[x, y, z]);
        self.call("glNormal3f", &args);
    }
    /// freeglut's inner calls (client arrays, 16 strips) collapse into this one line.
    fn solid_sphere(&mut self, radius: f64, slices: i32, stacks: i32) {
        let args = format!("{}, {slices}, {stacks}", self.double(radius));
        self.call("glutSolidSphere", &args);
    }
}

#[cfg(test)]
mod tests {
    use super::format_g;

    #[test]
    fn format_g_is_c_general_notation() {
        assert_eq!(format_g(-0.5440211, 7), "-0.5440211");
        assert_eq!(format_g(167.81430053710938, 16), "167.8143005371094");
        assert_eq!(format_g(2.414213562373095, 16), "2.414213562373095");
        assert_eq!(format_g(30.0, 7), "30");
        assert_eq!(format_g(-0.0, 7), "-0");
        assert_eq!(format_g(0.0001, 7), "0.0001");
        assert_eq!(format_g(0.00001234, 7), "1.234e-05");
        assert_eq!(format_g(12345678.0, 7), "1.234568e+07");
    }
}
