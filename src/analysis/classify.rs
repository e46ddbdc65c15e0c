//! Structure classification: the xy density fluctuation split into families (transverse,
//! along-flow, antisymmetric and symmetric x-varying rest; plus the spanwise content of the xz
//! and yz planes), each compared with the shot-noise power of a random arrangement with the
//! same counts, and named from the families that stand clearly above that noise.
//!
//! Families of the xy fluctuation f(i, j) = phi(i, j) - <phi> (i along x, j across y):
//! - transverse t(j) = mean_i f (modes (0, k_y), plug content),
//! - along-flow s(i) = mean_j f (modes (k_x, 0), slug content),
//! - rest r = f - t - s (modes k_x != 0, k_y != 0), split by the reflection y -> W - y into
//!   the antisymmetric part a = (r - r~)/2 (S-wave content) and the symmetric part r - a.
//!
//! The four parts are orthogonal projections, so their powers add up to the total, and for a
//! random (multinomial) arrangement of N centres each of the D dimensions of a family carries
//! on average the same power P0 = 2 (pi/6)^2 N / V_grid^2 (see [`noise_per_mode`]).

use super::spectrum::{multiplicity, power_2d};

/// Power of each family of one snapshot (or averaged over snapshots), in units of phi^2 with
/// the spectrum's normalisation (the sum of P over the family's unfolded modes).
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyPowers {
    pub transverse: f64,
    pub along_flow: f64,
    pub antisymmetric: f64,
    pub symmetric_rest: f64,
    /// xz modes with k_z != 0 and yz modes with k_y != 0, k_z != 0 (structure along z)
    pub spanwise: f64,
    /// power of the antisymmetric family at each |k_x| = 0 ..= n1/2 (summed over k_y)
    pub antisymmetric_by_kx: Vec<f64>,
}

impl FamilyPowers {
    /// All zero, for a grid with `n1` cells along x.
    pub fn zero(n1: usize) -> Self {
        FamilyPowers {
            transverse: 0.0,
            along_flow: 0.0,
            antisymmetric: 0.0,
            symmetric_rest: 0.0,
            spanwise: 0.0,
            antisymmetric_by_kx: vec![0.0; n1 / 2 + 1],
        }
    }

    /// Add `w` times `other` (for window averages).
    pub fn add_scaled(&mut self, other: &FamilyPowers, w: f64) {
        self.transverse += w * other.transverse;
        self.along_flow += w * other.along_flow;
        self.antisymmetric += w * other.antisymmetric;
        self.symmetric_rest += w * other.symmetric_rest;
        self.spanwise += w * other.spanwise;
        for (a, b) in self
            .antisymmetric_by_kx
            .iter_mut()
            .zip(&other.antisymmetric_by_kx)
        {
            *a += w * b;
        }
    }

    /// Powers in the order of [`FAMILY_NAMES`].
    pub fn as_array(&self) -> [f64; 5] {
        [
            self.transverse,
            self.along_flow,
            self.antisymmetric,
            self.symmetric_rest,
            self.spanwise,
        ]
    }
}

/// Names of the families, in the order of [`FamilyPowers::as_array`].
pub const FAMILY_NAMES: [&str; 5] = [
    "transverse",
    "along-flow",
    "antisymmetric",
    "symmetric-rest",
    "spanwise",
];

/// Number of independent (real) dimensions D of each family on an n1 x n2 x n3 grid:
/// n2 - 1, n1 - 1, (n1 - 1) floor(n2/2), (n1 - 1)(ceil(n2/2) - 1), (n1 + n2 - 1)(n3 - 1).
pub fn family_dims(n: [usize; 3]) -> [usize; 5] {
    let [n1, n2, n3] = n;
    [
        n2 - 1,
        n1 - 1,
        (n1 - 1) * (n2 / 2),
        (n1 - 1) * (n2.div_ceil(2) - 1),
        (n1 + n2 - 1) * (n3 - 1),
    ]
}

