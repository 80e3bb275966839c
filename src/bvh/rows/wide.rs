//! Eight short numbers read at once with AVX-512: the same arithmetic as
//! [`super::words::read_short_number`], one number per 64-bit lane.
//!
//! Reading a number one at a time takes some forty instructions, most of them for its shape
//! (sign, dot, digit count) and the digits' value; in vector lanes eight of them share each
//! instruction. The row loop only finds where each word starts and queues its first eight bytes.

use super::words::{Block, Problem, Sink, read_any_number};

use std::arch::x86_64::{
    __m512i, _mm_cvtsi64_si128, _mm256_storeu_ps, _mm512_add_epi64, _mm512_and_si512,
    _mm512_andnot_si512, _mm512_castpd_si512, _mm512_castsi512_pd, _mm512_cmpeq_epi8_mask,
    _mm512_cmpeq_epi64_mask, _mm512_cmple_epu64_mask, _mm512_cmplt_epu8_mask, _mm512_cvtepi32_pd,
    _mm512_cvtepi64_epi32, _mm512_cvtepu8_epi64, _mm512_cvtpd_ps, _mm512_loadu_pd,
    _mm512_lzcnt_epi64, _mm512_madd_epi16, _mm512_maddubs_epi16, _mm512_mask_set1_epi64,
    _mm512_mask_sub_epi64, _mm512_mask_xor_epi64, _mm512_maskz_sub_epi64, _mm512_movm_epi8,
    _mm512_mul_epu32, _mm512_mul_pd, _mm512_or_si512, _mm512_permutexvar_pd, _mm512_set1_epi8,
    _mm512_set1_epi16, _mm512_set1_epi32, _mm512_set1_epi64, _mm512_slli_epi64, _mm512_sllv_epi64,
    _mm512_srli_epi64, _mm512_sub_epi8, _mm512_sub_epi64, _mm512_test_epi64_mask,
    _mm512_testn_epi64_mask,
};

/// Whether this CPU can run [`Wide`]. The standard library asks the CPU once and keeps the
/// answer in atomics, without a lock that a child forked mid-question would wait on.
pub(super) fn available() -> bool {
    !super::words::ONE_AT_A_TIME.load(std::sync::atomic::Ordering::Relaxed)
        && std::arch::is_x86_feature_detected!("avx512f")
        && std::arch::is_x86_feature_detected!("avx512bw")
        && std::arch::is_x86_feature_detected!("avx512cd")
}

/// Words waiting to be read, eight at a time. The bodies are gathered in a vector register, not
/// in memory: eight stores read back as one vector load would wait for every store to land.
pub(super) struct Wide {
    /// The first eight bytes of each word's body (after a '-'), zeros past the text's end.
    bodies: __m512i,
    /// Each body's length in bytes (at most 8), one byte per word.
    lengths: u64,
    /// Where each word starts, for the words the lanes refuse.
    starts: [usize; 8],
    /// Bit k: word k has a '-'.
    negative: u8,
    queued: usize,
}

impl Default for Wide {
    fn default() -> Wide {
        Wide {
            // SAFETY: only made where the CPU has AVX-512 (see `available`); a zero vector.
            bodies: unsafe { std::mem::zeroed() },
            lengths: 0,
            starts: [0; 8],
            negative: 0,
            queued: 0,
        }
    }
}

impl Wide {
    /// Queues the word at `at` (`length` bytes; bit `i` of `block`), reading the queue when it
    /// is full. A body longer than eight bytes is no short number: the queue is read and the
    /// word read on its own.
    ///
    /// # Safety
    /// The CPU must have what [`available`] checks.
    #[inline(always)]
    pub(super) unsafe fn number<S: Sink>(
        &mut self,
        text: &[u8],
        at: usize,
        length: usize,
        block: &Block,
        i: usize,
        out: &mut S,
    ) -> Result<(), Problem> {
        let negative = block.minus_at(i);
        let body_length = length - negative;
        if body_length > 8 {
            // SAFETY: passed on from the caller.
            unsafe { self.flush(text, out)? };
            out.push(read_any_number(text, at)?);
            return Ok(());
        }
        let body = at + negative;
        let bytes = match text.get(body..body + 8) {
            Some(bytes) => u64::from_le_bytes(bytes.try_into().expect("eight bytes")),
            None => {
                let mut bytes = [0u8; 8];
                bytes[..text.len() - body].copy_from_slice(&text[body..]);
                u64::from_le_bytes(bytes)
            }
        };
        let k = self.queued;
        // SAFETY: passed on from the caller.
        self.bodies = unsafe { _mm512_mask_set1_epi64(self.bodies, 1 << k, bytes as i64) };
        self.lengths |= (body_length as u64) << (8 * k);
        self.starts[k] = at;
        self.negative |= (negative as u8) << k;
        self.queued = k + 1;
        if self.queued == 8 {
            // SAFETY: passed on from the caller.
            unsafe { self.flush(text, out)? };
        }
        Ok(())
    }

