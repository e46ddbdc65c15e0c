//! Velocity distribution functions (thesis 3.2): the distributions of the six fluctuation
//! components C_x, C_y, C_z, Omega_x, Omega_y, Omega_z per slab, and their skewness and
//! kurtosis (new: the thesis computes no moments).
//!
//! Per snapshot, slab and component the record keeps the power sums S_k = sum u^k (k = 2, 3, 4)
//! of the unbiased fluctuation u = sqrt(N_k/(N_k - 1)) C and a histogram of u / sigma_s, with
//! sigma_s = sqrt(S_2 / n) that snapshot's standard deviation (bins of width dx centred on
//! 0, 0 included, out to +-x_max; what falls outside is counted apart).
//!
//! Over the window:
//! - sigma = sqrt(sum S_2 / sum n) (pooled over the window's snapshots: the thesis' "standard
//!   deviation of the given quantity", per slab);
//! - skewness = m_3 / m_2^(3/2), kurtosis = m_4 / m_2^2 with m_k = sum S_k / sum n (the
//!   fluctuations of a cell sum to zero, so these are central moments); 0 and 3 for a
//!   Gaussian; errors: batch means over contiguous blocks of the window's snapshots;
//! - the histogram: each snapshot's, in units of its own sigma_s, is rescaled to the pooled
//!   sigma (x -> x sigma_s / sigma, each bin's count spread uniformly over the bins it then
//!   covers) and summed; density = counts / (n dx) (it integrates to the fraction inside
//!   +-x_max) and p = density / density(0), where density(0) is the value of the bin centred on
//!   0: "the vertical axis is scaled such that P(0) = 1" (thesis). The Gaussian reference is
//!   then exp(-x^2 / 2). An asymmetric VDF need not peak at 1. Rows run from the first to the
//!   last bin holding counts.

use super::blocks::batch_error;
use super::fluctuations::Fluctuation;
use serde::{Deserialize, Serialize};

/// Component names, in record order.
pub const COMPONENTS: [&str; 6] = ["C_x", "C_y", "C_z", "Omega_x", "Omega_y", "Omega_z"];

/// One snapshot's sums and histograms.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VdfSample {
    /// components recorded: 3 (no spins) or 6
    pub components: u8,
    /// J: the histogram has 2J + 1 bins, centred on -J dx .. J dx
    pub half: u32,
    /// dx, in units of sigma_s
    pub dx: f64,
    /// per slab and component (index slab * 6 + component): fluctuations counted
    pub count: Vec<u64>,
    /// S_2, S_3, S_4 of the unbiased fluctuation
    pub s2: Vec<f64>,
    pub s3: Vec<f64>,
    pub s4: Vec<f64>,
    /// histograms of u / sigma_s, (slab * 6 + component) * (2J + 1) + bin
    pub histogram: Vec<u32>,
    /// fluctuations beyond +-(J + 1/2) dx
    pub outside: Vec<u32>,
}

impl VdfSample {
    /// The sums and histograms of one snapshot's fluctuations over `slabs` slabs.
    pub fn of(f: &[Fluctuation], slabs: usize, spins: bool, half: u32, dx: f64) -> Self {
        let series = slabs * 6;
        let width = 2 * half as usize + 1;
        let components = if spins { 6 } else { 3 };
        let mut s = VdfSample {
            components: components as u8,
            half,
            dx,
            count: vec![0; series],
            s2: vec![0.0; series],
            s3: vec![0.0; series],
            s4: vec![0.0; series],
            histogram: vec![0; series * width],
            outside: vec![0; series],
        };
        let value =
            |p: &Fluctuation, a: usize| p.unbiased * if a < 3 { p.c[a] } else { p.omega[a - 3] };
        for p in f.iter().filter(|p| p.defined()) {
            for a in 0..components {
                let u = value(p, a);
                let k = p.slab * 6 + a;
                let u2 = u * u;
                s.count[k] += 1;
                s.s2[k] += u2;
                s.s3[k] += u2 * u;
                s.s4[k] += u2 * u2;
            }
        }
        let sigma: Vec<f64> = (0..series)
            .map(|k| (s.s2[k] / s.count[k].max(1) as f64).sqrt())
            .collect();
        for p in f.iter().filter(|p| p.defined()) {
            for a in 0..components {
                let k = p.slab * 6 + a;
                if sigma[k] <= 0.0 {
                    continue;
                }
                let j = (value(p, a) / sigma[k] / dx).round() + half as f64;
                if (0.0..width as f64).contains(&j) {
                    s.histogram[k * width + j as usize] += 1;
                } else {
                    s.outside[k] += 1;
                }
            }
        }
        s
    }

