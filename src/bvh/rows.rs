//! The MOTION rows, read in chunks that end at line ends, the chunks parsed on every core.
//!
//! C++: the row loop at the end of `BVH::loadFile`. The article reads `Frames` rows with fixed
//! strides from a buffer holding the whole file. Here the rows arrive in pieces (a file is never
//! held whole), the cores take the pieces in turn and parse them without a `String` per number,
//! and every error still names its exact line and column.

use crate::error::Error;
use std::io::Read;

/// Bytes of MOTION text handed to the parser at a time.
pub const CHUNK: usize = 1 << 20;

/// The smallest chunk: a small input is cut into about eight chunks, but not smaller ones.
const SMALLEST_CHUNK: usize = 64 * 1024;

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

/// One bit per byte of 64 bytes of text (bit i for byte i): whitespace, LF or CR, digits, '.', '-'.
#[derive(Clone, Copy, Default)]
struct Block {
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
        base += advance;
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

/// The result's spare room, written by several threads at once (each in its own stretch).
#[derive(Clone, Copy)]
struct Room(*mut std::mem::MaybeUninit<f32>);

impl Room {
    /// # Safety
    /// `start + length` is within the capacity, and no one else uses that stretch meanwhile.
    #[allow(clippy::mut_from_ref)]
    unsafe fn stretch(&self, start: usize, length: usize) -> &mut [std::mem::MaybeUninit<f32>] {
        // SAFETY: as the caller promises.
        unsafe { std::slice::from_raw_parts_mut(self.0.add(start), length) }
    }
}

// SAFETY: the threads write disjoint stretches; see `RowParser::feed_placed`.
unsafe impl Send for Room {}
unsafe impl Sync for Room {}

/// A chunk handed to a thread: its text is in the thread's buffer.
struct Job {
    index: usize,
    length: usize,
    /// Where its text starts.
    line: usize,
    column: usize,
    /// The row its rows go to, how many lines it has (at most that many rows), and how many rows
    /// it may write (fewer only in the last chunk, at the end of the room).
    placed: usize,
    bound: usize,
    limit: usize,
}

/// What a thread made of a chunk.
struct Chunk {
    index: usize,
    placed: usize,
    rows: usize,
    /// Values written from its place on (its rows', and part of a row with a problem).
    written: usize,
    problem: Option<Located>,
    /// The text beyond the rows the chunk could write, with its line and column.
    rest: Option<(Vec<u8>, usize, usize)>,
}

/// The reading side shared by the threads of `RowParser::feed_placed`.
struct Stream<'a> {
    input: &'a mut (dyn Read + Send),
    /// Text read after the last chunk handed out.
    carry: Vec<u8>,
    end_of_input: bool,
    next_index: usize,
    /// Bytes to read at a time.
    chunk: usize,
    /// Rows placed so far, and the room for rows.
    placed: usize,
    room_rows: usize,
    /// Where the next chunk starts.
    line: usize,
    column: usize,
    /// No more chunks: a problem was found, the room is used up, or the input ended.
    stop: bool,
    error: Option<std::io::Error>,
}

