//! Per-particle arrays on transparent huge pages: a large system's events touch its arrays at
//! random, and with 4 KiB pages nearly every such access also misses the address translation
//! caches (a second-level TLB of 2048 entries covers 8 MiB; the arrays of 10^5-10^6 spheres
//! span 20-200 MiB). [`HugeArray`] maps arrays of 2 MiB and more at a 2 MiB boundary and asks
//! Linux for huge pages there (`madvise(MADV_HUGEPAGE)`, which works where the system's
//! setting is `madvise` or `always`); smaller arrays, and other systems, use the heap. A plain
//! `Vec` is the reference: the tests check that both hold and change the same elements.

use std::ops::{Deref, DerefMut};
use std::ptr::NonNull;

/// Arrays of at least this many bytes go on huge pages (one huge page).
const HUGE_PAGE: usize = 2 << 20;

/// A fixed-length array of plain data (`Copy`), on huge pages when it is large.
pub(crate) struct HugeArray<T: Copy> {
    /// the elements (read without asking where they live: indexing costs what a Vec's does)
    data: NonNull<T>,
    len: usize,
    /// what owns the memory
    _owner: Owner<T>,
}

enum Owner<T: Copy> {
    Heap(#[allow(dead_code)] Vec<T>),
    #[cfg(target_os = "linux")]
    Mapped(#[allow(dead_code)] mapped::Mapping<T>),
}

// SAFETY: the array owns its elements (plain data) as a Vec does
unsafe impl<T: Copy + Send> Send for HugeArray<T> {}
// SAFETY: shared access only reads, as a Vec's does
unsafe impl<T: Copy + Sync> Sync for HugeArray<T> {}

impl<T: Copy> HugeArray<T> {
    /// `len` copies of `value`.
    pub(crate) fn new(len: usize, value: T) -> Self {
        Self::from_fn(len, |_| value)
    }

    /// The array of `f(0), f(1), ..., f(len - 1)`.
    pub(crate) fn from_fn(len: usize, mut f: impl FnMut(usize) -> T) -> Self {
        #[cfg(target_os = "linux")]
        if len * std::mem::size_of::<T>() >= HUGE_PAGE
            && let Some(mut mapping) = mapped::Mapping::new(len)
        {
            // written after the advice, so that the first touch of each 2 MiB takes a huge page
            for (k, slot) in mapping.uninit().iter_mut().enumerate() {
                slot.write(f(k));
            }
            // SAFETY: every element was written above
            let mut mapping = unsafe { mapping.assume_init() };
            return HugeArray {
                data: NonNull::from(mapping.as_mut_slice()).cast(),
                len,
                _owner: Owner::Mapped(mapping),
            };
        }
        let mut v: Vec<T> = (0..len).map(f).collect();
        HugeArray {
            data: NonNull::new(v.as_mut_ptr()).expect("a Vec's pointer is never null"),
            len,
            _owner: Owner::Heap(v),
        }
    }

    /// Whether the array is mapped on its own for huge pages (false: on the heap).
    #[cfg(test)]
    pub(crate) fn is_mapped(&self) -> bool {
        !matches!(self._owner, Owner::Heap(_))
    }
}

impl<T: Copy> Deref for HugeArray<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        // SAFETY: `data` points to `len` initialised elements that `owner` keeps alive (a
        // Vec's heap buffer or a mapping do not move when the array does)
        unsafe { std::slice::from_raw_parts(self.data.as_ptr(), self.len) }
    }
}

impl<T: Copy> DerefMut for HugeArray<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        // SAFETY: as in `deref`, and `&mut self` is the only access
        unsafe { std::slice::from_raw_parts_mut(self.data.as_ptr(), self.len) }
    }
}

impl<T: Copy> Clone for HugeArray<T> {
    fn clone(&self) -> Self {
        HugeArray::from_fn(self.len(), |k| self[k])
    }
}

impl<T: Copy + std::fmt::Debug> std::fmt::Debug for HugeArray<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Copy> Default for HugeArray<T> {
    fn default() -> Self {
        HugeArray::from_fn(0, |_| unreachable!("no elements"))
    }
}

impl<T: Copy> FromIterator<T> for HugeArray<T> {
    /// The elements of an iterator whose length is known exactly (as `ExactSizeIterator`'s
    /// are; others are collected on the heap first).
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut iter = iter.into_iter();
        match iter.size_hint() {
            (lower, Some(upper)) if lower == upper => {
                let array = HugeArray::from_fn(lower, |_| {
                    iter.next().expect("the iterator yields its size hint")
                });
                debug_assert!(iter.next().is_none());
                array
            }
            _ => {
                let items: Vec<T> = iter.collect();
                HugeArray::from_fn(items.len(), |k| items[k])
            }
        }
    }
}

/// Rearrange `data` in place so that element k becomes the element that was at `from[k]`
/// (`from` a permutation of 0..len), following the permutation's cycles: no second copy of
/// the array, only a bit per element.
pub(crate) fn permute<T: Copy>(data: &mut [T], from: &[u32]) {
    assert_eq!(data.len(), from.len(), "one source per element");
    let mut done = vec![0u64; data.len().div_ceil(64)];
    for start in 0..data.len() {
        if done[start / 64] >> (start % 64) & 1 == 1 {
            continue;
        }
        // the cycle start <- from[start] <- from[from[start]] <- ... <- start
        let first = data[start];
        let mut k = start;
        loop {
            done[k / 64] |= 1 << (k % 64);
            let source = from[k] as usize;
            if source == start {
                data[k] = first;
                break;
            }
            data[k] = data[source];
            k = source;
        }
    }
}

