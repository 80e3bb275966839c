//! Finding the rows' numbers: 64 bytes of text classified at a time, word starts and line ends
//! visited as bits, each number checked with a few mask operations.

use super::number::{eight_digits, is_blank, parse_number, read_decimal};
#[cfg(target_arch = "x86_64")]
use super::wide::Wide;
use crate::lines::is_line_end;

/// What went wrong in a row, at a byte offset of the part being parsed.
#[derive(Clone, Copy, Debug)]
pub(super) enum Problem {
    /// A value beyond the row's width starts here.
    TooMany(usize),
    /// The row ends here with this many values.
    TooFew(usize, usize),
    /// This word is not a finite number.
    NotANumber(usize, usize),
}

impl Problem {
    /// Where the problem is: where parsing stops.
    fn start(self) -> usize {
        match self {
            Problem::TooMany(at) | Problem::TooFew(at, _) | Problem::NotANumber(at, _) => at,
        }
    }
}

/// The result of parsing one part of a chunk.
pub(super) struct Part {
    pub(super) rows: usize,
    /// The problem and the row it is in (counted from the part's first row).
    pub(super) problem: Option<(usize, Problem)>,
    /// Where parsing stopped (after `rows` rows, or at the problem).
    pub(super) end: usize,
}

/// Where parsed values go.
pub(super) trait Sink {
    fn push(&mut self, value: f32);

    /// Eight values at once.
    fn push_eight(&mut self, values: &[f32; 8]);
}

impl Sink for Vec<f32> {
    #[inline(always)]
    fn push(&mut self, value: f32) {
        Vec::push(self, value)
    }

    #[inline(always)]
    fn push_eight(&mut self, values: &[f32; 8]) {
        self.extend_from_slice(values)
    }
}

/// Writes into uninitialised room of the result, front to back; `written` counts the values.
pub(super) struct SliceSink<'a> {
    pub(super) room: &'a mut [std::mem::MaybeUninit<f32>],
    pub(super) written: usize,
}

impl Sink for SliceSink<'_> {
    #[inline(always)]
    fn push(&mut self, value: f32) {
        // The room holds `limit` rows and no more are parsed; a value beyond would be a bug here,
        // and indexing stops it.
        self.room[self.written].write(value);
        self.written += 1;
    }

    #[inline(always)]
    fn push_eight(&mut self, values: &[f32; 8]) {
        let room = &mut self.room[self.written..self.written + 8];
        for (slot, &value) in room.iter_mut().zip(values) {
            slot.write(value);
        }
        self.written += 8;
    }
}

/// One bit per byte of 64 bytes of text (bit i for byte i): whitespace, LF or CR, digits, '.', '-'.
#[derive(Clone, Copy, Default)]
pub(super) struct Block {
    whitespace: u64,
    line_end: u64,
    digit: u64,
    dot: u64,
    minus: u64,
}

impl Block {
    /// The masks of `text[..64]`; a shorter text is padded with spaces.
    #[inline(always)]
    fn of(text: &[u8]) -> Block {
        match text.first_chunk::<64>() {
            Some(bytes) => Block::of_64(bytes),
            None => {
                let mut padded = [b' '; 64];
                padded[..text.len()].copy_from_slice(text);
                Block::of_64(&padded)
            }
        }
    }

    /// Sixteen bytes per SSE2 compare (SSE2 is part of every x86-64).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn of_64(bytes: &[u8; 64]) -> Block {
        use std::arch::x86_64::*;
        let mut block = Block::default();
        for lane in 0..4 {
            // SAFETY: SSE2 is always present on x86-64, and the 16 bytes read are inside `bytes`.
            unsafe {
                let v = _mm_loadu_si128(bytes.as_ptr().add(16 * lane).cast());
                let mask = |m: __m128i| u64::from(_mm_movemask_epi8(m) as u16) << (16 * lane);
                // `count` bytes from `low` on, as one signed compare: the range moved to -128.
                let within = |low: u8, count: i8| {
                    let moved = _mm_add_epi8(v, _mm_set1_epi8(0x80u8.wrapping_sub(low) as i8));
                    _mm_cmplt_epi8(moved, _mm_set1_epi8(-128 + count))
                };
                let is = |b: u8| _mm_cmpeq_epi8(v, _mm_set1_epi8(b as i8));
                // Tab, LF, VT, FF, CR (9 to 13) and space.
                block.whitespace |= mask(_mm_or_si128(within(9, 5), is(b' ')));
                block.line_end |= mask(_mm_or_si128(is(b'\n'), is(b'\r')));
                block.digit |= mask(within(b'0', 10));
                block.dot |= mask(is(b'.'));
                block.minus |= mask(is(b'-'));
            }
        }
        block
    }

    /// 1 when byte `i` is '-', else 0.
    #[inline(always)]
    pub(super) fn minus_at(&self, i: usize) -> usize {
        (self.minus >> i) as usize & 1
    }

    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    fn of_64(bytes: &[u8; 64]) -> Block {
        let mut block = Block::default();
        for (i, &b) in bytes.iter().enumerate() {
            block.whitespace |= u64::from(is_blank(b) || is_line_end(b)) << i;
            block.line_end |= u64::from(is_line_end(b)) << i;
            block.digit |= u64::from(b.is_ascii_digit()) << i;
            block.dot |= u64::from(b == b'.') << i;
            block.minus |= u64::from(b == b'-') << i;
        }
        block
    }
}

