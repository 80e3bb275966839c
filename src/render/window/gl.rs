//! The window and its GL context: a winit window with a compatibility-profile context from
//! glutin (no multisampling), what the machine must have for it, and the shared event-loop
//! plumbing of the viewer and the skinning demo.

use crate::io::error::Error;
use crate::render::fixed::GlTable;
use glutin::config::{ConfigTemplateBuilder, GlConfig};
use glutin::context::{ContextAttributesBuilder, GlProfile, PossiblyCurrentContext};
use glutin::display::{GetGlDisplay, GlDisplay};
use glutin::prelude::NotCurrentGlContext;
use glutin::surface::{Surface, WindowSurface};
use glutin_winit::{DisplayBuilder, GlWindow};
use raw_window_handle::HasWindowHandle;
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

/// C++: `glutInitWindowSize(600, 600)`.
pub const WINDOW_SIZE: u32 = 600;

/// Shared libraries the window needs, with the Debian package of each.
pub(super) const X_LIBRARIES: &[(&str, &str)] = &[
    ("libX11.so.6", "libx11-6"),
    ("libX11-xcb.so.1", "libx11-xcb1"),
    ("libxcb.so.1", "libxcb1"),
    ("libxkbcommon-x11.so.0", "libxkbcommon-x11-0"),
    ("libXcursor.so.1", "libxcursor1"),
    ("libXi.so.6", "libxi6"),
    ("libGL.so.1", "libgl1 libglx-mesa0 libgl1-mesa-dri"),
];

pub use crate::render::{SKIN_DEMO_OFFSCREEN, VIEWER_OFFSCREEN};

/// Fails with one clear line when there is no display to open a window on, or when the X
/// libraries winit loads at run time are missing (without libxkbcommon-x11 it panics).
/// `offscreen` names the command that draws the same without a display.
pub fn check_environment(offscreen: &str) -> Result<(), Error> {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    if !set("DISPLAY") {
        let why = if set("WAYLAND_DISPLAY") {
            "WAYLAND_DISPLAY is set but DISPLAY is not, and bvhview's window needs X11 (XWayland)"
        } else {
            "neither DISPLAY nor WAYLAND_DISPLAY is set"
        };
        return Err(Error::Environment(format!(
            "no display to open a window on: {why}. {offscreen} draws without one"
        )));
    }
    let missing: Vec<&str> = X_LIBRARIES
        .iter()
        // SAFETY: these are the system's X and GL libraries, whose initialisers are safe to run.
        .filter(|(library, _)| unsafe { libloading::Library::new(library) }.is_err())
        .map(|&(_, package)| package)
        .collect();
    if !missing.is_empty() {
        return Err(Error::Environment(format!(
            "the window needs X11 and OpenGL libraries that are missing; install them with: \
             apt-get install {}",
            missing.join(" ")
        )));
    }
    Ok(())
}

