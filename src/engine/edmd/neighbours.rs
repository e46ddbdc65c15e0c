//! Neighbour lists of bounding spheres (Donev, Torquato & Stillinger, J. Comput. Phys. 202,
//! 737 (2005)): every particle stays within skin/2 of its list's centre, so two particles can
//! only touch if their centres are closer than d + skin; each particle lists those, and the
//! lists are kept symmetric (j in i's list exactly when i is in j's), so renewing one list
//! never needs a search by anyone else.
//!
//! Storage is one flat array with a fixed number of words per particle (its list length, then
//! its entries): a particle's whole list is one or two cache lines, and nothing is allocated
//! per event. The stride doubles when a list overflows (rare; deterministic in the state).

use super::huge::HugeArray;
pub use super::images::Image;
use crate::engine::prefetch::prefetch_at;

/// One entry of a list: partner slot (27 bits) and the image of the partner that is near.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(transparent)]
pub struct Neighbour(u32);

impl Neighbour {
    const SLOT_BITS: u32 = 27;
    /// Largest number of particles the packing can address.
    pub const MAX_PARTICLES: usize = 1 << Self::SLOT_BITS;

    pub fn new(slot: u32, image: Image) -> Self {
        debug_assert!((slot as usize) < Self::MAX_PARTICLES);
        Neighbour(slot | (image.0 as u32) << Self::SLOT_BITS)
    }

    /// Storage slot of the partner.
    #[inline(always)]
    pub fn slot(self) -> u32 {
        self.0 & ((1 << Self::SLOT_BITS) - 1)
    }

    /// Which periodic image of the partner is the neighbour.
    #[inline(always)]
    pub fn image(self) -> Image {
        Image((self.0 >> Self::SLOT_BITS) as u8)
    }

    /// The entry for particle `i` in the list of this entry's partner (the opposite image).
    #[inline(always)]
    fn back_to(self, i: u32) -> Neighbour {
        Neighbour::new(i, self.image().opposite())
    }
}

/// Symmetric neighbour lists of all particles.
#[derive(Clone, Debug)]
pub struct NeighbourLists {
    /// words per particle: the length, then up to stride - 1 entries
    stride: usize,
    words: HugeArray<u32>,
}

impl NeighbourLists {
    const INITIAL_STRIDE: usize = 16;

    /// Empty lists for `particles` particles.
    pub fn new(particles: usize) -> Self {
        assert!(
            particles <= Neighbour::MAX_PARTICLES,
            "neighbour lists address at most {} particles",
            Neighbour::MAX_PARTICLES
        );
        NeighbourLists {
            stride: Self::INITIAL_STRIDE,
            words: HugeArray::new(particles * Self::INITIAL_STRIDE, 0),
        }
    }

    /// Number of particles.
    fn len(&self) -> usize {
        self.words.len() / self.stride
    }

