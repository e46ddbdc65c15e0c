//! Spatial velocity correlations (thesis 4.1.4, eq. 4.1), per slab of the test particle:
//!
//! ```text
//!     C_ab(r) = < (C_a^i C_b^j + C_b^i C_a^j) / 2 >_{pairs at r}  /  sqrt(<C_a^2> <C_b^2>)
//! ```
//!
//! the mean symmetrised product of the fluctuations of two particles at distance r (i in the
//! slab, j anywhere; each pair once per particle), over the slab's one-particle second
//! moments. This is our reading of the garbled eq. 4.1: its numerator sums products over the
//! pairs in a shell but is not divided by their number (it would grow as r^2 without any
//! correlation), and its denominator "sum_{i=j} c_a^i c_b^j" is the self term. We divide by
//! the pair count, so an uncorrelated gas gives 0 at every r, and normalise by
//! sqrt(<C_a^2> <C_b^2>) so that C_aa is the correlation coefficient (1 for identical
//! velocities) and the cross terms stay finite where <C_a C_b> vanishes. The velocities are
//! the fluctuations C (the thesis writes c, but reports C_xx ~ 0 in a plug, which the mean
//! flow would forbid), about the fluctuation cell's mean: pairs of one cell then carry
//! -1/(N_k - 1) of anticorrelation (see [`super::fluctuations`]), 1e-3 .. 1e-2 with slabs.
//! Only the six translational correlations are computed (the thesis shows no rotational
//! ones); the sums are pooled over the window.

use super::pairs::{PAIRS, PairSample};
use serde::{Deserialize, Serialize};

/// One point of a velocity correlation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    into = "(u32, f64, String, f64, f64, u64)",
    from = "(u32, f64, String, f64, f64, u64)"
)]
pub struct VelocityCorrelationRow {
    pub slab: u32,
    pub y: f64,
    /// xx, yy, zz, xy, xz, yz
    pub pair: String,
    /// bin centre, d
    pub r: f64,
    pub c: f64,
    /// ordered pairs over the window
    pub pairs: u64,
}

/// C_ab(r) of every slab over the window's samples.
pub fn analyse(
    samples: &[&PairSample],
    slabs: usize,
    y_of: &dyn Fn(usize) -> f64,
) -> Vec<VelocityCorrelationRow> {
    let Some(first) = samples.first() else {
        return Vec::new();
    };
    let bins = first.vcf_bins();
    let same: Vec<&PairSample> = samples
        .iter()
        .copied()
        .filter(|s| s.products.len() == first.products.len() && s.dr == first.dr)
        .collect();
    if first.self_count.len() != slabs {
        return Vec::new();
    }
    let width = first.dr * first.per_vcf_bin as f64;
    let mut rows = Vec::new();
    for slab in 0..slabs {
        let n: u64 = same.iter().map(|s| s.self_count[slab]).sum();
        if n == 0 {
            continue;
        }
        let second = |k: usize| {
            same.iter()
                .map(|s| s.self_products[slab * 6 + k])
                .sum::<f64>()
                / n as f64
        };
        let variance = [second(0), second(1), second(2)];
        for (k, name) in PAIRS.iter().enumerate() {
            let (a, b) = match k {
                0..=2 => (k, k),
                3 => (0, 1),
                4 => (0, 2),
                _ => (1, 2),
            };
            let norm = (variance[a] * variance[b]).sqrt();
            for v in 0..bins {
                let pairs: u64 = same
                    .iter()
                    .map(|s| u64::from(s.product_pairs[slab * bins + v]))
                    .sum();
                if pairs == 0 || norm <= 0.0 {
                    continue;
                }
                let sum: f64 = same
                    .iter()
                    .map(|s| s.products[(slab * bins + v) * 6 + k])
                    .sum();
                let hi = ((v + 1) as f64 * width).min(first.r_max);
                rows.push(VelocityCorrelationRow {
                    slab: slab as u32,
                    y: y_of(slab),
                    pair: (*name).into(),
                    r: 0.5 * (v as f64 * width + hi),
                    c: sum / pairs as f64 / norm,
                    pairs,
                });
            }
        }
    }
    rows
}

row_as_tuple!(VelocityCorrelationRow {
    slab: u32,
    y: f64,
    pair: String,
    r: f64,
    c: f64,
    pairs: u64
});
