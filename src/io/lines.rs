//! Line ends and line and column numbers, one definition for every reader: a line ends at LF,
//! CR LF or a lone CR; columns count characters, not bytes.

/// How an error shows a word it found in a file: quoted when it is text, cut to 40 characters
/// (enough to recognise it, no more of the file); named, never shown, when it is not text (a
/// control byte, or bytes that are not UTF-8).
pub fn shown_word(word: &[u8]) -> String {
    let Ok(text) = std::str::from_utf8(word) else {
        return "binary data".to_string();
    };
    if text.chars().any(|c| c.is_control() && c != '\t') {
        return "binary data".to_string();
    }
    if text.chars().count() > 40 {
        let short: String = text.chars().take(40).collect();
        format!("'{short}…'")
    } else {
        format!("'{text}'")
    }
}

/// How an error shows the first word of a file that does not begin as its format does. Such a
/// file may be anything (a link to a private file in a dataset folder): its words are its
/// content, so the word is shown only when it is a misspelling of one of `keywords` (within two
/// letters' changes, case aside), which is all a user needs to see; otherwise only what kind of
/// thing it is.
pub fn shown_first_word(word: &[u8], keywords: &[&str]) -> String {
    let near = |keyword: &str| {
        edit_distance(
            &word.to_ascii_uppercase(),
            &keyword.to_ascii_uppercase().into_bytes(),
        ) <= 2
    };
    if word.len() <= 40 && keywords.iter().any(|k| near(k)) {
        return shown_word(word);
    }
    match shown_word(word).as_str() {
        "binary data" => "binary data (not text)".to_string(),
        _ => "other text".to_string(),
    }
}

/// Levenshtein distance between two short byte strings.
fn edit_distance(a: &[u8], b: &[u8]) -> usize {
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, &x) in a.iter().enumerate() {
        let mut current = vec![i + 1; b.len() + 1];
        for (j, &y) in b.iter().enumerate() {
            current[j + 1] = (previous[j] + usize::from(x != y))
                .min(previous[j + 1] + 1)
                .min(current[j] + 1);
        }
        previous = current;
    }
    previous[b.len()]
}

/// An LF or a CR.
pub fn is_line_end(byte: u8) -> bool {
    byte == b'\n' || byte == b'\r'
}

/// The LFs and the CRs in `text`, counted in one pass: 255 bytes at a time into byte counters,
/// which the compiler turns into SIMD compares and adds.
fn count_lf_cr(text: &[u8]) -> (usize, usize) {
    text.chunks(255)
        .map(|block| {
            let (mut lf, mut cr) = (0u8, 0u8);
            for &b in block {
                lf += u8::from(b == b'\n');
                cr += u8::from(b == b'\r');
            }
            (usize::from(lf), usize::from(cr))
        })
        .fold((0, 0), |(lf, cr), (l, c)| (lf + l, cr + c))
}

/// Line breaks in `text` (LF, CRLF or a lone CR each count once) and the number of characters
/// after the last one.
pub fn count_lines(text: &[u8]) -> (usize, usize) {
    let (lf, cr) = count_lf_cr(text);
    let breaks = if cr == 0 {
        lf
    } else {
        let crlf = text
            .windows(2)
            .filter(|w| w[0] == b'\r' && w[1] == b'\n')
            .count();
        lf + cr - crlf
    };
    let tail = match text.iter().rposition(|&b| is_line_end(b)) {
        Some(i) => &text[i + 1..],
        None => text,
    };
    let since = tail.iter().filter(|&&b| (b & 0xC0) != 0x80).count();
    (breaks, since)
}

/// The line and column after text with `breaks` line breaks and `since` characters after the
/// last one, when the text starts at `(line, column)`.
pub fn advance((line, column): (usize, usize), (breaks, since): (usize, usize)) -> (usize, usize) {
    if breaks == 0 {
        (line, column + since)
    } else {
        (line + breaks, since + 1)
    }
}

/// 1-based line and column of byte `offset` in `text`. A UTF-8 byte-order mark is not a column,
/// and a CR whose LF comes at `offset` has not ended its line yet.
pub fn line_column(text: &[u8], offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let start = if text.starts_with(b"\xEF\xBB\xBF") && offset >= 3 {
        3
    } else {
        0
    };
    let head = &text[start..offset];
    match head.strip_suffix(b"\r") {
        Some(before) if text.get(offset) == Some(&b'\n') => {
            let (line, column) = advance((1, 1), count_lines(before));
            (line, column + 1)
        }
        _ => advance((1, 1), count_lines(head)),
    }
}

#[cfg(test)]
mod tests {
    /// A file that is not motion text is not quoted; a misspelt keyword is.
    #[test]
    fn a_first_word_is_shown_only_when_it_misspells_a_keyword() {
        let shown = |word: &[u8]| shown_first_word(word, &["HIERARCHY"]);
        assert_eq!(shown(b"HIERARCHIE"), "'HIERARCHIE'");
        assert_eq!(shown(b"hierachy"), "'hierachy'");
        assert_eq!(shown(b"API_KEY=sk-verysecret"), "other text");
        assert_eq!(shown(b"secret"), "other text");
        assert_eq!(shown(b"\x00\x01ELF"), "binary data (not text)");
        assert_eq!(shown(b"\xff\xfe"), "binary data (not text)");
        assert_eq!(shown_word(b"\x7fELF"), "binary data");
        assert_eq!(
            shown_word("x".repeat(50).as_bytes()),
            format!("'{}…'", "x".repeat(40))
        );
    }

    use super::*;

    /// Counting every byte one by one, as the loaders did before they shared this.
    fn by_hand(text: &[u8], offset: usize) -> (usize, usize) {
        let mut line = 1;
        let mut line_start = if text.starts_with(b"\xEF\xBB\xBF") && offset >= 3 {
            3
        } else {
            0
        };
        for (i, &byte) in text[..offset].iter().enumerate() {
            if byte == b'\n' || (byte == b'\r' && text.get(i + 1) != Some(&b'\n')) {
                line += 1;
                line_start = i + 1;
            }
        }
        let column = text[line_start..offset]
            .iter()
            .filter(|&&b| (b & 0xC0) != 0x80)
            .count();
        (line, column + 1)
    }

    #[test]
    fn every_offset_of_mixed_text_agrees_with_counting_by_hand() {
        let text = "\u{feff}ab\r\ncd\re\n\nf\u{e9}g\r\n\r\rh".as_bytes();
        for offset in 0..=text.len() {
            assert_eq!(
                line_column(text, offset),
                by_hand(text, offset),
                "offset {offset}"
            );
        }
    }
}