    /// The neighbours of particle `i`.
    #[inline(always)]
    pub fn of(&self, i: usize) -> impl Iterator<Item = Neighbour> + '_ {
        let start = i * self.stride;
        let len = self.words[start] as usize;
        self.words[start + 1..start + 1 + len]
            .iter()
            .map(|&w| Neighbour(w))
    }

    /// The neighbours of particle `i`, as a slice.
    #[inline(always)]
    pub fn entries(&self, i: usize) -> &[Neighbour] {
        let start = i * self.stride;
        let len = self.words[start] as usize;
        let words = &self.words[start + 1..start + 1 + len];
        // SAFETY: Neighbour is a transparent u32
        unsafe { std::slice::from_raw_parts(words.as_ptr().cast::<Neighbour>(), words.len()) }
    }

    /// Start loading particle `i`'s list into cache (its first two cache lines when lists
    /// have outgrown one).
    #[inline(always)]
    pub fn prefetch(&self, i: usize) {
        prefetch_at(&self.words, i * self.stride);
        if self.stride > Self::INITIAL_STRIDE {
            prefetch_at(&self.words, i * self.stride + Self::INITIAL_STRIDE);
        }
    }

    /// Empty every list.
    pub fn clear(&mut self) {
        self.words.fill(0);
    }

    /// Record that image `image` of `j` is near `i` (and so the opposite image of `i` is near
    /// `j`).
    pub fn link(&mut self, i: u32, j: u32, image: Image) {
        let entry = Neighbour::new(j, image);
        self.push(i as usize, entry);
        self.push(j as usize, entry.back_to(i));
    }

    /// Make `new` particle `i`'s list, editing only the lists of particles that left it or
    /// joined it (a renewal keeps most neighbours: removing and re-adding all of them costs a
    /// search in each of their lists).
    pub fn replace(&mut self, i: u32, new: &[Neighbour]) {
        let start = i as usize * self.stride;
        let len = self.words[start] as usize;
        let old = PaddedWords::of(&self.words[start + 1..start + 1 + len]);
        // SAFETY: Neighbour is a transparent u32
        let fresh = PaddedWords::of(unsafe {
            std::slice::from_raw_parts(new.as_ptr().cast::<u32>(), new.len())
        });
        // the former neighbours' lists are scattered: start loading all of them first
        for &word in old.entries() {
            prefetch_at(&self.words, Neighbour(word).slot() as usize * self.stride);
        }
        for &word in old.entries() {
            if !fresh.holds(word) {
                let gone = Neighbour(word);
                self.remove(gone.slot() as usize, gone.back_to(i));
            }
        }
        for &entry in new {
            if !old.holds(entry.0) {
                self.push(entry.slot() as usize, entry.back_to(i));
            }
        }
        // then i's own list is written in one go, after making room for it
        while new.len() >= self.stride {
            self.grow();
        }
        let start = i as usize * self.stride;
        self.words[start] = new.len() as u32;
        for (word, entry) in self.words[start + 1..start + 1 + new.len()]
            .iter_mut()
            .zip(new)
        {
            *word = entry.0;
        }
    }

    /// Memory used, in bytes.
    pub fn bytes(&self) -> usize {
        4 * self.words.len()
    }

    fn push(&mut self, i: usize, entry: Neighbour) {
        if self.words[i * self.stride] as usize + 1 == self.stride {
            self.grow();
        }
        let start = i * self.stride;
        let len = self.words[start] as usize;
        self.words[start + 1 + len] = entry.0;
        self.words[start] += 1;
    }

    /// Remove `entry` from particle `i`'s list (the last entry takes its place).
    fn remove(&mut self, i: usize, entry: Neighbour) {
        let start = i * self.stride;
        let len = self.words[start] as usize;
        let list = &mut self.words[start + 1..start + 1 + len];
        let at = list
            .iter()
            .position(|&w| w == entry.0)
            .expect("neighbour lists are symmetric");
        list[at] = list[len - 1];
        self.words[start] -= 1;
    }

    /// Double the room per particle, keeping every list as it is.
    fn grow(&mut self) {
        let n = self.len();
        let stride = 2 * self.stride;
        let mut words = HugeArray::new(n * stride, 0);
        for i in 0..n {
            let old = &self.words[i * self.stride..(i + 1) * self.stride];
            words[i * stride..i * stride + self.stride].copy_from_slice(old);
        }
        self.stride = stride;
        self.words = words;
    }
}

/// A list's words copied into a buffer padded with a word that no entry is (image codes stop
/// at 26, so the top five bits are never all set), so that membership is tested four entries
/// at a time with a few vector compares and no early exit (where a neighbour sits in a list
/// is random: an early exit would be a mispredicted branch per look-up). Longer lists (never
/// met in practice) are kept as they are and tested entry by entry.
struct PaddedWords {
    padded: [u32; PaddedWords::ROOM],
    len: usize,
    long: Vec<u32>,
}

impl PaddedWords {
    const ROOM: usize = 32;
    const NONE: u32 = u32::MAX;

    #[inline(always)]
    fn of(words: &[u32]) -> Self {
        let mut padded = [Self::NONE; Self::ROOM];
        let long = if words.len() <= Self::ROOM {
            padded[..words.len()].copy_from_slice(words);
            Vec::new()
        } else {
            words.to_vec()
        };
        PaddedWords {
            padded,
            len: words.len(),
            long,
        }
    }

    #[inline(always)]
    fn entries(&self) -> &[u32] {
        if self.len <= Self::ROOM {
            &self.padded[..self.len]
        } else {
            &self.long
        }
    }

