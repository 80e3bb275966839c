//! C++: main.cpp's `main` and `keyboard`: a 600×600 window whose `display` is the article's,
//! through glutin and winit on a compatibility-profile context with no multisampling.
//!
//! The article's keys: W next frame (wrapping), A/D turn the camera by 0.1 rad, Esc quits. The
//! article wraps the angle at 360 although it is in radians; here it wraps at 2π. Beyond the
//! article, all opt-in so the first picture stays the article's: Space plays at the file's frame
//! time, S goes back a frame, a mouse drag orbits, the wheel zooms, F frames the skeleton, B
//! toggles the stick figure, K the generated skin.

use super::gl::{check_environment, keep_or_exit};
use crate::io::error::Error;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::WindowId;

mod playback;
#[cfg(feature = "video")]
mod record;
mod state;
mod takes;

use playback::{frames_due, next_wake};
use state::Viewer;
pub use takes::{TakeSource, ViewerOptions, ViewerTake};

/// C++: `main` in main.cpp: a 600×600 window whose display, reshape and keyboard functions are
/// the article's. GLUT's main loop becomes winit's; the files are loaded by the caller, not in
/// `init`, so a bad file is reported before any window opens. Several takes stand side by side
/// on one timeline; files dropped on the window join them.
pub fn run(takes: Vec<ViewerTake>, options: ViewerOptions) -> Result<(), Error> {
    check_environment(super::gl::VIEWER_OFFSCREEN)?;
    if takes.is_empty() {
        return Err(Error::usage("nothing to show"));
    }
    let event_loop = super::gl::new_event_loop(super::gl::VIEWER_OFFSCREEN)?;
    let mut app = Viewer::new(takes, options);
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Environment(format!("the window's event loop failed: {e}")))?;
    // A recording under way when the window closes is written.
    let recorded = app.stop_recording();
    if app.error.is_none() {
        recorded?;
    }
    // The first output asked for that failed while the window was open (said then) ends the
    // program unsuccessfully, as a failed `snapshot -o` would.
    match (app.error, app.failed_output) {
        (Some(error), _) | (None, Some(error)) => Err(error),
        (None, None) => Ok(()),
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        let opened = self.create(event_loop);
        keep_or_exit(event_loop, opened, &mut self.running, &mut self.error);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let mut redraw = false;
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                self.resize(size);
                redraw = true;
            }
            WindowEvent::RedrawRequested => {
                if let Err(error) = self.redraw() {
                    self.error = Some(error);
                    event_loop.exit();
                }
            }
            WindowEvent::DroppedFile(path) => {
                self.add(path);
                redraw = true;
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                if !self.key(&event.logical_key) {
                    event_loop.exit();
                }
                redraw = true;
            }
            WindowEvent::ModifiersChanged(modifiers) => {
                self.shift = modifiers.state().shift_key();
            }
            WindowEvent::MouseInput {
                state,
                button: button @ (MouseButton::Left | MouseButton::Middle),
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                // A press on the timeline seeks, and so does the drag that follows it.
                let on_bar = self.bar_frame(false);
                match on_bar {
                    Some(frame) if pressed && button == MouseButton::Left => {
                        self.seeking = true;
                        self.frame = frame;
                        redraw = true;
                    }
                    _ => {
                        self.seeking = false;
                        self.dragging = pressed.then_some(button);
                    }
                }
                if !pressed {
                    self.seeking = false;
                }
                self.drag_from = None;
            }
            WindowEvent::CursorMoved { position, .. } if self.seeking => {
                self.cursor = (position.x, position.y);
                if let Some(frame) = self.bar_frame(true) {
                    self.frame = frame;
                    redraw = true;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if self.dragging.is_none() {
                    return;
                }
                if let Some((x, y)) = self.drag_from {
                    let (dx, dy) = ((position.x - x) as f32, (position.y - y) as f32);
                    // Shift or the middle button pans; otherwise across turns, up and down tilts.
                    if self.shift || self.dragging == Some(MouseButton::Middle) {
                        self.camera.pan(-dx * 0.002, dy * 0.002);
                    } else {
                        self.turn(dx * 0.01);
                        self.camera.pitch = (self.camera.pitch + dy * 0.01).clamp(-1.45, 1.45);
                    }
                    redraw = true;
                }
                self.drag_from = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.camera.distance =
                    (self.camera.distance * 0.9f32.powf(lines)).clamp(2.0, 900.0);
                redraw = true;
            }
            _ => {}
        }
        if redraw && let Some(running) = &self.running {
            running.window.request_redraw();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if !self.playing {
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        let now = Instant::now();
        if now >= self.next_tick {
            // Keep to the takes' time; after a stall, skip ahead rather than rush.
            let (frames, later) = frames_due(now - self.next_tick, self.frame_duration());
            self.next_tick += later;
            let count = self.frame_count() as u64;
            if self.looping {
                self.frame = ((self.frame as u64 + frames % count) % count) as usize;
            } else {
                // Without loop, playback stops at the last frame.
                let last = count - 1;
                self.frame = (self.frame as u64).saturating_add(frames).min(last) as usize;
                if self.frame as u64 == last {
                    self.playing = false;
                }
            }
            if let Some(running) = &self.running {
                running.window.request_redraw();
            }
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(next_wake(now, self.next_tick)));
    }
}

