//! The orientational correlation (thesis 3.4): Lambda(y) = <cos^2 Psi>, Psi the angle between a
//! particle's translational and rotational fluctuations C and Omega,
//!
//! ```text
//!     cos^2 Psi_i = (C_i . Omega_i)^2 / (C_i^2 Omega_i^2)
//! ```
//!
//! 1/3 when C and Omega are independent and one of them is isotropic (a molecular gas);
//! anisotropic fluctuations alone shift it. Per snapshot and slab the record keeps
//! sum cos^2 Psi and the count (particles with C != 0 and Omega != 0); over the window
//! Lambda = sum over snapshots of the sums / sum of the counts (each snapshot weighted by its
//! particles, where the thesis averages the per-snapshot means: the same in a steady state up
//! to O(1/N_slab)); the error by batch means. Engines without spins give no Lambda.

use super::blocks::batch_error;
use super::fluctuations::Fluctuation;
use serde::{Deserialize, Serialize};

/// One snapshot's sums per slab.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrientationSample {
    /// sum of cos^2 Psi per slab
    pub sum_cos2: Vec<f64>,
    /// particles counted per slab
    pub count: Vec<u64>,
}

impl OrientationSample {
    /// The sums of one snapshot's fluctuations.
    pub fn of(f: &[Fluctuation], slabs: usize) -> Self {
        let mut s = OrientationSample {
            sum_cos2: vec![0.0; slabs],
            count: vec![0; slabs],
        };
        for p in f.iter().filter(|p| p.defined()) {
            let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            let (cc, ww) = (dot(p.c, p.c), dot(p.omega, p.omega));
            if cc > 0.0 && ww > 0.0 {
                let cw = dot(p.c, p.omega);
                s.sum_cos2[p.slab] += cw * cw / (cc * ww);
                s.count[p.slab] += 1;
            }
        }
        s
    }
}

/// Lambda of one slab over the window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "(u32, f64, f64, f64, u64)", from = "(u32, f64, f64, f64, u64)")]
pub struct OrientationRow {
    pub slab: u32,
    pub y: f64,
    /// <cos^2 Psi>
    pub lambda: f64,
    /// batch-means standard error
    pub error: f64,
    /// particles counted over the window
    pub samples: u64,
}

fn lambda(samples: &[&OrientationSample], slab: usize) -> f64 {
    let n: u64 = samples.iter().map(|s| s.count[slab]).sum();
    if n == 0 {
        return f64::NAN;
    }
    samples.iter().map(|s| s.sum_cos2[slab]).sum::<f64>() / n as f64
}

/// Lambda(y) over the window's samples.
pub fn analyse(
    samples: &[&OrientationSample],
    slabs: usize,
    y_of: &dyn Fn(usize) -> f64,
) -> Vec<OrientationRow> {
    let same: Vec<&OrientationSample> = samples
        .iter()
        .copied()
        .filter(|s| s.count.len() == slabs)
        .collect();
    (0..slabs)
        .filter_map(|b| {
            let n: u64 = same.iter().map(|s| s.count[b]).sum();
            (n > 0).then(|| OrientationRow {
                slab: b as u32,
                y: y_of(b),
                lambda: lambda(&same, b),
                error: batch_error(&same, |blk| lambda(blk, b)),
                samples: n,
            })
        })
        .collect()
}

row_as_tuple!(OrientationRow {
    slab: u32,
    y: f64,
    lambda: f64,
    error: f64,
    samples: u64
});
