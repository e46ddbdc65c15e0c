//! Cache prefetching: ask the CPU to start loading a record before it is needed.

/// Ask the CPU to start loading element `index` of `records` into cache (no effect where
/// unsupported), without a bounds check: the address is only computed (with wrapping
/// arithmetic) and handed to the hint, never read, so an index past the end is harmless.
#[inline(always)]
pub(crate) fn prefetch_at<T>(records: &[T], index: usize) {
    prefetch_address(records.as_ptr().wrapping_add(index));
}

#[inline(always)]
fn prefetch_address<T>(address: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: prefetching is a hint; it never faults, whatever the address, and SSE is
        // part of the x86_64 baseline.
        #[allow(unused_unsafe)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(address.cast::<i8>())
        };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = address;
}
