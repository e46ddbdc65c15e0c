//! The pairs a neighbour search keeps for the square root: the first pass of the contact test
//! (no root) writes every pair met and keeps it by advancing a count, without a branch; the
//! second pass reads the kept ones in order.

use super::motion::PairApproach;
use std::mem::MaybeUninit;

/// Pairs kept by a search's first pass: (contact equation, partner, partner's collision
/// counter), in the order they were met.
pub(crate) struct KeptPairs {
    /// left uninitialised (zeroing it cost a memset per search); only `..len` is ever read
    entries: [MaybeUninit<(PairApproach, u32, u32)>; KeptPairs::CAPACITY],
    len: usize,
}

impl KeptPairs {
    const CAPACITY: usize = 32;

    #[inline(always)]
    pub(crate) fn new() -> Self {
        KeptPairs {
            entries: [const { MaybeUninit::uninit() }; Self::CAPACITY],
            len: 0,
        }
    }

    /// Write the pair and keep it if `keep` (without a branch); true when the buffer is full.
    #[inline(always)]
    pub(crate) fn push_if(
        &mut self,
        keep: bool,
        pair: PairApproach,
        partner: u32,
        collisions: u32,
    ) -> bool {
        self.entries[self.len].write((pair, partner, collisions));
        self.len += keep as usize;
        self.len == Self::CAPACITY
    }

    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    /// The kept pairs, in order.
    #[inline(always)]
    pub(crate) fn pairs(&self) -> impl Iterator<Item = (PairApproach, u32, u32)> + '_ {
        self.entries[..self.len].iter().map(|entry| {
            // SAFETY: entries 0..len were written by push_if (the entry at `len` is written
            // before `len` can move past it)
            unsafe { entry.assume_init_read() }
        })
    }
}
