//! The simulation box: extents, which directions are periodic, the minimum image and the
//! wrap of positions into the box. y (wall to wall) is never periodic; z always is; x is
//! periodic once the preparation's floor is removed.

use serde::{Deserialize, Serialize};

/// The box [0, L) x [0, W] x [0, B).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Domain {
    /// (L, W, B)
    pub extent: [f64; 3],
    /// whether x is periodic (false during the preparation)
    pub periodic_x: bool,
    /// half periods of x and z (infinite when not periodic: no image is ever taken)
    half: [f64; 3],
    /// wrap bounds: a coordinate >= hi is moved down by the period, one < lo up
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Domain {
    pub fn new(length: f64, width: f64, span: f64, periodic_x: bool) -> Domain {
        let extent = [length, width, span];
        let (half_x, lo_x, hi_x) = if periodic_x {
            (0.5 * length, 0.0, length)
        } else {
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY)
        };
        Domain {
            extent,
            periodic_x,
            half: [half_x, f64::INFINITY, 0.5 * span],
            lo: [lo_x, f64::NEG_INFINITY, 0.0],
            hi: [hi_x, f64::INFINITY, span],
        }
    }

    /// The minimum image of a separation: in x (when periodic) and z, a component beyond half
    /// a period is moved by one period. Symmetric: min_image(-d) = -min_image(d) bitwise.
    /// Written as selects (no branch: which pairs straddle a boundary is unpredictable, and
    /// loops over pairs can run it in vector lanes).
    #[inline(always)]
    pub fn min_image(&self, mut d: [f64; 3]) -> [f64; 3] {
        for k in [0, 2] {
            let (down, up) = (d[k] - self.extent[k], d[k] + self.extent[k]);
            d[k] = if d[k] > self.half[k] {
                down
            } else if d[k] < -self.half[k] {
                up
            } else {
                d[k]
            };
        }
        d
    }

    /// The half periods (x, y, z): a separation component beyond one is moved by a period in
    /// [`Self::min_image`] (infinite where no image is taken).
    #[inline(always)]
    pub fn half_periods(&self) -> [f64; 3] {
        self.half
    }

    /// Bring a position moved by at most one period back into the box (x when periodic, z).
    #[inline(always)]
    pub fn wrap(&self, x: &mut [f64; 3]) {
        for k in [0, 2] {
            if x[k] >= self.hi[k] {
                x[k] -= self.extent[k];
            } else if x[k] < self.lo[k] {
                x[k] += self.extent[k];
            }
        }
    }

    /// [`Self::wrap`] of every position, four positions (twelve coordinates) at a time as
    /// selects, which a loop can run in vector lanes: the same bits as one by one (y, never
    /// periodic, has infinite bounds and is left as it is).
    #[inline(always)]
    pub fn wrap_all(&self, x: &mut [[f64; 3]]) {
        let (lo, hi, period) = (by_axis(self.lo), by_axis(self.hi), by_axis(self.extent));
        let mut fours = x.as_flattened_mut().chunks_exact_mut(12);
        for c in &mut fours {
            for k in 0..12 {
                let (down, up) = (c[k] - period[k], c[k] + period[k]);
                c[k] = if c[k] >= hi[k] {
                    down
                } else if c[k] < lo[k] {
                    up
                } else {
                    c[k]
                };
            }
        }
        for rest in fours.into_remainder().chunks_exact_mut(3) {
            let mut p = [rest[0], rest[1], rest[2]];
            self.wrap(&mut p);
            rest.copy_from_slice(&p);
        }
    }

    /// Widen the box [lo, hi] to hold every minimum-image displacement
    /// [`Self::min_image`](x_i - from_i), four particles at a time as selects (min and max are
    /// exact: the same box in any order).
    #[inline(always)]
    pub fn widen_displacement_box(
        &self,
        x: &[[f64; 3]],
        from: &[[f64; 3]],
        lo: &mut [f64; 3],
        hi: &mut [f64; 3],
    ) {
        assert_eq!(x.len(), from.len());
        let (half, period) = (by_axis(self.half), by_axis(self.extent));
        let (mut lo4, mut hi4) = (by_axis(*lo), by_axis(*hi));
        let (x, from) = (x.as_flattened(), from.as_flattened());
        let (fours, fours_from) = (x.chunks_exact(12), from.chunks_exact(12));
        let rest = fours
            .remainder()
            .chunks_exact(3)
            .zip(fours_from.remainder().chunks_exact(3));
        for (c, f) in fours.zip(fours_from) {
            for k in 0..12 {
                let d = c[k] - f[k];
                let (down, up) = (d - period[k], d + period[k]);
                let s = if d > half[k] {
                    down
                } else if d < -half[k] {
                    up
                } else {
                    d
                };
                // (s is never NaN, and the sign of a zero bound does not matter)
                lo4[k] = if s < lo4[k] { s } else { lo4[k] };
                hi4[k] = if s > hi4[k] { s } else { hi4[k] };
            }
        }
        for (c, f) in rest {
            let s = self.min_image([c[0] - f[0], c[1] - f[1], c[2] - f[2]]);
            for k in 0..3 {
                lo4[k] = if s[k] < lo4[k] { s[k] } else { lo4[k] };
                hi4[k] = if s[k] > hi4[k] { s[k] } else { hi4[k] };
            }
        }
        for k in 0..12 {
            lo[k % 3] = if lo4[k] < lo[k % 3] {
                lo4[k]
            } else {
                lo[k % 3]
            };
            hi[k % 3] = if hi4[k] > hi[k % 3] {
                hi4[k]
            } else {
                hi[k % 3]
            };
        }
    }
}

