//! Bond-orientational order: the sums from which the analysis forms Steinhardt's Q6
//! (Steinhardt, Nelson & Ronchetti 1983) of any region and time span (Debnath, Rao & Kumaran
//! 2022 check Q6 < 0.4 in the plug, dem.md O22/N16; they cite Kumaran 2009 for the definition
//! without giving it).
//!
//! Definitions:
//! - a *bond* joins two particles whose centres are closer than [`BOND_CUTOFF`] times the mean
//!   of their diameters (minimum image in x and z): 1.2 lies near the first minimum of g(r) of
//!   a dense packing, between the touching shell (1) and the next one (sqrt 2 in fcc, about
//!   1.7-2 in a random packing);
//! - a bond belongs to the bin of its midpoint (as the pair dissipation does);
//! - per bin the record keeps the bond count and, for m = -6..6, the sum over the bonds of the
//!   *real* spherical harmonic Y_6m of the bond direction ([`harmonics`]; an orthonormal
//!   basis of the same space as the complex Y_6m, so sum_m |sum Y_6m|^2 is the same in either
//!   form, and the sign of a bond does not matter, l being even);
//! - the Q6 of a set of bonds ([`BondSums::q6`]) is the global one:
//!   Q6 = sqrt(4 pi / 13 sum_m |sum_bonds Y_6m|^2) / n_bonds, i.e. sqrt(4 pi / 13
//!   sum_m |<Y_6m>|^2) with <.> the mean over the bonds. Sums add, so bins and snapshots pool
//!   exactly. A perfect fcc lattice gives 0.5745, simple cubic 0.3536, hcp 0.4848, and n
//!   bonds of random directions about 1 / sqrt(n);
//! - besides, per bin, the particles with their centre in it and at least one bond and the
//!   sum of their *local* q6 (the same formula over a particle's own bonds), for the
//!   particle-averaged form: fcc gives 0.5745 too, but a disordered packing of about 6-12
//!   neighbours gives about 0.3-0.5 (a finite set of directions is never isotropic), so the
//!   two forms read a threshold like the paper's 0.4 differently.
//!
//! The sums are taken in tag order (particle i ascending, then its partners j > i ascending),
//! whatever the working order, so they are a function of the positions alone: bitwise the
//! same on any number of threads and after a checkpoint and restore.

use super::domain::Domain;
use super::neighbours::Grid;
use super::sampling::Bins;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Two particles are bonded when their centres are closer than this times the mean of their
/// two diameters.
pub const BOND_CUTOFF: f64 = 1.2;

/// The harmonics kept: m = -6..6 (index m + 6).
pub const HARMONICS: usize = 13;

/// The bond sums of one bin (at one snapshot, or summed over several).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BondSums {
    /// bonds whose midpoint is in the bin
    pub bonds: f64,
    /// sum over those bonds of the real Y_6m of the bond direction, m = -6..6 (index m + 6)
    pub harmonics: [f64; HARMONICS],
    /// particles with their centre in the bin and at least one bond
    pub particles: f64,
    /// sum over those particles of their local q6 (the Q6 of their own bonds)
    pub local_q6: f64,
}

impl BondSums {
    /// Add a bond along `r` (any length, either sign).
    pub fn add_bond(&mut self, r: [f64; 3]) {
        self.add_harmonics(&harmonics(unit(r)));
    }

    /// Add a bond whose harmonics are `y`.
    fn add_harmonics(&mut self, y: &[f64; HARMONICS]) {
        for (h, y) in self.harmonics.iter_mut().zip(y) {
            *h += y;
        }
        self.bonds += 1.0;
    }

    /// self += other
    pub fn add(&mut self, other: &BondSums) {
        self.bonds += other.bonds;
        for (a, b) in self.harmonics.iter_mut().zip(&other.harmonics) {
            *a += b;
        }
        self.particles += other.particles;
        self.local_q6 += other.local_q6;
    }

    /// The global Q6 of these bonds, sqrt(4 pi / 13 sum_m |sum Y_6m|^2) / n_bonds (NaN without
    /// bonds).
    pub fn q6(&self) -> f64 {
        if self.bonds <= 0.0 {
            return f64::NAN;
        }
        let s: f64 = self.harmonics.iter().map(|h| h * h).sum();
        (4.0 * PI / 13.0 * s).sqrt() / self.bonds
    }