/// Expected shot-noise power per family dimension (per unfolded mode) of a random arrangement
/// of `particles` centres in a gridded volume `volume`: P0 = 2 (pi/6)^2 N / V^2 = 2 phi^2 / N.
/// Exact for multinomial counts in equal cells, independent of the grid and of the plane.
pub fn noise_per_mode(particles: usize, volume: f64) -> f64 {
    let c = super::fields::SPHERE_VOLUME / volume;
    2.0 * c * c * particles as f64
}

/// Family powers of one snapshot from its plane fields (phi, layouts of
/// [`super::fields::plane_counts`]).
pub fn family_powers(xy: &[f64], xz: &[f64], yz: &[f64], n: [usize; 3]) -> FamilyPowers {
    let [n1, n2, n3] = n;
    let m = (n1 * n2) as f64;
    let mean = xy.iter().sum::<f64>() / m;
    let f: Vec<f64> = xy.iter().map(|v| v - mean).collect();
    let mut t = vec![0.0; n2];
    let mut s = vec![0.0; n1];
    for i in 0..n1 {
        for j in 0..n2 {
            t[j] += f[i * n2 + j] / n1 as f64;
            s[i] += f[i * n2 + j] / n2 as f64;
        }
    }
    let mut anti = vec![0.0; n1 * n2];
    let mut sym = vec![0.0; n1 * n2];
    for i in 0..n1 {
        for j in 0..n2 {
            let r = |j: usize| f[i * n2 + j] - t[j] - s[i];
            let a = 0.5 * (r(j) - r(n2 - 1 - j));
            anti[i * n2 + j] = a;
            sym[i * n2 + j] = r(j) - a;
        }
    }
    // Parseval: sum over unfolded modes of P = 2 sum g^2 / M
    let power = |g: &[f64], cells: f64| 2.0 * g.iter().map(|v| v * v).sum::<f64>() / cells;
    let mut by_kx = vec![0.0; n1 / 2 + 1];
    if n1 > 1 && n2 > 1 {
        let p = power_2d(&anti, n1, n2);
        for i in 0..n1 {
            let k = super::spectrum::folded_wavenumber(i, n1);
            by_kx[k] += p[i * n2..(i + 1) * n2].iter().sum::<f64>();
        }
    }
    FamilyPowers {
        transverse: power(&t, n2 as f64),
        along_flow: power(&s, n1 as f64),
        antisymmetric: power(&anti, m),
        symmetric_rest: power(&sym, m),
        spanwise: z_varying_power(xz, n1, n3, false) + z_varying_power(yz, n2, n3, true),
        antisymmetric_by_kx: by_kx,
    }
}

/// Power of the modes with k_z != 0 of a plane field g[a n3 + k] (and, when `drop_first`,
/// also without the modes with k_a = 0, which the xz plane already counts).
fn z_varying_power(g: &[f64], na: usize, n3: usize, drop_first: bool) -> f64 {
    let m = (na * n3) as f64;
    let row: Vec<f64> = (0..na)
        .map(|a| g[a * n3..(a + 1) * n3].iter().sum::<f64>() / n3 as f64)
        .collect();
    let mut col = vec![0.0; n3];
    let mean = g.iter().sum::<f64>() / m;
    for a in 0..na {
        for k in 0..n3 {
            col[k] += g[a * n3 + k] / na as f64;
        }
    }
    let mut sum = 0.0;
    for a in 0..na {
        for k in 0..n3 {
            let mut v = g[a * n3 + k] - row[a];
            if drop_first {
                v -= col[k] - mean;
            }
            sum += v * v;
        }
    }
    2.0 * sum / m
}

/// z of the one-sided significance test: a family is above noise when its power exceeds the
/// 5-sigma quantile of its noise distribution (false-alarm probability ~3e-7 per test).
pub const SIGNIFICANCE_Z: f64 = 5.0;

/// A family must also carry at least as much structure power as noise power (ratio >= 2) to
/// count as "clearly above noise", however many snapshots are averaged.
pub const MIN_RATIO: f64 = 2.0;

