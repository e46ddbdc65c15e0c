//! What a neighbour search keeps of the candidates it meets: every candidate is written and
//! kept by advancing a count, without a branch (whether a candidate is kept is a coin flip);
//! the kept ones are then read in order. The contact test's first pass (no square root) keeps
//! pairs for the second; a list renewal keeps the anchors within reach.

use super::motion::PairApproach;
use super::neighbours::Neighbour;
use std::mem::MaybeUninit;

/// Up to `CAPACITY` kept candidates, in the order they were met. A local buffer (its count
/// lives in a register, not behind a `Vec`'s length in memory), emptied by its owner when full.
pub(crate) struct Kept<T: Copy, const CAPACITY: usize> {
    /// left uninitialised (zeroing it cost a memset per search); only `..len` is ever read
    entries: [MaybeUninit<T>; CAPACITY],
    len: usize,
}

/// Pairs kept by a search's first pass: (contact equation, partner, partner's collision
/// counter).
pub(crate) type KeptPairs = Kept<(PairApproach, u32, u32), 32>;

/// Neighbours kept by a list renewal's test of the anchors around it.
pub(crate) type KeptNeighbours = Kept<Neighbour, 64>;

impl<T: Copy, const CAPACITY: usize> Kept<T, CAPACITY> {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Kept {
            entries: [const { MaybeUninit::uninit() }; CAPACITY],
            len: 0,
        }
    }

    /// Write `entry` and keep it if `keep` (without a branch); true when the buffer is full.
    #[inline(always)]
    pub(crate) fn push_if(&mut self, keep: bool, entry: T) -> bool {
        debug_assert!(self.len < CAPACITY);
        // SAFETY: len < CAPACITY: the owner empties the buffer as soon as it is full
        unsafe { self.entries.get_unchecked_mut(self.len) }.write(entry);
        self.len += keep as usize;
        self.len == CAPACITY
    }

    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    /// The kept entries, in order.
    #[inline(always)]
    pub(crate) fn as_slice(&self) -> &[T] {
        // SAFETY: entries 0..len were written by push_if (the entry at `len` is written
        // before `len` can move past it)
        unsafe { std::slice::from_raw_parts(self.entries.as_ptr().cast::<T>(), self.len) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The buffer keeps exactly the entries pushed with `keep`, in order, and says when full.
    #[test]
    fn keeps_the_kept_entries_in_order() {
        let mut kept = Kept::<u32, 4>::new();
        let mut want = Vec::new();
        let mut got = Vec::new();
        for k in 0..40u32 {
            let keep = k % 3 != 1;
            if keep {
                want.push(k);
            }
            if kept.push_if(keep, k) {
                got.extend_from_slice(kept.as_slice());
                kept.clear();
            }
        }
        got.extend_from_slice(kept.as_slice());
        assert_eq!(got, want);
    }
}