    /// The mean local q6 of the bonded particles (NaN without any).
    pub fn mean_local_q6(&self) -> f64 {
        if self.particles <= 0.0 {
            return f64::NAN;
        }
        self.local_q6 / self.particles
    }
}

fn unit(r: [f64; 3]) -> [f64; 3] {
    let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    [r[0] / len, r[1] / len, r[2] / len]
}

/// What a bond search fills: the bins' sums and each particle's own.
pub struct Accumulator<'a> {
    bins: &'a Bins,
    out: Vec<BondSums>,
    own: Vec<BondSums>,
}

impl<'a> Accumulator<'a> {
    /// Empty sums for `particles` particles in `bins`.
    pub fn new(bins: &'a Bins, particles: usize) -> Self {
        Accumulator {
            bins,
            out: vec![BondSums::default(); bins.len()],
            own: vec![BondSums::default(); particles],
        }
    }

    /// The bond between i and j (tags), r = x_i - x_j, with x_j the position of j: into the bin
    /// of its midpoint and into both particles' own sums.
    pub fn add(&mut self, i: usize, j: usize, r: [f64; 3], x_j: [f64; 3]) {
        let y = harmonics(unit(r));
        self.out[self.bins.of(x_j[1] + 0.5 * r[1])].add_harmonics(&y);
        self.own[i].add_harmonics(&y);
        self.own[j].add_harmonics(&y);
    }

    /// The bins' sums, with each bonded particle's local q6 added to the bin of its centre (in
    /// tag order).
    pub fn finish(mut self, positions: &[[f64; 3]]) -> Vec<BondSums> {
        for (own, x) in self.own.iter().zip(positions) {
            if own.bonds > 0.0 {
                let s = &mut self.out[self.bins.of(x[1])];
                s.particles += 1.0;
                s.local_q6 += own.q6();
            }
        }
        self.out
    }
}

/// The real spherical harmonics of degree 6 of a unit vector n, m = -6..6 (index m + 6), polar
/// axis z: Y_60 = K_0 P_6(z), and for m > 0 Y_6,m = sqrt 2 K_m P_6^m(z) cos(m phi),
/// Y_6,-m = sqrt 2 K_m P_6^m(z) sin(m phi), with K_m = sqrt(13 / (4 pi) (6 - m)! / (6 + m)!),
/// P_6^m(z) = (1 - z^2)^(m/2) d^m P_6 / dz^m (no Condon-Shortley sign: it cancels in the real
/// form) and (1 - z^2)^(m/2) e^(i m phi) = (x + i y)^m. Orthonormal on the unit sphere, and
/// sum_m Y_6m(n)^2 = 13 / (4 pi) for every n (the addition theorem).
pub fn harmonics(n: [f64; 3]) -> [f64; HARMONICS] {
    let [x, y, z] = n;
    let z2 = z * z;
    // d^m P_6 / dz^m, P_6 = (231 z^6 - 315 z^4 + 105 z^2 - 5) / 16
    let d = [
        (((231.0 * z2 - 315.0) * z2 + 105.0) * z2 - 5.0) / 16.0,
        (((1386.0 * z2 - 1260.0) * z2 + 210.0) * z) / 16.0,
        ((6930.0 * z2 - 3780.0) * z2 + 210.0) / 16.0,
        ((27720.0 * z2 - 7560.0) * z) / 16.0,
        (83160.0 * z2 - 7560.0) / 16.0,
        166320.0 * z / 16.0,
        166320.0 / 16.0,
    ];
    let mut out = [0.0; HARMONICS];
    out[6] = norm(0) * d[0];
    // (x + i y)^m
    let (mut re, mut im) = (1.0, 0.0);
    for m in 1..=6 {
        (re, im) = (re * x - im * y, re * y + im * x);
        let k = std::f64::consts::SQRT_2 * norm(m) * d[m];
        out[6 + m] = k * re;
        out[6 - m] = k * im;
    }
    out
}

/// K_m = sqrt(13 / (4 pi) (6 - m)! / (6 + m)!)
fn norm(m: usize) -> f64 {
    let ratio: f64 = ((6 - m + 1)..=(6 + m)).map(|k| 1.0 / k as f64).product();
    (13.0 / (4.0 * PI) * ratio).sqrt()
}

