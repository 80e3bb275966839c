//! An offscreen OpenGL context in memory through Mesa's OSMesa, loaded at run time
//! (`libOSMesa.so.8`, Debian package `libosmesa6`): no display, no GPU, no link-time GL.

use crate::io::error::Error;
use crate::render::fixed::GlTable;
use libloading::Library;
use std::ffi::{CStr, c_char, c_void};

const OSMESA_RGBA: u32 = 0x1908;
const GL_UNSIGNED_BYTE: u32 = 0x1401;
pub(crate) const LIBRARY: &str = "libOSMesa.so.8";

type CreateContextExt = unsafe extern "C" fn(u32, i32, i32, i32, *mut c_void) -> *mut c_void;
type MakeCurrent = unsafe extern "C" fn(*mut c_void, *mut c_void, u32, i32, i32) -> u8;
pub(crate) type GetProcAddress = unsafe extern "C" fn(*const c_char) -> *const c_void;
type DestroyContext = unsafe extern "C" fn(*mut c_void);

/// One OSMesa context drawing into its own RGBA buffer. A context is current per thread: make
/// one per thread, and draw with it on the thread that made it.
pub struct OsMesa {
    context: *mut c_void,
    make_current: MakeCurrent,
    destroy: DestroyContext,
    /// The colour buffer OSMesa renders into; it must not move while the context uses it.
    buffer: Vec<u8>,
    width: u32,
    height: u32,
    pub gl: GlTable,
    _library: Library,
}

impl OsMesa {
    /// A context with a 24-bit depth buffer and no multisampling (the article's window on
    /// llvmpipe), current on this thread, with a `width × height` buffer.
    pub fn new(width: u32, height: u32) -> Result<OsMesa, Error> {
        crate::limits::picture_size(width, height)?;
        // SAFETY: loading Mesa's OSMesa runs its initialisers, which have no preconditions.
        let library = unsafe { Library::new(LIBRARY) }.map_err(|e| {
            Error::Environment(format!(
                "offscreen rendering needs {LIBRARY} ({e}); install it with: apt-get install libosmesa6"
            ))
        })?;
        // SAFETY: the symbols have these C signatures in every OSMesa since 3.5.
        let (create, make_current, get_proc, destroy) = unsafe {
            let symbol_error = |e: libloading::Error| Error::Environment(format!("{LIBRARY}: {e}"));
            (
                *library
                    .get::<CreateContextExt>(b"OSMesaCreateContextExt\0")
                    .map_err(symbol_error)?,
                *library
                    .get::<MakeCurrent>(b"OSMesaMakeCurrent\0")
                    .map_err(symbol_error)?,
                *library
                    .get::<GetProcAddress>(b"OSMesaGetProcAddress\0")
                    .map_err(symbol_error)?,
                *library
                    .get::<DestroyContext>(b"OSMesaDestroyContext\0")
                    .map_err(symbol_error)?,
            )
        };
        // SAFETY: RGBA, 24 depth bits, no stencil, no accumulation buffer, no shared context.
        let context = unsafe { create(OSMESA_RGBA, 24, 0, 0, std::ptr::null_mut()) };
        if context.is_null() {
            return Err(Error::Environment(
                "OSMesa could not create a context".into(),
            ));
        }
        let buffer =
            crate::limits::zeroed_bytes(width as usize * height as usize * 4, "the picture");
        let mut buffer = match buffer {
            Ok(buffer) => buffer,
            Err(e) => {
                // SAFETY: the context was created above and is not used again.
                unsafe { destroy(context) };
                return Err(e);
            }
        };
        // SAFETY: the buffer holds width × height RGBA bytes and lives as long as the context.
        let current = unsafe {
            make_current(
                context,
                buffer.as_mut_ptr().cast(),
                GL_UNSIGNED_BYTE,
                width as i32,
                height as i32,
            )
        };
        if current == 0 {
            // SAFETY: the context was created above and is not used again.
            unsafe { destroy(context) };
            return Err(Error::Environment(
                "OSMesa could not make its context current".into(),
            ));
        }
        let loader = |name: &CStr| {
            // SAFETY: a NUL-terminated name; OSMesa returns null or the entry point.
            unsafe { get_proc(name.as_ptr()) }
        };
        // SAFETY: OSMesa's addresses belong to the context made current above, which stays
        // current on this thread while the OsMesa value (and the table in it) lives.
        let gl = unsafe { GlTable::load(loader) };
        let gl = match gl {
            Ok(gl) => gl,
            Err(e) => {
                // SAFETY: as above.
                unsafe { destroy(context) };
                return Err(e);
            }
        };
        Ok(OsMesa {
            context,
            make_current,
            destroy,
            buffer,
            width,
            height,
            gl,
            _library: library,
        })
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Makes this context current on the calling thread again (after another one was).
    pub fn make_current(&mut self) -> Result<(), Error> {
        // SAFETY: the buffer matches the size it was made for and outlives the context.
        let ok = unsafe {
            (self.make_current)(
                self.context,
                self.buffer.as_mut_ptr().cast(),
                GL_UNSIGNED_BYTE,
                self.width as i32,
                self.height as i32,
            )
        };
        if ok == 0 {
            return Err(Error::Environment(
                "OSMesa could not make its context current".into(),
            ));
        }
        Ok(())
    }

    /// Hands over the buffer holding the picture drawn so far (RGBA rows from the bottom up)
    /// and draws on into `spare` from now on, which must be as large. The next frame is drawn
    /// while the last one is encoded elsewhere, without a copy.
    pub fn swap_buffer(&mut self, spare: Vec<u8>) -> Result<Vec<u8>, Error> {
        if spare.len() != self.buffer.len() {
            return Err(Error::usage(format!(
                "a picture buffer of {} bytes for a {}x{} context",
                spare.len(),
                self.width,
                self.height
            )));
        }
        // SAFETY: this context is current on this thread (every drawing call needs it).
        unsafe { glow::HasContext::finish(&self.gl.gl) };
        let drawn = std::mem::replace(&mut self.buffer, spare);
        self.make_current()?;
        Ok(drawn)
    }

    /// The picture drawn so far, as RGB rows from the top down.
    pub fn read_rgb(&self) -> Vec<u8> {
        // OSMesa draws into our own buffer (bottom row first): once GL has finished, the picture
        // is read from there, flipped and stripped of alpha in one pass, without glReadPixels'
        // copy into a second buffer.
        // SAFETY: this context is current on this thread (every drawing call needs it).
        unsafe { glow::HasContext::finish(&self.gl.gl) };
        crate::render::image::Image::from_rgba_bottom_up(self.width, self.height, &self.buffer).rgb
    }
}

impl Drop for OsMesa {
    fn drop(&mut self) {
        // SAFETY: the context was created by this library and is destroyed once.
        unsafe { (self.destroy)(self.context) };
    }
}