#[cfg(target_os = "linux")]
mod mapped {
    use super::HUGE_PAGE;
    use std::mem::MaybeUninit;
    use std::ptr::NonNull;

    /// An anonymous private mapping holding `len` elements from a 2 MiB boundary.
    pub(super) struct Mapping<T> {
        /// start of the mapping (as mmap returned it) and its length, for munmap
        base: NonNull<libc::c_void>,
        bytes: usize,
        /// the first element, at the first 2 MiB boundary of the mapping
        data: NonNull<T>,
        len: usize,
    }

    impl<T> Mapping<MaybeUninit<T>> {
        /// A mapping for `len` elements with huge pages advised; None if the system refuses
        /// the mapping (the caller falls back to the heap).
        pub(super) fn new(len: usize) -> Option<Self> {
            let size = len.checked_mul(std::mem::size_of::<T>())?;
            let bytes = size.checked_add(HUGE_PAGE)?;
            // SAFETY: a fresh anonymous mapping; no existing memory is affected
            let base = unsafe {
                libc::mmap(
                    std::ptr::null_mut(),
                    bytes,
                    libc::PROT_READ | libc::PROT_WRITE,
                    libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                    -1,
                    0,
                )
            };
            if base == libc::MAP_FAILED {
                return None;
            }
            let start = (base as usize).next_multiple_of(HUGE_PAGE);
            // SAFETY: [start, start + size) lies inside the mapping (it has HUGE_PAGE bytes to
            // spare); the advice only changes how its pages are backed. Its failure (a kernel
            // without transparent huge pages) leaves ordinary pages, which is still correct.
            unsafe {
                libc::madvise(
                    start as *mut libc::c_void,
                    size.next_multiple_of(HUGE_PAGE),
                    libc::MADV_HUGEPAGE,
                );
            }
            Some(Mapping {
                base: NonNull::new(base)?,
                bytes,
                data: NonNull::new(start as *mut MaybeUninit<T>)?,
                len,
            })
        }

        pub(super) fn uninit(&mut self) -> &mut [MaybeUninit<T>] {
            self.as_mut_slice()
        }

        /// The mapping as initialised elements.
        ///
        /// # Safety
        /// Every element must have been written.
        pub(super) unsafe fn assume_init(self) -> Mapping<T> {
            let this = std::mem::ManuallyDrop::new(self);
            Mapping {
                base: this.base,
                bytes: this.bytes,
                data: this.data.cast(),
                len: this.len,
            }
        }
    }

    impl<T> Mapping<T> {
        pub(super) fn as_mut_slice(&mut self) -> &mut [T] {
            // SAFETY: `data` points to `len` elements inside the mapping, initialised (a
            // `Mapping<T>` of plain `T` exists only after `assume_init`), and `&mut self` is
            // the only access
            unsafe { std::slice::from_raw_parts_mut(self.data.as_ptr(), self.len) }
        }
    }

    impl<T> Drop for Mapping<T> {
        fn drop(&mut self) {
            // SAFETY: unmaps exactly the mapping made in `new` (elements are plain data:
            // nothing to drop)
            unsafe {
                libc::munmap(self.base.as_ptr(), self.bytes);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    /// Small and large arrays (on the heap and mapped) hold, change and clone the same elements
    /// as a Vec does.
    #[test]
    fn huge_arrays_hold_what_a_vec_holds() {
        let mut rng = Pcg64::seed_from_u64(3);
        for len in [0, 1, 1000, HUGE_PAGE / 8 + 17] {
            let mut fast = HugeArray::from_fn(len, |k| (k as u64).wrapping_mul(0x9e37));
            let mut plain: Vec<u64> = (0..len as u64).map(|k| k.wrapping_mul(0x9e37)).collect();
            assert_eq!(
                fast.is_mapped(),
                len * 8 >= HUGE_PAGE || !cfg!(target_os = "linux")
            );
            for _ in 0..len.min(10_000) {
                let k = rng.random_range(0..len);
                let v = rng.random::<u64>();
                fast[k] = v;
                plain[k] = v;
            }
            assert_eq!(&fast[..], &plain[..]);
            assert_eq!(&fast.clone()[..], &plain[..]);
            let collected: HugeArray<u64> = plain.iter().copied().collect();
            assert_eq!(&collected[..], &plain[..]);
        }
    }

    /// Permuting in place gives what gathering into a new array gives, for random
    /// permutations (cycles of every length) and the identity.
    #[test]
    fn permuting_in_place_equals_gathering() {
        let mut rng = Pcg64::seed_from_u64(4);
        for len in [0usize, 1, 2, 63, 64, 65, 5000] {
            let mut from: Vec<u32> = (0..len as u32).collect();
            for shuffle in [false, true] {
                if shuffle {
                    // Fisher-Yates
                    for k in (1..len).rev() {
                        from.swap(k, rng.random_range(0..=k));
                    }
                }
                let data: Vec<[f64; 2]> = (0..len).map(|k| [k as f64, -(k as f64)]).collect();
                let gathered: Vec<[f64; 2]> = from.iter().map(|&s| data[s as usize]).collect();
                let mut permuted = data.clone();
                permute(&mut permuted, &from);
                assert_eq!(permuted, gathered, "len {len}");
            }
        }
    }
}