/// The bond sums per bin of particles at `positions` with `radii` (both in tag order) in the
/// box `domain`: a cell search over cells at least as wide as the longest bond, O(N); the
/// sums are taken in tag order (see the module's documentation).
pub fn bond_sums(
    domain: &Domain,
    bins: &Bins,
    positions: &[[f64; 3]],
    radii: &[f64],
) -> Vec<BondSums> {
    let n = positions.len();
    let mut acc = Accumulator::new(bins, n);
    if n == 0 {
        return acc.finish(positions);
    }
    let reach = 2.0 * BOND_CUTOFF * radii.iter().fold(0.0f64, |a, &r| a.max(r));
    let grid = Grid::new(domain, positions, reach);
    // counting sort by cell; within a cell in tag order
    let cell: Vec<usize> = positions
        .iter()
        .map(|x| grid.index(grid.coord(x)))
        .collect();
    let mut start = vec![0usize; grid.cells() + 1];
    for &c in &cell {
        start[c + 1] += 1;
    }
    for c in 0..grid.cells() {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut order = vec![0usize; n];
    for (i, &c) in cell.iter().enumerate() {
        order[fill[c]] = i;
        fill[c] += 1;
    }
    let mut partners: Vec<(usize, [f64; 3])> = Vec::new();
    for i in 0..n {
        partners.clear();
        let c = grid.coord(&positions[i]);
        let around: [_; 3] = std::array::from_fn(|k| grid.around(k, c[k]));
        for &a in &around[0].0[..around[0].1] {
            for &b in &around[1].0[..around[1].1] {
                for &e in &around[2].0[..around[2].1] {
                    let cell = grid.index([a, b, e]);
                    for &j in &order[start[cell]..start[cell + 1]] {
                        if j <= i {
                            continue;
                        }
                        if let Some(r) = bond(domain, positions, radii, i, j) {
                            partners.push((j, r));
                        }
                    }
                }
            }
        }
        partners.sort_unstable_by_key(|p| p.0);
        for &(j, r) in &partners {
            acc.add(i, j, r, positions[j]);
        }
    }
    acc.finish(positions)
}

/// r = x_i - x_j (minimum image) when i and j are bonded.
#[inline]
pub fn bond(
    domain: &Domain,
    positions: &[[f64; 3]],
    radii: &[f64],
    i: usize,
    j: usize,
) -> Option<[f64; 3]> {
    let (a, b) = (positions[i], positions[j]);
    let r = domain.min_image([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    let cut = BOND_CUTOFF * (radii[i] + radii[j]);
    (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] < cut * cut).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 12 nearest-neighbour directions of fcc (cube edge 2: (+-1, +-1, 0) and permutations).
    fn fcc() -> Vec<[f64; 3]> {
        let mut v = Vec::new();
        for a in [-1.0, 1.0] {
            for b in [-1.0, 1.0] {
                v.push([a, b, 0.0]);
                v.push([a, 0.0, b]);
                v.push([0.0, a, b]);
            }
        }
        v
    }

    fn q6_of(bonds: &[[f64; 3]]) -> f64 {
        let mut s = BondSums::default();
        for &r in bonds {
            s.add_bond(r);
        }
        s.q6()
    }

    /// A rotation by `angle` about the unit axis `u` (Rodrigues).
    fn rotate(r: [f64; 3], u: [f64; 3], angle: f64) -> [f64; 3] {
        let (s, c) = angle.sin_cos();
        let dot = u[0] * r[0] + u[1] * r[1] + u[2] * r[2];
        let cross = [
            u[1] * r[2] - u[2] * r[1],
            u[2] * r[0] - u[0] * r[2],
            u[0] * r[1] - u[1] * r[0],
        ];
        std::array::from_fn(|k| r[k] * c + cross[k] * s + u[k] * dot * (1.0 - c))
    }

    /// A small deterministic generator (SplitMix64) for uniform numbers in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn the_harmonics_are_orthonormal_and_obey_the_addition_theorem() {
        // the addition theorem at scattered directions
        let mut rng = Rng(7);
        for _ in 0..100 {
            let z = 2.0 * rng.next() - 1.0;
            let phi = 2.0 * PI * rng.next();
            let s = (1.0 - z * z).sqrt();
            let y = harmonics([s * phi.cos(), s * phi.sin(), z]);
            let sum: f64 = y.iter().map(|v| v * v).sum();
            assert!((sum - 13.0 / (4.0 * PI)).abs() < 1e-12, "{sum}");
        }
        // Y_60 at the pole
        assert!((harmonics([0.0, 0.0, 1.0])[6] - (13.0 / (4.0 * PI)).sqrt()).abs() < 1e-13);
        // orthonormality: Gauss-Legendre-free quadrature, midpoints in z (the integrands are
        // polynomials of degree <= 12 in z) and 32 equal steps in phi (exact for cos/sin of
        // order < 32)
        let (nz, nphi) = (4000, 32);
        let mut gram = [[0.0; HARMONICS]; HARMONICS];
        for a in 0..nz {
            let z = -1.0 + (a as f64 + 0.5) * 2.0 / nz as f64;
            let s = (1.0 - z * z).sqrt();
            for b in 0..nphi {
                let phi = 2.0 * PI * b as f64 / nphi as f64;
                let y = harmonics([s * phi.cos(), s * phi.sin(), z]);
                let w = (2.0 / nz as f64) * (2.0 * PI / nphi as f64);
                for (row, yp) in gram.iter_mut().zip(y) {
                    for (g, yq) in row.iter_mut().zip(y) {
                        *g += w * yp * yq;
                    }
                }
            }
        }
        for (p, row) in gram.iter().enumerate() {
            for (q, g) in row.iter().enumerate() {
                let want = if p == q { 1.0 } else { 0.0 };
                assert!(
                    (g - want).abs() < 1e-5,
                    "<Y_{}, Y_{}> = {g}",
                    p as i32 - 6,
                    q as i32 - 6
                );
            }
        }
    }

    #[test]
    fn q6_of_fcc_simple_cubic_and_hcp() {
        assert!(
            (q6_of(&fcc()) - 0.574_524).abs() < 1e-3,
            "{}",
            q6_of(&fcc())
        );
        let sc = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        assert!((q6_of(&sc) - 0.353_553).abs() < 1e-3, "{}", q6_of(&sc));
        // hcp: 6 in the plane, 3 above and 3 below (eclipsed)
        let mut hcp = Vec::new();
        for k in 0..6 {
            let a = PI / 3.0 * k as f64;
            hcp.push([a.cos(), a.sin(), 0.0]);
        }
        for k in 0..3 {
            let a = PI / 6.0 + 2.0 * PI / 3.0 * k as f64;
            let (rho, h) = (1.0 / 3f64.sqrt(), (2.0f64 / 3.0).sqrt());
            hcp.push([rho * a.cos(), rho * a.sin(), h]);
            hcp.push([rho * a.cos(), rho * a.sin(), -h]);
        }
        assert!((q6_of(&hcp) - 0.484_762).abs() < 1e-3, "{}", q6_of(&hcp));
        // the sign and the length of a bond do not matter
        let flipped: Vec<[f64; 3]> = fcc().iter().map(|r| r.map(|v| -2.5 * v)).collect();
        assert!((q6_of(&flipped) - q6_of(&fcc())).abs() < 1e-14);
    }

    #[test]
    fn q6_is_invariant_under_rotations() {
        let want = q6_of(&fcc());
        let mut rng = Rng(3);
        for _ in 0..20 {
            let z = 2.0 * rng.next() - 1.0;
            let phi = 2.0 * PI * rng.next();
            let s = (1.0 - z * z).sqrt();
            let axis = [s * phi.cos(), s * phi.sin(), z];
            let angle = 2.0 * PI * rng.next();
            let turned: Vec<[f64; 3]> = fcc().iter().map(|&r| rotate(r, axis, angle)).collect();
            let q = q6_of(&turned);
            assert!((q - want).abs() < 1e-12, "{q} vs {want}");
        }
    }

    #[test]
    fn random_bonds_have_no_order() {
        let mut rng = Rng(11);
        let bonds: Vec<[f64; 3]> = (0..20_000)
            .map(|_| {
                let z = 2.0 * rng.next() - 1.0;
                let phi = 2.0 * PI * rng.next();
                let s = (1.0 - z * z).sqrt();
                [s * phi.cos(), s * phi.sin(), z]
            })
            .collect();
        let q = q6_of(&bonds);
        // about 1 / sqrt(n) = 0.007
        assert!(q < 0.03, "{q}");
        assert!(BondSums::default().q6().is_nan());
        assert!(BondSums::default().mean_local_q6().is_nan());
        // a single bond is perfectly ordered
        assert!((q6_of(&[[0.3, -0.2, 0.9]]) - 1.0).abs() < 1e-12);
    }

    /// A box of random centres (an ideal gas: overlaps allowed) of the debnath sizes.
    fn gas(domain: &Domain, n: usize, seed: u64) -> (Vec<[f64; 3]>, Vec<f64>) {
        let mut rng = Rng(seed);
        let e = domain.extent;
        let x = (0..n)
            .map(|_| [e[0] * rng.next(), e[1] * rng.next(), e[2] * rng.next()])
            .collect();
        let r = (0..n).map(|k| [0.45, 0.5, 0.55][k % 3]).collect();
        (x, r)
    }

    /// All pairs i < j in tag order, each bond into the bin of its midpoint.
    fn all_pairs(domain: &Domain, bins: &Bins, x: &[[f64; 3]], r: &[f64]) -> Vec<BondSums> {
        let mut acc = Accumulator::new(bins, x.len());
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                if let Some(d) = bond(domain, x, r, i, j) {
                    acc.add(i, j, d, x[j]);
                }
            }
        }
        acc.finish(x)
    }

    #[test]
    fn the_cell_search_is_the_all_pairs_sum_bit_for_bit() {
        for (periodic_x, (l, w, b)) in [(true, (10.0, 8.0, 5.0)), (false, (7.0, 12.0, 3.0))] {
            let domain = Domain::new(l, w, b, periodic_x);
            let bins = Bins::new(w);
            let (x, r) = gas(&domain, 600, 5);
            let fast = bond_sums(&domain, &bins, &x, &r);
            let slow = all_pairs(&domain, &bins, &x, &r);
            assert_eq!(fast, slow);
            let bonds: f64 = fast.iter().map(|s| s.bonds).sum();
            assert!(bonds > 500.0, "{bonds}");
            // pooled over the channel: an ideal gas has no order
            let mut all = BondSums::default();
            for s in &fast {
                all.add(s);
            }
            assert!(all.q6() < 4.0 / bonds.sqrt(), "{}", all.q6());
        }
    }

    #[test]
    fn an_fcc_packing_in_a_channel_has_the_fcc_q6_in_its_interior() {
        // touching spheres of diameter 1 on an fcc lattice (cube edge sqrt 2), periodic in x
        // and z over 4 cells; across y 6 cells. The bonds with their midpoint at least one
        // cube edge from the lattice's faces in y see every neighbour direction equally often.
        let a = 2f64.sqrt();
        let cells = [4usize, 6, 4];
        let domain = Domain::new(4.0 * a, 6.0 * a + 1.0, 4.0 * a, true);
        let bins = Bins::new(domain.extent[1]);
        let basis = [
            [0.0, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [0.5, 0.0, 0.5],
            [0.0, 0.5, 0.5],
        ];
        let mut x = Vec::new();
        for i in 0..cells[0] {
            for j in 0..cells[1] {
                for k in 0..cells[2] {
                    for b in &basis {
                        x.push([
                            (i as f64 + b[0]) * a,
                            0.5 + (j as f64 + b[1]) * a,
                            (k as f64 + b[2]) * a,
                        ]);
                    }
                }
            }
        }
        let r = vec![0.5; x.len()];
        let sums = bond_sums(&domain, &bins, &x, &r);
        let total: f64 = sums.iter().map(|s| s.bonds).sum();
        // 12 neighbours, fewer at the two faces
        assert!(
            total < 6.0 * x.len() as f64 && total > 5.0 * x.len() as f64,
            "{total}"
        );
        // midpoints lie on planes a/4 apart; a slab of whole periods a away from the faces
        let mut whole = BondSums::default();
        let mut reference = BondSums::default();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                if let Some(d) = bond(&domain, &x, &r, i, j) {
                    let mid = x[j][1] + 0.5 * d[1];
                    if mid > 0.5 + a - 1e-9 && mid < 0.5 + 5.0 * a - 1e-9 {
                        reference.add_bond(d);
                    }
                }
            }
        }
        for s in &sums {
            whole.add(s);
        }
        assert!(
            (reference.q6() - 0.574_524).abs() < 1e-3,
            "{}",
            reference.q6()
        );
        // the whole channel, faces included, stays close to fcc
        assert!((whole.q6() - 0.5745).abs() < 0.05, "{}", whole.q6());
        // the bins 1..=6 hold the lattice planes 2..=10, whose particles have all 12
        // neighbours: their local q6 is fcc's
        for (k, s) in sums.iter().enumerate().take(7).skip(1) {
            let q = s.mean_local_q6();
            assert!((q - 0.574_524).abs() < 1e-5, "bin {k}: {q}");
        }
        let bonded: f64 = sums.iter().map(|s| s.particles).sum();
        assert_eq!(bonded, x.len() as f64);
    }
}
