//! C++: the row loop at the end of `BVH::loadFile`, in plain Rust.

use super::ending::{Ending, nul_after_the_rows};
use super::located::Located;
use super::number::{is_blank, parse_number};
use super::words::Problem;
use crate::io::error::Error;
use crate::io::lines::{advance, count_lines, is_line_end};

/// C++: the row loop of `BVH::loadFile`:
///
/// ```c
/// for (unsigned int i = 0; i < frameCount; i++) {
///     for (int j = 0; j < dataCount; j++) {
///         frameData[i][j] = (float)atof((char*)p);
///         p += 8; while (*p != ' ' && *p != '\t') p++; p++;
///     }
///     p += 2;
/// }
/// ```
///
/// The same two loops, `for frame in 0..frames { for channel in 0..width { … } }`, over a cursor
/// (the article's `p`) in the text after `Frame Time:`, on one thread. `width` values make a row
/// (the article's `dataCount`, here the sum of the CHANNELS counts). What changed:
/// - the article steps over 8 bytes and then to the next blank, and over exactly two line-end
///   bytes after a row; here the cursor steps over any blanks to the next word, and a row ends
///   at its line end (LF, CR LF or CR);
/// - each word must be a finite number, read as `(float)atof` reads it (the nearest double, then
///   the nearest float), and each row must hold exactly `width` of them; a line of blanks before
///   a row is stepped over; each mistake is an error at its line and column (`start` is where
///   the text begins);
/// - the article reads `frameCount` rows whatever the file holds; here the end of the text
///   before the last row is an error at the end;
/// - after the last row, lines that are not blank are counted and ignored, with a warning; a NUL
///   byte there is an error (the rest of the file is not text);
/// - with no channels at all (`width == 0`) a frame is a line end, as the article's `p += 2`
///   steps over one.
///
/// The loader runs the engine instead ([`super::RowParser`]: the same reading on every core as the
/// file streams in); a test proves the two give the same values, bit for bit, and the same errors.
/// Returns the values, `frames × width`, and the warnings.
pub fn read_rows_simple(
    text: &[u8],
    source: &str,
    (frames, frames_line): (u64, usize),
    width: usize,
    start: (usize, usize),
) -> Result<(Vec<f32>, Vec<String>), Error> {
    let mut p = Cursor { text, p: 0 };
    let mut data = Vec::new();
    let place = |offset: usize| advance(start, count_lines(&text[..offset]));
    let located = |frame: u64, problem: Problem| {
        Located::new(text, start, 0, problem).into_error(source, width, frame as usize)
    };
    let the_end = |rows: u64| Ending {
        rows,
        at: place(text.len()),
        extra: None,
    };
    for frame in 0..frames {
        if width == 0 {
            // A row of no values: the article's `p += 2`, over one line end.
            if !p.next_line() {
                return Err(the_end(frame).error(source, frames, frames_line, width));
            }
            continue;
        }
        p.skip_blank_lines();
        if p.at_end() {
            return Err(the_end(frame).error(source, frames, frames_line, width));
        }
        for channel in 0..width {
            // frameData[i][j] = (float)atof(p), then on to the next value.
            p.skip_blanks();
            if p.at_line_end() {
                return Err(located(frame, Problem::TooFew(p.p, channel)));
            }
            let (word_start, word) = p.word();
            match parse_number(word) {
                Some(value) => data.push(value),
                None => return Err(located(frame, Problem::NotANumber(word_start, p.p))),
            }
        }
        // p += 2: past the line end, which must come after the last value.
        p.skip_blanks();
        if !p.at_line_end() {
            return Err(located(frame, Problem::TooMany(p.p)));
        }
        p.next_line();
    }
    // Past the last row: lines that are not blank are counted, and ignored.
    let mut extra: Option<(usize, usize)> = None;
    while width > 0 && !p.at_end() {
        p.skip_blanks();
        if !p.at_line_end() {
            extra.get_or_insert((place(p.p).0, 0)).1 += 1;
            while !p.at_line_end() {
                if p.text[p.p] == 0 {
                    return Err(nul_after_the_rows(source, place(p.p)));
                }
                p.p += 1;
            }
        }
        p.next_line();
    }
    let ending = Ending {
        rows: frames,
        at: place(text.len()),
        extra,
    };
    Ok((data, ending.warnings(frames, frames_line)))
}

/// The article's `p`: a place in the text, moved forward as the loop reads.
struct Cursor<'a> {
    text: &'a [u8],
    p: usize,
}

impl Cursor<'_> {
    fn at_end(&self) -> bool {
        self.p >= self.text.len()
    }

    /// At a CR or LF, or at the end of the text.
    fn at_line_end(&self) -> bool {
        self.text.get(self.p).is_none_or(|&b| is_line_end(b))
    }

    /// Over spaces and tabs (and the other blanks) on this line.
    fn skip_blanks(&mut self) {
        while self.text.get(self.p).is_some_and(|&b| is_blank(b)) {
            self.p += 1;
        }
    }

    /// To the start of the next line: past the next LF, CR LF or CR. False, at the end of the
    /// text, when no line end is left.
    fn next_line(&mut self) -> bool {
        while !self.at_line_end() {
            self.p += 1;
        }
        match (self.text.get(self.p), self.text.get(self.p + 1)) {
            (None, _) => false,
            (Some(b'\r'), Some(b'\n')) => {
                self.p += 2;
                true
            }
            _ => {
                self.p += 1;
                true
            }
        }
    }

    /// Over lines that hold nothing but blanks, up to the first that holds a word (or the end).
    fn skip_blank_lines(&mut self) {
        loop {
            self.skip_blanks();
            if self.at_end() || !self.at_line_end() {
                return;
            }
            self.next_line();
        }
    }

    /// The word at the cursor, up to a blank or the line end: where it starts, and its bytes.
    fn word(&mut self) -> (usize, &[u8]) {
        let start = self.p;
        while !self.at_line_end() && !is_blank(self.text[self.p]) {
            self.p += 1;
        }
        (start, &self.text[start..self.p])
    }
}