/// A window of `width × height` with a current compatibility-profile context (a depth buffer, no
/// multisampling: the article's GLUT_DOUBLE | GLUT_RGBA | GLUT_DEPTH) and its GL table.
pub(super) fn open_gl_window(
    event_loop: &ActiveEventLoop,
    title: String,
    width: u32,
    height: u32,
) -> Result<Running, Error> {
    let failed =
        |what: &str, e: &dyn std::fmt::Display| Error::Environment(format!("cannot {what}: {e}"));
    let attributes = Window::default_attributes()
        .with_title(title)
        .with_inner_size(PhysicalSize::new(width, height));
    let template = ConfigTemplateBuilder::new().with_depth_size(24);
    let (window, config) = DisplayBuilder::new()
        .with_window_attributes(Some(attributes))
        .build(event_loop, template, |configs| {
            // glutin calls this with at least one configuration.
            configs
                .max_by_key(|c| {
                    (
                        c.num_samples() == 0,
                        c.depth_size() == 24,
                        c.alpha_size() == 8,
                    )
                })
                .expect("glutin offers at least one configuration")
        })
        .map_err(|e| failed("find an OpenGL configuration", &e))?;
    let window = window.ok_or_else(|| Error::Environment("no window was created".into()))?;
    let handle = window
        .window_handle()
        .map_err(|e| failed("get the window handle", &e))?
        .as_raw();
    let display = config.display();
    let attributes = ContextAttributesBuilder::new()
        .with_profile(GlProfile::Compatibility)
        .build(Some(handle));
    // SAFETY: the handle belongs to the window, which outlives the context and the surface
    // (`Running` drops the window last).
    let context = unsafe { display.create_context(&config, &attributes) }
        .map_err(|e| failed("create an OpenGL context", &e))?;
    let surface_attributes = window
        .build_surface_attributes(Default::default())
        .map_err(|e| failed("describe the window surface", &e))?;
    // SAFETY: as above.
    let surface = unsafe { display.create_window_surface(&config, &surface_attributes) }
        .map_err(|e| failed("create the window surface", &e))?;
    let context = context
        .make_current(&surface)
        .map_err(|e| failed("make the OpenGL context current", &e))?;
    // SAFETY: the display's addresses belong to the context made current just above, which
    // the window keeps current on this thread while it draws with the table.
    let gl = unsafe { GlTable::load(|name| display.get_proc_address(name)) }?;
    let size = window.inner_size();
    Ok(Running {
        window,
        surface,
        context,
        gl,
        size: (size.width.max(1), size.height.max(1)),
    })
}

/// A window just opened is kept and drawn; if it could not be opened, the error is kept and the
/// event loop ends.
pub(super) fn keep_or_exit(
    event_loop: &ActiveEventLoop,
    opened: Result<Running, Error>,
    running: &mut Option<Running>,
    error: &mut Option<Error>,
) {
    match opened {
        Ok(window) => {
            window.window.request_redraw();
            *running = Some(window);
        }
        Err(e) => {
            *error = Some(e);
            event_loop.exit();
        }
    }
}

/// Runs `f`, turning a panic into an error message instead of a backtrace with source paths.
pub(super) fn quietly<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    std::panic::set_hook(hook);
    result.map_err(|panic| {
        let text = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "unknown failure".into());
        format!(
            "{text} (the X libraries may be missing: apt-get install libx11-6 libx11-xcb1 \
             libxcb1 libxkbcommon-x11-0 libxcursor1 libxi6 libgl1 libglx-mesa0 libgl1-mesa-dri)"
        )
    })
}

/// winit's event loop on the X display, or one line that says why not: winit's own words
/// without the source path its errors carry ("os error at …/event_loop.rs:NN:").
pub(super) fn new_event_loop(offscreen: &str) -> Result<winit::event_loop::EventLoop<()>, Error> {
    match quietly(winit::event_loop::EventLoop::new) {
        Ok(Ok(event_loop)) => Ok(event_loop),
        Ok(Err(e)) => {
            let text = e.to_string();
            let said = match text.split_once("os error at ") {
                Some((before, rest)) => {
                    format!(
                        "{before}{}",
                        rest.split_once(": ").map_or(rest, |(_, why)| why)
                    )
                }
                None => text,
            };
            let display = std::env::var("DISPLAY").unwrap_or_default();
            Err(Error::Environment(format!(
                "cannot open the X display {display:?}: {said}. {offscreen} draws without one"
            )))
        }
        Err(panicked) => Err(Error::Environment(format!(
            "cannot open the X display: {panicked}"
        ))),
    }
}

/// The window, its surface and its context, once the event loop has started.
///
/// Fields drop in the order they are declared, and glutin requires the surface (and the context
/// drawing into it) to go before the window they were made for: keep `window` last.
pub(super) struct Running {
    pub(super) gl: GlTable,
    pub(super) surface: Surface<WindowSurface>,
    pub(super) context: PossiblyCurrentContext,
    pub(super) size: (u32, u32),
    pub(super) window: Window,
}
