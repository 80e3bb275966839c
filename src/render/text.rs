//! Text in the GL picture without GLUT: the font8x8 glyphs drawn with `glBitmap`, each pixel
//! doubled so that the 8×8 glyphs read at the article's 600×600. Works in the window and under
//! OSMesa alike. Nothing of the article's picture uses it; the overlays call it on top.

use crate::render::fixed::{FixedFunction, GL_LIGHTING};
use font8x8::UnicodeFonts;

/// Pixels per glyph cell, and per line of text.
pub const GLYPH: i32 = 16;
pub const LINE: i32 = 18;

/// A glyph as `glBitmap` takes it: 16 rows of 16 bits, bottom row first, most significant bit
/// leftmost. font8x8 gives 8 rows top first, least significant bit leftmost. `?` for a character
/// it lacks.
pub fn glyph(c: char) -> [u8; 32] {
    let rows = font8x8::BASIC_FONTS
        .get(c)
        .or_else(|| font8x8::BASIC_FONTS.get('?'))
        .unwrap_or([0; 8]);
    let mut bits = [0u8; 32];
    for (row, &pattern) in rows.iter().enumerate() {
        // Each source bit becomes two: 16 pixels, two bytes.
        let mut wide = 0u16;
        for x in 0..8 {
            if pattern & (1 << x) != 0 {
                wide |= 0b11 << (14 - 2 * x);
            }
        }
        let [high, low] = wide.to_be_bytes();
        // Source row 0 is the top: it becomes the last two of the 16 rows.
        for copy in 0..2 {
            let at = (15 - (2 * row + copy)) * 2;
            bits[at] = high;
            bits[at + 1] = low;
        }
    }
    bits
}

/// A glyph at the font's own size, 8×8 (joint names, which must not hide the figure): 8 rows of
/// one byte, bottom row first, most significant bit leftmost.
pub fn small_glyph(c: char) -> [u8; 8] {
    let rows = font8x8::BASIC_FONTS
        .get(c)
        .or_else(|| font8x8::BASIC_FONTS.get('?'))
        .unwrap_or([0; 8]);
    let mut bits = [0u8; 8];
    for (row, &pattern) in rows.iter().enumerate() {
        bits[7 - row] = pattern.reverse_bits();
    }
    bits
}

/// Draws `text` in small glyphs at the raster position already set, which moves on as it goes.
pub fn draw_small<G: FixedFunction>(gl: &mut G, text: &str) {
    for c in text.chars() {
        gl.bitmap(8, 8, 8.0, &small_glyph(c));
    }
}

/// The size text is drawn at on a picture: the doubled 16-pixel glyphs that read at the
/// article's 600×600, or the font's own 8 pixels on a small picture, where the big ones would
/// cover it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Font {
    /// Pixels per glyph cell, and per line.
    pub cell: i32,
    pub line: i32,
}

impl Font {
    pub const BIG: Font = Font {
        cell: GLYPH,
        line: LINE,
    };
    pub const SMALL: Font = Font { cell: 8, line: 10 };

    /// Big glyphs from 400×320 up, small ones below.
    pub fn for_picture(width: u32, height: u32) -> Font {
        if width >= 400 && height >= 320 {
            Font::BIG
        } else {
            Font::SMALL
        }
    }

    /// Characters that fit across `pixels`, with 8 pixels of margin on the left and 4 on the
    /// right (the HUD's band).
    pub fn columns(self, pixels: u32) -> usize {
        ((pixels as i32 - 12) / self.cell).max(1) as usize
    }
}

/// `text` in at most `columns` characters: whole, or its start and end with `...` between (a
/// long file name keeps what tells it apart: its start and its extension); in 5 or fewer, its
/// start.
pub fn shorten_middle(text: &str, columns: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= columns {
        return text.to_string();
    }
    // Too narrow for a start, `...` and an end to say more than a plain start.
    if columns <= 5 {
        return chars[..columns].iter().collect();
    }
    let keep = columns - 3;
    let tail = keep / 2;
    let head = keep - tail;
    let mut out: String = chars[..head].iter().collect();
    out.push_str("...");
    out.extend(&chars[chars.len() - tail..]);
    out
}