    fn width(&self) -> usize {
        2 * self.half as usize + 1
    }
}

/// One point of a VDF.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    into = "(u32, f64, String, f64, f64, f64)",
    from = "(u32, f64, String, f64, f64, f64)"
)]
pub struct VdfRow {
    pub slab: u32,
    /// slab centre, d
    pub y: f64,
    /// C_x ... Omega_z
    pub component: String,
    /// fluctuation over the slab's pooled standard deviation
    pub x: f64,
    /// density / density(0): P(0) = 1 as the thesis scales it
    pub p: f64,
    /// probability density of x (integrates to the fraction within the range)
    pub density: f64,
}

/// The moments of one slab and component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    into = "(u32, f64, String, u64, f64, f64, f64, f64, f64)",
    from = "(u32, f64, String, u64, f64, f64, f64, f64, f64)"
)]
pub struct MomentRow {
    pub slab: u32,
    pub y: f64,
    pub component: String,
    /// fluctuations counted over the window
    pub samples: u64,
    /// pooled standard deviation, in sqrt(g d) (C) or sqrt(g / d) (Omega); simulation units
    /// without gravity
    pub sigma: f64,
    pub skewness: f64,
    pub skewness_error: f64,
    pub kurtosis: f64,
    pub kurtosis_error: f64,
}

/// Pooled moments (n, m2, m3, m4) of one series over some samples.
fn pooled(samples: &[&VdfSample], k: usize) -> (u64, f64, f64, f64) {
    let n: u64 = samples.iter().map(|s| s.count[k]).sum();
    let m = |f: &dyn Fn(&VdfSample) -> f64| samples.iter().map(|s| f(s)).sum::<f64>() / n as f64;
    (n, m(&|s| s.s2[k]), m(&|s| s.s3[k]), m(&|s| s.s4[k]))
}

fn skewness(m: (u64, f64, f64, f64)) -> f64 {
    if m.0 == 0 || m.1 <= 0.0 {
        f64::NAN
    } else {
        m.2 / m.1.powf(1.5)
    }
}

fn kurtosis(m: (u64, f64, f64, f64)) -> f64 {
    if m.0 == 0 || m.1 <= 0.0 {
        f64::NAN
    } else {
        m.3 / (m.1 * m.1)
    }
}

/// Add `count` spread uniformly over [a, b) (in units of dx, bin j covering
/// [j - J - 1/2, j - J + 1/2)) into `target`; what falls outside is dropped.
fn spread(target: &mut [f64], half: usize, a: f64, b: f64, count: f64) {
    let width = b - a;
    if count == 0.0 || width <= 0.0 {
        return;
    }
    let first = (a + half as f64 + 0.5).floor().max(0.0) as usize;
    let last = ((b + half as f64 + 0.5).floor() as isize).min(target.len() as isize - 1);
    for j in first..=(last.max(0) as usize) {
        let lo = j as f64 - half as f64 - 0.5;
        let overlap = (b.min(lo + 1.0) - a.max(lo)).max(0.0);
        if let Some(t) = target.get_mut(j) {
            *t += count * overlap / width;
        }
    }
}