/// Fraction of the antisymmetric excess power in one k_x above which the antisymmetric content
/// is a wave coherent over the whole length (an S-wave with that many humps) rather than a
/// modulation confined to a slug (which spreads over about L / slug length wave numbers).
pub const COHERENCE_THRESHOLD: f64 = 0.5;

/// Threshold on the ratio power / mean noise power of a family with `dims` dimensions averaged
/// over `snapshots` independent snapshots. Under noise the ratio is chi^2_nu / nu with
/// nu = dims x snapshots; the SIGNIFICANCE_Z quantile is taken from the Wilson-Hilferty cube-root
/// normal approximation, nu (1 - 2/(9 nu) + z sqrt(2/(9 nu)))^3, and floored at MIN_RATIO.
pub fn threshold_ratio(dims: usize, snapshots: usize) -> f64 {
    let nu = (dims * snapshots) as f64;
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    let h = 2.0 / (9.0 * nu);
    (1.0 - h + SIGNIFICANCE_Z * h.sqrt()).powi(3).max(MIN_RATIO)
}

/// The verdict on one set of family powers, with the numbers behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct Assessment {
    /// "homogeneous", "plug", "s-wave", "slug", "wavy-slug" or "s-wave+slug"
    pub label: &'static str,
    /// humps of the S-wave (dominant k_x of the antisymmetric family), 0 without an S-wave
    pub humps: u32,
    /// structure along z stands above noise
    pub three_dimensional: bool,
    /// power / expected noise power, per family ([`FAMILY_NAMES`] order)
    pub ratios: [f64; 5],
    /// the thresholds the ratios were compared with
    pub thresholds: [f64; 5],
    /// dominant |k_x| of the antisymmetric excess power (0 if there is none)
    pub antisymmetric_kx: u32,
    /// fraction of the antisymmetric excess power in that k_x
    pub coherence: f64,
}

/// Name the structure from family powers averaged over `snapshots` snapshots, with noise P0
/// per dimension, on grid `n`.
pub fn assess(p: &FamilyPowers, n: [usize; 3], p0: f64, snapshots: usize) -> Assessment {
    let dims = family_dims(n);
    let powers = p.as_array();
    let mut ratios = [0.0; 5];
    let mut thresholds = [0.0; 5];
    let mut sig = [false; 5];
    for f in 0..5 {
        ratios[f] = if dims[f] > 0 && p0 > 0.0 {
            powers[f] / (dims[f] as f64 * p0)
        } else {
            0.0
        };
        thresholds[f] = threshold_ratio(dims[f], snapshots);
        sig[f] = ratios[f] > thresholds[f];
    }
    // excess antisymmetric power per |k_x| over its noise, floor(n2/2) dims per unfolded k_x
    let mut best = (0usize, 0.0f64);
    let mut total = 0.0;
    for (k, &pk) in p.antisymmetric_by_kx.iter().enumerate().skip(1) {
        let noise = (multiplicity(k, n[0]) * (n[1] / 2)) as f64 * p0;
        let excess = (pk - noise).max(0.0);
        total += excess;
        if excess > best.1 {
            best = (k, excess);
        }
    }
    let coherence = if total > 0.0 { best.1 / total } else { 0.0 };
    let [transverse, along, anti, sym, span] = sig;
    let (label, humps) = if anti && along {
        if coherence >= COHERENCE_THRESHOLD {
            ("s-wave+slug", best.0 as u32)
        } else {
            ("wavy-slug", 0)
        }
    } else if anti {
        ("s-wave", best.0 as u32)
    } else if along {
        ("slug", 0)
    } else if transverse || sym {
        ("plug", 0)
    } else {
        ("homogeneous", 0)
    };
    Assessment {
        label,
        humps,
        three_dimensional: span,
        ratios,
        thresholds,
        antisymmetric_kx: best.0 as u32,
        coherence,
    }
}
