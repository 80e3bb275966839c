//! The fixed-function OpenGL the article calls, which glow does not have: matrix stack, immediate
//! mode, lights, client-side vertex arrays. The pointers come from the same loader closure as
//! glow's (OSMesa's, GLX's or EGL's `GetProcAddress`).
//!
//! The scene and the draw code call GL only through the [`FixedFunction`] trait, so the same code
//! can render or be recorded.

use crate::io::error::Error;
use crate::render::sphere::Sphere;
use glow::HasContext;
use std::ffi::{CStr, c_void};

pub const GL_MODELVIEW: u32 = 0x1700;
pub const GL_PROJECTION: u32 = 0x1701;
pub const GL_MODELVIEW_MATRIX: u32 = 0x0BA6;
pub const GL_PROJECTION_MATRIX: u32 = 0x0BA7;
pub const GL_LIGHTING: u32 = 0x0B50;
pub const GL_COLOR_MATERIAL: u32 = 0x0B57;
pub const GL_FRONT_AND_BACK: u32 = 0x0408;
pub const GL_AMBIENT: u32 = 0x1200;
pub const GL_DIFFUSE: u32 = 0x1201;
pub const GL_LIGHT0: u32 = 0x4000;
pub const GL_POSITION: u32 = 0x1203;
pub const GL_DEPTH_TEST: u32 = 0x0B71;
pub const GL_NORMALIZE: u32 = 0x0BA1;
pub const GL_CULL_FACE: u32 = 0x0B44;
pub const GL_LINES: u32 = 0x0001;
pub const GL_LINE_LOOP: u32 = 0x0002;
pub const GL_LINE_STRIP: u32 = 0x0003;
pub const GL_QUADS: u32 = 0x0007;
pub const GL_TRIANGLE_STRIP: u32 = 0x0005;
pub const GL_VERTEX_ARRAY: u32 = 0x8074;
pub const GL_NORMAL_ARRAY: u32 = 0x8075;
pub const GL_FLOAT: u32 = 0x1406;
pub const GL_UNSIGNED_SHORT: u32 = 0x1403;
pub const GL_UNSIGNED_BYTE: u32 = 0x1401;
pub const GL_UNSIGNED_INT: u32 = 0x1405;
pub const GL_TRIANGLES: u32 = 0x0004;
pub const GL_RGBA: u32 = 0x1908;
pub const GL_COLOR_BUFFER_BIT: u32 = 0x4000;
pub const GL_DEPTH_BUFFER_BIT: u32 = 0x0100;
pub const GL_VERSION: u32 = 0x1F02;

/// Every GL call the article's `init`, `reshape` and `display` make, one method per call, with
/// the C names' meaning. `solid_sphere` stands for `glutSolidSphere`.
pub trait FixedFunction {
    fn clear_color(&mut self, r: f32, g: f32, b: f32, a: f32);
    fn clear(&mut self, mask: u32);
    fn enable(&mut self, cap: u32);
    fn disable(&mut self, cap: u32);
    fn lightfv(&mut self, light: u32, pname: u32, params: [f32; 4]);
    /// `glMaterialfv(GL_FRONT_AND_BACK, pname, params)`.
    fn materialfv(&mut self, pname: u32, params: [f32; 4]);
    fn line_width(&mut self, width: f32);
    fn color3f(&mut self, r: f32, g: f32, b: f32);
    fn viewport(&mut self, x: i32, y: i32, width: i32, height: i32);
    fn matrix_mode(&mut self, mode: u32);
    fn load_identity(&mut self);
    fn mult_matrixf(&mut self, m: &[f32; 16]);
    fn mult_matrixd(&mut self, m: &[f64; 16]);
    fn push_matrix(&mut self);
    fn pop_matrix(&mut self);
    fn translatef(&mut self, x: f32, y: f32, z: f32);
    fn translated(&mut self, x: f64, y: f64, z: f64);
    fn rotatef(&mut self, angle: f32, x: f32, y: f32, z: f32);
    fn begin(&mut self, mode: u32);
    fn end(&mut self);
    fn vertex3f(&mut self, x: f32, y: f32, z: f32);
    fn normal3f(&mut self, x: f32, y: f32, z: f32);
    /// C++: `glutSolidSphere(radius, slices, stacks)`.
    fn solid_sphere(&mut self, radius: f64, slices: i32, stacks: i32);
    /// `glGetFloatv(GL_MODELVIEW_MATRIX, m)`.
    fn get_modelview(&mut self) -> [f32; 16];
    /// `glLoadMatrixf(m)`.
    fn load_matrix(&mut self, m: &[f32; 16]);
    /// Lit triangles from client-side arrays: `glDrawElements(GL_TRIANGLES, …)`.
    fn draw_triangles(&mut self, positions: &[glam::Vec3], normals: &[glam::Vec3], indices: &[u32]);
    /// `glWindowPos2i(x, y)`: where the next bitmap goes, in pixels from the bottom left.
    fn window_pos(&mut self, x: i32, y: i32);
    /// `glRasterPos3f(x, y, z)`: where the next bitmap goes, a point carried through the
    /// modelview and projection matrices (and coloured as a vertex would be).
    fn raster_pos(&mut self, x: f32, y: f32, z: f32);
    /// `glBitmap(width, height, 0, 0, advance, 0, bits)`: one bit per pixel, rows from the bottom
    /// up, each row whole bytes, most significant bit leftmost. Drawn in the current raster
    /// colour, then the raster position moves `advance` pixels right.
    fn bitmap(&mut self, width: i32, height: i32, advance: f32, bits: &[u8]);
    /// What the calls that follow draw, for a reader of the calls (`bvhview trace --explain`);
    /// GL itself has no such call, and ignores it.
    fn note(&mut self, _note: Note) {}
}

