//! The viewer's state and what each key and mouse move does to it (the article's `keyboard`:
//! W the next frame, A/D the camera), and drawing one picture of it.

use super::playback::{SPEEDS, playback_step};
use super::takes::{TakeSource, ViewerOptions, ViewerTake};
use crate::io::error::Error;
use crate::model::motion::Motion;
use crate::model::pose::OffsetMode;
use crate::render::draw::Style;
use crate::render::paint::{Clock, Painter, Shown};
use crate::render::scene::Camera;
use crate::render::timeline::Bar;
use crate::render::window::gl::{Running, WINDOW_SIZE, open_gl_window};
#[cfg(feature = "video")]
use crate::render::window::viewer::record;
use crate::render::{Look, Overlay, SnapshotOptions, scene};
use glutin::prelude::GlSurface;
use std::f32::consts::TAU;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use winit::dpi::PhysicalSize;
use winit::event::MouseButton;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};

pub(super) struct Viewer {
    pub(super) takes: Vec<ViewerTake>,
    pub(super) options: ViewerOptions,
    /// The tick of the takes' shared timeline ([`Clock`]): with one take, its frame.
    pub(super) frame: usize,
    pub(super) camera: Camera,
    pub(super) fit: bool,
    pub(super) playing: bool,
    pub(super) next_tick: Instant,
    pub(super) drag_from: Option<(f64, f64)>,
    /// The mouse button held down for a drag, if any.
    pub(super) dragging: Option<MouseButton>,
    pub(super) shift: bool,
    pub(super) running: Option<Running>,
    pub(super) error: Option<Error>,
    /// The step view: how many joints, in drawing order, are drawn (J, Shift+J; Esc leaves it).
    pub(super) step: Option<usize>,
    /// The HUD (I) and the help (H), bottom left above the timeline (top left in the step view);
    /// the help takes the HUD's place while shown.
    pub(super) hud: bool,
    pub(super) help: bool,
    /// Joint names beside the joints (N).
    pub(super) names: bool,
    /// Playback speed (`+`, `-`) and whether playback wraps at the end (L).
    pub(super) speed: f64,
    pub(super) looping: bool,
    /// In the studio look, the camera follows the first take's root (T).
    pub(super) follow: bool,
    /// Where the mouse is, and whether a press on the timeline is seeking.
    pub(super) cursor: (f64, f64),
    pub(super) seeking: bool,
    /// The last reload's or drop's error, shown first of the HUD's lines until the next one
    /// succeeds.
    pub(super) problem: Option<String>,
    /// The first output asked for that could not be written (a recording, a picture): shown
    /// like a problem, and the program's exit status when the window closes.
    pub(super) failed_output: Option<Error>,
    pub(super) painter: Painter,
    /// The recording under way (M, `--record`), and one `--record` asked for when the window
    /// opens.
    #[cfg(feature = "video")]
    pub(super) recording: Option<record::Recording>,
    pub(super) record_at_start: Option<PathBuf>,
}

impl Viewer {
    pub(super) fn new(takes: Vec<ViewerTake>, options: ViewerOptions) -> Viewer {
        let start = Camera {
            angle: crate::render::paint::start_angle(takes.len()),
            ..Camera::default()
        };
        Viewer {
            takes,
            frame: 0,
            camera: start,
            fit: false,
            playing: false,
            next_tick: Instant::now(),
            drag_from: None,
            dragging: None,
            shift: false,
            running: None,
            error: None,
            step: None,
            hud: false,
            help: false,
            names: false,
            speed: 1.0,
            looping: true,
            follow: false,
            cursor: (0.0, 0.0),
            seeking: false,
            problem: None,
            failed_output: None,
            painter: Painter::default(),
            #[cfg(feature = "video")]
            recording: None,
            record_at_start: options.record.clone(),
            options,
        }
    }

    pub(super) fn clock(&self) -> Clock {
        let motions: Vec<&Motion> = self.takes.iter().map(|t| &t.loaded.motion).collect();
        Clock::new(&motions)
    }

