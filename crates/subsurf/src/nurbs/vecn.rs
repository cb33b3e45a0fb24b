//! Small helpers on `[f64; D]` points and stack scratch buffers (private).

/// `(1 − a) p + a q`, componentwise; `a = 0` returns `p` exactly.
#[inline]
pub(crate) fn lerp<const D: usize>(p: &[f64; D], q: &[f64; D], a: f64) -> [f64; D] {
    if a == 0.0 {
        return *p;
    }
    let b = 1.0 - a;
    std::array::from_fn(|c| b * p[c] + a * q[c])
}

/// `acc + s p`, componentwise.
#[inline]
pub(crate) fn axpy<const D: usize>(acc: &mut [f64; D], s: f64, p: &[f64; D]) {
    for c in 0..D {
        acc[c] += s * p[c];
    }
}

/// Whether every coordinate is finite.
#[inline]
pub(crate) fn is_finite<const D: usize>(p: &[f64; D]) -> bool {
    p.iter().all(|c| c.is_finite())
}

/// Runs `f` on a scratch slice of `len` copies of `zero`: on the stack for up to 32 entries
/// (every degree in practice), else on the heap.
#[inline]
pub(crate) fn with_scratch<T: Copy, R>(len: usize, zero: T, f: impl FnOnce(&mut [T]) -> R) -> R {
    if len <= 32 {
        let mut a = [zero; 32];
        f(&mut a[..len])
    } else {
        let mut v = vec![zero; len];
        f(&mut v)
    }
}