impl Stream<'_> {
    /// Reads the next chunk into `buffer`: the carried text, then up to a chunk's worth, cut
    /// after its last line end.
    fn next_chunk(&mut self, buffer: &mut Vec<u8>) -> Option<Job> {
        if self.stop {
            return None;
        }
        let mut filled = self.carry.len();
        if buffer.len() < filled * 2 {
            buffer.resize(filled * 2, 0);
        }
        buffer[..filled].copy_from_slice(&self.carry);
        let cut = loop {
            while !self.end_of_input && filled < self.chunk.min(buffer.len()) {
                match self.input.read(&mut buffer[filled..]) {
                    Ok(0) => self.end_of_input = true,
                    Ok(read) => filled += read,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        self.error = Some(e);
                        self.stop = true;
                        return None;
                    }
                }
            }
            if self.end_of_input {
                break filled;
            }
            match last_line_end(&buffer[..filled]) {
                Some(cut) => break cut,
                None => buffer.resize(buffer.len() * 2, 0),
            }
        };
        self.carry.clear();
        self.carry.extend_from_slice(&buffer[cut..filled]);
        if cut == 0 {
            self.stop = true;
            return None;
        }
        let (breaks, since) = count_lines(&buffer[..cut]);
        let bound = breaks + usize::from(since > 0);
        let job = Job {
            index: self.next_index,
            length: cut,
            line: self.line,
            column: self.column,
            placed: self.placed,
            bound,
            limit: bound.min(self.room_rows - self.placed),
        };
        self.next_index += 1;
        self.placed += job.limit;
        (self.line, self.column) = advance((self.line, self.column), (breaks, since));
        self.stop = self.placed == self.room_rows || self.end_of_input;
        Some(job)
    }
}

/// Takes the lock spinning: it is held only to read a chunk, and a thread put to sleep here
/// can take long to wake.
fn lock<T>(mutex: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    let mut spins = 0u32;
    loop {
        match mutex.try_lock() {
            Ok(guard) => return guard,
            Err(std::sync::TryLockError::Poisoned(poisoned)) => return poisoned.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => {
                spins += 1;
                if spins.is_multiple_of(1024) {
                    std::thread::yield_now();
                } else {
                    std::hint::spin_loop();
                }
            }
        }
    }
}

/// The line and column after text with `breaks` line breaks and `since` characters after the
/// last one, when the text starts at `(line, column)`.
fn advance((line, column): (usize, usize), (breaks, since): (usize, usize)) -> (usize, usize) {
    if breaks == 0 {
        (line, column + since)
    } else {
        (line + breaks, since + 1)
    }
}

/// A problem found in a chunk, placed in the file but not yet numbered: a chunk parsed on another
/// thread does not know how many rows the chunks before it hold.
struct Located {
    line: usize,
    column: usize,
    /// The row it is in, counted from the chunk's first row.
    row_in_chunk: usize,
    /// The frame's problem (its value count), or a word that is not a number.
    what: Result<Option<usize>, String>,
}