    pub(super) fn frame_count(&self) -> usize {
        self.clock().count
    }

    /// Frames are counted from 0, as `--frame` counts them; with several takes, the time.
    pub(super) fn title(&self) -> String {
        let mode = match self.options.offset_mode {
            OffsetMode::Replace => "",
            OffsetMode::Add => " - position channels added to OFFSET",
        };
        let names: Vec<&str> = self.takes.iter().map(|t| t.name.as_str()).collect();
        let clock = self.clock();
        let at = if self.takes.len() == 1 {
            crate::render::hud::frame_of(self.frame, clock.count)
        } else {
            format!(
                "{:.3} s of {:.3} s",
                clock.seconds(self.frame),
                clock.seconds(clock.count - 1)
            )
        };
        // The article's view stays the article's picture; the title says how to see more of
        // a take it leaves empty or cut off.
        let hint = if self.options.look == Look::Article && !self.fit {
            " - F frames it, V studio, H keys"
        } else {
            ""
        };
        format!("bvhview - {} - {at}{mode}{hint}", names.join(" + "))
    }

    /// How long each tick shows at the playback speed.
    pub(super) fn frame_duration(&self) -> Duration {
        playback_step(self.clock().step / self.speed)
    }

    /// The next speed up or down the list.
    pub(super) fn change_speed(&mut self, faster: bool) {
        let at = SPEEDS
            .iter()
            .position(|&s| s >= self.speed)
            .unwrap_or(SPEEDS.len() - 1);
        let at = if faster {
            (at + 1).min(SPEEDS.len() - 1)
        } else {
            at.saturating_sub(1)
        };
        self.speed = SPEEDS[at];
    }

    pub(super) fn create(&mut self, event_loop: &ActiveEventLoop) -> Result<Running, Error> {
        let mut running = open_gl_window(event_loop, self.title(), WINDOW_SIZE, WINDOW_SIZE)?;
        scene::init(&mut running.gl);
        let (width, height) = running.size;
        scene::reshape(&mut running.gl, width, height, &self.camera);
        Ok(running)
    }

    /// The HUD's lines (or the help's), with the last reload's error first.
    pub(super) fn hud_lines(&self, size: (u32, u32)) -> Vec<String> {
        use crate::render::hud::{self, Line};
        let mut lines = Vec::new();
        if let Some(problem) = &self.problem {
            // The reload's error, wrapped to the picture: it matters more than any HUD line.
            lines.extend(hud::fit(
                &[Line::text(0, problem, problem)],
                size,
                usize::MAX,
            ));
        }
        if self.help {
            lines.extend(hud::help_fitted(size));
        } else if self.hud {
            let clock = self.clock();
            let takes = self
                .takes
                .iter()
                .map(|t| crate::render::hud::HudTake {
                    name: &t.name,
                    frame: clock.frame_of(&t.loaded.motion, self.frame),
                    frames: t.loaded.motion.frame_count(),
                    frame_time: t.loaded.motion.frame_time,
                })
                .collect();
            let other_mode_likely = self.takes.iter().any(|t| {
                crate::info::offset_mode_warning(
                    &t.loaded.skeleton,
                    &t.loaded.motion,
                    t.offset_mode(self.options.offset_mode),
                )
                .is_some()
            });
            let hud = crate::render::hud::Hud {
                takes,
                time: clock.seconds(self.frame),
                playing: self.playing,
                speed: self.speed,
                looping: self.looping,
                look: self.options.look,
                follow: self.follow,
                style: self.options.style,
                skin: self.options.skin,
                fit: self.fit,
                offset_mode: self.options.offset_mode,
                other_mode_likely,
                lying_along_z: self.takes.iter().any(|t| {
                    t.up == crate::model::pose::Up::Z
                        && self.drawn_up(t) == crate::model::pose::Up::Y
                }),
            };
            lines.extend(hud.lines(size));
        }
        lines
    }