    /// Whether the list holds `word` (an entry, never the padding word).
    #[inline(always)]
    fn holds(&self, word: u32) -> bool {
        debug_assert!(word != Self::NONE);
        if self.len <= Self::ROOM {
            let chunks = self.len.div_ceil(4);
            self.padded[..4 * chunks]
                .chunks_exact(4)
                .fold(false, |found, c| {
                    found | ((c[0] == word) | (c[1] == word)) | ((c[2] == word) | (c[3] == word))
                })
        } else {
            self.long.contains(&word)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;
    use std::collections::BTreeSet;

    #[test]
    fn images_code_and_invert() {
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    let image = Image::new([x, y, z]);
                    assert_eq!(image.offsets(), [x, y, z]);
                    assert_eq!(image.opposite().offsets(), [-x, -y, -z]);
                }
            }
        }
        assert_eq!(Image::SAME.offsets(), [0, 0, 0]);
    }

    /// The padded copy finds exactly the words a plain search finds, for lists of every length
    /// up to and past the padded room (including the word next to the padding's).
    #[test]
    fn padded_words_hold_what_the_list_holds() {
        let mut rng = Pcg64::seed_from_u64(3);
        for len in 0..=2 * PaddedWords::ROOM + 3 {
            let words: Vec<u32> = (0..len).map(|_| rng.random_range(0..200u32) * 7).collect();
            let padded = PaddedWords::of(&words);
            assert_eq!(padded.entries(), &words[..]);
            for probe in (0..1400u32).chain([u32::MAX - 1]) {
                let want = words.contains(&probe);
                assert_eq!(padded.holds(probe), want, "len {len}, word {probe}");
            }
        }
    }

    /// Through random links and renewals (with enough neighbours to overflow the initial
    /// room), the packed lists hold exactly the pairs of a plain set of (i, j, image).
    #[test]
    fn packed_lists_agree_with_a_set_of_pairs() {
        let n = 40u32;
        let mut lists = NeighbourLists::new(n as usize);
        let mut pairs: BTreeSet<(u32, u32, Image)> = BTreeSet::new();
        let mut rng = Pcg64::seed_from_u64(11);
        for step in 0..20_000 {
            let i = rng.random_range(0..n);
            let roll = rng.random::<f64>();
            if roll < 0.1 {
                lists.replace(i, &[]);
                pairs.retain(|&(a, b, _)| a != i && b != i);
            } else if roll < 0.2 {
                // a renewal: keep some neighbours, drop others, add new ones
                let mut new: Vec<Neighbour> = lists
                    .of(i as usize)
                    .filter(|_| rng.random::<f64>() < 0.7)
                    .collect();
                for _ in 0..rng.random_range(0..6) {
                    let j = (i + rng.random_range(1..n)) % n;
                    let entry = Neighbour::new(j, Image(rng.random_range(0..27u8)));
                    if !new.contains(&entry) {
                        new.push(entry);
                    }
                }
                lists.replace(i, &new);
                pairs.retain(|&(a, b, _)| a != i && b != i);
                for e in &new {
                    pairs.insert((i, e.slot(), e.image()));
                    pairs.insert((e.slot(), i, e.image().opposite()));
                }
            } else {
                let j = (i + rng.random_range(1..n)) % n;
                let image = Image(rng.random_range(0..27u8));
                if !pairs.contains(&(i, j, image)) {
                    lists.link(i, j, image);
                    pairs.insert((i, j, image));
                    pairs.insert((j, i, image.opposite()));
                }
            }
            if step % 100 == 0 {
                for p in 0..n {
                    let got: BTreeSet<(u32, u32, Image)> = lists
                        .of(p as usize)
                        .map(|e| (p, e.slot(), e.image()))
                        .collect();
                    let want: BTreeSet<(u32, u32, Image)> =
                        pairs.iter().filter(|e| e.0 == p).copied().collect();
                    assert_eq!(got, want, "particle {p} at step {step}");
                    assert_eq!(lists.of(p as usize).count(), want.len(), "duplicates");
                }
            }
        }
        assert!(lists.stride > NeighbourLists::INITIAL_STRIDE, "never grew");
    }
}
