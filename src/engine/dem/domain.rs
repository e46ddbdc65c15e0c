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
}