/// The window's VDF rows and moment rows from its samples (`y_of(slab)`: slab centres;
/// `velocity_scale`, `spin_scale`: the units sigma is reported in).
pub fn analyse(
    samples: &[&VdfSample],
    slabs: usize,
    y_of: &dyn Fn(usize) -> f64,
    velocity_scale: f64,
    spin_scale: f64,
) -> (Vec<VdfRow>, Vec<MomentRow>) {
    let Some(first) = samples.first() else {
        return (Vec::new(), Vec::new());
    };
    let same: Vec<&VdfSample> = samples
        .iter()
        .copied()
        .filter(|s| {
            s.count.len() == first.count.len()
                && s.half == first.half
                && s.dx == first.dx
                && s.components == first.components
        })
        .collect();
    let (half, dx, width) = (first.half as usize, first.dx, first.width());
    let mut rows = Vec::new();
    let mut moments = Vec::new();
    for slab in 0..slabs.min(first.count.len() / 6) {
        for (a, name) in COMPONENTS
            .iter()
            .enumerate()
            .take(first.components as usize)
        {
            let k = slab * 6 + a;
            let m = pooled(&same, k);
            if m.0 == 0 || m.1 <= 0.0 {
                continue;
            }
            let sigma = m.1.sqrt();
            let scale = if a < 3 { velocity_scale } else { spin_scale };
            let (skew_err, kurt_err) = (
                batch_error(&same, |b| skewness(pooled(b, k))),
                batch_error(&same, |b| kurtosis(pooled(b, k))),
            );
            moments.push(MomentRow {
                slab: slab as u32,
                y: y_of(slab),
                component: (*name).into(),
                samples: m.0,
                sigma: sigma / scale,
                skewness: skewness(m),
                skewness_error: skew_err,
                kurtosis: kurtosis(m),
                kurtosis_error: kurt_err,
            });
            // each snapshot's histogram, rescaled from its own sigma to the pooled one
            let mut h = vec![0.0; width];
            for s in &same {
                let n = s.count[k];
                if n == 0 {
                    continue;
                }
                let f = (s.s2[k] / n as f64).sqrt() / sigma;
                for j in 0..width {
                    let c = s.histogram[k * width + j] as f64;
                    let centre = j as f64 - half as f64;
                    spread(&mut h, half, (centre - 0.5) * f, (centre + 0.5) * f, c);
                }
            }
            let density: Vec<f64> = h.iter().map(|c| c / (m.0 as f64 * dx)).collect();
            let zero = density[half];
            // the rows span the bins from the first to the last that holds counts
            let first = h.iter().position(|c| *c > 0.0).unwrap_or(0);
            let last = h.iter().rposition(|c| *c > 0.0).unwrap_or(0);
            for (j, d) in density.iter().enumerate().take(last + 1).skip(first) {
                rows.push(VdfRow {
                    slab: slab as u32,
                    y: y_of(slab),
                    component: (*name).into(),
                    x: (j as f64 - half as f64) * dx,
                    p: if zero > 0.0 { d / zero } else { f64::NAN },
                    density: *d,
                });
            }
        }
    }
    (rows, moments)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spreading_keeps_counts_inside_the_range() {
        let mut t = vec![0.0; 5];
        // [-0.75, 0.75) in units of dx over bins centred on -2..2: bins -1, 0, 1
        spread(&mut t, 2, -0.75, 0.75, 3.0);
        assert!((t.iter().sum::<f64>() - 3.0).abs() < 1e-12);
        assert!((t[1] - 0.5).abs() < 1e-12 && (t[2] - 2.0).abs() < 1e-12);
        let mut t = vec![0.0; 5];
        spread(&mut t, 2, 2.0, 3.0, 1.0);
        assert!((t[4] - 0.5).abs() < 1e-12, "{t:?}");
    }
}

row_as_tuple!(VdfRow {
    slab: u32,
    y: f64,
    component: String,
    x: f64,
    p: f64,
    density: f64
});

row_as_tuple!(MomentRow {
    slab: u32,
    y: f64,
    component: String,
    samples: u64,
    sigma: f64,
    skewness: f64,
    skewness_error: f64,
    kurtosis: f64,
    kurtosis_error: f64
});
