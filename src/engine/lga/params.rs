//! Parameters of the lattice gas (rho, p, g, b, L, W, seed), their validation and the integer
//! thresholds the random decisions compare against.

use super::rng::{ONE, threshold};
use serde::{Deserialize, Serialize};

/// Largest number of sites L W (the hop stream indexes sites with 53 bits; this bound keeps
/// a lattice far below memory limits too).
pub const MAX_SITES: usize = 1 << 30;

/// Parameters of one lattice-gas run (Peng & Herrmann 1994).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LgaParams {
    /// L, sites along the pipe (periodic, along gravity), e.g. 220 or 2200
    pub length: usize,
    /// W, sites across the pipe between the two walls, e.g. 11
    pub width: usize,
    /// rho, mean particles per site; only the six moving states are filled initially (each
    /// with probability rho / 6), so 0 <= rho <= 6 although a site holds up to 7
    pub density: f64,
    /// p, dissipation probability of rules (2) and (3)
    pub dissipation: f64,
    /// g, probability of the gravity rule (6)
    pub gravity: f64,
    /// b, bounce-back probability at the walls, rule (7) (0: smooth walls)
    pub bounce_back: f64,
    /// seed of the counter-based random stream
    pub seed: u64,
}

impl Default for LgaParams {
    /// The seed's Fig. 2 run: L = 220, W = 11, rho = 1, p = g = b = 0.5.
    fn default() -> Self {
        LgaParams {
            length: 220,
            width: 11,
            density: 1.0,
            dissipation: 0.5,
            gravity: 0.5,
            bounce_back: 0.5,
            seed: 1,
        }
    }
}

impl LgaParams {
    /// Check the parameters; the message names the key, its value and the allowed range.
    pub fn validate(&self) -> Result<(), String> {
        if self.length == 0 {
            return Err(format!(
                "length (L) = {} is not allowed: at least 1 site along the pipe",
                self.length
            ));
        }
        if self.width == 0 {
            return Err(format!(
                "width (W) = {} is not allowed: at least 1 site across the pipe",
                self.width
            ));
        }
        if self
            .length
            .checked_mul(self.width)
            .is_none_or(|n| n > MAX_SITES)
        {
            return Err(format!(
                "length x width (L W) = {} x {} is too large: at most {MAX_SITES} sites",
                self.length, self.width
            ));
        }
        if !(self.density.is_finite() && (0.0..=6.0).contains(&self.density)) {
            return Err(format!(
                "density (rho) = {} is out of range [0, 6]: a site holds up to 7 particles, \
                 but the initial state fills only the six moving states (each with probability \
                 rho / 6), so rho <= 6",
                self.density
            ));
        }
        for (key, sym, v) in [
            ("dissipation", "p", self.dissipation),
            ("gravity", "g", self.gravity),
            ("bounce_back", "b", self.bounce_back),
        ] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(format!(
                    "{key} ({sym}) = {v} is out of range [0, 1]: it is a probability"
                ));
            }
        }
        Ok(())
    }

    /// The thresholds of the random decisions of these parameters.
    pub fn thresholds(&self) -> Thresholds {
        let p = threshold(self.dissipation);
        Thresholds {
            half: ONE / 2,
            dissipation: p,
            third: (p + 1) / 3,
            two_thirds: (2 * p + 1) / 3,
            gravity: threshold(self.gravity),
            bounce_back: threshold(self.bounce_back),
            occupation: threshold(self.density / 6.0),
        }
    }
}

/// Integer thresholds t (a decision with probability t / 2^32 is `u < t`, see
/// [`super::rng`]). The triple's three dissipative outcomes split [0, t_p) into thirds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Thresholds {
    /// 1/2: rule (1) turns a head-on pair counterclockwise when u < half
    pub half: u64,
    /// p, rules (2) and (3)
    pub dissipation: u64,
    /// round(t_p / 3): rule (3) puts the head-on pair on axis v1/v4 when u < third
    pub third: u64,
    /// round(2 t_p / 3): on axis v2/v5 when third <= u < two_thirds, else v3/v6
    pub two_thirds: u64,
    /// g, rule (6)
    pub gravity: u64,
    /// b, rule (7)
    pub bounce_back: u64,
    /// rho / 6, initial occupation of each moving state
    pub occupation: u64,
}