/// 10⁻⁰ to 10⁻⁷, each rounded to the nearest double.
pub(super) const INV_POW10_F64: [f64; 8] = [1e0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7];

/// `digits / 10^scale` as `(float)atof` reads it, for `digits < 10⁷` and `scale ≤ 7`.
///
/// `atof` gives the double nearest the quotient, then the cast rounds that to a float. Here the
/// quotient is a product with the rounded reciprocal (a multiplication is several times cheaper
/// than a division). The reciprocal and the product are each rounded once, so the product lies
/// within 2⁻⁵² (and a term of 2⁻¹⁰⁶) of the quotient, relative. Both doubles round to the same
/// float unless the quotient lies that close to a midpoint between two floats, and none does: a
/// quotient that is a binary fraction has at most 24 significant bits, so it is a float itself,
/// and for every other one the test of all 80 million (digits, scale) cases shows it.
#[inline(always)]
pub(super) fn short_decimal(digits: u32, scale: usize) -> f32 {
    (f64::from(digits) * INV_POW10_F64[scale]) as f32
}

/// The value of `word`, a word of up to 9 bytes ('-', then digits with at most one '.') whose
/// masks within its block are given from its first byte on; `None` for any other word.
///
/// The value is [`short_decimal`] of the word's digits and scale, with the sign.
#[inline(always)]
pub(super) fn read_short_number(
    text: &[u8],
    at: usize,
    length: usize,
    block: &Block,
    i: usize,
) -> Option<f32> {
    const LOW: u64 = 0x0101_0101_0101_0101;
    let negative = block.minus_at(i);
    let body_length = length - negative;
    let body_mask = (1u64 << body_length.min(63)) - 1;
    let body = ((block.digit | block.dot) >> i) >> negative;
    let dots = ((block.dot >> i) >> negative) & body_mask;
    let count = body_length - usize::from(dots != 0);
    let p = at + negative;
    let bytes = text.get(p..)?.first_chunk::<8>()?;
    if body & body_mask != body_mask
        || dots & dots.wrapping_sub(1) != 0
        || !(1..=7).contains(&count)
    {
        return None;
    }
    let word = u64::from_le_bytes(*bytes);
    // Take the '.' out: the bytes after it move down one.
    let dot_at = dots.trailing_zeros() as usize; // 64 without a dot
    let before = if dot_at >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * dot_at)) - 1
    };
    let joined = (word & before) | ((word >> 8) & !before);
    let scale = if dots != 0 {
        body_length - 1 - dot_at
    } else {
        0
    };
    let digits = joined.wrapping_sub(0x30 * LOW) << (8 * (8 - count));
    let magnitude = short_decimal(eight_digits(digits) as u32, scale);
    Some(f32::from_bits(
        magnitude.to_bits() | ((negative as u32) << 31),
    ))
}

/// A number in any form `(float)atof` takes, or the problem with the word at `at`.
#[cold]
#[inline(never)]
pub(super) fn read_any_number(text: &[u8], at: usize) -> Result<f32, Problem> {
    if let Some((value, _)) = read_decimal(text, at) {
        return Ok(value);
    }
    let end = word_end(text, at);
    parse_number(&text[at..end]).ok_or(Problem::NotANumber(at, end))
}

/// Where the word at `at` ends: at whitespace or the end of `text`.
pub(super) fn word_end(text: &[u8], at: usize) -> usize {
    text[at..]
        .iter()
        .position(|&b| is_blank(b) || is_line_end(b))
        .map_or(text.len(), |n| at + n)
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
            words.push(word);
        }
        for word in &words {
            let want = reference(word);
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
