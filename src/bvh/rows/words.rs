//! What the two number readers of the row engine share (the one-at-a-time loop in `scan`
//! and the eight-lane `wide`): the problems a row can have, where values go, the 64-byte
//! blocks of classified text, and the reading of one number.

use super::number::{decimal_to_f32, eight_digits, is_blank, parse_number, read_decimal};
use crate::io::lines::is_line_end;

/// Set: the rows go through the one-at-a-time reader even where the CPU has AVX-512, as on a
/// machine without it (`bvhview-bench --no-avx512` measures that reader here). Same values.
pub(super) static ONE_AT_A_TIME: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

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
    pub(super) fn start(self) -> usize {
        match self {
            Problem::TooMany(at) | Problem::TooFew(at, _) | Problem::NotANumber(at, _) => at,
        }
    }
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
    pub(super) whitespace: u64,
    pub(super) line_end: u64,
    pub(super) digit: u64,
    pub(super) dot: u64,
    pub(super) minus: u64,
}

impl Block {
    /// The masks of `text[..64]`; a shorter text is padded with spaces.
    #[inline(always)]
    pub(super) fn of(text: &[u8]) -> Block {
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
        use std::arch::x86_64::{
            __m128i, _mm_add_epi8, _mm_cmpeq_epi8, _mm_cmplt_epi8, _mm_loadu_si128,
            _mm_movemask_epi8, _mm_or_si128, _mm_set1_epi8,
        };
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

/// The value of `word`, a word of up to 10 bytes ('-', then up to 7 digits with at most one
/// '.', or 8 digits and one '.') whose masks within its block are given from its first byte on;
/// `None` for any other word.
///
/// The value is [`short_decimal`] of the word's digits and scale, with the sign (for eight
/// digits, `decimal_to_f32`).
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
    if body & body_mask != body_mask || dots & dots.wrapping_sub(1) != 0 {
        return None;
    }
    if count == 8 && dots != 0 {
        // Eight digits and a dot, nine bytes (`84.730760`: Xsens's and other six-decimal
        // files): the ninth byte joins the eight, and the quotient is rounded as `atof` rounds
        // it by `decimal_to_f32` (`short_decimal`'s proof covers seven digits).
        let ninth = *text.get(p + 8)?;
        let word = u64::from_le_bytes(*bytes);
        let dot_at = dots.trailing_zeros() as usize; // 0 to 8
        let joined = if dot_at == 8 {
            word
        } else {
            let before = (1u64 << (8 * dot_at)) - 1;
            (word & before) | ((word >> 8) & !before) | (u64::from(ninth) << 56)
        };
        let digits = eight_digits(joined.wrapping_sub(0x30 * LOW));
        return Some(decimal_to_f32(digits, 8 - dot_at, negative != 0));
    }
    if !(1..=7).contains(&count) {
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

/// A number in any form `(float)atof` takes, or the problem with the word at `at`: the words the
/// eight-byte path leaves (exponents, long ones), common in some files, so not marked cold.
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