#[cfg(test)]
mod tests {
    use super::playback::{SHORTEST_WAKE, playback_step};
    use super::*;
    use crate::model::pose::OffsetMode;
    use crate::render::Camera;
    use crate::render::draw::Style;
    use crate::render::options::Look;
    use std::path::{Path, PathBuf};
    use std::time::Duration;
    use winit::keyboard::Key;

    /// The window's defaults, saying nothing of pictures written.
    fn quiet_options() -> ViewerOptions {
        ViewerOptions {
            offset_mode: OffsetMode::Replace,
            style: Style::Points,
            skin: false,
            look: Look::Article,
            quiet: true,
            true_scale: false,
            style_chosen: false,
            record: None,
            spelling: &crate::io::message::RustSpelling,
        }
    }

    fn viewer_on(path: &Path) -> Viewer {
        let source = TakeSource {
            path: path.to_path_buf(),
            motion: None,
            frame_time: None,
            max_size: u64::MAX,
            take: None,
            insist: Default::default(),
            body_model: None,
            units: None,
            up: None,
        };
        Viewer::new(
            vec![
                ViewerTake::from_source(
                    source,
                    OffsetMode::Replace,
                    &crate::io::message::RustSpelling,
                )
                .unwrap(),
            ],
            quiet_options(),
        )
    }

    /// P names its picture after the first file, and after the walk for the bundled walk (issue
    /// 27: it wrote `the bundled walk_frame00020.png`).
    #[test]
    fn p_names_the_picture_after_the_file_or_the_walk() {
        let mut viewer = walk_viewer();
        viewer.frame = 20;
        assert_eq!(viewer.picture_name(), PathBuf::from("walk_frame00020.png"));
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/oracle/inputs/tiny_crlf.bvh");
        let viewer = viewer_on(&file);
        assert_eq!(
            viewer.picture_name(),
            PathBuf::from("tiny_crlf_frame00000.png")
        );
    }

    /// A file dropped on the window joins the takes; one that does not load is reported and
    /// changes nothing. R loads every file again, and keeps the last good take of a broken one.
    /// (No window is needed: these are the handlers the window's events call.)
    fn walk_viewer() -> Viewer {
        let loaded = crate::take::Take::bundled().unwrap();
        let walk = ViewerTake {
            name: crate::DEFAULT_MOTION_NAME.to_string(),
            source: None,
            up: crate::model::pose::Up::Y,
            stance: loaded.stance(OffsetMode::Replace),
            loaded,
            up_asked: None,
            character: None,
        };
        Viewer::new(vec![walk], quiet_options())
    }

    /// The camera the window would draw with at 600×600.
    fn camera_drawn(viewer: &Viewer) -> Camera {
        let (options, overlay) = viewer.picture((600, 600));
        let ups = viewer.drawn_ups();
        crate::render::paint::Painter::default()
            .camera(
                &Viewer::shown(&viewer.takes, &ups),
                &options,
                &overlay,
                Some(&viewer.camera),
            )
            .unwrap()
    }

