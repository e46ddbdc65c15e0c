//! Periodic images: which copy of the box a partner is near in, as one small code.

/// A periodic image offset per axis, each in {-1, 0, +1}, coded as one number in 0..27.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Image(pub(super) u8);

impl Image {
    /// No periodic shift.
    pub const SAME: Image = Image(13);
    /// Number of distinct images.
    pub const COUNT: usize = 27;

    /// The image with offsets `k` (each -1, 0 or +1) box lengths along each axis.
    pub fn new(k: [i8; 3]) -> Self {
        debug_assert!(k.iter().all(|v| (-1..=1).contains(v)));
        Image(((k[0] + 1) + 3 * (k[1] + 1) + 9 * (k[2] + 1)) as u8)
    }

    /// The image with index `index` in 0..27 (see [`Image::index`]).
    pub fn from_index(index: usize) -> Self {
        assert!(index < Self::COUNT);
        Image(index as u8)
    }

    /// The image with code (kx + 1) + 3 (ky + 1) + 9 (kz + 1) for offsets k in {-1, 0, 1}.
    #[inline(always)]
    pub(crate) fn from_code(code: u8) -> Self {
        debug_assert!((code as usize) < Self::COUNT);
        Image(code)
    }

    /// Offsets in box lengths along each axis.
    pub fn offsets(self) -> [i8; 3] {
        let c = self.0 as i8;
        [c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1]
    }

    /// The opposite shift (seen from the partner).
    pub fn opposite(self) -> Self {
        Image(26 - self.0)
    }

    /// Index in 0..27 (for tables of shift vectors).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// The shift vector of each periodic image, looked up without a bounds check: the 27 vectors
/// padded to 32 (entries 27-31 are never read), indexed by the code masked to 5 bits (codes
/// are below 27).
#[derive(Clone, Debug)]
pub struct ImageShifts([[f64; 3]; 32]);

impl ImageShifts {
    /// Shifts of `k` box lengths `extents` along each periodic axis (none along the others).
    pub fn new(extents: [f64; 3], periodic: [bool; 3]) -> Self {
        ImageShifts(std::array::from_fn(|index| {
            let k = Image::from_index(index.min(Image::COUNT - 1)).offsets();
            std::array::from_fn(|a| {
                if periodic[a] {
                    k[a] as f64 * extents[a]
                } else {
                    0.0
                }
            })
        }))
    }

    /// Shift vector of `image`.
    #[inline(always)]
    pub fn of(&self, image: Image) -> &[f64; 3] {
        &self.0[(image.0 & 31) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The masked table gives each image's shift as computed directly from its offsets: k box
    /// lengths along periodic axes, none along the others.
    #[test]
    fn image_shift_table_agrees_with_the_offsets() {
        let extents = [3.0, 5.0, 7.0];
        let periodic = [true, false, true];
        let shifts = ImageShifts::new(extents, periodic);
        for index in 0..Image::COUNT {
            let image = Image::from_index(index);
            let k = image.offsets();
            let want: [f64; 3] = std::array::from_fn(|a| {
                if periodic[a] {
                    k[a] as f64 * extents[a]
                } else {
                    0.0
                }
            });
            assert_eq!(*shifts.of(image), want, "image {index}");
        }
    }
}
