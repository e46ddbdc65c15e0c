//! Free paths between collisions, tallied by an engine while statistics are on (thesis 3.1.1):
//! a free path is the straight-line displacement l = |r(t_2) - r(t_1)| of a particle between two
//! successive collisions of its own (pair or wall), the chord of its parabolic flight, not the
//! arc.
//!
//! An engine that knows each particle's last collision time t_1 needs no extra state: at the
//! next collision (time t_2, flight time tau = t_2 - t_1, velocity c just before it) the flight
//! under gravity g along +x gave
//!
//! ```text
//!     dr = c tau - (g tau^2 / 2) x_hat          (c(t_1) = c - g tau x_hat)
//! ```
//!
//! A path belongs to the slab of the midpoint of its chord, y_mid = y(t_2) - dy / 2 (gravity
//! does not act along y, so this is also the time-midpoint of the flight): a path that crosses
//! several slabs is counted once, where most of it lies. Paths ended by a wall collision are
//! counted like the others (the wall changes the velocity as a collision does) and also
//! apart, so that their share is known. A particle's first path (from the start of the run to
//! its first collision) is not a path between collisions and is never counted.
//!
//! Lengths are binned on a base-2 logarithmic scale read off the bits of the f64 (no log per
//! path): [`SUB_BINS`] equal bins per octave from 2^[`MIN_OCTAVE`] d to 2^[`MAX_OCTAVE`] d,
//! with one bin below and one above; the exact sum of the lengths is kept apart, so the mean
//! free path does not depend on the binning.

use serde::{Deserialize, Serialize};

/// Bins per octave (from the top three bits of the mantissa: equal widths within an octave).
pub const SUB_BINS: usize = 8;
/// Lower end of the binned range: 2^-12 d = 2.4e-4 d.
pub const MIN_OCTAVE: i32 = -12;
/// Upper end of the binned range: 2^14 d = 16384 d.
pub const MAX_OCTAVE: i32 = 14;
/// Number of length bins between 2^MIN_OCTAVE and 2^MAX_OCTAVE.
pub const LENGTH_BINS: usize = (MAX_OCTAVE - MIN_OCTAVE) as usize * SUB_BINS;
/// Entries per slab: below the range, the [`LENGTH_BINS`] bins, above the range.
pub const STRIDE: usize = LENGTH_BINS + 2;

/// Index of a length in a slab's entries: 0 below 2^MIN_OCTAVE (and for l = 0), 1 + k for
/// bin k, STRIDE - 1 above 2^MAX_OCTAVE (and for NaN).
#[inline(always)]
pub fn length_index(l: f64) -> usize {
    let bits = l.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
    if l < 0.0 || exponent < MIN_OCTAVE {
        return 0;
    }
    if exponent >= MAX_OCTAVE || l.is_nan() {
        return STRIDE - 1;
    }
    let sub = ((bits >> (52 - 3)) & 0x7) as usize;
    1 + (exponent - MIN_OCTAVE) as usize * SUB_BINS + sub
}

/// Lower and upper edge (in d) of length bin `k` (0 <= k < LENGTH_BINS):
/// 2^o (1 + s/8) and 2^o (1 + (s+1)/8) with o = MIN_OCTAVE + k / 8, s = k % 8.
pub fn length_edges(k: usize) -> (f64, f64) {
    let octave = MIN_OCTAVE + (k / SUB_BINS) as i32;
    let s = (k % SUB_BINS) as f64;
    let base = 2f64.powi(octave);
    (
        base * (1.0 + s / SUB_BINS as f64),
        base * (1.0 + (s + 1.0) / SUB_BINS as f64),
    )
}

/// The free paths ended since the tally was last taken, per slab across y.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreePathTally {
    /// slabs across y, over [0, W]
    pub slabs: usize,
    /// W, extent along y
    pub width: f64,
    /// y is periodic (no walls): midpoints wrap into [0, W)
    pub periodic: bool,
    /// per slab, [`STRIDE`] counts: below the range, the length bins, above the range
    pub counts: Vec<u64>,
    /// per slab, the sum of the lengths l (d)
    pub total_length: Vec<f64>,
    /// per slab, the paths ended by a wall collision
    pub wall_ended: Vec<u64>,
}

