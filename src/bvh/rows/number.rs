//! Reading one number as the article's `(float)atof` does, exactly and fast.

use crate::io::lines::is_line_end;

pub(super) fn is_blank(byte: u8) -> bool {
    matches!(byte, b' ' | b'\t' | 0x0B | 0x0C)
}

pub(super) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// 10ᵏ as integers, for joining a fraction's digits to the integer part.
pub(super) const POW10_INT: [u64; 8] = [1, 10, 100, 1000, 10_000, 100_000, 1_000_000, 10_000_000];

/// 10⁻ᵏ, rounded to the nearest double.
pub(super) const INV_POW10: [f64; 23] = [
    1e0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14,
    1e-15, 1e-16, 1e-17, 1e-18, 1e-19, 1e-20, 1e-21, 1e-22,
];

/// `mantissa / 10^scale` rounded to a float exactly as rounding the correctly rounded double
/// would (`(float)atof`), for `mantissa < 2^53`, `scale ≤ 22`. A multiplication by the rounded
/// reciprocal lands within two units in the last place of the exact quotient; rounding to a float
/// can only differ from the exact division when that double sits next to the midpoint between two
/// floats, which its low 29 bits show. Only then is the (slow) division done.
#[inline]
pub(super) fn decimal_to_f32(mantissa: u64, scale: usize, negative: bool) -> f32 {
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
pub(super) fn digit_run(text: &[u8], p: usize) -> Option<(u64, usize)> {
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
/// float; `None` unless the whole word is a finite number. The usual shapes go through
/// `read_decimal`; anything else (long mantissas, exponents past 10^±22 from the mantissa)
/// through the standard library's parser, which gives the same answer.
pub fn parse_number(word: &[u8]) -> Option<f32> {
    if let Some((value, end)) = read_decimal(word, 0)
        && end == word.len()
    {
        return Some(value);
    }
    let value = std::str::from_utf8(word).ok()?.parse::<f64>().ok()? as f32;
    value.is_finite().then_some(value)
}

/// The usual MOTION number at `p`, `[-+]digits[.digits][(e|E)[-+]digits]` with 1 to 15 mantissa
/// digits and followed by a blank, a line end or the end of `text`: its value (rounded exactly
/// as `(float)atof` rounds, by Clinger's fast path: the mantissa is exact below 2^53 and the
/// power of ten, at most 10^22, is exact too, so one multiplication or division rounds once)
/// and where it ends. `None` for anything else, which the caller hands to the standard parser.
#[inline(always)]
pub(super) fn read_decimal(text: &[u8], mut p: usize) -> Option<(f32, usize)> {
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
    // Exporters that write `%g` (Bandai-Namco's, Blender's for tiny values) add an exponent.
    let mut exponent: i64 = 0;
    if matches!(text.get(p), Some(b'e' | b'E')) {
        p += 1;
        let negative_exponent = text.get(p) == Some(&b'-');
        p += usize::from(negative_exponent || text.get(p) == Some(&b'+'));
        let exponent_start = p;
        while let Some(&c) = text.get(p).filter(|c| c.is_ascii_digit()) {
            // Past 10^4 the value is far outside a float either way: the slow path decides.
            exponent = (exponent * 10 + i64::from(c - b'0')).min(10_000);
            p += 1;
        }
        if p == exponent_start {
            return None;
        }
        if negative_exponent {
            exponent = -exponent;
        }
    }
    let ends = p == text.len() || is_blank(text[p]) || is_line_end(text[p]);
    if !ends || digits == 0 || digits > 15 {
        return None;
    }
    let power = exponent - scale as i64;
    let value = match power {
        0..=22 => {
            // Both factors exact (the mantissa below 2^53): the product rounds once.
            let magnitude = (mantissa as i64 as f64 * POW10[power as usize]) as f32;
            if negative { -magnitude } else { magnitude }
        }
        -22..=-1 => decimal_to_f32(mantissa, (-power) as usize, negative),
        _ => return None,
    };
    Some((value, p))
}

/// The value of eight decimal digits, one per byte, the most significant in the lowest byte.
#[inline(always)]
pub(super) fn eight_digits(digits: u64) -> u64 {
    // Pairs, then quads, then the whole, each in one multiply-and-shift step.
    let value = digits.wrapping_mul(10).wrapping_add(digits >> 8);
    let pairs = value & 0x0000_00FF_0000_00FF;
    let others = (value >> 16) & 0x0000_00FF_0000_00FF;
    (pairs
        .wrapping_mul(0x000F_4240_0000_0064)
        .wrapping_add(others.wrapping_mul(0x0000_2710_0000_0001)))
        >> 32
}
