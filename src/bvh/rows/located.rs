//! A problem found in a chunk, placed in the file before its frame is known.

use super::words::Problem;
use crate::io::error::{Error, counted};
use crate::io::lines::{advance, count_lines};

/// A problem found in a chunk, placed in the file but not yet numbered: a chunk parsed on another
/// thread does not know how many rows the chunks before it hold.
pub(super) struct Located {
    pub(super) line: usize,
    pub(super) column: usize,
    /// The row it is in, counted from the chunk's first row.
    pub(super) row_in_chunk: usize,
    /// The frame's problem (its value count), or a word that is not a number.
    pub(super) what: Result<Option<usize>, String>,
}

impl Located {
    /// Where `problem`, in row `row_in_chunk` of `chunk` (which starts at `start`), is in the file.
    pub(super) fn new(
        chunk: &[u8],
        start: (usize, usize),
        row_in_chunk: usize,
        problem: Problem,
    ) -> Located {
        let (offset, what) = match problem {
            Problem::TooMany(at) => (at, Ok(None)),
            Problem::TooFew(at, count) => (at, Ok(Some(count))),
            Problem::NotANumber(at, end) => {
                let word = String::from_utf8_lossy(&chunk[at..end]);
                let word: String = if word.chars().count() > 40 {
                    format!("{}…", word.chars().take(40).collect::<String>())
                } else {
                    word.into_owned()
                };
                (at, Err(word))
            }
        };
        let (line, column) = advance(start, count_lines(&chunk[..offset]));
        Located {
            line,
            column,
            row_in_chunk,
            what,
        }
    }

    /// The error, once the chunk's first row is known to be row `first_row` (counted from 0) of
    /// the MOTION section; `width` values make a row. Frames are named from 0, as `--frame`
    /// names them.
    pub(super) fn into_error(self, source: &str, width: usize, first_row: usize) -> Error {
        let frame = first_row + self.row_in_chunk;
        let message = match self.what {
            Ok(None) => format!(
                "frame {frame} has more than the {} the channels need",
                counted(width, "value")
            ),
            Ok(Some(count)) => format!(
                "frame {frame} has {}, expected {width} (one per channel)",
                counted(count, "value")
            ),
            Err(word) => format!("expected a finite number, found '{word}'"),
        };
        Error::Parse {
            path: source.to_string(),
            line: self.line,
            column: self.column,
            message,
        }
    }
}