/// A mark in the stream of calls: where the draw of a joint starts and ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Note {
    /// The calls for joint `index` (of the skeleton being drawn) start.
    Joint(usize),
    /// The calls of the joint whose start was marked last (and not yet ended) end.
    JointEnd,
}

type Fn0 = unsafe extern "system" fn();
type FnU32 = unsafe extern "system" fn(u32);
type Fn3f = unsafe extern "system" fn(f32, f32, f32);
type Fn3d = unsafe extern "system" fn(f64, f64, f64);
type Fn4f = unsafe extern "system" fn(f32, f32, f32, f32);
type FnPtrF = unsafe extern "system" fn(*const f32);
type FnPtrD = unsafe extern "system" fn(*const f64);
type FnLightfv = unsafe extern "system" fn(u32, u32, *const f32);
type FnGetFloatv = unsafe extern "system" fn(u32, *mut f32);
type FnVertexPointer = unsafe extern "system" fn(i32, u32, i32, *const c_void);
type FnNormalPointer = unsafe extern "system" fn(u32, i32, *const c_void);
type FnDrawElements = unsafe extern "system" fn(u32, i32, u32, *const c_void);
type Fn2i = unsafe extern "system" fn(i32, i32);
type FnBitmap = unsafe extern "system" fn(i32, i32, f32, f32, f32, f32, *const u8);

/// The GL entry points, loaded once per context.
pub struct GlTable {
    /// The calls glow has (clear, enable, viewport, strings, read-back).
    pub gl: glow::Context,
    lightfv: FnLightfv,
    materialfv: FnLightfv,
    color3f: Fn3f,
    matrix_mode: FnU32,
    load_identity: Fn0,
    load_matrixf: FnPtrF,
    mult_matrixf: FnPtrF,
    mult_matrixd: FnPtrD,
    push_matrix: Fn0,
    pop_matrix: Fn0,
    translatef: Fn3f,
    translated: Fn3d,
    rotatef: Fn4f,
    begin: FnU32,
    end: Fn0,
    vertex3f: Fn3f,
    normal3f: Fn3f,
    get_floatv: FnGetFloatv,
    enable_client_state: FnU32,
    disable_client_state: FnU32,
    vertex_pointer: FnVertexPointer,
    normal_pointer: FnNormalPointer,
    draw_elements: FnDrawElements,
    window_pos2i: Fn2i,
    raster_pos3f: Fn3f,
    bitmap: FnBitmap,
    /// glutSolidSphere's geometry for the last (radius, slices, stacks) asked for.
    sphere: Option<Sphere>,
}

macro_rules! load_all {
    ($gl:expr, $loader:expr, $($field:ident: $ty:ty = $name:literal),* $(,)?) => {{
        $(
            let pointer = $loader(CStr::from_bytes_with_nul(concat!($name, "\0").as_bytes())
                .expect("literal names have one NUL"));
            if pointer.is_null() {
                return Err(Error::Environment(format!("OpenGL has no {}", $name)));
            }
            // SAFETY: a non-null pointer from the context's loader for this exact name has the
            // C signature the field's type spells out (OpenGL 1.1).
            let $field = unsafe { std::mem::transmute::<*const c_void, $ty>(pointer) };
        )*
        GlTable { gl: $gl, $($field,)* sphere: None }
    }};
}

