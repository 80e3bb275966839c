//! C++: the row loop at the end of `BVH::loadFile`, in plain Rust.

use super::words::Problem;
use super::{Ending, Located, is_blank, parse_number};
use crate::error::Error;
use crate::lines::{advance, count_lines, is_line_end};

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
/// The same loop over the text after `Frame Time:`, one line and one word at a time, one thread.
/// `width` values make a row (the article's `dataCount`, from the CHANNELS lines). What changed:
/// - the article steps over 8 bytes and then to the next blank, and over exactly two line-end
///   bytes; here a row is a line (LF, CR LF or CR) and a value is a word between any blanks;
/// - each word must be a finite number, read as `(float)atof` reads it (the nearest double, then
///   the nearest float), and each row must hold exactly `width` of them; a line of blanks is
///   skipped; each mistake is an error at its line and column (`start` is where the text begins);
/// - fewer rows than `frames` is an error at the end; rows beyond it are counted and ignored,
///   with a warning.
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
    let mut data = Vec::new();
    let mut rows = 0u64;
    let mut extra: Option<(usize, usize)> = None;
    let place = |offset: usize| advance(start, count_lines(&text[..offset]));
    let mut line_start = 0;
    while line_start < text.len() {
        // The line: up to its CR, LF or CR LF, or the end of the text.
        let line_end = text[line_start..]
            .iter()
            .position(|&b| is_line_end(b))
            .map_or(text.len(), |n| line_start + n);
        let line = &text[line_start..line_end];
        let blank = line.iter().all(|&b| is_blank(b));
        if width == 0 {
            // No channels: each line end counts as a frame.
        } else if rows == frames {
            if !blank {
                extra.get_or_insert((place(line_start).0, 0)).1 += 1;
            }
        } else if !blank {
            // One row: `width` words, each a number.
            let mut values = 0;
            let mut at = line_start;
            while at < line_end {
                if is_blank(text[at]) {
                    at += 1;
                    continue;
                }
                let word_end = text[at..line_end]
                    .iter()
                    .position(|&b| is_blank(b))
                    .map_or(line_end, |n| at + n);
                if values == width {
                    return Err(located(
                        text,
                        start,
                        rows,
                        Problem::TooMany(at),
                        source,
                        width,
                    ));
                }
                match parse_number(&text[at..word_end]) {
                    Some(value) => data.push(value),
                    None => {
                        let problem = Problem::NotANumber(at, word_end);
                        return Err(located(text, start, rows, problem, source, width));
                    }
                }
                values += 1;
                at = word_end;
            }
            if values < width {
                let problem = Problem::TooFew(line_end, values);
                return Err(located(text, start, rows, problem, source, width));
            }
            rows += 1;
        }
        // Past the line end: CR LF is one.
        line_start = match (text.get(line_end), text.get(line_end + 1)) {
            (Some(b'\r'), Some(b'\n')) => line_end + 2,
            _ => line_end + 1,
        };
    }
    let ending = Ending {
        rows: if width == 0 {
            count_lines(text).0 as u64
        } else {
            rows
        },
        at: place(text.len()),
        extra,
    };
    ending.check(source, frames, frames_line, width)?;
    Ok((data, ending.warnings(frames, frames_line)))
}

/// The error for `problem` in row `row`, placed in the file.
fn located(
    text: &[u8],
    start: (usize, usize),
    row: u64,
    problem: Problem,
    source: &str,
    width: usize,
) -> Error {
    Located::new(text, start, 0, problem).into_error(source, width, row as usize)
}
