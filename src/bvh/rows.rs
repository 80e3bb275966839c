//! The MOTION rows, read in chunks that end at line ends, each chunk split across the cores.
//!
//! C++: the row loop at the end of `BVH::loadFile`. The article reads `Frames` rows with fixed
//! strides from a buffer holding the whole file. Here the rows arrive in pieces (a file is never
//! held whole), each piece is parsed in parallel without a `String` per number, and every error
//! still names its exact line and column.

use crate::error::Error;

/// Bytes of MOTION text handed to the parser at a time.
pub const CHUNK: usize = 1 << 20;

/// Below this a chunk is parsed on one thread: starting one costs more than it saves.
const PARALLEL_MIN: usize = 64 * 1024;

fn is_line_end(byte: u8) -> bool {
    byte == b'\n' || byte == b'\r'
}

fn is_blank(byte: u8) -> bool {
    matches!(byte, b' ' | b'\t' | 0x0B | 0x0C)
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// 10ᵏ as integers, for joining a fraction's digits to the integer part.
const POW10_INT: [u64; 8] = [1, 10, 100, 1000, 10_000, 100_000, 1_000_000, 10_000_000];

/// 10⁻ᵏ, rounded to the nearest double.
const INV_POW10: [f64; 23] = [
    1e0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14,
    1e-15, 1e-16, 1e-17, 1e-18, 1e-19, 1e-20, 1e-21, 1e-22,
];

/// `mantissa / 10^scale` rounded to a float exactly as rounding the correctly rounded double
/// would (`(float)atof`), for `mantissa < 2^53`, `scale ≤ 22`. A multiplication by the rounded
/// reciprocal lands within two units in the last place of the exact quotient; rounding to a float
/// can only differ from the exact division when that double sits next to the midpoint between two
/// floats, which its low 29 bits show. Only then is the (slow) division done.
#[inline]
fn decimal_to_f32(mantissa: u64, scale: usize, negative: bool) -> f32 {
    // Below 2^53: the signed conversion is one instruction and exact.
    let m = mantissa as i64 as f64;
    let mut value = m * INV_POW10[scale];
    let low = value.to_bits() & ((1 << 29) - 1);
    if scale != 0 && low.abs_diff(1 << 28) <= 8 {
        value = m / POW10[scale];
    }
    (if negative { -value } else { value }) as f32
}

/// The run of ASCII digits at `p`, read eight bytes at a time: its value and length, for runs of
/// 0 to 7 digits. `None` when fewer than eight bytes remain or the run is longer; the caller
/// then reads it byte by byte.
#[inline(always)]
fn digit_run(text: &[u8], p: usize) -> Option<(u64, usize)> {
    let bytes: [u8; 8] = text.get(p..p + 8)?.try_into().ok()?;
    let digits = u64::from_le_bytes(bytes).wrapping_sub(0x3030_3030_3030_3030);
    // A byte is a digit when subtracting '0' leaves 0..9: no borrow, and adding 0x76 no carry
    // into its top bit. Bytes after the first non-digit may be misflagged; only the first counts.
    let flags = (digits | digits.wrapping_add(0x7676_7676_7676_7676)) & 0x8080_8080_8080_8080;
    if flags == 0 {
        return None;
    }
    let length = (flags.trailing_zeros() / 8) as usize;
    if length == 0 {
        return Some((0, 0));
    }
    // Keep the run, most significant digit highest, leading zero digits below.
    let value = eight_digits(digits << (8 * (8 - length)));
    Some((value, length))
}

/// One number, as the article reads it with `(float)atof(p)`: the nearest double, rounded to a
/// float; `None` unless the whole word is a finite number. The usual shape goes through
/// [`read_decimal`]; anything else (exponents, long mantissas) through the standard library's
/// parser, which gives the same answer.
pub fn parse_number(word: &[u8]) -> Option<f32> {
    if let Some((value, end)) = read_decimal(word, 0)
        && end == word.len()
    {
        return Some(value);
    }
    let value = std::str::from_utf8(word).ok()?.parse::<f64>().ok()? as f32;
    value.is_finite().then_some(value)
}

/// The usual MOTION number at `p`, `[-+]digits[.digits]` with 1 to 15 digits and followed by a
/// blank, a line end or the end of `text`: its value (rounded exactly as `(float)atof` rounds,
/// by Clinger's fast path: the mantissa is exact below 2^53 and the scale at most 15) and where
/// it ends. `None` for anything else, which the caller hands to the standard parser.
#[inline(always)]
fn read_decimal(text: &[u8], mut p: usize) -> Option<(f32, usize)> {
    let negative = *text.get(p)? == b'-';
    p += usize::from(negative || text[p] == b'+');
    let mut mantissa: u64 = 0;
    let digits_start = p;
    if let Some((value, length)) = digit_run(text, p) {
        mantissa = value;
        p += length;
    } else {
        while let Some(&c) = text.get(p).filter(|c| c.is_ascii_digit()) {
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
            p += 1;
        }
    }
    let mut digits = p - digits_start;
    let mut scale = 0;
    if text.get(p) == Some(&b'.') {
        p += 1;
        let fraction_start = p;
        match digit_run(text, p) {
            Some((value, length)) if digits <= 8 => {
                mantissa = mantissa * POW10_INT[length] + value;
                p += length;
            }
            _ => {
                while let Some(&c) = text.get(p).filter(|c| c.is_ascii_digit()) {
                    mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                    p += 1;
                }
            }
        }
        scale = p - fraction_start;
        digits += scale;
    }
    let ends = p == text.len() || is_blank(text[p]) || is_line_end(text[p]);
    (ends && digits > 0 && digits <= 15).then(|| (decimal_to_f32(mantissa, scale, negative), p))
}

/// What went wrong in a row, at a byte offset of the part being parsed.
#[derive(Clone, Copy, Debug)]
enum Problem {
    /// A value beyond the row's width starts here.
    TooMany(usize),
    /// The row ends here with this many values.
    TooFew(usize, usize),
    /// This word is not a finite number.
    NotANumber(usize, usize),
}

/// The result of parsing one part of a chunk.
struct Part {
    /// Line breaks in the part, and characters after the last one.
    lines: (usize, usize),
    rows: usize,
    /// The problem and the row it is in (counted from the part's first row).
    problem: Option<(usize, Problem)>,
    /// Where parsing stopped (after `rows` rows, or at the problem).
    end: usize,
}

/// Where parsed values go.
trait Sink {
    fn push(&mut self, value: f32);
}

impl Sink for Vec<f32> {
    #[inline(always)]
    fn push(&mut self, value: f32) {
        Vec::push(self, value)
    }
}

/// Writes into uninitialised room of the result, front to back; `written` counts the values.
struct SliceSink<'a> {
    room: &'a mut [std::mem::MaybeUninit<f32>],
    written: usize,
}