    /// The up axis a take is drawn with: the one asked for (`--up`); otherwise in the article's
    /// view as written (Y up, the article's picture for every file), and in a view that frames
    /// the takes (F, the studio look) the one guessed from the motion.
    pub(super) fn drawn_up(&self, take: &ViewerTake) -> crate::model::pose::Up {
        let framed = self.fit || self.options.look == Look::Studio;
        match take.up_asked {
            Some(up) => up,
            None if framed => take.up,
            None => crate::model::pose::Up::Y,
        }
    }

    /// What a `width × height` picture of the window shows: `snapshot`'s options and overlay
    /// for the window's state.
    pub(super) fn picture(&self, (width, height): (u32, u32)) -> (SnapshotOptions, Overlay) {
        let options = SnapshotOptions {
            frame: self.frame,
            angle: self.camera.angle,
            width,
            height,
            style: self.options.style,
            fit: self.fit,
            offset_mode: self.options.offset_mode,
            skin: self.options.skin,
            step: self.step,
            up: self.drawn_up(&self.takes[0]),
            look: self.options.look,
            follow: self.follow,
            whole_take: false,
            true_scale: self.options.true_scale,
            overlaid: false,
        };
        let several = self.takes.len() > 1;
        let overlay = Overlay {
            lines: self.hud_lines((width, height)),
            timeline: self.hud.then_some((self.frame, self.frame_count())),
            names: self.names,
            labels: if self.hud && several {
                self.takes.iter().map(|t| t.name.clone()).collect()
            } else {
                Vec::new()
            },
        };
        (options, overlay)
    }

