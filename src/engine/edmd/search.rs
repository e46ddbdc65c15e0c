//! Partners of a neighbour search collected in batches, so that the memory latency of many
//! partner records overlaps instead of adding up.

use super::images::Image;

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