impl Located {
    /// Where `problem`, in row `row_in_chunk` of `chunk` (which starts at `start`), is in the file.
    fn new(chunk: &[u8], start: (usize, usize), row_in_chunk: usize, problem: Problem) -> Located {
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
    /// the MOTION section; `width` values make a row.
    fn into_error(self, source: &str, width: usize, first_row: usize) -> Error {
        let frame = first_row + self.row_in_chunk + 1;
        let message = match self.what {
            Ok(None) => format!("frame {frame} has more than the {width} values the channels need"),
            Ok(Some(count)) => {
                format!("frame {frame} has {count} values, expected {width} (one per channel)")
            }
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
    /// Bytes read at a time: a megabyte, less for a small input (so that it is still split).
    chunk: usize,
    /// Bytes of input after the rows' start.
    input_left: u64,
    /// Rows moved down after the parallel pass (only blank lines should cause any).
    rows_moved: usize,
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
            chunk: (room / 8)
                .clamp(SMALLEST_CHUNK as u64, CHUNK as u64)
                .min(room + 1) as usize,
            input_left: room,
            rows_moved: 0,
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
        let lines = count_lines(chunk);
        if self.width == 0 {
            self.line_ends += lines.0 as u64;
        } else if self.rows >= self.frames {
            self.count_extra(chunk, 0);
        } else {
            self.feed_rows(chunk)?;
        }
        (self.line, self.column) = advance((self.line, self.column), lines);
        Ok(())
    }

    /// Parses the rows of a chunk in order. This reads what the parallel pass leaves (see
    /// [`RowParser::feed_all`]), usually nothing.
    fn feed_rows(&mut self, chunk: &[u8]) -> Result<(), Error> {
        let needed = (self.frames - self.rows).min(usize::MAX as u64) as usize;
        let part = parse_rows(chunk, self.width, needed, &mut self.data);
        let first_row = self.rows;
        self.rows += part.rows as u64;
        if let Some((row, problem)) = part.problem {
            let located = Located::new(chunk, (self.line, self.column), row, problem);
            return Err(located.into_error(&self.source, self.width, first_row as usize));
        }
        if part.rows == needed {
            self.count_extra(chunk, part.end);
        }
        Ok(())
    }

    /// Reads and parses all the rows: `carry` (rows already read) and then everything `input`
    /// holds. `io_error` names the input in a read error.
    ///
    /// Every thread runs the same loop: under a lock it reads the next chunk (cut at a line end)
    /// and counts its lines, which places the chunk's rows in the result (each line at most one
    /// row); then it parses the chunk into that place while another thread reads. No thread waits
    /// for another at every chunk, and the reading overlaps the parsing. What the placing cannot
    /// cover (rows after `Frames`, or a file with blank lines that used up the room) is read
    /// after them in order.
    pub fn feed_all(
        &mut self,
        carry: &[u8],
        input: &mut (dyn Read + Send),
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(), Error> {
        let mut carry = carry.to_vec();
        if self.width > 0 && self.rows == 0 {
            let (rest, after) = self.feed_placed(carry, input, io_error)?;
            carry = after;
            if let Some((text, line, column)) = rest {
                (self.line, self.column) = (line, column);
                self.feed(&text)?;
            }
        }
        self.feed_in_order(carry, input, io_error)
    }

    /// The parallel pass of [`RowParser::feed_all`]: the rows placed by line counts. Returns the
    /// text left in the last chunk (beyond the rows placed, with its line and column) and the
    /// text read after the last chunk.
    #[allow(clippy::type_complexity)]
    fn feed_placed(
        &mut self,
        carry: Vec<u8>,
        input: &mut (dyn Read + Send),
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(Option<(Vec<u8>, usize, usize)>, Vec<u8>), Error> {
        let width = self.width;
        let room_rows =
            (self.frames.min(usize::MAX as u64) as usize).min(self.data.capacity() / width);
        let stream = std::sync::Mutex::new(Stream {
            input,
            carry,
            end_of_input: false,
            next_index: 0,
            chunk: self.chunk,
            placed: 0,
            room_rows,
            line: self.line,
            column: self.column,
            stop: room_rows == 0,
            error: None,
        });
        let room = Room(self.data.spare_capacity_mut().as_mut_ptr());
        let done = std::sync::Mutex::new(Vec::<Chunk>::new());
        let chunk_size = self.chunk;
        let work = || {
            let mut buffer = vec![0u8; chunk_size + chunk_size / 4];
            loop {
                let Some(job) = lock(&stream).next_chunk(&mut buffer) else {
                    return;
                };
                let text = &buffer[..job.length];
                // SAFETY: each job's stretch starts where the previous job's ends and all of them
                // end by `room_rows`, inside the capacity; the result is not touched until every
                // worker has ended.
                let stretch = unsafe { room.stretch(job.placed * width, job.limit * width) };
                let mut sink = SliceSink {
                    room: stretch,
                    written: 0,
                };
                let part = parse_rows(text, width, job.limit, &mut sink);
                let mut chunk = Chunk {
                    index: job.index,
                    placed: job.placed,
                    rows: part.rows,
                    written: sink.written,
                    problem: None,
                    rest: None,
                };
                let start = (job.line, job.column);
                if let Some((row, problem)) = part.problem {
                    chunk.problem = Some(Located::new(text, start, row, problem));
                    lock(&stream).stop = true;
                } else if part.rows == job.limit && job.limit < job.bound {
                    let (line, column) = advance(start, count_lines(&text[..part.end]));
                    chunk.rest = Some((text[part.end..].to_vec(), line, column));
                }
                lock(&done).push(chunk);
            }
        };
        // No more threads than chunks.
        let threads = self
            .threads
            .min(1 + (self.input_left / self.chunk as u64) as usize);
        if threads <= 1 {
            work();
        } else {
            std::thread::scope(|scope| {
                for _ in 1..threads {
                    scope.spawn(work);
                }
                work();
            });
        }
        let stream = stream.into_inner().unwrap_or_else(|e| e.into_inner());
        if let Some(error) = stream.error {
            return Err(io_error(error));
        }
        let mut chunks = done.into_inner().unwrap_or_else(|e| e.into_inner());
        chunks.sort_by_key(|c| c.index);
        // In file order: the first problem wins; rows placed after blank lines move down.
        let mut rows = 0;
        let mut rest = None;
        for chunk in chunks {
            // Every chunk before this one has ended, so `rows` is where its rows begin.
            if let Some(problem) = chunk.problem {
                return Err(problem.into_error(&self.source, width, rows));
            }
            // What `set_len` below relies on: the chunk's rows were all written.
            debug_assert!(chunk.written >= chunk.rows * width, "chunk {}", chunk.index);
            if chunk.placed != rows {
                self.rows_moved += chunk.rows;
                self.data.spare_capacity_mut().copy_within(
                    chunk.placed * width..(chunk.placed + chunk.rows) * width,
                    rows * width,
                );
            }
            rows += chunk.rows;
            rest = chunk.rest.or(rest);
        }
        debug_assert!(rows * width <= self.data.capacity());
        // SAFETY: the first `rows` rows of the spare room were written by the workers (each
        // wrote its rows front to back from its place) and moved down to follow each other.
        unsafe { self.data.set_len(rows * width) };
        self.rows = rows as u64;
        (self.line, self.column) = (stream.line, stream.column);
        Ok((rest, stream.carry))
    }

    /// The rest of the rows in order, one chunk at a time.
    fn feed_in_order(
        &mut self,
        carry: Vec<u8>,
        input: &mut (dyn Read + Send),
        io_error: &dyn Fn(std::io::Error) -> Error,
    ) -> Result<(), Error> {
        let mut buffer = carry;
        let mut filled = buffer.len();
        buffer.resize((self.chunk + self.chunk / 4).max(filled * 2), 0);
        loop {
            let mut end_of_input = false;
            while filled < self.chunk.min(buffer.len()) {
                let read = input.read(&mut buffer[filled..]).map_err(io_error)?;
                if read == 0 {
                    end_of_input = true;
                    break;
                }
                filled += read;
            }
            if end_of_input {
                return self.feed(&buffer[..filled]);
            }
            match last_line_end(&buffer[..filled]) {
                Some(cut) => {
                    self.feed(&buffer[..cut])?;
                    buffer.copy_within(cut..filled, 0);
                    filled -= cut;
                }
                // A line longer than the buffer: make room and read on.
                None => buffer.resize(buffer.len() * 2, 0),
            }
        }
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

    /// Rows are placed by counting lines, so without blank lines none has to move afterwards.
    #[test]
    fn rows_without_blank_lines_are_parsed_in_place() {
        for newline in ["\n", "\r\n", "\r"] {
            let row = format!("1 2.5 -3{newline}");
            let rows = row.repeat(4 * SMALLEST_CHUNK / row.len());
            let frames = (4 * SMALLEST_CHUNK / row.len()) as u64;
            let mut parser =
                RowParser::new("t.bvh", frames, 3, 1, (2, 1), rows.len() as u64).with_threads(2);
            parser.chunk = SMALLEST_CHUNK;
            parser.input_left = rows.len() as u64;
            parser
                .feed_all(&[], &mut rows.as_bytes(), &|e| {
                    Error::io(std::path::Path::new("t"), e)
                })
                .unwrap();
            assert_eq!(parser.rows, frames);
            assert_eq!(parser.rows_moved, 0, "{newline:?}");
            let (data, _) = parser.finish().unwrap();
            assert_eq!(&data[data.len() - 3..], [1.0, 2.5, -3.0]);
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
