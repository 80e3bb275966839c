//! The HUD (I in the window, `snapshot --hud`) and the help (H): text on top of the picture,
//! top left, never part of the article's picture.

use crate::pose::OffsetMode;
use crate::render::draw::Style;
use crate::render::fixed::FixedFunction;
use crate::render::pixels::{self, Rect};
use crate::render::text::{self, Corner};

/// One take on the HUD.
#[derive(Clone, Debug)]
pub struct HudTake<'a> {
    /// The file's name (without its folder).
    pub name: &'a str,
    /// The frame shown, and how many there are (0 for a rest pose).
    pub frame: usize,
    pub frames: usize,
    pub frame_time: f64,
}

/// What the HUD reports.
#[derive(Clone, Debug)]
pub struct Hud<'a> {
    /// The takes shown (one, or several side by side).
    pub takes: Vec<HudTake<'a>>,
    /// Seconds into the timeline.
    pub time: f64,
    pub playing: bool,
    /// Playback speed, 1 for the files' own rate, and whether playback wraps at the end.
    pub speed: f64,
    pub looping: bool,
    /// The studio look, and whether its camera follows the root.
    pub look: crate::render::Look,
    pub follow: bool,
    pub style: Style,
    pub skin: bool,
    pub fit: bool,
    pub offset_mode: OffsetMode,
    /// Whether a file looks written for the other offset mode (said, with the key to switch).
    pub other_mode_likely: bool,
    /// Whether a file that stands along z is drawn as written (the article's view): said, with
    /// what stands it up.
    pub lying_along_z: bool,
}

/// What the article's view says of a file whose rest pose stands along z: it is drawn as
/// written, as the article draws every file, and what stands it up.
pub const LYING_HINT: &str = "stands taller along z than along y at rest: drawn as written, as \
     the article draws every file (--up z or --look studio stands it up; V in the window)";

fn frames_text(take: &HudTake) -> String {
    if take.frames == 0 {
        "rest pose (no frames)".to_string()
    } else {
        format!("frame {} of 0-{}", take.frame, take.frames - 1)
    }
}

fn rate_text(frame_time: f64) -> String {
    if frame_time > 0.0 {
        format!("{:.2} frames/s", 1.0 / frame_time)
    } else {
        "no frame time".to_string()
    }
}

impl Hud<'_> {
    /// The HUD's lines, at most `columns` characters each.
    pub fn lines(&self, columns: usize) -> Vec<String> {
        let mut lines = match &self.takes[..] {
            [take] => vec![
                take.name.to_string(),
                frames_text(take),
                format!("{:.3} s, {}", self.time, rate_text(take.frame_time)),
            ],
            // A name and its frame on lines of their own: one line held both and lost its end.
            takes => {
                let mut lines: Vec<String> = takes
                    .iter()
                    .flat_map(|t| {
                        [
                            t.name.to_string(),
                            format!("  {}, {}", frames_text(t), rate_text(t.frame_time)),
                        ]
                    })
                    .collect();
                lines.push(format!("{:.3} s", self.time));
                lines
            }
        };
        let style = match (self.style, self.skin) {
            (Style::Points, false) => "spheres",
            (Style::Sticks, false) => "stick figure",
            (Style::Both, false) => "spheres and sticks",
            (Style::Points, true) => "skin",
            (_, true) => "skin and sticks",
        };
        let camera = match (self.look, self.follow, self.fit) {
            (crate::render::Look::Studio, true, _) => "studio, following the root",
            (crate::render::Look::Studio, false, _) => "studio",
            (_, _, true) => "framed",
            _ => "the article's camera",
        };
        let mode = match self.offset_mode {
            OffsetMode::Replace => "positions replace OFFSET",
            OffsetMode::Add => "positions added to OFFSET",
        };
        lines.extend([
            format!(
                "{} at {}x, loop {}",
                if self.playing { "playing" } else { "paused" },
                trim_number(self.speed),
                if self.looping { "on" } else { "off" }
            ),
            format!("{style}, {camera}"),
            mode.to_string(),
        ]);
        if self.other_mode_likely {
            lines.push("looks written for the other mode (O)".to_string());
        }
        if self.lying_along_z {
            lines.push("stands along z: V stands it up".to_string());
        }
        lines.push("H: keys".to_string());
        lines
            .into_iter()
            .map(|line| line.chars().take(columns).collect())
            .collect()
    }
}

fn trim_number(value: f64) -> String {
    let text = format!("{value:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The help overlay: every key of the window.
pub fn help_lines() -> Vec<String> {
    [
        "W / S      next / previous frame",
        "A / D      turn the camera",
        "Space      play / pause",
        "Home / End first / last frame",
        "+ / -      faster / slower",
        "L          loop on / off",
        "click bar  seek (with the HUD)",
        "drag       turn and tilt",
        "Shift+drag pan; wheel: zoom",
        "F          frame the skeleton",
        "C          the article's camera",
        "B          next style",
        "V          studio look",
        "T          follow the root",
        "N          joint names",
        "R          reload the files",
        "P          write this picture",
        "drop       add a file",
        "K          skin on / off",
        "O          offset mode",
        "J/Shift+J  step the recursion",
        "I          HUD on / off",
        "H          this help",
        "Esc        quit",
    ]
    .map(str::to_string)
    .to_vec()
}

/// The colour behind the HUD's lines: near black, so white text reads over bright bones, a take's
/// label or the studio grid.
const BACKING: [f32; 3] = [0.05, 0.05, 0.07];

/// Draws `lines` top left on a picture `width × height`, in white, each on a dark band as wide as
/// its text.
pub fn draw<G: FixedFunction>(gl: &mut G, (width, height): (u32, u32), lines: &[String]) {
    let bands: Vec<_> = lines
        .iter()
        .enumerate()
        .filter(|(_, line)| !line.is_empty())
        .map(|(i, line)| (BACKING, band(height, i, line.chars().count())))
        .collect();
    pixels::fill(gl, (width, height), &bands);
    text::draw_lines(gl, height, Corner::TopLeft, lines, [1.0, 1.0, 1.0]);
}

/// The band behind top-left line `index` of `chars` glyphs: the glyphs' cells and the gap below
/// them, with 4 pixels to each side, so the bands of consecutive lines meet.
fn band(height: u32, index: usize, chars: usize) -> Rect {
    let baseline = height as i32 - 8 - text::LINE * (index as i32 + 1);
    Rect {
        left: 4.0,
        right: (8 + text::GLYPH * chars as i32 + 4) as f32,
        bottom: (baseline - (text::LINE - text::GLYPH)) as f32,
        top: (baseline + text::GLYPH) as f32,
    }
}
