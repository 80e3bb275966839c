//! The HUD (I in the window, `snapshot --hud`) and the help (H): text on top of the picture,
//! bottom left above the timeline (top left in the step view), never part of the article's
//! picture.

use crate::model::pose::OffsetMode;
use crate::render::draw::Style;
use crate::render::fixed::FixedFunction;
use crate::render::pixels::{self, Rect};
use crate::render::text::{self, Corner, Font};

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
    pub look: crate::render::options::Look,
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

/// How the HUD and the title say the frame shown: counted from 0, as `--frame` counts it, with
/// the range the take holds: `frame 0 (0-39)`.
pub fn frame_of(frame: usize, frames: usize) -> String {
    format!("frame {frame} (0-{})", frames.saturating_sub(1))
}

fn frames_text(take: &HudTake) -> (String, String) {
    if take.frames == 0 {
        ("rest pose (no frames)".to_string(), "rest pose".to_string())
    } else {
        let long = frame_of(take.frame, take.frames);
        // The short form drops the word, not the form: `0 (0-39)`.
        let short = long.trim_start_matches("frame ").to_string();
        (long, short)
    }
}

fn rate_text(frame_time: f64) -> (String, String) {
    if frame_time > 0.0 {
        (
            format!("{:.2} frames/s", 1.0 / frame_time),
            format!("{}/s", trim_number(1.0 / frame_time)),
        )
    } else {
        ("no frame time".to_string(), "no rate".to_string())
    }
}

/// One line of text over the picture before it is fitted to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// Lines of a higher rank go first when the picture is too short for all (0: never).
    pub rank: u8,
    /// What it says, and its short form for a narrow picture.
    pub long: String,
    pub short: String,
    /// A file's name: shortened in the middle rather than wrapped.
    pub name: bool,
}

impl Line {
    pub fn text(rank: u8, long: impl Into<String>, short: impl Into<String>) -> Line {
        Line {
            rank,
            long: long.into(),
            short: short.into(),
            name: false,
        }
    }

    pub fn name(rank: u8, name: &str) -> Line {
        Line {
            rank,
            long: name.to_string(),
            short: name.to_string(),
            name: true,
        }
    }
}

/// How many of the HUD's lines a picture `height` pixels high has room for: a third of it, and
/// two at least.
pub fn most_lines(height: u32, font: Font) -> usize {
    (((height as i32 / 3) - 8) / font.line).max(2) as usize
}

/// `lines` fitted to a `width × height` picture in its font (see [`Font::for_picture`]): each in
/// its long form where it fits, else its short one, else wrapped between words (names shortened
/// in the middle), never cut mid-word; the highest ranks left out while they exceed `room` lines.
pub fn fit(lines: &[Line], (width, height): (u32, u32), room: usize) -> Vec<String> {
    let font = Font::for_picture(width, height);
    let columns = font.columns(width);
    let shaped: Vec<Vec<String>> = lines
        .iter()
        .map(|line| {
            if line.name {
                vec![text::shorten_middle(&line.long, columns)]
            } else if line.long.chars().count() <= columns {
                vec![line.long.clone()]
            } else if line.short.chars().count() <= columns {
                vec![line.short.clone()]
            } else {
                text::wrap(&line.short, columns)
            }
        })
        .collect();
    let mut kept: Vec<bool> = vec![true; lines.len()];
    let count = |kept: &[bool]| -> usize {
        shaped
            .iter()
            .zip(kept)
            .filter(|(_, k)| **k)
            .map(|(s, _)| s.len())
            .sum()
    };
    while count(&kept) > room {
        // The last line of the highest rank left goes first.
        let drop = (0..lines.len())
            .filter(|&i| kept[i] && lines[i].rank > 0)
            .max_by_key(|&i| (lines[i].rank, i));
        match drop {
            Some(i) => kept[i] = false,
            None => break,
        }
    }
    shaped
        .into_iter()
        .zip(kept)
        .filter(|(_, k)| *k)
        .flat_map(|(s, _)| s)
        .collect()
}

