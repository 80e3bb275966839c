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

/// Where on the picture a block of lines goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// Bottom left, the last line lowest: the step view (the article's camera shows the skeleton
    /// in the upper half).
    BottomLeft,
    /// Top left, the first line highest: the HUD and the help.
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
    gl.disable(GL_LIGHTING);
    gl.color3f(colour[0], colour[1], colour[2]);
    for (i, line) in lines.iter().enumerate() {
        let baseline = match corner {
            Corner::BottomLeft => 8 + LINE * (lines.len() - 1 - i) as i32,
            Corner::TopLeft => height as i32 - 8 - LINE * (i as i32 + 1),
        };
        gl.window_pos(8, baseline);
        for c in line.chars() {
            gl.bitmap(GLYPH, GLYPH, GLYPH as f32, &glyph(c));
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