impl FreePathTally {
    /// An empty tally over `slabs` slabs of [0, width].
    pub fn new(slabs: usize, width: f64, periodic: bool) -> Self {
        let slabs = slabs.max(1);
        FreePathTally {
            slabs,
            width,
            periodic,
            counts: vec![0; slabs * STRIDE],
            total_length: vec![0.0; slabs],
            wall_ended: vec![0; slabs],
        }
    }

    /// An empty tally of the same slabs (what is left after [`std::mem::replace`]).
    pub fn emptied(&self) -> Self {
        Self::new(self.slabs, self.width, self.periodic)
    }

    /// Count the path that ends at height `y_end` after a flight of `tau` under gravity `g`
    /// (along +x) with velocity `c` just before the collision that ends it.
    #[inline(always)]
    pub fn add_flight(&mut self, y_end: f64, c: [f64; 3], tau: f64, g: f64, wall: bool) {
        let dx = tau * (c[0] - 0.5 * g * tau);
        let dy = tau * c[1];
        let dz = tau * c[2];
        let l = (dx * dx + dy * dy + dz * dz).sqrt();
        self.add(y_end - 0.5 * dy, l, wall);
    }

    /// Count a path of length `l` whose chord's midpoint is at height `y_mid`.
    #[inline(always)]
    pub fn add(&mut self, y_mid: f64, l: f64, wall: bool) {
        let y = if self.periodic {
            y_mid.rem_euclid(self.width)
        } else {
            y_mid
        };
        // `as usize` saturates: below 0 (and NaN) is slab 0
        let slab = ((y / self.width * self.slabs as f64) as usize).min(self.slabs - 1);
        self.counts[slab * STRIDE + length_index(l)] += 1;
        self.total_length[slab] += l;
        self.wall_ended[slab] += u64::from(wall);
    }

    /// Paths counted in a slab.
    pub fn paths(&self, slab: usize) -> u64 {
        self.counts[slab * STRIDE..(slab + 1) * STRIDE].iter().sum()
    }

    /// Add another tally of the same slabs.
    pub fn merge(&mut self, other: &FreePathTally) {
        if other.counts.len() != self.counts.len() {
            return;
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        for (a, b) in self.total_length.iter_mut().zip(&other.total_length) {
            *a += b;
        }
        for (a, b) in self.wall_ended.iter_mut().zip(&other.wall_ended) {
            *a += b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_fall_between_their_bin_edges() {
        for &l in &[
            3e-4, 0.01, 0.1234, 0.5, 1.0, 1.0625, 1.99, 7.3, 100.0, 9000.0,
        ] {
            let i = length_index(l);
            assert!(i > 0 && i < STRIDE - 1, "{l}");
            let (lo, hi) = length_edges(i - 1);
            assert!(lo <= l && l < hi, "{l} in [{lo}, {hi})");
        }
        assert_eq!(length_index(0.0), 0);
        assert_eq!(length_index(1e-5), 0);
        assert_eq!(length_index(1e5), STRIDE - 1);
        assert_eq!(length_index(f64::INFINITY), STRIDE - 1);
        // contiguous edges
        for k in 1..LENGTH_BINS {
            assert_eq!(length_edges(k - 1).1, length_edges(k).0);
        }
    }

    #[test]
    fn a_parabolic_flight_is_measured_by_its_chord() {
        // start at the origin with c0 = (1, 2, 0), g = 2: at tau = 1.5, r = (1.5 + 2.25, 3, 0)
        let (c0, g, tau) = ([1.0, 2.0, 0.0], 2.0, 1.5);
        let end_velocity = [c0[0] + g * tau, c0[1], c0[2]];
        let mut t = FreePathTally::new(4, 8.0, false);
        t.add_flight(3.0, end_velocity, tau, g, true);
        let l = (3.75f64 * 3.75 + 9.0).sqrt();
        assert!((t.total_length.iter().sum::<f64>() - l).abs() < 1e-12);
        // midpoint y = 1.5: slab 0 of [0, 2)
        assert_eq!(t.paths(0), 1);
        assert_eq!(t.wall_ended[0], 1);
    }
}