/// Where the HUD's lines (or the help's) sit on a picture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Place {
    /// Bottom left, the last line lowest, its band starting this many pixels up: just above the
    /// timeline. The article's camera puts the figure in the upper two thirds of the picture
    /// and the floor's near half below it, so the HUD covers the floor, not the head.
    BottomLeft(f32),
    /// Top left, the first line highest: in the step view, whose text takes the bottom.
    TopLeft,
}

impl Place {
    /// The HUD's place on a `width × height` picture: bottom left, above the timeline when it is
    /// shown (8 pixels up when not), or top left in the step view (`stepping`).
    pub fn for_picture((width, height): (u32, u32), timeline: bool, stepping: bool) -> Place {
        if stepping {
            Place::TopLeft
        } else if timeline {
            Place::BottomLeft(crate::render::timeline::Bar::for_picture(width, height).room())
        } else {
            Place::BottomLeft(8.0)
        }
    }
}

/// Pixels along the top that `lines` HUD lines cover in `font`, with a gap below them (the HUD
/// top left, in the step view).
pub fn reserved_height(lines: usize, font: Font) -> f32 {
    if lines == 0 {
        0.0
    } else {
        (8 + font.line * lines as i32 + (font.line - font.cell) + 6) as f32
    }
}

/// Pixels along the top and along the bottom that `lines` HUD lines at `place` keep from a framed
/// figure in `font`, with a gap beside them: `(top, bottom)`; the bottom one counts from the
/// picture's edge, the timeline's room with it.
pub fn reserved(lines: usize, font: Font, place: Place) -> (f32, f32) {
    match place {
        Place::TopLeft => (reserved_height(lines, font), 0.0),
        Place::BottomLeft(_) if lines == 0 => (0.0, 0.0),
        Place::BottomLeft(above) => (0.0, above + (font.line * lines as i32 + 6) as f32),
    }
}

