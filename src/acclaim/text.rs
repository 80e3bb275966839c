//! Lines of words with their line and column, for the ASF and AMC readers: '#' starts a comment,
//! lines end at LF, CRLF or a lone CR, words are separated by any whitespace.

use crate::error::Error;

#[derive(Clone, Copy, Debug)]
pub(crate) struct Word<'a> {
    pub text: &'a str,
    pub line: usize,
    pub column: usize,
}

impl Word<'_> {
    pub fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword)
    }
}

/// Every line that has a word, as its words.
pub(crate) fn lines(text: &str) -> Vec<Vec<Word<'_>>> {
    let mut out = Vec::new();
    let mut line_number = 0;
    let mut rest = text.strip_prefix('\u{feff}').unwrap_or(text);
    while !rest.is_empty() || line_number == 0 {
        line_number += 1;
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let line = &rest[..end];
        rest = &rest[end..];
        if rest.starts_with("\r\n") {
            rest = &rest[2..];
        } else if !rest.is_empty() {
            rest = &rest[1..];
        }
        let content = line.split('#').next().unwrap_or("");
        let mut words = Vec::new();
        let mut start: Option<(usize, usize)> = None;
        for (column, (byte, c)) in (1..).zip(content.char_indices()) {
            if c.is_whitespace() {
                if let Some((from, col)) = start.take() {
                    words.push(Word {
                        text: &content[from..byte],
                        line: line_number,
                        column: col,
                    });
                }
            } else if start.is_none() {
                start = Some((byte, column));
            }
        }
        if let Some((from, col)) = start {
            words.push(Word {
                text: &content[from..],
                line: line_number,
                column: col,
            });
        }
        if !words.is_empty() {
            out.push(words);
        }
        if rest.is_empty() {
            break;
        }
    }
    out
}

/// `source:line:column: message`.
pub(crate) fn error_at(source: &str, line: usize, column: usize, message: String) -> Error {
    Error::Parse {
        path: source.to_string(),
        line,
        column,
        message,
    }
}

/// An error at a word, saying what was expected there.
pub(crate) fn expected(source: &str, word: &Word<'_>, what: &str) -> Error {
    error_at(
        source,
        word.line,
        word.column,
        format!("expected {what}, found '{}'", word.text),
    )
}

/// An error after the last word of a line that is missing something.
pub(crate) fn expected_after(source: &str, line: &[Word<'_>], what: &str) -> Error {
    let last = line.last().expect("lines have words");
    let column = last.column + last.text.chars().count();
    error_at(
        source,
        last.line,
        column,
        format!("expected {what}, found end of line"),
    )
}

/// A finite number.
pub(crate) fn number(source: &str, word: &Word<'_>, what: &str) -> Result<f64, Error> {
    match word.text.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        _ => Err(expected(source, word, what)),
    }
}