    /// C in the studio look once did nothing visible after T; it resets that view's
    /// camera (turn, zoom, following) and stays in the look.
    #[test]
    fn c_resets_the_studio_camera_too() {
        let mut viewer = walk_viewer();
        let press = |viewer: &mut Viewer, key: &str| {
            viewer.key(&Key::Character(key.into()));
        };
        press(&mut viewer, "v");
        viewer.frame = 30;
        let start = camera_drawn(&viewer);
        press(&mut viewer, "a");
        press(&mut viewer, "t");
        viewer.camera.distance *= 0.5;
        assert_ne!(camera_drawn(&viewer), start);
        press(&mut viewer, "c");
        assert_eq!(viewer.options.look, Look::Studio);
        assert_eq!(camera_drawn(&viewer), start);
    }

    /// The article's view says in the title how to frame a take it leaves
    /// empty or cut off; its picture stays the article's.
    #[test]
    fn the_article_view_says_how_to_see_more_in_its_title() {
        let mut viewer = walk_viewer();
        assert!(
            viewer.title().ends_with(" - F frames it, V studio, H keys"),
            "{}",
            viewer.title()
        );
        viewer.key(&Key::Character("v".into()));
        assert!(!viewer.title().contains("F frames it"));
        assert_eq!(
            viewer.options.style,
            Style::Both,
            "the studio draws sticks with spheres"
        );
        viewer.key(&Key::Character("v".into()));
        assert_eq!(viewer.options.style, Style::Points);
        // A style asked for stays through V.
        viewer.key(&Key::Character("b".into()));
        assert_eq!(viewer.options.style, Style::Sticks);
        for _ in 0..2 {
            viewer.key(&Key::Character("v".into()));
            assert_eq!(viewer.options.style, Style::Sticks);
        }
    }

    /// O works each take's stance out again in the new mode (its height sizes framed views).
    #[test]
    fn o_guesses_each_stance_again_in_the_new_mode() {
        let mut viewer = walk_viewer();
        let before = viewer.takes[0].stance;
        viewer.key(&Key::Character("o".into()));
        assert_eq!(viewer.options.offset_mode, OffsetMode::Add);
        assert_eq!(viewer.takes[0].stance.mode, OffsetMode::Add);
        viewer.key(&Key::Character("o".into()));
        assert_eq!(viewer.takes[0].stance, before);
    }

    /// A reload's error is wrapped between words to any picture, never cut.
    #[test]
    fn a_reload_error_is_wrapped_to_the_picture() {
        let mut viewer = walk_viewer();
        viewer.hud = true;
        let error = "tests/data/bvh/a_take_with_a_rather_long_file_name.bvh:12:5: expected a \
                     number after OFFSET, found 'x'";
        viewer.problem = Some(error.to_string());
        for size in [(160, 120), (240, 240), (600, 600)] {
            let font = crate::render::text::Font::for_picture(size.0, size.1);
            let lines = viewer.hud_lines(size);
            assert!(
                lines
                    .iter()
                    .all(|l| l.chars().count() <= font.columns(size.0)),
                "{size:?}: {lines:?}"
            );
            let shown: Vec<&str> = lines.iter().flat_map(|l| l.split_whitespace()).collect();
            for word in "expected a number after OFFSET, found 'x'".split(' ') {
                assert!(
                    shown.contains(&word),
                    "{size:?}: '{word}' not whole in {lines:?}"
                );
            }
        }
    }