impl Sink for SliceSink<'_> {
    #[inline(always)]
    fn push(&mut self, value: f32) {
        // The room holds `limit` rows and no more are parsed; a value beyond would be a bug here,
        // and indexing stops it.
        self.room[self.written].write(value);
        self.written += 1;
    }
}

/// One bit per byte of 64 bytes of text (bit i for byte i): whitespace, LF, CR, digits, '.', '-'.
#[derive(Clone, Copy)]
struct Block {
    whitespace: u64,
    lf: u64,
    cr: u64,
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
                block.lf |= mask(is(b'\n'));
                block.cr |= mask(is(b'\r'));
                block.digit |= mask(within(b'0', 10));
                block.dot |= mask(is(b'.'));
                block.minus |= mask(is(b'-'));
            }
        }
        block
    }

    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    fn of_64(bytes: &[u8; 64]) -> Block {
        let mut block = Block::default();
        for (i, &b) in bytes.iter().enumerate() {
            block.whitespace |= u64::from(is_blank(b) || is_line_end(b)) << i;
            block.lf |= u64::from(b == b'\n') << i;
            block.cr |= u64::from(b == b'\r') << i;
            block.digit |= u64::from(b.is_ascii_digit()) << i;
            block.dot |= u64::from(b == b'.') << i;
            block.minus |= u64::from(b == b'-') << i;
        }
        block
    }
}

impl Default for Block {
    fn default() -> Block {
        Block {
            whitespace: 0,
            lf: 0,
            cr: 0,
            digit: 0,
            dot: 0,
            minus: 0,
        }
    }
}

/// 10⁰ to 10⁷, each exact as a float.
const POW10_F32: [f32; 8] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7];