    /// Reads every queued word into `out`, in order; a word the lanes refuse is read on its own,
    /// and the first that is no number is the problem.
    ///
    /// # Safety
    /// The CPU must have what [`available`] checks.
    #[inline(always)]
    pub(super) unsafe fn flush<S: Sink>(
        &mut self,
        text: &[u8],
        out: &mut S,
    ) -> Result<(), Problem> {
        let queued = std::mem::take(&mut self.queued);
        if queued == 0 {
            return Ok(());
        }
        // SAFETY: passed on from the caller.
        let (values, read) = unsafe { read_eight(self.bodies, self.lengths, self.negative) };
        (self.negative, self.lengths) = (0, 0);
        if queued == 8 && read == u8::MAX {
            out.push_eight(&values);
            return Ok(());
        }
        #[allow(clippy::needless_range_loop)]
        for k in 0..queued {
            if read >> k & 1 != 0 {
                out.push(values[k]);
            } else {
                out.push(read_any_number(text, self.starts[k])?);
            }
        }
        Ok(())
    }
}

/// The values of eight bodies (as [`Wide`] holds them) and a bit for each one read: a body of
/// 1 to 7 digits with at most one '.'. Lanes with their bit clear hold nothing of use.
///
/// # Safety
/// The CPU must have AVX-512 F, BW and CD.
#[target_feature(enable = "avx512f,avx512bw,avx512cd")]
fn read_eight(text: __m512i, lengths: u64, negative: u8) -> ([f32; 8], u8) {
    let all = |x: u64| _mm512_set1_epi64(x as i64);
    let length = _mm512_cvtepu8_epi64(_mm_cvtsi64_si128(lengths as i64));
    // The body's bytes: (1 << 8·length) - 1, all eight when the shift reaches 64.
    let body = _mm512_sub_epi64(
        _mm512_sllv_epi64(all(1), _mm512_slli_epi64(length, 3)),
        all(1),
    );
    let zero = _mm512_set1_epi8(b'0' as i8);
    let digits = _mm512_movm_epi8(_mm512_cmplt_epu8_mask(
        _mm512_sub_epi8(text, zero),
        _mm512_set1_epi8(10),
    ));
    let dot_bytes = _mm512_movm_epi8(_mm512_cmpeq_epi8_mask(text, _mm512_set1_epi8(b'.' as i8)));
    let shaped = _mm512_cmpeq_epi64_mask(
        _mm512_and_si512(_mm512_or_si512(digits, dot_bytes), body),
        body,
    );
    // The dots of the body, one bit each (the low bit of its byte).
    let dots = _mm512_and_si512(
        _mm512_and_si512(dot_bytes, body),
        all(0x0101_0101_0101_0101),
    );
    let below_dot = _mm512_sub_epi64(dots, all(1)); // every byte without a dot
    let one_dot_at_most = _mm512_testn_epi64_mask(dots, below_dot);
    let has_dot = _mm512_test_epi64_mask(dots, dots);
    let count = _mm512_mask_sub_epi64(length, has_dot, length, all(1));
    let count_fits = _mm512_cmple_epu64_mask(_mm512_sub_epi64(count, all(1)), all(6));
    // Digits after the dot: length - 1 - the dot's byte.
    let dot_byte = _mm512_srli_epi64(_mm512_sub_epi64(all(63), _mm512_lzcnt_epi64(dots)), 3);
    let scale = _mm512_maskz_sub_epi64(has_dot, _mm512_sub_epi64(length, all(1)), dot_byte);
    // The dot taken out (the bytes after it move down one), then the digits moved to the top
    // bytes, the most significant lowest, as `eight_digits` takes them.
    let joined = _mm512_or_si512(
        _mm512_and_si512(text, below_dot),
        _mm512_andnot_si512(below_dot, _mm512_srli_epi64(text, 8)),
    );
    let moved = _mm512_sllv_epi64(
        _mm512_sub_epi8(joined, zero),
        _mm512_slli_epi64(_mm512_sub_epi64(all(8), count), 3),
    );
    // Pairs (10·a + b), fours (100·ab + cd), then the eight (10000·abcd + efgh).
    let pairs = _mm512_maddubs_epi16(moved, _mm512_set1_epi16(0x010A));
    let fours = _mm512_madd_epi16(pairs, _mm512_set1_epi32(0x0001_0064));
    let whole = _mm512_add_epi64(
        _mm512_mul_epu32(fours, all(10_000)),
        _mm512_srli_epi64(fours, 32),
    );
    // As `short_decimal`: the integer (below 10⁷, so exact) times the rounded 10^-scale, then a
    // float; the sign flipped before rounding, which rounds symmetrically.
    let whole = _mm512_cvtepi32_pd(_mm512_cvtepi64_epi32(whole));
    // SAFETY: the table holds eight doubles.
    let inverse = unsafe { _mm512_loadu_pd(super::words::INV_POW10_F64.as_ptr()) };
    let product = _mm512_mul_pd(whole, _mm512_permutexvar_pd(scale, inverse));
    let signed = _mm512_mask_xor_epi64(
        _mm512_castpd_si512(product),
        negative,
        _mm512_castpd_si512(product),
        all(1 << 63),
    );
    let mut values = [0f32; 8];
    // SAFETY: the store writes the 32 bytes of `values`.
    unsafe {
        _mm256_storeu_ps(
            values.as_mut_ptr(),
            _mm512_cvtpd_ps(_mm512_castsi512_pd(signed)),
        )
    };
    (values, shaped & one_dot_at_most & count_fits)
}
