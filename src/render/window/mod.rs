//! The window: a GL context on a winit window (glutin, compatibility profile), and the two
//! programs that run in it, the viewer (`viewer/`, the article's `main` and `keyboard`) and
//! the skinning demo (`skin_demo.rs`, the skinning tutorial's).

mod gl;
mod skin_demo;
mod viewer;

pub use gl::{VIEWER_OFFSCREEN, check_environment};
pub use skin_demo::run_skin_demo;
pub use viewer::{TakeSource, ViewerOptions, ViewerTake, run};