/// The value of `word`, a word of up to 9 bytes ('-', then digits with at most one '.') whose
/// masks within its block are given from its first byte on; `None` for any other word.
///
/// With at most 7 digits, `digits / 10^scale` divided in floats is exactly `(float)atof`: both
/// numbers are exact floats, so the division rounds the exact quotient once. `atof` rounds it to a
/// double first, but that can only change the float when the quotient lies within 2⁻⁵³ of a
/// midpoint between two floats without being on it, and a quotient of a 7-digit integer by
/// 10^scale is never that close (its distance is at least 2⁻⁴⁸ of the value).
#[inline(always)]
fn read_short_number(
    text: &[u8],
    at: usize,
    length: usize,
    block: &Block,
    i: usize,
) -> Option<f32> {
    const LOW: u64 = 0x0101_0101_0101_0101;
    let negative = (block.minus >> i) as usize & 1;
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
    let magnitude = eight_digits(digits) as u32 as f32 / POW10_F32[scale];
    Some(f32::from_bits(
        magnitude.to_bits() | ((negative as u32) << 31),
    ))
}

/// The value of eight decimal digits, one per byte, the most significant in the lowest byte.
#[inline(always)]
fn eight_digits(digits: u64) -> u64 {
    // Pairs, then quads, then the whole, each in one multiply-and-shift step.
    let value = digits.wrapping_mul(10).wrapping_add(digits >> 8);
    let pairs = value & 0x0000_00FF_0000_00FF;
    let others = (value >> 16) & 0x0000_00FF_0000_00FF;
    (pairs
        .wrapping_mul(0x000F_4240_0000_0064)
        .wrapping_add(others.wrapping_mul(0x0000_2710_0000_0001)))
        >> 32
}

/// A number in any form `(float)atof` takes, or the problem with the word at `at`.
#[cold]
#[inline(never)]
fn read_any_number(text: &[u8], at: usize) -> Result<f32, Problem> {
    if let Some((value, _)) = read_decimal(text, at) {
        return Ok(value);
    }
    let end = word_end(text, at);
    parse_number(&text[at..end]).ok_or(Problem::NotANumber(at, end))
}

/// Where the word at `at` ends: at whitespace or the end of `text`.
fn word_end(text: &[u8], at: usize) -> usize {
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
fn parse_rows<S: Sink>(text: &[u8], width: usize, limit: usize, out: &mut S) -> Part {
    let stopped = |rows, problem, end| Part {
        lines: count_lines(text),
        rows,
        problem,
        end,
    };
    if limit == 0 {
        return stopped(0, None, 0);
    }
    let mut rows = 0;
    let mut values = 0; // in the current row
    let mut breaks = 0;
    let mut after_last_break = 0;
    // Whether the byte before the window is whitespace (the text's start counts as such) or a CR.
    let mut after_whitespace = 1;
    let mut after_cr = 0;
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
            if values == width {
                return stopped(rows, Some((rows, Problem::TooMany(base))), base);
            }
            match read_any_number(text, base) {
                Ok(value) => out.push(value),
                Err(problem) => return stopped(rows, Some((rows, problem)), base),
            }
            values += 1;
            base = word_end(text, base);
            (after_whitespace, after_cr) = (1, 0);
            continue;
        }
        let inside = u64::MAX >> (64 - advance);
        let line_ends = (block.lf | block.cr) & inside;
        // LF, CR and CRLF each break a line once.
        let crlf = block.lf & ((block.cr << 1) | after_cr) & inside;
        breaks += (line_ends.count_ones() - crlf.count_ones()) as usize;
        if line_ends != 0 {
            after_last_break = base + 64 - line_ends.leading_zeros() as usize;
        }
        let mut events = (starts & inside) | line_ends;
        while events != 0 {
            let i = events.trailing_zeros() as usize;
            events &= events - 1;
            let at = base + i;
            if line_ends >> i & 1 != 0 {
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
                return stopped(rows, Some((rows, Problem::TooMany(at))), at);
            }
            let length = (block.whitespace >> i).trailing_zeros() as usize;
            let value = match read_short_number(text, at, length, &block, i) {
                Some(value) => value,
                None => match read_any_number(text, at) {
                    Ok(value) => value,
                    Err(problem) => return stopped(rows, Some((rows, problem)), at),
                },
            };
            out.push(value);
            values += 1;
        }
        after_whitespace = (block.whitespace >> (advance - 1)) & 1;
        after_cr = (block.cr >> (advance - 1)) & 1;
        base += advance;
    }
    if values == width {
        rows += 1;
    } else if values != 0 {
        let problem = Problem::TooFew(text.len(), values);
        return stopped(rows, Some((rows, problem)), text.len());
    }
    let since = text[after_last_break..]
        .iter()
        .filter(|&&b| (b & 0xC0) != 0x80)
        .count();
    Part {
        lines: (breaks, since),
        rows,
        problem: None,
        end: text.len(),
    }
}