impl Hud<'_> {
    /// The HUD's lines before they are fitted to a picture.
    pub fn items(&self) -> Vec<Line> {
        let mut lines = match &self.takes[..] {
            [take] => {
                let (frames, frames_short) = frames_text(take);
                let (rate, rate_short) = rate_text(take.frame_time);
                vec![
                    Line::name(0, take.name),
                    Line::text(0, frames, frames_short),
                    Line::text(
                        1,
                        format!("{:.3} s, {rate}", self.time),
                        format!("{:.2} s {rate_short}", self.time),
                    ),
                ]
            }
            // A name and its frame on lines of their own: one line held both and lost its end.
            takes => {
                let mut lines: Vec<Line> = Vec::new();
                for (index, t) in takes.iter().enumerate() {
                    let (frames, frames_short) = frames_text(t);
                    let (rate, _) = rate_text(t.frame_time);
                    // The first take's lines stay on any picture; the others' go before the
                    // time when the picture is short (their labels still name them).
                    lines.push(Line::name(if index == 0 { 0 } else { 1 }, t.name));
                    lines.push(Line::text(
                        if index == 0 { 0 } else { 2 },
                        format!("  {frames}, {rate}"),
                        format!("  {frames_short}"),
                    ));
                }
                lines.push(Line::text(
                    1,
                    format!("{:.3} s", self.time),
                    format!("{:.2} s", self.time),
                ));
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
            (crate::render::options::Look::Studio, true, _) => "studio, following the root",
            (crate::render::options::Look::Studio, false, _) => "studio",
            (_, _, true) => "framed",
            _ => "the article's camera",
        };
        let (mode, mode_short) = match self.offset_mode {
            OffsetMode::Replace => ("positions replace OFFSET", "replace OFFSET"),
            OffsetMode::Add => ("positions added to OFFSET", "add to OFFSET"),
        };
        let playing = if self.playing { "playing" } else { "paused" };
        let speed = trim_number(self.speed);
        let looping = if self.looping { "on" } else { "off" };
        lines.extend([
            Line::text(
                3,
                format!("{playing} at {speed}x, loop {looping}"),
                format!("{playing} {speed}x, loop {looping}"),
            ),
            Line::text(
                4,
                format!("{style}, {camera}"),
                format!("{style}, {camera}"),
            ),
            Line::text(5, mode, mode_short),
        ]);
        if self.other_mode_likely {
            lines.push(Line::text(
                2,
                "looks written for the other mode (O)",
                "other mode? (O)",
            ));
        }
        if self.lying_along_z {
            lines.push(Line::text(2, "stands along z: V stands it up", "z up: V"));
        }
        lines.push(Line::text(6, "H: keys", "H: keys"));
        lines
    }

    /// The HUD's lines fitted to a `width × height` picture.
    pub fn lines(&self, size: (u32, u32)) -> Vec<String> {
        let font = Font::for_picture(size.0, size.1);
        fit(&self.items(), size, most_lines(size.1, font))
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
        "F          frame the pose",
        "C          the start camera",
        "B          next style",
        "V          studio look",
        "T          follow the root",
        "N          joint names",
        "R          reload the files",
        "P          write this picture",
        "M          record a video / stop",
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

/// The help's lines fitted to a `width × height` picture: as many as its height holds above the
/// timeline.
pub fn help_fitted(size: (u32, u32)) -> Vec<String> {
    let font = Font::for_picture(size.0, size.1);
    let lines: Vec<Line> = help_lines()
        .into_iter()
        .map(|line| Line::text(1, line.clone(), line))
        .collect();
    // Below them, the timeline's room (the help sits where the HUD does).
    let below = crate::render::timeline::Bar::for_picture(size.0, size.1).room() as i32;
    let room = ((size.1 as i32 - 16 - below) / font.line).max(1) as usize;
    fit(&lines, size, room)
}

/// The colour behind the HUD's lines: near black, so white text reads over bright bones, a take's
/// label or the studio grid.
const BACKING: [f32; 3] = [0.05, 0.05, 0.07];

/// Draws `lines` at `place` on a picture `width × height`, in white, each on a dark band as wide
/// as its text.
pub fn draw<G: FixedFunction>(
    gl: &mut G,
    (width, height): (u32, u32),
    lines: &[String],
    place: Place,
) {
    let font = Font::for_picture(width, height);
    let bands: Vec<_> = bands((width, height), lines, place)
        .into_iter()
        .map(|band| (BACKING, band))
        .collect();
    pixels::fill(gl, (width, height), &bands);
    let corner = match place {
        Place::TopLeft => Corner::TopLeft,
        Place::BottomLeft(above) => Corner::BottomLeftAt(baseline_above(above, font)),
    };
    text::draw_lines_in(gl, height, corner, lines, [1.0, 1.0, 1.0], font);
}

/// Where `lines` go at `place` on a `width × height` picture: the band behind each one that is
/// not empty.
pub fn bands((width, height): (u32, u32), lines: &[String], place: Place) -> Vec<Rect> {
    let font = Font::for_picture(width, height);
    lines
        .iter()
        .enumerate()
        .filter(|(_, line)| !line.is_empty())
        .map(|(i, line)| {
            let baseline = match place {
                Place::TopLeft => height as i32 - 8 - font.line * (i as i32 + 1),
                Place::BottomLeft(above) => {
                    baseline_above(above, font) + font.line * (lines.len() - 1 - i) as i32
                }
            };
            band(baseline, line.chars().count(), font)
        })
        .collect()
}

/// The baseline of the lowest line whose band starts `above` pixels up.
fn baseline_above(above: f32, font: Font) -> i32 {
    above.ceil() as i32 + (font.line - font.cell)
}

/// The band behind a line of `chars` glyphs on `baseline`: the glyphs' cells and the gap below
/// them, with 4 pixels to each side, so the bands of consecutive lines meet.
fn band(baseline: i32, chars: usize, font: Font) -> Rect {
    Rect {
        left: 4.0,
        right: (8 + font.cell * chars as i32 + 4) as f32,
        bottom: (baseline - (font.line - font.cell)) as f32,
        top: (baseline + font.cell) as f32,
    }
}
