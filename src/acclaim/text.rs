//! Lines of words with their line and column, for the ASF and AMC readers: '#' starts a comment,
//! lines end at LF, CRLF or a lone CR, words are separated by any whitespace.

use crate::io::error::Error;

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
    let mut words = LineWords::new(text);
    while let Some(line) = words.next_line() {
        out.push(line.to_vec());
    }
    out
}

/// The lines of a text that have a word, one at a time, as their words: a reader that holds one
/// line's words, however long the text (an AMC take of many megabytes).
pub(crate) struct LineWords<'a> {
    rest: &'a str,
    line_number: usize,
    words: Vec<Word<'a>>,
}

impl<'a> LineWords<'a> {
    pub fn new(text: &'a str) -> LineWords<'a> {
        LineWords {
            rest: text.strip_prefix('\u{feff}').unwrap_or(text),
            line_number: 0,
            words: Vec::new(),
        }
    }

    /// The words of the next line that has any; `None` at the end of the text.
    pub fn next_line(&mut self) -> Option<&[Word<'a>]> {
        while !self.rest.is_empty() {
            self.line_number += 1;
            let end = self.rest.find(['\n', '\r']).unwrap_or(self.rest.len());
            let line = &self.rest[..end];
            let after = &self.rest[end..];
            self.rest = match after.strip_prefix("\r\n") {
                Some(rest) => rest,
                None if after.is_empty() => after,
                None => &after[1..],
            };
            let content = line.split('#').next().unwrap_or("");
            self.words.clear();
            let mut start: Option<(usize, usize)> = None;
            for (column, (byte, c)) in (1..).zip(content.char_indices()) {
                if c.is_whitespace() {
                    if let Some((from, col)) = start.take() {
                        self.words.push(Word {
                            text: &content[from..byte],
                            line: self.line_number,
                            column: col,
                        });
                    }
                } else if start.is_none() {
                    start = Some((byte, column));
                }
            }
            if let Some((from, col)) = start {
                self.words.push(Word {
                    text: &content[from..],
                    line: self.line_number,
                    column: col,
                });
            }
            if !self.words.is_empty() {
                return Some(&self.words);
            }
        }
        None
    }
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
        format!(
            "expected {what}, found {}",
            crate::io::lines::shown_word(word.text.as_bytes())
        ),
    )
}

/// An error at the first word of a file that does not begin as `keywords` would: the word is
/// shown only when it misspells one of them ([`crate::io::lines::shown_first_word`]).
pub(crate) fn expected_at_start(
    source: &str,
    word: &Word<'_>,
    what: &str,
    keywords: &[&str],
) -> Error {
    let found = crate::io::lines::shown_first_word(word.text.as_bytes(), keywords);
    error_at(
        source,
        word.line,
        word.column,
        format!("expected {what}, found {found}"),
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

/// A number that is finite as the 32-bit float the skeleton keeps.
pub(crate) fn number(source: &str, word: &Word<'_>, what: &str) -> Result<f64, Error> {
    match word.text.parse::<f64>() {
        Ok(value) if (value as f32).is_finite() => Ok(value),
        _ => Err(expected(source, word, what)),
    }
}