/// How often `byte` occurs: counted in u8 lanes over 255-byte blocks, so it vectorises.
fn count_byte(text: &[u8], byte: u8) -> usize {
    text.chunks(255)
        .map(|block| block.iter().fold(0u8, |n, &b| n + u8::from(b == byte)) as usize)
        .sum()
}

/// Line breaks in `text` (LF, CRLF or a lone CR each count once) and the number of characters
/// after the last one. Written as whole-slice counts, which the compiler turns into SIMD.
fn count_lines(text: &[u8]) -> (usize, usize) {
    let lf = count_byte(text, b'\n');
    let cr = count_byte(text, b'\r');
    let breaks = if cr == 0 {
        lf
    } else {
        let crlf = text
            .windows(2)
            .filter(|w| w[0] == b'\r' && w[1] == b'\n')
            .count();
        lf + cr - crlf
    };
    let tail = match text.iter().rposition(|&b| b == b'\n' || b == b'\r') {
        Some(i) => &text[i + 1..],
        None => text,
    };
    let since = tail.iter().filter(|&&b| (b & 0xC0) != 0x80).count();
    (breaks, since)
}

/// The last place a chunk may end: after an LF, or after a CR that is not the buffer's last byte
/// (it might be followed by an LF in the next read). `None` if there is none.
pub fn last_line_end(buffer: &[u8]) -> Option<usize> {
    let last = buffer.len().checked_sub(1)?;
    for i in (0..=last).rev() {
        match buffer[i] {
            b'\n' => return Some(i + 1),
            b'\r' if i < last => return Some(i + 1),
            _ => {}
        }
    }
    None
}

/// Collects `frames` rows of `width` values from text fed in line-aligned chunks.
pub struct RowParser {
    source: String,
    frames: u64,
    width: usize,
    frames_line: usize,
    rows: u64,
    data: Vec<f32>,
    /// The line the next chunk starts on, and the column after the text so far.
    line: usize,
    column: usize,
    /// The first ignored row's line, and how many rows are ignored.
    extra: Option<(usize, usize)>,
    /// Line ends seen, for a skeleton without channels.
    line_ends: u64,
    threads: usize,
}

impl RowParser {
    /// The first chunk starts at `(start_line, start_column)`; `room` is the bytes left in the input,
    /// which bounds the allocation whatever `Frames:` says.
    pub fn new(
        source: &str,
        frames: u64,
        width: usize,
        frames_line: usize,
        (start_line, start_column): (usize, usize),
        room: u64,
    ) -> RowParser {
        // Each value takes at least two bytes ("0 "), so no more than this can be in the file.
        let possible = room / 2 + 1;
        let wanted = frames.saturating_mul(width as u64).min(possible);
        let threads = crate::cores().clamp(1, 8);
        let data = Vec::with_capacity(wanted as usize);
        RowParser {
            source: source.to_string(),
            frames,
            width,
            frames_line,
            rows: 0,
            data,
            line: start_line,
            column: start_column,
            extra: None,
            line_ends: 0,
            threads,
        }
    }

    fn error_at(&self, chunk: &[u8], offset: usize, message: String) -> Error {
        let (breaks, since) = count_lines(&chunk[..offset]);
        let column = if breaks == 0 {
            self.column + since
        } else {
            since + 1
        };
        Error::Parse {
            path: self.source.clone(),
            line: self.line + breaks,
            column,
            message,
        }
    }

    fn problem_error(&self, chunk: &[u8], base: usize, row: u64, problem: Problem) -> Error {
        match problem {
            Problem::TooMany(at) => self.error_at(
                chunk,
                base + at,
                format!(
                    "frame {} has more than the {} values the channels need",
                    row + 1,
                    self.width
                ),
            ),
            Problem::TooFew(at, count) => self.error_at(
                chunk,
                base + at,
                format!(
                    "frame {} has {count} values, expected {} (one per channel)",
                    row + 1,
                    self.width
                ),
            ),
            Problem::NotANumber(start, end) => {
                let word = String::from_utf8_lossy(&chunk[base + start..base + end]);
                let word: String = if word.chars().count() > 40 {
                    format!("{}…", word.chars().take(40).collect::<String>())
                } else {
                    word.into_owned()
                };
                self.error_at(
                    chunk,
                    base + start,
                    format!("expected a finite number, found '{word}'"),
                )
            }
        }
    }

