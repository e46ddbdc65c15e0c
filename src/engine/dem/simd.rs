//! Running a kernel's loops compiled for the CPU's vector extension (AVX2, detected at run
//! time), one place for the particle pass and the candidate scan.

/// Run `f` compiled for AVX2 where the CPU has it (its loops over coordinates or pairs then
/// take four at a time; IEEE operations lane by lane, no contraction: the same bits on every
/// path). Give the closure `#[inline(always)]` so that its body is compiled inside the AVX2
/// function rather than called from it.
#[inline(always)]
pub fn with_avx2<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    {
        #[target_feature(enable = "avx2")]
        fn avx2<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above)
            return unsafe { avx2(f) };
        }
    }
    f()
}
