//! How the rows ended, as both readers report it, and the NUL byte that ends them early.

use crate::io::error::{Error, counted};

/// How the rows ended, as both readers report it: rows read (lines, for a skeleton without
/// channels), the place where the text ended, and the rows beyond `Frames:` (the first one's
/// line, how many).
pub(super) struct Ending {
    pub(super) rows: u64,
    pub(super) at: (usize, usize),
    pub(super) extra: Option<(usize, usize)>,
}

impl Ending {
    /// An error at the end of the text when fewer than `frames` rows came.
    pub(super) fn check(
        &self,
        source: &str,
        frames: u64,
        frames_line: usize,
        width: usize,
    ) -> Result<(), Error> {
        if self.rows >= frames {
            return Ok(());
        }
        Err(self.error(source, frames, frames_line, width))
    }

    /// The error of a text that ends after `self.rows` rows, fewer than `frames`.
    pub(super) fn error(
        &self,
        source: &str,
        frames: u64,
        frames_line: usize,
        width: usize,
    ) -> Error {
        let message = if width == 0 {
            format!(
                "Frames: {frames} (line {frames_line}) but only {} {}",
                counted(self.rows, "line"),
                if self.rows == 1 { "follows" } else { "follow" }
            )
        } else {
            format!(
                "expected {} as Frames: says (line {frames_line}), found {}: the file ends",
                counted(frames, "frame"),
                self.rows
            )
        };
        Error::Parse {
            path: source.to_string(),
            line: self.at.0,
            column: self.at.1,
            message,
        }
    }

    /// The warning about rows beyond `Frames:`, if any.
    pub(super) fn warnings(&self, frames: u64, frames_line: usize) -> Vec<String> {
        self.extra
            .map(|(line, count)| {
                let rows = if count == 1 { "row" } else { "rows" };
                format!(
                    "{count} extra {rows} after the {frames} announced by Frames: (line {frames_line}) ignored, from line {line} on"
                )
            })
            .into_iter()
            .collect()
    }
}

/// A NUL byte after the last row, at `(line, column)`: no text file holds one, and zeros there
/// are what a file cut short, or one longer than what was written into it, holds. Both readers
/// stop there, rather than count the rest of the file as rows to ignore.
pub(super) fn nul_after_the_rows(source: &str, (line, column): (usize, usize)) -> Error {
    Error::Parse {
        path: source.to_string(),
        line,
        column,
        message: "found a NUL byte after the last frame: from here on the file is not text"
            .to_string(),
    }
}
