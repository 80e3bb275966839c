//! Finding the rows' numbers: 64 bytes of text classified at a time, word starts and line ends
//! visited as bits, each number checked with a few mask operations.

#[cfg(target_arch = "x86_64")]
use super::wide::Wide;
use super::words::{Block, Problem, Sink, read_any_number, read_short_number, word_end};

/// The result of parsing one part of a chunk.
pub(super) struct Part {
    pub(super) rows: usize,
    /// The problem and the row it is in (counted from the part's first row).
    pub(super) problem: Option<(usize, Problem)>,
    /// Where parsing stopped (after `rows` rows, or at the problem).
    pub(super) end: usize,
}

/// Parses up to `limit` rows of exactly `width` numbers, one row per non-blank line, into `out`.
///
/// The text is classified 64 bytes at a time (whitespace, line ends, digits, dots, minus signs);
/// the bits of word starts and line ends are then visited in order. So where the next number
/// starts never waits for the previous one to be read, and a number's shape is checked with a few
/// mask operations. A window ends before a word that runs past it, which starts the next window.
///
/// Where the CPU has AVX-512, numbers are queued and read eight at a time ([`Wide`]), with the
/// same results.
pub(super) fn parse_rows<S: Sink>(text: &[u8], width: usize, limit: usize, out: &mut S) -> Part {
    #[cfg(target_arch = "x86_64")]
    if super::wide::available() {
        // SAFETY: the CPU has just been found to have what `Wide` needs.
        return unsafe { parse_rows_wide(text, width, limit, out) };
    }
    parse_rows_with(text, width, limit, out, &mut OneByOne)
}

/// [`parse_rows`] compiled for AVX-512, reading through [`Wide`].
///
/// # Safety
/// The CPU must have what [`super::wide::available`] checks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512bw,avx512cd")]
unsafe fn parse_rows_wide<S: Sink>(text: &[u8], width: usize, limit: usize, out: &mut S) -> Part {
    parse_rows_with(text, width, limit, out, &mut WideReader(Wide::default()))
}

/// How the row loop reads the numbers it finds: at once, or queued and read in a batch.
trait NumberReader {
    /// Reads (or queues) the word at `at`, `length` bytes long, at bit `i` of `block`.
    fn number<S: Sink>(
        &mut self,
        text: &[u8],
        at: usize,
        length: usize,
        block: &Block,
        i: usize,
        out: &mut S,
    ) -> Result<(), Problem>;

    /// Reads every queued word; the row loop calls it before it counts a row or stops.
    fn flush<S: Sink>(&mut self, text: &[u8], out: &mut S) -> Result<(), Problem>;
}

/// Each number read where it is found.
struct OneByOne;

impl NumberReader for OneByOne {
    #[inline(always)]
    fn number<S: Sink>(
        &mut self,
        text: &[u8],
        at: usize,
        length: usize,
        block: &Block,
        i: usize,
        out: &mut S,
    ) -> Result<(), Problem> {
        let value = match read_short_number(text, at, length, block, i) {
            Some(value) => value,
            None => read_any_number(text, at)?,
        };
        out.push(value);
        Ok(())
    }

    #[inline(always)]
    fn flush<S: Sink>(&mut self, _: &[u8], _: &mut S) -> Result<(), Problem> {
        Ok(())
    }
}

/// Numbers queued and read eight at a time; only made where the CPU can run [`Wide`].
#[cfg(target_arch = "x86_64")]
struct WideReader(Wide);

#[cfg(target_arch = "x86_64")]
impl NumberReader for WideReader {
    #[inline(always)]
    fn number<S: Sink>(
        &mut self,
        text: &[u8],
        at: usize,
        length: usize,
        block: &Block,
        i: usize,
        out: &mut S,
    ) -> Result<(), Problem> {
        // SAFETY: a `WideReader` is only made by `parse_rows_wide`, whose caller checked the CPU.
        unsafe { self.0.number(text, at, length, block, i, out) }
    }

    #[inline(always)]
    fn flush<S: Sink>(&mut self, text: &[u8], out: &mut S) -> Result<(), Problem> {
        // SAFETY: as in `number`.
        unsafe { self.0.flush(text, out) }
    }
}

