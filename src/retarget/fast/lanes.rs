//! Eight frames side by side: a value per lane, and the loops over lanes the compiler turns
//! into vector instructions. A file of its own, so that the fast pass's parts take them from a
//! sibling rather than from the module above.

/// Frames computed side by side: lane `l` of every value belongs to frame `l` of the batch.
pub(super) const LANES: usize = 8;
pub(super) type Lanes = [f64; LANES];

/// The lanes `f(0), …, f(7)`, by a plain loop: one the compiler vectorises (`std::array::from_fn`
/// it leaves scalar once the body is more than a few operations).
#[inline(always)]
pub(super) fn lanes(mut f: impl FnMut(usize) -> f64) -> Lanes {
    let mut out = [0.0; LANES];
    for (l, value) in out.iter_mut().enumerate() {
        *value = f(l);
    }
    out
}

/// [`lanes`] of a condition.
#[inline(always)]
pub(super) fn mask(mut f: impl FnMut(usize) -> bool) -> [bool; LANES] {
    let mut out = [false; LANES];
    for (l, value) in out.iter_mut().enumerate() {
        *value = f(l);
    }
    out
}
