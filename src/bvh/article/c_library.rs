//! The C library's `isspace` and `strtod` as glibc has them, which the article's `atof` calls:
//! what the original reads from a number depends on them.

/// C's `isspace` in the C locale.
pub(super) fn is_c_space(byte: u8) -> bool {
    matches!(byte, b' ' | b'\t' | b'\n' | b'\r' | 0x0B | 0x0C)
}

/// C's `strtod` in the C locale: white space, then the longest decimal number, `inf`,
/// `infinity`, `nan` (with or without `(…)`) or hexadecimal number; its value, rounded as glibc
/// rounds, and the bytes it used (0 when there is no number: the value is then 0).
pub(super) fn c_strtod(text: &[u8]) -> (f64, usize) {
    let mut i = 0;
    while text.get(i).is_some_and(|&b| is_c_space(b)) {
        i += 1;
    }
    let sign_at = i;
    let negative = text.get(i) == Some(&b'-');
    if matches!(text.get(i), Some(b'-' | b'+')) {
        i += 1;
    }
    let signed = |v: f64| if negative { -v } else { v };
    let lower = |at: usize, word: &[u8]| {
        text.len() >= at + word.len()
            && text[at..at + word.len()]
                .iter()
                .zip(word)
                .all(|(a, b)| a.to_ascii_lowercase() == *b)
    };
    if lower(i, b"infinity") {
        return (signed(f64::INFINITY), i + 8);
    }
    if lower(i, b"inf") {
        return (signed(f64::INFINITY), i + 3);
    }
    if lower(i, b"nan") {
        let mut end = i + 3;
        if text.get(end) == Some(&b'(') {
            let close = text[end + 1..]
                .iter()
                .position(|&b| !(b.is_ascii_alphanumeric() || b == b'_'));
            if let Some(n) = close.filter(|&n| text.get(end + 1 + n) == Some(&b')')) {
                end += n + 2;
            }
        }
        return (f64::NAN, end);
    }
    if text.get(i) == Some(&b'0') && matches!(text.get(i + 1), Some(b'x' | b'X')) {
        if let Some((value, end)) = hexadecimal(text, i + 2) {
            return (signed(value), end);
        }
        // "0x" with no hexadecimal digit after it: the 0 alone.
        return (signed(0.0), i + 1);
    }
    let digits = |mut at: usize| {
        while text.get(at).is_some_and(u8::is_ascii_digit) {
            at += 1;
        }
        at
    };
    let whole = digits(i);
    let mut end = whole;
    let mut any = whole > i;
    if text.get(end) == Some(&b'.') {
        let fraction = digits(end + 1);
        any |= fraction > end + 1;
        if any {
            end = fraction;
        }
    }
    if !any {
        return (0.0, 0);
    }
    if matches!(text.get(end), Some(b'e' | b'E')) {
        let mut at = end + 1;
        if matches!(text.get(at), Some(b'-' | b'+')) {
            at += 1;
        }
        let exponent = digits(at);
        if exponent > at {
            end = exponent;
        }
    }
    let number = std::str::from_utf8(&text[sign_at..end]).expect("ASCII");
    // Rust's parser rounds correctly, as glibc's strtod does; it wants a digit before the dot.
    let number = number
        .replacen("-.", "-0.", 1)
        .replacen("+.", "0.", 1)
        .trim_start_matches('+')
        .to_string();
    let number = if number.starts_with('.') {
        format!("0{number}")
    } else {
        number
    };
    (number.parse().unwrap_or(0.0), end)
}

/// A hexadecimal number after `0x`: digits, an optional fraction and an optional `p` exponent.
pub(super) fn hexadecimal(text: &[u8], start: usize) -> Option<(f64, usize)> {
    let digit = |b: u8| (b as char).to_digit(16);
    let mut at = start;
    let mut mantissa = 0f64;
    let mut scale = 0i32;
    let mut any = false;
    while let Some(d) = text.get(at).and_then(|&b| digit(b)) {
        mantissa = mantissa * 16.0 + f64::from(d);
        any = true;
        at += 1;
    }
    if text.get(at) == Some(&b'.') {
        let mut fraction = at + 1;
        while let Some(d) = text.get(fraction).and_then(|&b| digit(b)) {
            mantissa = mantissa * 16.0 + f64::from(d);
            scale -= 4;
            any = true;
            fraction += 1;
        }
        if any {
            at = fraction;
        }
    }
    if !any {
        return None;
    }
    if matches!(text.get(at), Some(b'p' | b'P')) {
        let mut e = at + 1;
        let negative = text.get(e) == Some(&b'-');
        if matches!(text.get(e), Some(b'-' | b'+')) {
            e += 1;
        }
        let first = e;
        let mut exponent = 0i32;
        while let Some(&b) = text.get(e).filter(|b| b.is_ascii_digit()) {
            exponent = exponent
                .saturating_mul(10)
                .saturating_add(i32::from(b - b'0'));
            e += 1;
        }
        if e > first {
            scale = scale.saturating_add(if negative { -exponent } else { exponent });
            at = e;
        }
    }
    Some((mantissa * 2f64.powi(scale), at))
}
