//! The skinning tutorial's linear blend skinning demo in a window: two bones, three quads, a
//! right-button drag bends the second bone.

use super::gl::{Running, check_environment, keep_or_exit, open_gl_window};
use crate::io::error::Error;
use glutin::prelude::GlSurface;
use std::num::NonZeroU32;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};
use winit::window::WindowId;

/// The skinning tutorial's demo in a window: a right-button drag bends the second bone about Y
/// (up and down) and Z (left and right); Esc quits.
pub fn run_skin_demo(bend: (f32, f32)) -> Result<(), Error> {
    check_environment(super::gl::SKIN_DEMO_OFFSCREEN)?;
    let event_loop = super::gl::new_event_loop(super::gl::SKIN_DEMO_OFFSCREEN)?;
    let mut app = SkinDemo {
        bend,
        drag: None,
        dragging: false,
        running: None,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Environment(format!("the window's event loop failed: {e}")))?;
    app.error.map_or(Ok(()), Err)
}

struct SkinDemo {
    bend: (f32, f32),
    drag: Option<(f64, f64)>,
    dragging: bool,
    running: Option<Running>,
    error: Option<Error>,
}

impl SkinDemo {
    fn title(&self) -> String {
        format!(
            "bvhview skin-demo - bend Y {:.0}°, Z {:.0}° (right-drag)",
            self.bend.0, self.bend.1
        )
    }
}

impl ApplicationHandler for SkinDemo {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        let (width, height) = crate::render::skin_demo::SIZE;
        let opened = open_gl_window(event_loop, self.title(), width, height);
        keep_or_exit(event_loop, opened, &mut self.running, &mut self.error);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let title = self.title();
        let Some(running) = self.running.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed
                    && event.logical_key == Key::Named(NamedKey::Escape) =>
            {
                event_loop.exit()
            }
            WindowEvent::Resized(size) => {
                if let (Some(w), Some(h)) =
                    (NonZeroU32::new(size.width), NonZeroU32::new(size.height))
                {
                    running.surface.resize(&running.context, w, h);
                    running.size = (w.get(), h.get());
                }
                running.window.request_redraw();
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Right,
                ..
            } => {
                self.dragging = state == ElementState::Pressed;
                self.drag = None;
            }
            WindowEvent::CursorMoved { position, .. } if self.dragging => {
                if let Some((x, y)) = self.drag {
                    // As the tutorial has it: one degree per pixel; Z follows x, Y follows y.
                    self.bend.1 += (position.x - x) as f32;
                    self.bend.0 -= (position.y - y) as f32;
                    running.window.request_redraw();
                }
                self.drag = Some((position.x, position.y));
            }
            WindowEvent::RedrawRequested => {
                let (width, height) = running.size;
                crate::render::skin_demo::draw(&mut running.gl, self.bend, width, height);
                if let Err(e) = running.surface.swap_buffers(&running.context) {
                    self.error = Some(Error::Environment(format!(
                        "cannot present the picture: {e}"
                    )));
                    event_loop.exit();
                }
                running.window.set_title(&title);
            }
            _ => {}
        }
    }
}
