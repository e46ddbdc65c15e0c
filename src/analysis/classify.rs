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
//!
//! Two tests per family at the noise distribution of one snapshot, either one makes it
//! significant: the *sum test* (the family's total power against D P0; sensitive to structure
//! spread over many modes) and the *peak test* (the family's strongest folded mode against that
//! mode's noise, with the false-alarm probability shared among the family's modes; sensitive to
//! a structure in a few modes however fine the grid, since a family sum over many noise modes
//! dilutes it). Labels follow from the significant families ([`assess`]).

use super::spectrum::{fold, folded_shape, multiplicity, power_2d};

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
    /// folded spectra (layout of [`fold`]): the whole xy field, its antisymmetric and
    /// symmetric-rest parts, the xz and yz fields
    pub xy: Vec<f64>,
    pub antisymmetric_modes: Vec<f64>,
    pub symmetric_modes: Vec<f64>,
    pub xz: Vec<f64>,
    pub yz: Vec<f64>,
}

impl FamilyPowers {
    /// All zero, for grid `n`.
    pub fn zero(n: [usize; 3]) -> Self {
        let size = |a: usize, b: usize| {
            let (m1, m2) = folded_shape(a, b);
            vec![0.0; m1 * m2]
        };
        FamilyPowers {
            transverse: 0.0,
            along_flow: 0.0,
            antisymmetric: 0.0,
            symmetric_rest: 0.0,
            spanwise: 0.0,
            xy: size(n[0], n[1]),
            antisymmetric_modes: size(n[0], n[1]),
            symmetric_modes: size(n[0], n[1]),
            xz: size(n[0], n[2]),
            yz: size(n[1], n[2]),
        }
    }

