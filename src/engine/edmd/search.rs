//! Neighbour-search helpers: partners collected in batches, and cache prefetching, so that
//! the memory latency of many partner records overlaps instead of adding up.

use super::neighbours::Image;

/// Partners of a neighbour search collected before they are tested (see `scan_cells`), each
/// with the periodic image in which it is near.
pub(crate) struct PartnerBatch {
    ids: [u32; PartnerBatch::CAPACITY],
    images: [Image; PartnerBatch::CAPACITY],
    len: usize,
}

impl PartnerBatch {
    const CAPACITY: usize = 32;

    #[inline(always)]
    pub(crate) fn new() -> Self {
        PartnerBatch {
            ids: [0; Self::CAPACITY],
            images: [Image::SAME; Self::CAPACITY],
            len: 0,
        }
    }

    /// Add a partner; true when the batch is full.
    #[inline(always)]
    pub(crate) fn push(&mut self, id: u32, image: Image) -> bool {
        self.ids[self.len] = id;
        self.images[self.len] = image;
        self.len += 1;
        self.len == Self::CAPACITY
    }

    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    #[inline(always)]
    pub(crate) fn partners(&self) -> impl Iterator<Item = (u32, Image)> + '_ {
        self.ids[..self.len]
            .iter()
            .copied()
            .zip(self.images[..self.len].iter().copied())
    }
}

/// Ask the CPU to start loading `record` into cache (no effect where unsupported).
#[inline(always)]
pub(crate) fn prefetch<T>(record: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: prefetching is a hint; it never faults, whatever the address, and SSE is
        // part of the x86_64 baseline.
        #[allow(unused_unsafe)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>((record as *const T).cast::<i8>())
        };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = record;
}