impl GlTable {
    /// Loads every entry point with `loader`, then checks that the context is one where the
    /// fixed-function calls exist: Mesa's loaders return non-null even for names they do not
    /// have, so the version string is the only honest answer.
    ///
    /// # Safety
    ///
    /// `loader` must return, for each name, null or the address of that GL function of a
    /// context that is current on this thread and stays current while the table is used: every
    /// method of the table calls through these addresses.
    pub unsafe fn load(mut loader: impl FnMut(&CStr) -> *const c_void) -> Result<GlTable, Error> {
        // SAFETY: the caller promises that the loader's addresses are this context's functions.
        let gl = unsafe { glow::Context::from_loader_function_cstr(&mut loader) };
        let table = load_all!(
            gl,
            loader,
            lightfv: FnLightfv = "glLightfv",
            materialfv: FnLightfv = "glMaterialfv",
            color3f: Fn3f = "glColor3f",
            matrix_mode: FnU32 = "glMatrixMode",
            load_identity: Fn0 = "glLoadIdentity",
            load_matrixf: FnPtrF = "glLoadMatrixf",
            mult_matrixf: FnPtrF = "glMultMatrixf",
            mult_matrixd: FnPtrD = "glMultMatrixd",
            push_matrix: Fn0 = "glPushMatrix",
            pop_matrix: Fn0 = "glPopMatrix",
            translatef: Fn3f = "glTranslatef",
            translated: Fn3d = "glTranslated",
            rotatef: Fn4f = "glRotatef",
            begin: FnU32 = "glBegin",
            end: Fn0 = "glEnd",
            vertex3f: Fn3f = "glVertex3f",
            normal3f: Fn3f = "glNormal3f",
            get_floatv: FnGetFloatv = "glGetFloatv",
            enable_client_state: FnU32 = "glEnableClientState",
            disable_client_state: FnU32 = "glDisableClientState",
            vertex_pointer: FnVertexPointer = "glVertexPointer",
            normal_pointer: FnNormalPointer = "glNormalPointer",
            draw_elements: FnDrawElements = "glDrawElements",
            window_pos2i: Fn2i = "glWindowPos2i",
            raster_pos3f: Fn3f = "glRasterPos3f",
            bitmap: FnBitmap = "glBitmap",
        );
        let version = table.string(GL_VERSION);
        if !is_compatibility(&version) {
            return Err(Error::Environment(format!(
                "the OpenGL context is \"{version}\"; bvhview draws with the fixed-function \
                 pipeline and needs a compatibility profile (or a version below 3.2)"
            )));
        }
        Ok(table)
    }

    /// `glGetString(name)`, or an empty string.
    pub fn string(&self, name: u32) -> String {
        // SAFETY: a plain query on the current context.
        unsafe { self.gl.get_parameter_string(name) }
    }

    /// `glGetFloatv` of a 4×4 matrix (`GL_MODELVIEW_MATRIX`, `GL_PROJECTION_MATRIX`).
    pub fn get_matrix(&self, pname: u32) -> [f32; 16] {
        let mut m = [0.0f32; 16];
        // SAFETY: both matrix queries write exactly 16 floats.
        unsafe { (self.get_floatv)(pname, m.as_mut_ptr()) };
        m
    }

    /// `glLoadMatrixf`.
    pub fn load_matrixf(&mut self, m: &[f32; 16]) {
        // SAFETY: a pointer to 16 floats, as the call reads.
        unsafe { (self.load_matrixf)(m.as_ptr()) }
    }

    /// Reads the colour buffer as RGBA rows, bottom row first (GL's order).
    pub fn read_rgba(&self, width: usize, height: usize) -> Vec<u8> {
        let mut pixels = vec![0u8; width * height * 4];
        // SAFETY: the buffer holds width × height RGBA bytes; the default pack alignment (4)
        // divides a row of RGBA bytes.
        unsafe {
            self.gl.finish();
            self.gl.read_pixels(
                0,
                0,
                width as i32,
                height as i32,
                GL_RGBA,
                GL_UNSIGNED_BYTE,
                glow::PixelPackData::Slice(Some(&mut pixels)),
            );
        }
        pixels
    }
}

/// True for "x.y (Compatibility Profile) …", and for any version below 3.2 (which has only the
/// compatibility pipeline).
pub fn is_compatibility(version: &str) -> bool {
    if version.contains("Compatibility") {
        return true;
    }
    let mut numbers = version
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<u32>().unwrap_or(0));
    match (numbers.next(), numbers.next()) {
        (Some(major), Some(minor)) => (major, minor) < (3, 2) && !version.contains("Core"),
        _ => false,
    }
}