/// `text` broken between words into lines of at most `columns` characters, each after the first
/// indented by two spaces; a word longer than a line is shortened in the middle.
pub fn wrap(text: &str, columns: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        let indent = if lines.is_empty() { 0 } else { 2 };
        let used = line.chars().count();
        let room = columns.saturating_sub(indent).max(1);
        if used > 0 && used + 1 + word.chars().count() <= room {
            line.push(' ');
            line.push_str(word);
            continue;
        }
        if used > 0 {
            lines.push(std::mem::take(&mut line));
        }
        let indent = if lines.is_empty() { 0 } else { 2 };
        line = shorten_middle(word, columns.saturating_sub(indent).max(1));
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
        .into_iter()
        .enumerate()
        .map(|(i, l)| if i == 0 { l } else { format!("  {l}") })
        .collect()
}

/// Where on the picture a block of lines goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// Bottom left, the last line lowest: the step view (the article's camera shows the skeleton
    /// in the upper half).
    BottomLeft,
    /// Bottom left, the last line's baseline this many pixels up: the HUD, above the timeline.
    BottomLeftAt(i32),
    /// Top left, the first line highest: the HUD and the help in the step view.
    TopLeft,
}

/// Draws `lines` in a corner of a picture `height` pixels high, in `colour`, unlit; the lighting
/// is switched back on after (the scene draws lit).
pub fn draw_lines<G: FixedFunction>(
    gl: &mut G,
    height: u32,
    corner: Corner,
    lines: &[String],
    colour: [f32; 3],
) {
    draw_lines_in(gl, height, corner, lines, colour, Font::BIG);
}

/// [`draw_lines`] in `font`.
pub fn draw_lines_in<G: FixedFunction>(
    gl: &mut G,
    height: u32,
    corner: Corner,
    lines: &[String],
    colour: [f32; 3],
    font: Font,
) {
    gl.disable(GL_LIGHTING);
    gl.color3f(colour[0], colour[1], colour[2]);
    for (i, line) in lines.iter().enumerate() {
        let baseline = match corner {
            Corner::BottomLeft => 8 + font.line * (lines.len() - 1 - i) as i32,
            Corner::BottomLeftAt(lowest) => lowest + font.line * (lines.len() - 1 - i) as i32,
            Corner::TopLeft => height as i32 - 8 - font.line * (i as i32 + 1),
        };
        gl.window_pos(8, baseline);
        for c in line.chars() {
            if font == Font::BIG {
                gl.bitmap(GLYPH, GLYPH, GLYPH as f32, &glyph(c));
            } else {
                gl.bitmap(8, 8, 8.0, &small_glyph(c));
            }
        }
    }
    // Back to the state the article's init leaves: its green (the stick figure's colour), lit.
    gl.color3f(0.0, 1.0, 0.0);
    gl.enable(GL_LIGHTING);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_glyph_is_its_font_pattern_doubled_and_upside_down() {
        let bits = glyph('I');
        let rows = font8x8::BASIC_FONTS.get('I').unwrap();
        for (row, &pattern) in rows.iter().enumerate() {
            for x in 0..16 {
                let on = pattern & (1 << (x / 2)) != 0;
                for copy in 0..2 {
                    let r = 15 - (2 * row + copy);
                    let byte = bits[r * 2 + x / 8];
                    assert_eq!(byte & (0x80 >> (x % 8)) != 0, on, "row {row} x {x}");
                }
            }
        }
        assert_eq!(glyph('\u{2603}'), glyph('?'));
    }

    #[test]
    fn long_text_is_shortened_in_the_middle_and_wrapped_between_words() {
        assert_eq!(shorten_middle("short.bvh", 20), "short.bvh");
        let name = "amcbvhviewer_bvh2amc_bvh_animation.bvh";
        let short = shorten_middle(name, 20);
        assert_eq!(short, "amcbvhvie...tion.bvh");
        assert_eq!(short.chars().count(), 20);
        assert_eq!(
            wrap("looks written for the other mode (O)", 16),
            ["looks written", "  for the other", "  mode (O)"]
        );
        for line in wrap("a very long sentence that must never be cut in a word", 12) {
            assert!(line.chars().count() <= 12, "{line}");
        }
        // A word longer than a line is shortened, not cut.
        assert_eq!(wrap(name, 12), ["amcbv....bvh"]);
    }

    #[test]
    fn a_small_glyph_is_its_font_pattern_upside_down_and_mirrored() {
        let rows = font8x8::BASIC_FONTS.get('L').unwrap();
        let bits = small_glyph('L');
        for (row, &pattern) in rows.iter().enumerate() {
            for x in 0..8 {
                let on = pattern & (1 << x) != 0;
                assert_eq!(bits[7 - row] & (0x80 >> x) != 0, on, "row {row} x {x}");
            }
        }
    }
}