    #[test]
    fn dropped_files_join_and_reloads_keep_the_last_good_take() {
        let folder = tempfile::tempdir().unwrap();
        let dir = folder.path();
        let take = |frames: usize| {
            let mut text = String::from(
                "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation \
                 Yrotation\n End Site\n {\n  OFFSET 0 10 0\n }\n}\nMOTION\n",
            );
            text += &format!("Frames: {frames}\nFrame Time: 0.1\n");
            text += &"0 0 0\n".repeat(frames);
            text
        };
        let first = dir.join("first.bvh");
        let second = dir.join("second.bvh");
        std::fs::write(&first, take(3)).unwrap();
        std::fs::write(&second, take(5)).unwrap();
        let mut viewer = viewer_on(&first);
        assert_eq!(viewer.frame_count(), 3);
        viewer.add(second.clone());
        assert_eq!(viewer.takes.len(), 2);
        assert_eq!(viewer.problem, None);
        assert_eq!(viewer.frame_count(), 5);
        assert_eq!(
            viewer.title(),
            "bvhview - first.bvh + second.bvh - 0.000 s of 0.400 s - F frames it, V studio, H keys"
        );
        viewer.add(dir.join("missing.bvh"));
        assert_eq!(viewer.takes.len(), 2);
        assert!(viewer.problem.as_deref().unwrap().contains("missing.bvh"));

        viewer.frame = 4;
        std::fs::write(&second, take(2)).unwrap();
        viewer.reload();
        assert_eq!(viewer.problem, None);
        assert_eq!(viewer.takes[1].loaded.motion.frame_count(), 2);
        // The timeline got shorter: the frame shown stays on it.
        assert_eq!((viewer.frame_count(), viewer.frame), (3, 2));
        // Rewritten to stand along z: the reload guesses its up axis again.
        assert_eq!(viewer.takes[1].up, crate::model::pose::Up::Y);
        let standing_along_z = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation \
             Xrotation Yrotation\n JOINT Spine\n {\n  OFFSET 0 0 10\n  CHANNELS 3 Zrotation \
             Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 0 10\n  }\n }\n}\nMOTION\n\
             Frames: 2\nFrame Time: 0.1\n0 0 0 0 0 0\n0 0 0 0 0 0\n";
        std::fs::write(&second, standing_along_z).unwrap();
        viewer.reload();
        assert_eq!(viewer.takes[1].up, crate::model::pose::Up::Z);
        std::fs::write(&second, "HIERARCHY\nROOT Hips\n{\n").unwrap();
        viewer.reload();
        assert!(viewer.problem.as_deref().unwrap().contains("second.bvh:"));
        assert_eq!(viewer.takes[1].loaded.motion.frame_count(), 2);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn any_frame_time_plays_at_a_bounded_rate() {
        assert_eq!(playback_step(0.01), Duration::from_millis(10));
        assert_eq!(playback_step(1e300), Duration::from_secs(3600));
        assert_eq!(playback_step(1e-300), Duration::from_nanos(1));
        for odd in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(playback_step(odd), Duration::from_secs_f64(1.0 / 30.0));
        }
    }

    #[test]
    fn a_stall_skips_frames_in_one_step() {
        let step = Duration::from_millis(10);
        assert_eq!(frames_due(Duration::ZERO, step), (1, step));
        assert_eq!(frames_due(Duration::from_millis(25), step), (3, step * 3));
        // A day late at 1 ms per frame: one division, not 86 million turns of a loop.
        let (frames, later) = frames_due(Duration::from_secs(86_400), Duration::from_millis(1));
        assert_eq!(frames, 86_400_001);
        assert_eq!(later, Duration::from_millis(86_400_001));
    }

    /// 4000 ticks a second (a 1000 Hz take at 4×) keep real time although the window wakes
    /// at most every millisecond: one simulated second steps 4000 ticks.
    #[test]
    fn ticks_shorter_than_a_wake_keep_real_time() {
        for (frame_time, speed, expected) in [(0.001, 4.0, 4000), (1.0 / 120.0, 1.0, 120)] {
            let tick = playback_step(frame_time / speed);
            let start = Instant::now();
            let (mut now, mut next_tick, mut ticks) = (start, start + tick, 0u64);
            while now <= start + Duration::from_secs(1) {
                if now >= next_tick {
                    let (frames, later) = frames_due(now - next_tick, tick);
                    next_tick += later;
                    ticks += frames;
                }
                let wake = next_wake(now, next_tick);
                assert!(wake - now >= SHORTEST_WAKE);
                now = wake;
            }
            assert!(
                ticks.abs_diff(expected) <= 1,
                "{frame_time} at {speed}x: {ticks}"
            );
        }
    }
}
