//! Pictures: golden snapshots, the studio look and its scale, framing, the HUD, MP4 video and
//! the window under Xvfb.
//! One test binary; `cargo test --test render MODULE` runs one file's tests
//! (`BVHVIEW_BLESS=1 cargo test --test render golden_pictures` rewrites the golden pictures).

#[path = "../common/mod.rs"]
mod common;

mod every_take_framed_in_studio;
mod golden_pictures;
mod hud_fits_small_pictures;
mod studio_look_and_scale;
mod video_mp4;
#[cfg(feature = "window")]
mod window_under_xvfb;
