//! What the processor can do, detected at run time: the kernels for positions (the
//! plan's patches, the limit surface's bicubic patches) have an AVX2 + FMA version, which
//! the default x86-64 target does not enable.

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
