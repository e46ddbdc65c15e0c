//! Free paths over the window (thesis 3.1.1): their distribution P(l) per slab and overall, the
//! mean free path lambda(y) and the Knudsen number Kn(y) = lambda(y) / W, W the wall-to-wall
//! width (the thesis first writes lambda / L, then computes lambda / W). What a path is and
//! where it belongs: [`crate::engine::free_paths`]. The tallies are those the engine handed
//! over at the window's snapshots after its first, so every path ended inside the window
//! counts once; lambda is the exact mean of the lengths, P(l) = count / (paths dl) on the
//! logarithmic bins (per d; it integrates to the fraction of paths within 2.4e-4 .. 16384 d).

use crate::engine::free_paths::{FreePathTally, LENGTH_BINS, STRIDE, length_edges};
use serde::{Deserialize, Serialize};

/// One point of P(l).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    into = "(Option<u32>, f64, f64, f64)",
    from = "(Option<u32>, f64, f64, f64)"
)]
pub struct FreePathRow {
    /// slab of the paths' midpoints; None: all slabs
    pub slab: Option<u32>,
    pub y: f64,
    /// bin centre, d
    pub l: f64,
    /// probability density of l, per d
    pub p: f64,
}

/// The mean free path of one slab.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "(u32, f64, f64, f64, u64)", from = "(u32, f64, f64, f64, u64)")]
pub struct KnudsenRow {
    pub slab: u32,
    pub y: f64,
    /// lambda, d
    pub mean_free_path: f64,
    /// lambda / W
    pub knudsen: f64,
    pub paths: u64,
}

/// What the window's tallies give.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FreePaths {
    pub distribution: Vec<FreePathRow>,
    pub profile: Vec<KnudsenRow>,
    /// lambda over all paths, d
    pub mean: f64,
    /// paths counted
    pub paths: u64,
    /// fraction of them ended by a wall collision
    pub wall_fraction: f64,
}

/// Sum the window's tallies (those of one shape) and derive P(l), lambda(y), Kn(y).
pub fn analyse(
    tallies: &[&FreePathTally],
    width: f64,
    y_of: &dyn Fn(usize) -> f64,
) -> Option<FreePaths> {
    let first = tallies.first()?;
    let mut total = first.emptied();
    for t in tallies {
        total.merge(t);
    }
    let slabs = total.slabs;
    let mut out = FreePaths::default();
    let all: u64 = (0..slabs).map(|s| total.paths(s)).sum();
    if all == 0 {
        return None;
    }
    out.paths = all;
    out.mean = total.total_length.iter().sum::<f64>() / all as f64;
    out.wall_fraction = total.wall_ended.iter().sum::<u64>() as f64 / all as f64;
    let mut rows = Vec::new();
    let mut distribution = |slab: Option<usize>, counts: &dyn Fn(usize) -> u64, n: u64| {
        if n == 0 {
            return;
        }
        for k in 0..LENGTH_BINS {
            let c = counts(1 + k);
            if c == 0 {
                continue;
            }
            let (lo, hi) = length_edges(k);
            rows.push(FreePathRow {
                slab: slab.map(|s| s as u32),
                y: slab.map_or(f64::NAN, y_of),
                l: 0.5 * (lo + hi),
                p: c as f64 / (n as f64 * (hi - lo)),
            });
        }
    };
    distribution(
        None,
        &|i| (0..slabs).map(|s| total.counts[s * STRIDE + i]).sum(),
        all,
    );
    for s in 0..slabs {
        distribution(Some(s), &|i| total.counts[s * STRIDE + i], total.paths(s));
    }
    out.distribution = rows;
    for s in 0..slabs {
        let n = total.paths(s);
        if n > 0 {
            let mean = total.total_length[s] / n as f64;
            out.profile.push(KnudsenRow {
                slab: s as u32,
                y: y_of(s),
                mean_free_path: mean,
                knudsen: mean / width,
                paths: n,
            });
        }
    }
    Some(out)
}

row_as_tuple!(FreePathRow { slab: Option<u32>, y: f64, l: f64, p: f64 });

row_as_tuple!(KnudsenRow {
    slab: u32,
    y: f64,
    mean_free_path: f64,
    knudsen: f64,
    paths: u64
});