/// A per-axis value for each of twelve coordinates: four positions (x y z x y z ...) side by
/// side.
#[inline(always)]
fn by_axis(v: [f64; 3]) -> [f64; 12] {
    std::array::from_fn(|c| v[c % 3])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    /// The four-at-a-time wrap and displacement box give the bits of the one-by-one wrap and
    /// minimum image, for every count of positions (the remainder too), periodic x or not,
    /// with positions outside the box on both sides and displacements across a boundary.
    #[test]
    fn the_four_at_a_time_forms_equal_the_one_by_one_forms() {
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        let (mut moved, mut imaged) = (0, 0);
        for (n, periodic_x) in (0..40).zip([true, false].into_iter().cycle()) {
            let domain = Domain::new(7.0, 5.0, 3.0, periodic_x);
            let x: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    std::array::from_fn(|k| (rng.random::<f64>() * 1.4 - 0.2) * domain.extent[k])
                })
                .collect();
            let mut wrapped = x.clone();
            domain.wrap_all(&mut wrapped);
            for (one, all) in x.iter().zip(&wrapped) {
                let mut p = *one;
                domain.wrap(&mut p);
                assert_eq!(p.map(f64::to_bits), all.map(f64::to_bits));
                moved += (p != *one) as usize;
            }
            let from: Vec<[f64; 3]> = wrapped
                .iter()
                .map(|p| {
                    std::array::from_fn(|k| {
                        (p[k] + rng.random::<f64>() - 0.5).rem_euclid(domain.extent[k])
                    })
                })
                .collect();
            let (mut lo, mut hi) = ([-0.01; 3], [0.01; 3]);
            domain.widen_displacement_box(&wrapped, &from, &mut lo, &mut hi);
            let (mut lo1, mut hi1) = ([-0.01f64; 3], [0.01f64; 3]);
            for (p, f) in wrapped.iter().zip(&from) {
                let raw = [p[0] - f[0], p[1] - f[1], p[2] - f[2]];
                let s = domain.min_image(raw);
                imaged += (s != raw) as usize;
                for k in 0..3 {
                    lo1[k] = lo1[k].min(s[k]);
                    hi1[k] = hi1[k].max(s[k]);
                }
            }
            assert_eq!((lo, hi), (lo1, hi1), "{n} positions");
        }
        assert!(
            moved > 50 && imaged > 20,
            "{moved} wrapped, {imaged} imaged"
        );
    }
}
