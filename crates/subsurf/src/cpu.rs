//! What the processor can do, detected at run time: the kernels for positions (the
//! plan's patches, the limit surface's bicubic patches) have an AVX2 + FMA version, which
//! the default x86-64 target does not enable. And the point loads and stores those
//! kernels share.

/// Whether the processor has AVX2 and FMA (detected once and cached by the standard
/// library; always `false` off x86-64).
#[inline]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether the processor has AVX-512F (and AVX2 and FMA, which every processor with it
/// has; detected once and cached by the standard library; always `false` off x86-64).
#[inline]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn has_avx512f() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx512f") && has_avx2_fma()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The three `f64` at `p` in the low lanes of a 256-bit vector, the fourth zero: one
/// masked load, which does not touch the memory past the third.
///
/// # Safety
/// `p` points to three `f64`; the processor has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(crate) unsafe fn load3(p: *const f64) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    // SAFETY: the mask loads the three `f64` (the caller's).
    unsafe { _mm256_maskload_pd(p, _mm256_setr_epi64x(-1, -1, -1, 0)) }
}

/// Writes the low three lanes of `v` to the three `f64` at `p`, straight from the
/// register (two stores). Through an array on the stack, a later load could wait on that
/// store wherever its address had the same low 12 bits as the array's (4K aliasing), so
/// the time would depend on where the stack happens to lie (BENCHMARKS.md, "Processes
/// that are slow from where their stack lies").
///
/// # Safety
/// `p` points to three `f64`; the processor has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(crate) unsafe fn store3(p: *mut f64, v: std::arch::x86_64::__m256d) {
    use std::arch::x86_64::*;
    // SAFETY: three `f64` (the caller's).
    unsafe {
        _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
        _mm_store_sd(p.add(2), _mm256_extractf128_pd::<1>(v));
    }
}