    /// Counts the non-blank lines of `chunk` from `from` on as ignored rows.
    fn count_extra(&mut self, chunk: &[u8], from: usize) {
        let mut line = self.line + count_lines(&chunk[..from]).0;
        let mut p = from;
        while p < chunk.len() {
            let b = chunk[p];
            if b == b'\n' || (b == b'\r' && chunk.get(p + 1) != Some(&b'\n')) {
                line += 1;
                p += 1;
            } else if is_blank(b) || b == b'\r' {
                p += 1;
            } else {
                let entry = self.extra.get_or_insert((line, 0));
                entry.1 += 1;
                while p < chunk.len() && !is_line_end(chunk[p]) {
                    p += 1;
                }
            }
        }
    }

    /// Parses on at most `threads` threads (the default is every core).
    pub fn with_threads(mut self, threads: usize) -> RowParser {
        self.threads = threads.clamp(1, 8);
        self
    }

    /// Parses one chunk that ends at a line end (or at the end of the input).
    pub fn feed(&mut self, chunk: &[u8]) -> Result<(), Error> {
        // Nothing to parse (a file that ends right after `Frame Time:`): no parts to split into.
        if chunk.is_empty() {
            return Ok(());
        }
        let (breaks, since) = if self.width == 0 {
            let lines = count_lines(chunk);
            self.line_ends += lines.0 as u64;
            lines
        } else if self.rows >= self.frames {
            self.count_extra(chunk, 0);
            count_lines(chunk)
        } else {
            self.feed_rows(chunk)?
        };
        if breaks == 0 {
            self.column += since;
        } else {
            self.line += breaks;
            self.column = since + 1;
        }
        Ok(())
    }