impl FixedFunction for GlTable {
    // SAFETY (all methods): the pointers were loaded for a compatibility context that is current
    // on this thread whenever these are called, and each call passes the arguments its C
    // signature takes.
    fn window_pos(&mut self, x: i32, y: i32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.window_pos2i)(x, y) }
    }
    fn raster_pos(&mut self, x: f32, y: f32, z: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.raster_pos3f)(x, y, z) }
    }
    fn bitmap(&mut self, width: i32, height: i32, advance: f32, bits: &[u8]) {
        // GL reads ceil(width / 8) bytes for each of `height` rows: a shorter slice draws nothing.
        let needed = usize::try_from(width.max(0)).unwrap_or(0).div_ceil(8)
            * usize::try_from(height.max(0)).unwrap_or(0);
        if bits.len() < needed {
            return;
        }
        // SAFETY: the current context's entry points (see the impl); `bits` holds the rows GL reads (checked above).
        unsafe {
            self.gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
            (self.bitmap)(width, height, 0.0, 0.0, advance, 0.0, bits.as_ptr());
        }
    }
    fn clear_color(&mut self, r: f32, g: f32, b: f32, a: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.clear_color(r, g, b, a) }
    }
    fn clear(&mut self, mask: u32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.clear(mask) }
    }
    fn enable(&mut self, cap: u32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.enable(cap) }
    }
    fn disable(&mut self, cap: u32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.disable(cap) }
    }
    fn lightfv(&mut self, light: u32, pname: u32, params: [f32; 4]) {
        // SAFETY: the current context's entry point (see the impl); `params` holds the 4 floats it reads.
        unsafe { (self.lightfv)(light, pname, params.as_ptr()) }
    }
    fn materialfv(&mut self, pname: u32, params: [f32; 4]) {
        // SAFETY: the current context's entry point (see the impl); `params` holds the 4 floats it reads.
        unsafe { (self.materialfv)(GL_FRONT_AND_BACK, pname, params.as_ptr()) }
    }
    fn line_width(&mut self, width: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.line_width(width) }
    }
    fn color3f(&mut self, r: f32, g: f32, b: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.color3f)(r, g, b) }
    }
    fn viewport(&mut self, x: i32, y: i32, width: i32, height: i32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { self.gl.viewport(x, y, width, height) }
    }
    fn matrix_mode(&mut self, mode: u32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.matrix_mode)(mode) }
    }
    fn load_identity(&mut self) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.load_identity)() }
    }
    fn mult_matrixf(&mut self, m: &[f32; 16]) {
        // SAFETY: the current context's entry point (see the impl); `m` holds the 16 values it reads.
        unsafe { (self.mult_matrixf)(m.as_ptr()) }
    }
    fn mult_matrixd(&mut self, m: &[f64; 16]) {
        // SAFETY: the current context's entry point (see the impl); `m` holds the 16 values it reads.
        unsafe { (self.mult_matrixd)(m.as_ptr()) }
    }
    fn push_matrix(&mut self) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.push_matrix)() }
    }
    fn pop_matrix(&mut self) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.pop_matrix)() }
    }
    fn translatef(&mut self, x: f32, y: f32, z: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.translatef)(x, y, z) }
    }
    fn translated(&mut self, x: f64, y: f64, z: f64) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.translated)(x, y, z) }
    }
    fn rotatef(&mut self, angle: f32, x: f32, y: f32, z: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.rotatef)(angle, x, y, z) }
    }
    fn begin(&mut self, mode: u32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.begin)(mode) }
    }
    fn end(&mut self) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.end)() }
    }
    fn vertex3f(&mut self, x: f32, y: f32, z: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.vertex3f)(x, y, z) }
    }
    fn normal3f(&mut self, x: f32, y: f32, z: f32) {
        // SAFETY: the current context's entry point (see the impl), arguments by value.
        unsafe { (self.normal3f)(x, y, z) }
    }

    fn get_modelview(&mut self) -> [f32; 16] {
        self.get_matrix(GL_MODELVIEW_MATRIX)
    }
    fn load_matrix(&mut self, m: &[f32; 16]) {
        self.load_matrixf(m)
    }
    fn draw_triangles(
        &mut self,
        positions: &[glam::Vec3],
        normals: &[glam::Vec3],
        indices: &[u32],
    ) {
        // GL reads `positions[i]` and `normals[i]` for every index without checking: an index
        // past the arrays would read outside them. Such a call draws nothing.
        let in_range = indices.iter().all(|&i| (i as usize) < positions.len());
        let Ok(count) = i32::try_from(indices.len()) else {
            return;
        };
        if count == 0 || positions.len() != normals.len() || !in_range {
            return;
        }
        // Vec3 is three packed f32s, as glVertexPointer(3, GL_FLOAT, 0) and glNormalPointer read.
        // SAFETY: the current context's entry points (see the impl), with the arguments their C signatures take.
        unsafe {
            (self.enable_client_state)(GL_VERTEX_ARRAY);
            (self.enable_client_state)(GL_NORMAL_ARRAY);
            (self.vertex_pointer)(3, GL_FLOAT, 0, positions.as_ptr().cast());
            (self.normal_pointer)(GL_FLOAT, 0, normals.as_ptr().cast());
            (self.draw_elements)(
                GL_TRIANGLES,
                count,
                GL_UNSIGNED_INT,
                indices.as_ptr().cast(),
            );
            (self.disable_client_state)(GL_VERTEX_ARRAY);
            (self.disable_client_state)(GL_NORMAL_ARRAY);
        }
    }

    /// As freeglut: client-side vertex and normal arrays, one `glDrawElements` triangle strip per
    /// stack. The geometry is built on the first call and kept.
    fn solid_sphere(&mut self, radius: f64, slices: i32, stacks: i32) {
        let (radius, slices, stacks) = (
            radius as f32,
            slices.max(1) as usize,
            stacks.max(2) as usize,
        );
        let cached = self
            .sphere
            .as_ref()
            .is_some_and(|s| s.radius == radius && s.slices == slices && s.stacks == stacks);
        if !cached {
            self.sphere = Some(Sphere::new(radius, slices, stacks));
        }
        let sphere = self.sphere.as_ref().expect("built above");
        let strip = sphere.strip_len();
        // SAFETY: the current context's entry points (see the impl), with the arguments their C signatures take.
        unsafe {
            (self.enable_client_state)(GL_VERTEX_ARRAY);
            (self.enable_client_state)(GL_NORMAL_ARRAY);
            (self.vertex_pointer)(3, GL_FLOAT, 0, sphere.positions.as_ptr().cast());
            (self.normal_pointer)(GL_FLOAT, 0, sphere.normals.as_ptr().cast());
            for part in 0..sphere.stacks {
                let first = sphere.indices[part * strip..].as_ptr();
                (self.draw_elements)(
                    GL_TRIANGLE_STRIP,
                    strip as i32,
                    GL_UNSIGNED_SHORT,
                    first.cast(),
                );
            }
            (self.disable_client_state)(GL_VERTEX_ARRAY);
            (self.disable_client_state)(GL_NORMAL_ARRAY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::osmesa::{GetProcAddress, LIBRARY, OsMesa};

    /// A GL without an entry point bvhview needs is the machine's shortcoming: exit code 1.
    #[test]
    fn a_missing_entry_point_is_the_machines_failure() {
        // A current context, so that the rest of the table loads for real.
        let _context = OsMesa::new(8, 8).unwrap();
        // SAFETY: the same library the context came from; its symbol has this signature.
        let library = unsafe { libloading::Library::new(LIBRARY) }.unwrap();
        // SAFETY: OSMesaGetProcAddress has this signature in the library loaded above.
        let get_proc = unsafe {
            *library
                .get::<GetProcAddress>(b"OSMesaGetProcAddress\0")
                .unwrap()
        };
        let loader = |name: &CStr| {
            if name.to_bytes() == b"glLightfv" {
                std::ptr::null()
            } else {
                // SAFETY: a NUL-terminated name.
                unsafe { get_proc(name.as_ptr()) }
            }
        };
        // SAFETY: the context made above is current on this thread; the table is not used.
        let error = unsafe { GlTable::load(loader) }.err().unwrap();
        assert_eq!(error.to_string(), "OpenGL has no glLightfv");
        assert!(!error.is_the_callers(), "the machine's, not the input's");
    }

    #[test]
    fn only_compatibility_contexts_are_accepted() {
        assert!(is_compatibility("4.5 (Compatibility Profile) Mesa 22.3.6"));
        assert!(is_compatibility("2.1 Mesa 22.3.6"));
        assert!(!is_compatibility("4.5 (Core Profile) Mesa 22.3.6"));
    }
}
