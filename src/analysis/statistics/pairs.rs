//! One pass over the pairs of a snapshot closer than r_max, with cell lists (O(N) for a fixed
//! r_max): the counts behind g(r) and the sums behind the velocity correlations, per slab of
//! the test particle, and the fine profile of centres across y that normalises g(r).
//!
//! Every unordered pair {i, j} with r_ij < r_max (minimum image along the periodic axes) is
//! counted twice: once in the slab of i at the distance bin of r_ij, once in the slab of j. So
//! a slab's counts are "partners at distance r of a particle in the slab", partners anywhere
//! in the box. For the velocity correlations the pair adds the symmetrised product
//! (C_a^i C_b^j + C_b^i C_a^j) / 2 for the six pairs of components xx, yy, zz, xy, xz, yz, when
//! both particles have a fluctuation.
//!
//! Cells have sides >= r_max / 2 (and >= the volume per particle^(1/3)), so a pair closer than
//! r_max lies within two cells of each other along every axis (a stencil of 5 x 5 x 5 cells, half of it visited from each cell);
//! a periodic axis with fewer than five such cells is one cell wide (every pair along it is
//! then found by the minimum image, which is unique because r_max is at most half the period).
//! The minimum image is taken by comparison with half the period (centres lie in the box), not
//! by a division.

use super::fluctuations::Fluctuation;
use crate::engine::Particles;
use serde::{Deserialize, Serialize};

/// Component pairs of the velocity correlations, in record order.
pub const PAIRS: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];
const PAIR_AXES: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// Fine cells of the centre profile across y: about this wide (d).
pub const FINE_CELL: f64 = 0.1;

/// One snapshot's pair sums.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairSample {
    /// r_max used (the setting, capped at half the shortest periodic extent)
    pub r_max: f64,
    /// dr of the g(r) bins
    pub dr: f64,
    /// g(r) bins per slab: ceil(r_max / dr)
    pub r_bins: u32,
    /// g(r) bins per velocity-correlation bin
    pub per_vcf_bin: u32,
    /// fine cells per slab of the centre profile
    pub fine_per_slab: u32,
    /// centres per fine cell across y (over [0, W])
    pub fine_counts: Vec<u32>,
    /// ordered pairs per slab and distance bin, slab * r_bins + bin
    pub counts: Vec<u32>,
    /// sums of the symmetrised products, (slab * vcf_bins + bin) * 6 + component pair
    pub products: Vec<f64>,
    /// ordered pairs in those sums (both particles with a fluctuation), slab * vcf_bins + bin
    pub product_pairs: Vec<u32>,
    /// per slab, sum over its particles of C_a C_b (the six pairs; the normalisation)
    pub self_products: Vec<f64>,
    /// per slab, particles with a fluctuation
    pub self_count: Vec<u64>,
}

impl PairSample {
    /// Velocity-correlation bins per slab.
    pub fn vcf_bins(&self) -> usize {
        (self.r_bins as usize).div_ceil(self.per_vcf_bin.max(1) as usize)
    }
}

/// The largest r_max a box allows: half its shortest periodic extent.
pub fn max_range(p: &Particles) -> f64 {
    let [l, w, h] = p.geometry.extents();
    let mut m = 0.5 * l.min(h);
    if !p.geometry.walls {
        m = m.min(0.5 * w);
    }
    m
}