    /// Parses the rows of a chunk; returns its line count (as `count_lines`).
    ///
    /// Two steps per chunk, each on every core: count the lines of each part (which bounds its
    /// rows), then parse each part straight into its own stretch of the result's spare room. No
    /// value is copied, and the result's pages are first touched by the threads that fill them.
    fn feed_rows(&mut self, chunk: &[u8]) -> Result<(usize, usize), Error> {
        let needed = (self.frames - self.rows).min(usize::MAX as u64) as usize;
        let width = self.width;
        // Split at line ends into one part per thread.
        let parts = if chunk.len() < PARALLEL_MIN {
            1
        } else {
            self.threads
        };
        let mut bounds = vec![0];
        for k in 1..parts {
            let target = chunk.len() * k / parts;
            let from = (*bounds.last().expect("starts with 0")).max(target);
            let breaks_here = |i: usize| {
                chunk[i] == b'\n' || (chunk[i] == b'\r' && chunk.get(i + 1) != Some(&b'\n'))
            };
            match (from..chunk.len()).find(|&i| breaks_here(i)) {
                Some(i) => bounds.push(i + 1),
                None => break,
            }
        }
        bounds.push(chunk.len());
        bounds.dedup();
        let slices: Vec<&[u8]> = bounds.windows(2).map(|w| &chunk[w[0]..w[1]]).collect();
        let on_all_cores = |work: &(dyn Fn(usize) -> Part + Sync)| -> Vec<Part> {
            if slices.len() == 1 {
                return vec![work(0)];
            }
            std::thread::scope(|scope| {
                let handles: Vec<_> = (1..slices.len())
                    .map(|k| scope.spawn(move || work(k)))
                    .collect();
                let mut results = vec![work(0)];
                results.extend(
                    handles
                        .into_iter()
                        .map(|h| h.join().expect("a row parser panicked")),
                );
                results
            })
        };
        // Room per part: a row of `width` values takes at least 2·width − 1 bytes, which bounds
        // the rows without looking. Untouched room costs no memory; only when the rest of the
        // allocation is too small are the lines counted first for an exact bound.
        let mut limits: Vec<usize> = slices
            .iter()
            .map(|part| (part.len() / (2 * width - 1) + 1).min(needed))
            .collect();
        if limits.iter().sum::<usize>() * width > self.data.capacity() - self.data.len() {
            let counted = on_all_cores(&|k| Part {
                lines: count_lines(slices[k]),
                rows: 0,
                problem: None,
                end: 0,
            });
            limits = counted
                .iter()
                .map(|p| (p.lines.0 + 1).min(needed))
                .collect();
        }
        // Step 2: parse each part into its own stretch of spare room.
        let room_needed: usize = limits.iter().sum::<usize>() * width;
        self.data.reserve(room_needed);
        let mut rooms: Vec<&mut [std::mem::MaybeUninit<f32>]> = Vec::new();
        let mut spare = &mut self.data.spare_capacity_mut()[..room_needed];
        for &limit in &limits {
            let (room, rest) = spare.split_at_mut(limit * width);
            rooms.push(room);
            spare = rest;
        }
        let rooms: Vec<std::sync::Mutex<&mut [std::mem::MaybeUninit<f32>]>> =
            rooms.into_iter().map(std::sync::Mutex::new).collect();
        let results = on_all_cores(&|k| {
            let mut room = rooms[k].lock().expect("each room has one user");
            let mut sink = SliceSink {
                room: &mut room,
                written: 0,
            };
            parse_rows(slices[k], width, limits[k], &mut sink)
        });
        let mut lines = (0, 0);
        for part in &results {
            lines = if part.lines.0 == 0 {
                (lines.0, lines.1 + part.lines.1)
            } else {
                (lines.0 + part.lines.0, part.lines.1)
            };
        }
        // Take the parts in order until the frames are complete; a problem counts only in a row
        // that is needed (rows beyond Frames are ignored, whatever they hold). Parts are moved
        // down to follow each other.
        let mut stop: Option<usize> = None;
        let mut filled = 0; // values in the spare room that are in place
        let mut taken_rows = 0;
        let mut room_start = 0;
        let mut problem_found = None;
        for (k, part) in results.iter().enumerate() {
            let remaining = needed - taken_rows;
            if let Some((row, problem)) = part.problem
                && row < remaining
            {
                problem_found = Some((k, row, problem));
                break;
            }
            let take = part.rows.min(remaining);
            if room_start != filled {
                self.data
                    .spare_capacity_mut()
                    .copy_within(room_start..room_start + take * width, filled);
            }
            filled += take * width;
            taken_rows += take;
            room_start += limits[k] * width;
            if taken_rows == needed {
                // Where the last needed row ends.
                let end = if take == part.rows && part.problem.is_none() {
                    part.end
                } else {
                    parse_rows(slices[k], width, take, &mut Vec::new()).end
                };
                stop = Some(bounds[k] + end);
                break;
            }
        }
        // SAFETY: the first `filled` values of the spare room were written by the parts (each
        // wrote its rows' values front to back) and moved down to follow each other above.
        unsafe { self.data.set_len(self.data.len() + filled) };
        self.rows += taken_rows as u64;
        if let Some((k, row, problem)) = problem_found {
            return Err(self.problem_error(chunk, bounds[k], self.rows + row as u64, problem));
        }
        if let Some(stop) = stop {
            self.count_extra(chunk, stop);
        }
        Ok(lines)
    }

    /// Checks that every frame arrived; returns the values and the warnings.
    pub fn finish(self) -> Result<(Vec<f32>, Vec<String>), Error> {
        if self.width == 0 {
            if self.frames > self.line_ends {
                return Err(Error::Parse {
                    path: self.source,
                    line: self.line,
                    column: self.column,
                    message: format!(
                        "Frames: {} (line {}) but only {} lines follow",
                        self.frames, self.frames_line, self.line_ends
                    ),
                });
            }
            return Ok((Vec::new(), Vec::new()));
        }
        if self.rows < self.frames {
            return Err(Error::Parse {
                path: self.source,
                line: self.line,
                column: self.column,
                message: format!(
                    "expected {} frames as Frames: says (line {}), found {}: the file ends",
                    self.frames, self.frames_line, self.rows
                ),
            });
        }
        let mut warnings = Vec::new();
        if let Some((line, count)) = self.extra {
            let rows = if count == 1 { "row" } else { "rows" };
            warnings.push(format!(
                "{count} extra {rows} after the {} announced by Frames: (line {}) ignored, from line {line} on",
                self.frames, self.frames_line
            ));
        }
        Ok((self.data, warnings))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            assert_eq!(part.lines, count_lines(text.as_bytes()));
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
            let values = (start + 3) / 4;
            let part = parse_rows(&text, values + 2, 1, &mut Vec::new());
            match part.problem {
                Some((0, Problem::NotANumber(s, e))) => assert_eq!((s, e), (start, start + 5)),
                other => panic!("at {at}: {other:?}"),
            }
        }
    }
}