    /// The takes as the painter draws them, with the up axes they are drawn with.
    pub(super) fn shown<'a>(
        takes: &'a [ViewerTake],
        ups: &[crate::model::pose::Up],
    ) -> Vec<Shown<'a>> {
        takes
            .iter()
            .zip(ups)
            .map(|(t, &up)| Shown {
                skeleton: &t.loaded.skeleton,
                motion: &t.loaded.motion,
                up,
                stance: t.stance,
                mesh: t.character.as_ref().map(|c| &c.mesh),
            })
            .collect()
    }

    pub(super) fn drawn_ups(&self) -> Vec<crate::model::pose::Up> {
        self.takes.iter().map(|t| self.drawn_up(t)).collect()
    }

    /// Paints the picture into the window's back buffer (`snapshot`'s picture for the same
    /// state), without presenting it.
    pub(super) fn paint(&mut self) -> Result<(u32, u32), Error> {
        let Some(running) = self.running.as_ref() else {
            return Ok((0, 0));
        };
        let size = running.size;
        let (options, overlay) = self.picture(size);
        let ups = self.drawn_ups();
        let shown = Viewer::shown(&self.takes, &ups);
        let running = self.running.as_mut().expect("checked above");
        self.painter.paint(
            &mut running.gl,
            &shown,
            &options,
            &overlay,
            Some(&self.camera),
        )?;
        Ok(size)
    }

    pub(super) fn redraw(&mut self) -> Result<(), Error> {
        let size = self.paint()?;
        // The recording takes the picture before it is presented (the back buffer).
        if let Err(error) = self.record(size) {
            self.output_failed(error);
        }
        let title = self.title();
        let Some(running) = self.running.as_mut() else {
            return Ok(());
        };
        running
            .surface
            .swap_buffers(&running.context)
            .map_err(|e| Error::Environment(format!("cannot present the picture: {e}")))?;
        running.window.set_title(&title);
        Ok(())
    }

    /// Where P writes: `<first file's stem>_frame<N>.png`, `walk_frame<N>.png` for the bundled
    /// walk (its shown name, "the bundled walk", is no file name).
    pub(super) fn picture_name(&self) -> PathBuf {
        let take = &self.takes[0];
        let stem = match &take.source {
            Some(source) => source
                .path
                .file_stem()
                .map_or("bvhview".into(), |s| s.to_string_lossy().into_owned()),
            None => "walk".to_string(),
        };
        PathBuf::from(format!("{stem}_frame{:05}.png", self.frame))
    }

    /// P: the picture as shown, written to `<first file>_frame<N>.png` in the working folder.
    pub(super) fn write_picture(&mut self) -> Result<(), Error> {
        let (width, height) = self.paint()?;
        let Some(running) = self.running.as_ref() else {
            return Ok(());
        };
        let rgba = running.gl.read_rgba(width as usize, height as usize);
        let image = crate::render::Image::from_rgba_bottom_up(width, height, &rgba);
        let path = self.picture_name();
        image.write_png(&path)?;
        if !self.options.quiet {
            eprintln!("bvhview: wrote {} ({width}x{height})", path.display());
        }
        Ok(())
    }

    /// Where M records: `<first file's stem>_frame<N>.mp4`, N the frame it starts at.
    pub(super) fn recording_name(&self) -> PathBuf {
        self.picture_name().with_extension("mp4")
    }

    /// The picture just painted, into the recording if one is under way (`--record` starts
    /// one when the window first draws).
    fn record(&mut self, size: (u32, u32)) -> Result<(), Error> {
        if let Some(path) = self.record_at_start.take() {
            self.start_recording(path, size)?;
        }
        #[cfg(feature = "video")]
        if let (Some(recording), Some(running)) = (self.recording.as_mut(), self.running.as_ref()) {
            let rgba = running.gl.read_rgba(size.0 as usize, size.1 as usize);
            let picture = crate::render::Image::from_rgba_bottom_up(size.0, size.1, &rgba);
            let result = recording.capture(Instant::now(), picture);
            if result.is_err() {
                self.recording = None;
            }
            result?;
        }
        Ok(())
    }

    /// M: starts recording into `<first file>_frame<N>.mp4`, or stops and writes the file.
    pub(super) fn toggle_recording(&mut self) -> Result<(), Error> {
        #[cfg(feature = "video")]
        if self.recording.is_some() {
            return self.stop_recording();
        }
        let size = self
            .running
            .as_ref()
            .map_or((600, 600), |running| running.size);
        self.start_recording(self.recording_name(), size)
    }

    #[cfg(feature = "video")]
    fn start_recording(&mut self, path: PathBuf, size: (u32, u32)) -> Result<(), Error> {
        let fps = crate::render::animation::default_fps(
            self.clock().step / self.speed,
            crate::render::animation::AnimationFormat::Mp4,
        );
        let recording = record::Recording::start(path, size, fps, Instant::now())?;
        if !self.options.quiet {
            eprintln!(
                "bvhview: recording {} (M stops)",
                recording.path().display()
            );
        }
        self.recording = Some(recording);
        Ok(())
    }

    #[cfg(not(feature = "video"))]
    fn start_recording(&mut self, path: PathBuf, _: (u32, u32)) -> Result<(), Error> {
        Err(crate::io::absent::without(
            "video",
            "MP4 video",
            &path.display().to_string(),
        ))
    }

    /// An output asked for could not be written: said now, shown in the window, and kept (the
    /// first) for the exit status.
    pub(super) fn output_failed(&mut self, error: Error) {
        eprintln!("bvhview: {error}");
        self.problem = Some(error.to_string());
        self.failed_output.get_or_insert(error);
    }

    /// Ends the recording under way, if any, and writes its file.
    pub(super) fn stop_recording(&mut self) -> Result<(), Error> {
        #[cfg(feature = "video")]
        if let Some(recording) = self.recording.take() {
            let written = recording.finish(Instant::now())?;
            if !self.options.quiet {
                eprintln!(
                    "bvhview: wrote {}: {:.2} s, {}",
                    written.path.display(),
                    written.seconds,
                    crate::io::error::counted(written.pictures as usize, "picture")
                );
            }
        }
        Ok(())
    }

    /// R: every take loaded again from its file. A file that no longer loads keeps its last good
    /// take, and its error is shown until a reload succeeds.
    pub(super) fn reload(&mut self) {
        let mut problems = Vec::new();
        for take in &mut self.takes {
            let Some(source) = &take.source else {
                continue;
            };
            let character = take.character.clone();
            let loaded = source.load().and_then(|loaded| match &character {
                // A take on a character is put on it again.
                Some(character) => character
                    .dress_file(
                        &loaded,
                        &source.path,
                        source.insist,
                        crate::io::parallel::cores(),
                    )
                    .map(|(dressed, _)| dressed),
                None => Ok(loaded),
            });
            match loaded {
                Ok(loaded) => {
                    take.stance = loaded.stance(take.offset_mode(self.options.offset_mode));
                    take.up = take.up_asked.unwrap_or(take.stance.up);
                    take.loaded = loaded;
                }
                Err(error) => problems.push(error.to_string()),
            }
        }
        self.after_change(problems);
    }

    /// A file dropped on the window joins the takes.
    pub(super) fn add(&mut self, path: PathBuf) {
        let source = TakeSource {
            path,
            motion: None,
            frame_time: None,
            max_size: crate::take::DEFAULT_MAX_SIZE,
            take: None,
            insist: Default::default(),
            body_model: None,
            units: None,
            up: None,
        };
        let spelling = self.options.spelling;
        let problems = match ViewerTake::from_source(source, self.options.offset_mode, spelling) {
            Ok(take) => {
                self.takes.push(take);
                Vec::new()
            }
            Err(error) => vec![error.spelled(spelling)],
        };
        self.after_change(problems);
    }

    pub(super) fn after_change(&mut self, problems: Vec<String>) {
        for problem in &problems {
            eprintln!("bvhview: {problem}");
        }
        self.problem = problems.into_iter().next();
        self.painter.forget();
        self.frame = self.frame.min(self.frame_count() - 1);
        let joints = self.takes[0].loaded.skeleton.joints.len().max(1);
        self.step = self.step.map(|shown| shown.min(joints));
    }

    pub(super) fn resize(&mut self, size: PhysicalSize<u32>) {
        let Some(running) = self.running.as_mut() else {
            return;
        };
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return;
        };
        running.surface.resize(&running.context, w, h);
        running.size = (w.get(), h.get());
        scene::reshape(&mut running.gl, w.get(), h.get(), &self.camera);
    }

    /// The frame under the mouse on the timeline (shown with the HUD, not in the step view);
    /// `along`: anywhere across, as a drag that started on the bar counts.
    pub(super) fn bar_frame(&self, along: bool) -> Option<usize> {
        let running = self.running.as_ref()?;
        if !self.hud || self.step.is_some() {
            return None;
        }
        let (width, height) = running.size;
        let bar = Bar::for_picture(width, height);
        let frames = self.frame_count();
        let (x, y) = self.cursor;
        if along {
            Some(bar.frame_along(x, frames))
        } else {
            bar.frame_at(x, y, height, frames)
        }
    }

    pub(super) fn turn(&mut self, radians: f32) {
        self.camera.angle += radians;
        if self.camera.angle >= TAU {
            self.camera.angle -= TAU;
        } else if self.camera.angle < 0.0 {
            self.camera.angle += TAU;
        }
    }

    /// C++: `keyboard`. Returns false to quit.
    pub(super) fn key(&mut self, key: &Key) -> bool {
        let count = self.frame_count();
        match key {
            // In the step view, Esc goes back to the whole picture; otherwise it quits.
            Key::Named(NamedKey::Escape) if self.step.is_some() => self.step = None,
            Key::Named(NamedKey::Escape) => return false,
            Key::Character(text) if text.as_str() == "J" => {
                self.step = Some(self.step.map_or(1, |shown| shown.saturating_sub(1).max(1)));
            }
            Key::Character(text) if text.as_str() == "j" => {
                let joints = self.takes[0].loaded.skeleton.joints.len().max(1);
                self.step = Some(self.step.map_or(1, |shown| (shown + 1).min(joints)));
            }
            Key::Named(NamedKey::Space) => {
                self.playing = !self.playing;
                // Without loop, playing from the last frame starts again from the first.
                if self.playing && !self.looping && self.frame + 1 >= count {
                    self.frame = 0;
                }
                self.next_tick = Instant::now() + self.frame_duration();
            }
            Key::Named(NamedKey::Home) => self.frame = 0,
            Key::Named(NamedKey::End) => self.frame = count - 1,
            Key::Character(text) if matches!(text.as_str(), "+" | "=") => self.change_speed(true),
            Key::Character(text) if matches!(text.as_str(), "-" | "_") => self.change_speed(false),
            Key::Character(text) => match text.to_ascii_lowercase().as_str() {
                "w" => self.frame = (self.frame + 1) % count,
                "s" => self.frame = (self.frame + count - 1) % count,
                "a" => self.turn(0.1),
                "d" => self.turn(-0.1),
                "i" => self.hud = !self.hud,
                "h" => self.help = !self.help,
                "n" => self.names = !self.names,
                "l" => self.looping = !self.looping,
                "t" => self.follow = !self.follow,
                "r" => self.reload(),
                "m" => {
                    if let Err(error) = self.toggle_recording() {
                        self.output_failed(error);
                    }
                }
                "p" => {
                    if let Err(error) = self.write_picture() {
                        self.output_failed(error);
                    }
                }
                // The studio look and back; the camera starts again from the look's own.
                "v" => {
                    self.options.look = match self.options.look {
                        Look::Article => Look::Studio,
                        Look::Studio => Look::Article,
                    };
                    // The studio draws sticks with the spheres; back in the article's look,
                    // its spheres alone; a style asked for (`--style`, B) stays.
                    if !self.options.style_chosen {
                        self.options.style = match self.options.look {
                            Look::Studio => Style::Both,
                            Look::Article => Style::Points,
                        };
                    }
                    self.camera = Camera {
                        angle: self.camera.angle,
                        ..Camera::default()
                    };
                }
                // Framing starts from the article's level view at this angle: no zoom, tilt or
                // pan carries over either way.
                "f" => {
                    self.fit = !self.fit;
                    self.camera = Camera {
                        angle: self.camera.angle,
                        ..Camera::default()
                    };
                }
                // The other offset mode (position channels replace or add to OFFSET); skins and
                // the stage are made again for it.
                "o" => {
                    self.options.offset_mode = match self.options.offset_mode {
                        OffsetMode::Replace => OffsetMode::Add,
                        OffsetMode::Add => OffsetMode::Replace,
                    };
                    // Each take's stance as drawn in the new mode (its height sizes the view).
                    for take in &mut self.takes {
                        take.stance = take
                            .loaded
                            .stance(take.offset_mode(self.options.offset_mode));
                        take.up = take.up_asked.unwrap_or(take.stance.up);
                    }
                    self.painter.forget();
                }
                // Back to the camera the program starts with (the article's for one take); in
                // the studio look, the studio's start camera: no turn, tilt, pan, zoom or
                // following left.
                "c" => {
                    self.fit = false;
                    self.follow = false;
                    self.camera = Camera {
                        angle: crate::render::paint::start_angle(self.takes.len()),
                        ..Camera::default()
                    };
                }
                "k" => self.options.skin = !self.options.skin,
                // Every style in turn. With the skin on, the skin stands for the spheres, so
                // only the stick figure over it changes anything: B turns it on and off.
                "b" => {
                    self.options.style_chosen = true;
                    self.options.style = match (self.options.style, self.options.skin) {
                        (Style::Points, _) => Style::Sticks,
                        (Style::Sticks, false) => Style::Both,
                        (Style::Sticks, true) | (Style::Both, _) => Style::Points,
                    }
                }
                _ => return true,
            },
            _ => return true,
        }
        true
    }
}