    /// Add `w` times `other` (for window averages).
    pub fn add_scaled(&mut self, other: &FamilyPowers, w: f64) {
        self.transverse += w * other.transverse;
        self.along_flow += w * other.along_flow;
        self.antisymmetric += w * other.antisymmetric;
        self.symmetric_rest += w * other.symmetric_rest;
        self.spanwise += w * other.spanwise;
        for (mine, theirs) in [
            (&mut self.xy, &other.xy),
            (&mut self.antisymmetric_modes, &other.antisymmetric_modes),
            (&mut self.symmetric_modes, &other.symmetric_modes),
            (&mut self.xz, &other.xz),
            (&mut self.yz, &other.yz),
        ] {
            for (a, b) in mine.iter_mut().zip(theirs) {
                *a += w * b;
            }
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
    let folded = |g: &[f64], a: usize, b: usize| fold(&power_2d(g, a, b), a, b);
    FamilyPowers {
        transverse: power(&t, n2 as f64),
        along_flow: power(&s, n1 as f64),
        antisymmetric: power(&anti, m),
        symmetric_rest: power(&sym, m),
        spanwise: z_varying_power(xz, n1, n3, false) + z_varying_power(yz, n2, n3, true),
        xy: folded(xy, n1, n2),
        antisymmetric_modes: folded(&anti, n1, n2),
        symmetric_modes: folded(&sym, n1, n2),
        xz: folded(xz, n1, n3),
        yz: folded(yz, n2, n3),
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
/// 5-sigma quantile of its noise distribution (false-alarm probability ~2.9e-7 per test).
pub const SIGNIFICANCE_Z: f64 = 5.0;

/// A family must also carry at least as much structure power as noise power (ratio >= 2) to
/// count as "clearly above noise".
pub const MIN_RATIO: f64 = 2.0;

/// Share of the antisymmetric excess power in the odd harmonics of one fundamental k_x = n
/// at or above which the antisymmetric content is an S-wave with n humps: the glide-symmetric
/// part carries at least twice the power of the rest. An S-wave (a band whose centre snakes
/// along x with n humps, whatever its shape, amplitude or thickness modulation) is invariant
/// under the glide x -> x + L/(2n), y -> W - y, so its antisymmetric power lies at k_x = n, 3n,
/// 5n, ... only (share 1 up to noise); an antisymmetric modulation confined to a slug spreads
/// over neighbouring wave numbers, odd and even alike (share about 1/2).
pub const COHERENCE_THRESHOLD: f64 = 2.0 / 3.0;

/// False-alarm probability of one test, P(Z > SIGNIFICANCE_Z) for a standard normal Z.
pub fn false_alarm() -> f64 {
    0.5 * libm::erfc(SIGNIFICANCE_Z / std::f64::consts::SQRT_2)
}

/// Sum-test threshold on the ratio power / mean noise power of a family with `dims` dimensions:
/// the quantile of chi^2_D / D at the false-alarm probability of [`false_alarm`], at least
/// MIN_RATIO. The noise distribution is that of one snapshot: a structure is named when it
/// would stand out of the noise of a single snapshot; averaging the window makes its measured
/// power precise but does not lower the bar (so a longer run does not turn faint modulations
/// into new labels).
pub fn threshold_ratio(dims: usize) -> f64 {
    chi2_ratio_quantile(dims as f64, false_alarm()).max(MIN_RATIO)
}

/// The x / nu with P(chi^2_nu > x) = p (bisection on the regularised upper incomplete gamma
/// function Q(nu/2, x/2)).
pub fn chi2_ratio_quantile(nu: f64, p: f64) -> f64 {
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    let (mut lo, mut hi) = (0.0, nu + 60.0 * (2.0 * nu).sqrt() + 400.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if gamma_q(0.5 * nu, 0.5 * mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / nu
}

/// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): series for
/// x < a + 1, Lentz continued fraction otherwise (Numerical Recipes 6.2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_prefactor = -x + a * x.ln() - libm::lgamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * ln_prefactor.exp()).max(0.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        ln_prefactor.exp() * h
    }
}

/// A folded mode of a family: plane, wave numbers, power, and its real dimensions (its noise
/// power is dims x P0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    pub plane: &'static str,
    pub k1: usize,
    pub k2: usize,
    pub power: f64,
    pub dims: usize,
}

/// The folded modes of each family ([`FAMILY_NAMES`] order) with their dimensions.
/// Transverse: xy (0, k_y); along-flow: xy (k_x, 0); antisymmetric and symmetric rest: their
/// fields' (k_x >= 1, k_y >= 1), where the reflection y -> W - y splits the dimensions of a
/// folded mode evenly, except at the Nyquist k_y = n2/2, which is purely antisymmetric;
/// spanwise: xz (k_x, k_z >= 1) and yz (k_y >= 1, k_z >= 1).
pub fn family_modes(p: &FamilyPowers, n: [usize; 3]) -> [Vec<Mode>; 5] {
    let [n1, n2, n3] = n;
    let mut out: [Vec<Mode>; 5] = Default::default();
    let (m1, m2) = folded_shape(n1, n2);
    let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
    for k1 in 0..m1 {
        for k2 in 0..m2 {
            let i = k1 * m2 + k2;
            let dims = multiplicity(k1, n1) * multiplicity(k2, n2);
            let mode = |plane, power, dims| Mode {
                plane,
                k1,
                k2,
                power,
                dims,
            };
            match (k1, k2) {
                (0, 0) => {}
                (0, _) => out[0].push(mode("xy", at(&p.xy, i), dims)),
                (_, 0) => out[1].push(mode("xy", at(&p.xy, i), dims)),
                _ => {
                    let nyquist = 2 * k2 == n2;
                    let (da, ds) = if nyquist {
                        (dims, 0)
                    } else {
                        (dims / 2, dims / 2)
                    };
                    out[2].push(mode("xy-antisymmetric", at(&p.antisymmetric_modes, i), da));
                    if ds > 0 {
                        out[3].push(mode("xy-symmetric", at(&p.symmetric_modes, i), ds));
                    }
                }
            }
        }
    }
    for (plane, v, na) in [("xz", &p.xz, n1), ("yz", &p.yz, n2)] {
        let (ma, m3) = folded_shape(na, n3);
        for ka in 0..ma {
            for k3 in 1..m3 {
                if plane == "yz" && ka == 0 {
                    continue; // (0, k_z) of yz is (0, k_z) of xz
                }
                out[4].push(Mode {
                    plane,
                    k1: ka,
                    k2: k3,
                    power: at(v, ka * m3 + k3),
                    dims: multiplicity(ka, na) * multiplicity(k3, n3),
                });
            }
        }
    }
    out
}

/// The modes of a folded plane spectrum (layout of [`fold`], grid `na` x `nb`) that stand
/// above shot noise on their own: power / (dims P0) above the peak test's threshold with the
/// false-alarm probability shared among the plane's modes, as the families' peak test shares
/// it among theirs. Returns (k1, k2, power / (dims P0), threshold), strongest first.
pub fn significant_plane_modes(
    folded: &[f64],
    na: usize,
    nb: usize,
    p0: f64,
) -> Vec<(usize, usize, f64, f64)> {
    let (m1, m2) = folded_shape(na, nb);
    let modes: Vec<(usize, usize, f64, usize)> = (0..m1)
        .flat_map(|k1| (0..m2).map(move |k2| (k1, k2)))
        .filter(|&(k1, k2)| k1 + k2 > 0 && k1 * m2 + k2 < folded.len())
        .map(|(k1, k2)| {
            let dims = multiplicity(k1, na) * multiplicity(k2, nb);
            (k1, k2, folded[k1 * m2 + k2], dims)
        })
        .collect();
    if modes.is_empty() || p0 <= 0.0 {
        return Vec::new();
    }
    let p_mode = false_alarm() / modes.len() as f64;
    let mut out: Vec<(usize, usize, f64, f64)> = modes
        .into_iter()
        .filter_map(|(k1, k2, power, dims)| {
            let ratio = power / (dims as f64 * p0);
            let threshold = chi2_ratio_quantile(dims as f64, p_mode).max(MIN_RATIO);
            (ratio > threshold).then_some((k1, k2, ratio, threshold))
        })
        .collect();
    out.sort_by(|a, b| b.2.total_cmp(&a.2));
    out
}

/// The strongest mode of a family relative to its peak-test threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    pub mode: Mode,
    /// power / (dims P0)
    pub ratio: f64,
    /// the peak-test threshold of that mode
    pub threshold: f64,
}

/// The verdict on one set of family powers, with the numbers behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct Assessment {
    /// "homogeneous", "plug", "s-wave", "slug", "wavy-slug" or "s-wave+slug"
    pub label: &'static str,
    /// humps of the S-wave (the fundamental k_x of the antisymmetric family), 0 without an
    /// S-wave
    pub humps: u32,
    /// structure along z stands above noise
    pub three_dimensional: bool,
    /// family power / expected noise power ([`FAMILY_NAMES`] order)
    pub ratios: [f64; 5],
    /// the sum-test thresholds the ratios were compared with
    pub thresholds: [f64; 5],
    /// the strongest mode of each family against its peak-test threshold
    pub peaks: [Option<Peak>; 5],
    /// max(ratio / threshold, peak ratio / peak threshold): > 1 means significant
    pub significance: [f64; 5],
    /// the same test on the slug content: the along-flow modes that are not even harmonics
    /// (2n, 4n, ...) of an S-wave with n humps (all along-flow modes without an S-wave)
    pub slug: f64,
    /// fundamental k_x = n of the antisymmetric excess power (0 if there is none)
    pub antisymmetric_kx: u32,
    /// share of the antisymmetric excess power in the odd harmonics n, 3n, 5n, ... of it
    pub coherence: f64,
}

/// Sum test and peak test of a set of modes with `dims` dimensions in all: (ratio, sum-test
/// threshold, strongest mode against its peak threshold, significance).
fn test_modes(modes: &[Mode], p0: f64) -> (f64, f64, Option<Peak>, f64) {
    let dims: usize = modes.iter().map(|m| m.dims).sum();
    let power: f64 = modes.iter().map(|m| m.power).sum();
    let ratio = if dims > 0 && p0 > 0.0 {
        power / (dims as f64 * p0)
    } else {
        0.0
    };
    let threshold = threshold_ratio(dims);
    let mut significance = ratio / threshold;
    let tested: Vec<&Mode> = modes.iter().filter(|m| m.dims > 0).collect();
    if tested.is_empty() || p0 <= 0.0 {
        return (ratio, threshold, None, significance);
    }
    // the family's false-alarm probability shared among its modes (Bonferroni)
    let p_mode = false_alarm() / tested.len() as f64;
    let mut peak: Option<Peak> = None;
    for m in tested {
        let ratio = m.power / (m.dims as f64 * p0);
        let threshold = chi2_ratio_quantile(m.dims as f64, p_mode).max(MIN_RATIO);
        if peak.is_none_or(|q| ratio / threshold > q.ratio / q.threshold) {
            peak = Some(Peak {
                mode: *m,
                ratio,
                threshold,
            });
        }
    }
    if let Some(q) = peak {
        significance = significance.max(q.ratio / q.threshold);
    }
    (ratio, threshold, peak, significance)
}

/// The S-wave content of the antisymmetric modes: (fundamental n, share of the excess power
/// in n, 3n, 5n, ...). The dominant k_x column (largest excess over its noise) is an odd
/// harmonic of the fundamental; the fundamental is its smallest divisor d with an odd
/// quotient whose column stands above noise by the peak test (dims of the column, the
/// family's false-alarm probability shared among the columns), so a sharp band whose third
/// harmonic outweighs its first still has one hump. Excess powers are not clipped at zero,
/// so noise columns add nothing on average.
fn s_wave_content(antisymmetric: &[Mode], n1: usize, p0: f64) -> (u32, f64) {
    let mut columns = vec![(0.0, 0usize); n1 / 2 + 1];
    for m in antisymmetric {
        columns[m.k1].0 += m.power;
        columns[m.k1].1 += m.dims;
    }
    let excess: Vec<f64> = columns.iter().map(|&(p, d)| p - d as f64 * p0).collect();
    let total: f64 = excess.iter().skip(1).sum();
    let Some(dominant) = (1..columns.len())
        .filter(|&k| columns[k].1 > 0)
        .max_by(|&a, &b| excess[a].total_cmp(&excess[b]))
    else {
        return (0, 0.0);
    };
    if total <= 0.0 || excess[dominant] <= 0.0 {
        return (0, 0.0);
    }
    let p_column = false_alarm() / (columns.len() - 1) as f64;
    let stands_out = |k: usize| {
        let (p, d) = columns[k];
        d > 0 && p / (d as f64 * p0) > chi2_ratio_quantile(d as f64, p_column).max(MIN_RATIO)
    };
    let fundamental = (1..=dominant)
        .find(|&d| dominant % d == 0 && (dominant / d) % 2 == 1 && stands_out(d))
        .unwrap_or(dominant);
    let odd_harmonics: f64 = (fundamental..columns.len())
        .step_by(2 * fundamental)
        .map(|k| excess[k])
        .sum();
    (fundamental as u32, (odd_harmonics / total).clamp(0.0, 1.0))
}

/// Name the structure from family powers (of one snapshot or averaged over a window), with
/// noise P0 per dimension, on grid `n`.
pub fn assess(p: &FamilyPowers, n: [usize; 3], p0: f64) -> Assessment {
    let modes = family_modes(p, n);
    let mut ratios = [0.0; 5];
    let mut thresholds = [0.0; 5];
    let mut peaks: [Option<Peak>; 5] = [None; 5];
    let mut significance = [0.0; 5];
    for f in 0..5 {
        (ratios[f], thresholds[f], peaks[f], significance[f]) = test_modes(&modes[f], p0);
    }
    let (kx, coherence) = s_wave_content(&modes[2], n[0], p0);
    let s_wave = significance[2] > 1.0 && coherence >= COHERENCE_THRESHOLD;
    // an S-wave's own along-flow content (its band's thickness or density varying along it,
    // a glide-symmetric part) lies at the even harmonics 2n, 4n, ...: not a slug
    let slug = if s_wave {
        let own = |m: &&Mode| m.k1 % (2 * kx as usize) != 0;
        let rest: Vec<Mode> = modes[1].iter().filter(own).copied().collect();
        test_modes(&rest, p0).3
    } else {
        significance[1]
    };
    let mut sig = significance.map(|s| s > 1.0);
    sig[1] = slug > 1.0;
    let (label, humps) = name_structure(sig, coherence, kx);
    Assessment {
        label,
        humps,
        three_dimensional: sig[4],
        ratios,
        thresholds,
        peaks,
        significance,
        slug,
        antisymmetric_kx: kx,
        coherence,
    }
}

/// The structure named by which contents are significant ([`FAMILY_NAMES`] order, with the
/// slug content in place of the along-flow family), the share of the antisymmetric excess in
/// the odd harmonics of its fundamental and that fundamental k_x (the label table of
/// docs/analysis.md).
pub fn name_structure(significant: [bool; 5], coherence: f64, kx: u32) -> (&'static str, u32) {
    let [transverse, slug, anti, sym, _span] = significant;
    let wave = coherence >= COHERENCE_THRESHOLD;
    if anti && slug {
        if wave {
            ("s-wave+slug", kx)
        } else {
            ("wavy-slug", 0)
        }
    } else if anti {
        ("s-wave", kx)
    } else if slug {
        ("slug", 0)
    } else if transverse || sym {
        ("plug", 0)
    } else {
        ("homogeneous", 0)
    }
}