/// The pair sums of one snapshot: g(r) bins of width `dr` up to `r_max` (capped by
/// [`max_range`]), velocity-correlation bins of `per_vcf_bin` g(r) bins.
pub fn sample(
    p: &Particles,
    f: &[Fluctuation],
    slabs: usize,
    r_max: f64,
    dr: f64,
    per_vcf_bin: usize,
) -> PairSample {
    let [l, w, h] = p.geometry.extents();
    let ext = [l, w, h];
    let periodic = [true, !p.geometry.walls, true];
    let r_max = r_max.min(max_range(p));
    let r_bins = ((r_max / dr).ceil() as usize).max(1);
    let per = per_vcf_bin.max(1);
    let vcf_bins = r_bins.div_ceil(per);
    let fine_per_slab = ((w / slabs as f64 / FINE_CELL).round() as usize).max(1);
    let mut s = PairSample {
        r_max,
        dr,
        r_bins: r_bins as u32,
        per_vcf_bin: per as u32,
        fine_per_slab: fine_per_slab as u32,
        fine_counts: vec![0; slabs * fine_per_slab],
        counts: vec![0; slabs * r_bins],
        products: vec![0.0; slabs * vcf_bins * 6],
        product_pairs: vec![0; slabs * vcf_bins],
        self_products: vec![0.0; slabs * 6],
        self_count: vec![0; slabs],
    };
    let fine = slabs * fine_per_slab;
    for (r, q) in p.positions.iter().zip(f) {
        s.fine_counts[super::fluctuations::slab_of(r[1], w, fine)] += 1;
        if q.defined() {
            s.self_count[q.slab] += 1;
            for (k, &(a, b)) in PAIR_AXES.iter().enumerate() {
                s.self_products[q.slab * 6 + k] += q.c[a] * q.c[b];
            }
        }
    }
    // cells of side >= r_max / REACH; a periodic axis with fewer than 2 REACH + 1 is one
    // cell wide
    // (and of at least the volume per particle, so that a dilute box with a short r_max is
    // not cut into far more cells than it has particles)
    const REACH: usize = 2;
    let per_particle = (l * w * h / p.len().max(1) as f64).cbrt();
    let side = (r_max / REACH as f64).max(per_particle);
    let n: [usize; 3] = [0, 1, 2].map(|a| {
        let k = ((ext[a] / side).floor() as usize).clamp(1, 1 << 10);
        if periodic[a] && k < 2 * REACH + 1 {
            1
        } else {
            k
        }
    });
    let cell_of = |r: &[f64; 3]| -> usize {
        let c = [0, 1, 2].map(|a| super::fluctuations::slab_of(r[a], ext[a], n[a]));
        (c[0] * n[1] + c[1]) * n[2] + c[2]
    };
    let cells = n[0] * n[1] * n[2];
    // counting sort of the particles by cell
    let cell: Vec<usize> = p.positions.iter().map(cell_of).collect();
    let mut start = vec![0usize; cells + 1];
    for &c in &cell {
        start[c + 1] += 1;
    }
    for c in 0..cells {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut order = vec![0usize; cell.len()];
    for (i, &c) in cell.iter().enumerate() {
        order[fill[c]] = i;
        fill[c] += 1;
    }
    // the particles' data in cell order
    let items: Vec<Item> = order
        .iter()
        .map(|&i| Item {
            r: p.positions[i],
            c: f[i].c,
            slab: f[i].slab,
            defined: f[i].defined(),
        })
        .collect();
    let offsets =
        |a: usize| -> &'static [isize] { if n[a] == 1 { &[0] } else { &[-2, -1, 0, 1, 2] } };
    let mut stencil = Vec::new();
    for &dx in offsets(0) {
        for &dy in offsets(1) {
            for &dz in offsets(2) {
                if (dx, dy, dz) > (0, 0, 0) {
                    stencil.push([dx, dy, dz]);
                }
            }
        }
    }
    let lp = PairLoop {
        r2_max: r_max * r_max,
        inv_dr: 1.0 / dr,
        period: [0, 1, 2].map(|a| if periodic[a] { ext[a] } else { 0.0 }),
        half: [0, 1, 2].map(|a| {
            if periodic[a] {
                0.5 * ext[a]
            } else {
                f64::INFINITY
            }
        }),
        r_bins,
        per,
        vcf_bins,
    };
    for cx in 0..n[0] {
        for cy in 0..n[1] {
            for cz in 0..n[2] {
                let c = (cx * n[1] + cy) * n[2] + cz;
                let here = &items[start[c]..start[c + 1]];
                for (k, a) in here.iter().enumerate() {
                    for b in &here[k + 1..] {
                        lp.visit(a, b, &mut s);
                    }
                }
                for o in &stencil {
                    let mut d = [0usize; 3];
                    let mut inside = true;
                    for (a, (&at, &off)) in [cx, cy, cz].iter().zip(o).enumerate() {
                        let q = at as isize + off;
                        if (0..n[a] as isize).contains(&q) {
                            d[a] = q as usize;
                        } else if periodic[a] {
                            d[a] = q.rem_euclid(n[a] as isize) as usize;
                        } else {
                            inside = false;
                        }
                    }
                    if !inside {
                        continue;
                    }
                    let other = (d[0] * n[1] + d[1]) * n[2] + d[2];
                    let there = &items[start[other]..start[other + 1]];
                    for a in here {
                        for b in there {
                            lp.visit(a, b, &mut s);
                        }
                    }
                }
            }
        }
    }
    s
}

/// A particle as the pair loop reads it (in cell order).
struct Item {
    r: [f64; 3],
    c: [f64; 3],
    slab: usize,
    defined: bool,
}

/// The constants of the pair loop.
struct PairLoop {
    r2_max: f64,
    inv_dr: f64,
    /// the period along each axis (0 along a wall axis)
    period: [f64; 3],
    /// half the period (infinite along a wall axis)
    half: [f64; 3],
    r_bins: usize,
    per: usize,
    vcf_bins: usize,
}

impl PairLoop {
    /// Count the pair if it is closer than r_max (minimum image by comparison: centres lie in
    /// the box, so one period at most is to be taken off).
    #[inline(always)]
    fn visit(&self, a: &Item, b: &Item, s: &mut PairSample) {
        let mut d2 = 0.0;
        for k in 0..3 {
            let d = a.r[k] - b.r[k];
            let d = if d > self.half[k] {
                d - self.period[k]
            } else if d < -self.half[k] {
                d + self.period[k]
            } else {
                d
            };
            d2 += d * d;
        }
        if d2 < self.r2_max {
            self.count(a, b, d2, s);
        }
    }

    /// Add a pair closer than r_max to both particles' slabs.
    #[inline(always)]
    fn count(&self, a: &Item, b: &Item, d2: f64, s: &mut PairSample) {
        let bin = ((d2.sqrt() * self.inv_dr) as usize).min(self.r_bins - 1);
        s.counts[a.slab * self.r_bins + bin] += 1;
        s.counts[b.slab * self.r_bins + bin] += 1;
        if a.defined && b.defined {
            let v = bin / self.per;
            let (p, q) = (&a.c, &b.c);
            let products = [
                p[0] * q[0],
                p[1] * q[1],
                p[2] * q[2],
                0.5 * (p[0] * q[1] + p[1] * q[0]),
                0.5 * (p[0] * q[2] + p[2] * q[0]),
                0.5 * (p[1] * q[2] + p[2] * q[1]),
            ];
            for slab in [a.slab, b.slab] {
                let at = slab * self.vcf_bins + v;
                let sums = &mut s.products[at * 6..at * 6 + 6];
                for k in 0..6 {
                    sums[k] += products[k];
                }
                s.product_pairs[at] += 1;
            }
        }
    }
}