/// [`parse_rows`] reading numbers through `reader`.
#[inline(always)]
fn parse_rows_with<S: Sink, R: NumberReader>(
    text: &[u8],
    width: usize,
    limit: usize,
    out: &mut S,
    reader: &mut R,
) -> Part {
    let stopped = |rows, problem, end| Part { rows, problem, end };
    if limit == 0 {
        return stopped(0, None, 0);
    }
    let mut rows = 0;
    let mut values = 0; // in the current row
    // Whether the byte before the window is whitespace (the text's start counts as such).
    let mut after_whitespace = 1;
    let mut base = 0;
    while base < text.len() {
        let block = Block::of(&text[base..]);
        let starts = !block.whitespace & ((block.whitespace << 1) | after_whitespace);
        let advance = if text.len() - base <= 64 || block.whitespace >> 63 != 0 {
            64
        } else {
            63 - starts.leading_zeros() as usize
        };
        if advance == 0 {
            // One word fills the window (it starts here: every window starts after whitespace).
            if let Err(problem) = reader.flush(text, out) {
                return stopped(rows, Some((rows, problem)), problem.start());
            }
            if values == width {
                return stopped(rows, Some((rows, Problem::TooMany(base))), base);
            }
            match read_any_number(text, base) {
                Ok(value) => out.push(value),
                Err(problem) => return stopped(rows, Some((rows, problem)), base),
            }
            values += 1;
            base = word_end(text, base);
            after_whitespace = 1;
            continue;
        }
        let inside = u64::MAX >> (64 - advance);
        let line_ends = block.line_end & inside;
        let mut events = (starts & inside) | line_ends;
        while events != 0 {
            let i = events.trailing_zeros() as usize;
            events &= events - 1;
            let at = base + i;
            if line_ends >> i & 1 != 0 {
                if let Err(problem) = reader.flush(text, out) {
                    return stopped(rows, Some((rows, problem)), problem.start());
                }
                if values == width {
                    rows += 1;
                    values = 0;
                    if rows == limit {
                        return stopped(rows, None, at);
                    }
                } else if values != 0 {
                    return stopped(rows, Some((rows, Problem::TooFew(at, values))), at);
                }
                continue;
            }
            if values == width {
                // A word queued before this one may be the first problem.
                let problem = reader
                    .flush(text, out)
                    .err()
                    .unwrap_or(Problem::TooMany(at));
                return stopped(rows, Some((rows, problem)), problem.start());
            }
            let length = (block.whitespace >> i).trailing_zeros() as usize;
            if let Err(problem) = reader.number(text, at, length, &block, i, out) {
                return stopped(rows, Some((rows, problem)), problem.start());
            }
            values += 1;
        }
        after_whitespace = (block.whitespace >> (advance - 1)) & 1;
        base += advance;
    }
    if let Err(problem) = reader.flush(text, out) {
        return stopped(rows, Some((rows, problem)), problem.start());
    }
    if values == width {
        rows += 1;
    } else if values != 0 {
        let problem = Problem::TooFew(text.len(), values);
        return stopped(rows, Some((rows, problem)), text.len());
    }
    Part {
        rows,
        problem: None,
        end: text.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::rows::number::parse_number;
    use crate::bvh::rows::words::short_decimal;

    /// [`super::parse_rows`] one number at a time and, where the CPU has the lanes, eight at a
    /// time, which must agree in everything: rows, problem, where parsing stopped, and values.
    fn parse_rows(text: &[u8], width: usize, limit: usize, out: &mut Vec<f32>) -> Part {
        let part = parse_rows_with(text, width, limit, out, &mut OneByOne);
        #[cfg(target_arch = "x86_64")]
        if super::super::wide::available() {
            let mut wide_out = Vec::new();
            // SAFETY: the CPU has just been found to have the lanes.
            let wide = unsafe { parse_rows_wide(text, width, limit, &mut wide_out) };
            let text = String::from_utf8_lossy(text);
            assert_eq!(
                (wide.rows, wide.end, format!("{:?}", wide.problem)),
                (part.rows, part.end, format!("{:?}", part.problem)),
                "{text:?}"
            );
            let bits = |values: &[f32]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&wide_out), bits(out), "{text:?}");
        }
        part
    }

    /// Says in the test run's output whether the comparisons with the AVX-512 reader ran here
    /// (`scripts/test.sh` repeats the line at the end), and checks one row both ways.
    #[test]
    fn say_whether_the_avx512_comparisons_ran() {
        let mut out = Vec::new();
        let part = parse_rows(b"1.5 -2.25 3e2 0.125 7 8 9 10 11\n", 9, 1, &mut out);
        assert_eq!(part.rows, 1);
        assert_eq!(out, [1.5, -2.25, 300.0, 0.125, 7.0, 8.0, 9.0, 10.0, 11.0]);
        #[cfg(target_arch = "x86_64")]
        let ran = super::super::wide::available();
        #[cfg(not(target_arch = "x86_64"))]
        let ran = false;
        if ran {
            println!("row reader: AVX-512 comparisons ran (rows/wide.rs against rows/scan.rs)");
        } else {
            println!("row reader: AVX-512 comparisons skipped: this CPU has no AVX-512");
        }
    }

    /// What `(float)atof(word)` gives: the nearest double, then the nearest float.
    fn reference(word: &str) -> f32 {
        word.parse::<f64>().unwrap() as f32
    }

    #[test]
    fn every_path_reads_numbers_as_atof_does() {
        // A deterministic spread of shapes: signs, leading zeros, dots anywhere, 1 to 17 digits,
        // exponents, values on float rounding midpoints.
        let mut words: Vec<String> = vec![
            "0",
            "-0",
            "0.0",
            "-0.000",
            "1",
            "-1",
            "17.8693",
            "-17.3198",
            ".5",
            "5.",
            "-.25",
            "1.87007e-05",
            "1e-007",
            "5.1072e-06",
            "-1.3905e-06",
            "-3E+02",
            "1e22",
            "1e23",
            "123456789012345e-22",
            "1.5e-45",
            "7e-46",
            "+3.5",
            "0000000001.5",
            "123456789012345",
            "1234567890123456",
            "0.000000000000001",
            "16777217",
            "16777217.0",
            "0.1",
            "3.4028235e38",
            "9007199254740993",
        ]
        .into_iter()
        .map(String::from)
        .collect();
        let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for _ in 0..200_000 {
            let digits = 1 + (next() % 17) as usize;
            let mut word = String::new();
            if next() % 3 == 0 {
                word.push('-');
            }
            for _ in 0..digits {
                word.push((b'0' + (next() % 10) as u8) as char);
            }
            if next() % 4 != 0 {
                let at = 1 + (next() as usize) % word.len();
                word.insert(at.min(word.len()), '.');
                if word.ends_with('.') && next() % 2 == 0 {
                    word.push('7');
                }
                if word.starts_with("-.") || word.starts_with('.') {
                    word = word.replacen('.', "0.", 1);
                }
            }
            // Exponents as `%g` writes them, and past what the fast path takes (10^±22 from
            // the mantissa) on both sides.
            if next() % 3 == 0 {
                let e = if next() % 2 == 0 { 'e' } else { 'E' };
                let sign = ["", "-", "+"][(next() % 3) as usize];
                let exponent = next() % 40;
                word.push_str(&format!("{e}{sign}{exponent:02}"));
            }
            words.push(word);
        }
        for word in &words {
            let want = reference(word);
            if !want.is_finite() {
                // Past a float's range: not a number the loader takes (as before exponents
                // had a fast path).
                assert_eq!(parse_number(word.as_bytes()), None, "{word}");
                continue;
            }
            assert_eq!(
                parse_number(word.as_bytes()).map(f32::to_bits),
                Some(want.to_bits()),
                "{word}"
            );
            // In a row, where the 16-byte path applies.
            let row = format!("{word} 1                \n");
            let mut out = Vec::new();
            let part = parse_rows(row.as_bytes(), 2, 1, &mut out);
            assert!(part.problem.is_none(), "{word}");
            assert_eq!(out[0].to_bits(), want.to_bits(), "{word}");
        }
    }

    #[test]
    fn every_shape_of_short_word_reads_as_atof_at_the_text_end_and_before_more() {
        // Bodies of 0 to 9 bytes, a dot at every place or none, with or without '-': the shapes
        // the lanes read or refuse, read where the eight bytes after a word run past the text
        // and where they hold the next words.
        let mut seed: u64 = 0x853C_49E6_748F_EA9B;
        for length in 0..=9 {
            for dot in (0..=length).map(Some).chain([None]) {
                for sign in ["", "-"] {
                    for _ in 0..40 {
                        let mut body: Vec<u8> = (0..length)
                            .map(|_| {
                                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                                b'0' + (seed >> 60) as u8 % 10
                            })
                            .collect();
                        if let Some(dot) = dot {
                            body.insert(dot, b'.');
                        }
                        let word = format!("{sign}{}", String::from_utf8(body).unwrap());
                        if word.is_empty() {
                            continue;
                        }
                        let want = word.parse::<f64>().ok().map(|v| (v as f32).to_bits());
                        for text in [
                            word.clone(),
                            format!("{word}\n"),
                            format!("{word} 7.25 -1\n"),
                        ] {
                            let width = text.split_whitespace().count().max(1);
                            let mut out = Vec::new();
                            let part = parse_rows(text.as_bytes(), width, 1, &mut out);
                            let got = part.problem.is_none().then(|| out[0].to_bits());
                            assert_eq!(got, want, "{text:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn every_short_decimal_is_the_quotient_rounded_as_atof_rounds_it() {
        for scale in 0..=7 {
            let power = 10f64.powi(scale as i32);
            for digits in 0..10_000_000u32 {
                // Both exact doubles: the IEEE quotient is the double nearest the decimal, as
                // `atof` gives it.
                let want = (f64::from(digits) / power) as f32;
                assert_eq!(
                    short_decimal(digits, scale).to_bits(),
                    want.to_bits(),
                    "{digits} / 10^{scale}"
                );
            }
        }
    }

    #[test]
    fn words_that_are_not_numbers_are_refused() {
        for word in [
            "1.2.3", "--1", "1-", "abc", "1e", "nan", "inf", "0x10", "1,5", "12a", "-", ".",
        ] {
            assert_eq!(parse_number(word.as_bytes()), None, "{word}");
            let row = format!("{word}                  \n");
            let part = parse_rows(row.as_bytes(), 1, 1, &mut Vec::new());
            assert!(
                matches!(part.problem, Some((0, Problem::NotANumber(0, _)))),
                "{word}"
            );
        }
    }

    #[test]
    fn rows_of_every_shape_read_as_a_split_and_atof_would() {
        // Words of every length around the 64-byte windows: short and long numbers, words longer
        // than a window, separators of every kind; compared with splitting at whitespace.
        let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        for _ in 0..300 {
            let width = 1 + next(12) as usize;
            let rows = 1 + next(40) as usize;
            let mut text = String::new();
            let mut words = Vec::new();
            for _ in 0..rows {
                if next(10) == 0 {
                    text.push_str(["\n", "\r\n", "  \t\n"][next(3) as usize]);
                }
                for k in 0..width {
                    let longest = if next(20) == 0 { 80 } else { 9 };
                    let digits = 1 + next(longest) as usize;
                    let mut word: String = (0..digits)
                        .map(|_| (b'0' + next(10) as u8) as char)
                        .collect();
                    if digits > 30 {
                        // Long, but within a float's range.
                        word.insert(1, '.');
                    } else if next(3) != 0 {
                        word.insert(next(digits as u64 + 1) as usize, '.');
                    }
                    if word == "." {
                        word.push('5');
                    }
                    if next(2) == 0 {
                        word.insert(0, '-');
                    }
                    if k > 0 || next(4) == 0 {
                        text.push_str([" ", "\t", "  ", " \x0b", "\x0c"][next(5) as usize]);
                    }
                    text.push_str(&word);
                    words.push(word);
                }
                text.push_str(["\n", "\r\n", "\r", " \n", "\t\r\n"][next(5) as usize]);
            }
            let mut out = Vec::new();
            let part = parse_rows(text.as_bytes(), width, usize::MAX, &mut out);
            assert!(part.problem.is_none(), "{:?} {text:?}", part.problem);
            assert_eq!(part.rows, rows);
            let want: Vec<u32> = words.iter().map(|w| reference(w).to_bits()).collect();
            let got: Vec<u32> = out.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, want, "{text:?}");
        }
    }

    #[test]
    fn a_bad_word_anywhere_in_a_window_is_found_where_it_starts() {
        for at in 0..140 {
            let mut text = Vec::new();
            while text.len() < at {
                text.extend_from_slice(b"1.5 ");
            }
            text.truncate(at);
            if at > 0 {
                text.push(b' ');
            }
            let start = text.len();
            text.extend_from_slice(b"1.2.3 4\n");
            let values = start.div_ceil(4);
            let part = parse_rows(&text, values + 2, 1, &mut Vec::new());
            match part.problem {
                Some((0, Problem::NotANumber(s, e))) => assert_eq!((s, e), (start, start + 5)),
                other => panic!("at {at}: {other:?}"),
            }
        }
    }
}
