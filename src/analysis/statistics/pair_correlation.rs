//! The pair correlation function g(r), per slab and overall, with a shell normalisation that
//! holds next to walls and in an inhomogeneous channel (the thesis' formula,
//! g = (2 V_j / N_j^2) < sum_i sum_{j>i} delta(r - r_ij) >, has no shell volume).
//!
//! Estimator: g_b(r) = (pairs at distance r of the slab's particles) / (the same count for an
//! uncorrelated gas with the window's density profile n(y)):
//!
//! ```text
//!     g_b(r_1 .. r_2) = sum_snapshots sum_{i in b} #{j : r_1 <= r_ij < r_2}
//!                     / [ (N - 1)/N  sum_snapshots sum_{i in b} R(y_i) ],
//!     R(y) = int_{r_1}^{r_2} 2 pi r [ C(y + r) - C(y - r) ] dr,   C(y) = int_0^y n(y') dy'
//! ```
//!
//! (a spherical shell's area between two planes y and y + dy is 2 pi r dy, whatever the
//! planes' height). n(y) is the window-averaged number density on fine cells of about
//! [`FINE_CELL`](super::pairs::FINE_CELL) d, zero beyond the walls (a shell cut by a wall counts
//! only its part inside), periodic without walls; R is integrated by 3-point Gauss-Legendre
//! on each bin, and y_i is taken at the centre of its fine cell. In a homogeneous periodic box
//! this is the textbook estimator, counts / (N (N - 1)/V 4 pi (r_2^3 - r_1^3)/3), so g -> 1 at
//! large r; r is the full 3D distance (the thesis' "r spans along the (x, z)-plane" is read as
//! the plane of the periodic directions over which r may range, not as a projection).
//!
//! The contact value g(d+) is the value at r = d of a least-squares parabola through the
//! bins from d to 1.2 d (at least 4; a straight line through 3 when there are no more): wide
//! enough that the bins' noise does not swing the extrapolation, narrow enough that a parabola
//! follows g (at phi = 0.3 the cubic term of g's decay changes g(d+) by < 0.5 %).

use super::pairs::PairSample;
use serde::{Deserialize, Serialize};

/// One point of g(r).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    into = "(Option<u32>, f64, f64, f64, u64)",
    from = "(Option<u32>, f64, f64, f64, u64)"
)]
pub struct PairCorrelationRow {
    /// slab of the test particle; None: all slabs
    pub slab: Option<u32>,
    pub y: f64,
    /// bin centre, d
    pub r: f64,
    pub g: f64,
    /// ordered pairs counted over the window
    pub pairs: u64,
}

/// What the normalisation needs of the box.
#[derive(Clone, Copy, Debug)]
pub struct PairBox {
    /// L, W, H
    pub extent: [f64; 3],
    /// walls at y = 0 and W (else periodic)
    pub walls: bool,
    /// N
    pub particles: usize,
}

/// The window's sums of compatible samples: counts per slab and bin, fine centre counts.
struct Totals {
    r_bins: usize,
    dr: f64,
    fine_per_slab: usize,
    counts: Vec<u64>,
    fine: Vec<u64>,
    snapshots: usize,
}

fn totals(samples: &[&PairSample]) -> Option<Totals> {
    let first = samples.first()?;
    let mut t = Totals {
        r_bins: first.r_bins as usize,
        dr: first.dr,
        fine_per_slab: first.fine_per_slab as usize,
        counts: vec![0; first.counts.len()],
        fine: vec![0; first.fine_counts.len()],
        snapshots: 0,
    };
    for s in samples.iter().filter(|s| {
        s.counts.len() == first.counts.len()
            && s.fine_counts.len() == first.fine_counts.len()
            && s.dr == first.dr
    }) {
        t.snapshots += 1;
        for (a, b) in t.counts.iter_mut().zip(&s.counts) {
            *a += u64::from(*b);
        }
        for (a, b) in t.fine.iter_mut().zip(&s.fine_counts) {
            *a += u64::from(*b);
        }
    }
    Some(t)
}

/// C(y) = int_0^y n: piecewise linear over the fine cells, periodic or zero beyond [0, W].
struct Cumulative {
    /// C at the fine-cell edges (len cells + 1)
    edges: Vec<f64>,
    dy: f64,
    width: f64,
    periodic: bool,
}

impl Cumulative {
    fn at(&self, y: f64) -> f64 {
        let total = *self.edges.last().unwrap_or(&0.0);
        let (wraps, y) = if self.periodic {
            let k = (y / self.width).floor();
            (k, y - k * self.width)
        } else {
            (0.0, y.clamp(0.0, self.width))
        };
        let u = y / self.dy;
        let i = (u.floor() as usize).min(self.edges.len() - 2);
        let f = u - i as f64;
        wraps * total + self.edges[i] + f * (self.edges[i + 1] - self.edges[i])
    }
}

/// 3-point Gauss-Legendre nodes and weights on [-1, 1].
const GAUSS: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// g(r) of every slab and of all slabs over the window's samples.
pub fn analyse(
    samples: &[&PairSample],
    slabs: usize,
    b: PairBox,
    y_of: &dyn Fn(usize) -> f64,
) -> Vec<PairCorrelationRow> {
    let Some(t) = totals(samples) else {
        return Vec::new();
    };
    if t.snapshots == 0 || t.counts.len() != slabs * t.r_bins {
        return Vec::new();
    }
    let [l, w, h] = b.extent;
    let fine_cells = t.fine.len();
    let dy = w / fine_cells as f64;
    let per_volume = 1.0 / (t.snapshots as f64 * l * h * dy);
    let mut edges = vec![0.0; fine_cells + 1];
    for f in 0..fine_cells {
        edges[f + 1] = edges[f] + t.fine[f] as f64 * per_volume * dy;
    }
    let cumulative = Cumulative {
        edges,
        dy,
        width: w,
        periodic: !b.walls,
    };
    let others = (b.particles.saturating_sub(1)) as f64 / b.particles.max(1) as f64;
    // R(y) of one bin at the centre of fine cell f
    let shell = |y: f64, r1: f64, r2: f64| -> f64 {
        let (mid, half) = (0.5 * (r1 + r2), 0.5 * (r2 - r1));
        GAUSS
            .iter()
            .map(|(x, wt)| {
                let r = mid + half * x;
                wt * 2.0 * std::f64::consts::PI * r * (cumulative.at(y + r) - cumulative.at(y - r))
            })
            .sum::<f64>()
            * half
    };
    let mut reference = vec![0.0; slabs * t.r_bins];
    for f in 0..fine_cells {
        if t.fine[f] == 0 {
            continue;
        }
        let slab = (f / t.fine_per_slab).min(slabs - 1);
        let y = (f as f64 + 0.5) * dy;
        for k in 0..t.r_bins {
            let r1 = k as f64 * t.dr;
            reference[slab * t.r_bins + k] += others * t.fine[f] as f64 * shell(y, r1, r1 + t.dr);
        }
    }
    let mut rows = Vec::new();
    let mut row = |slab: Option<u32>, y: f64, k: usize, pairs: u64, reference: f64| {
        if reference > 0.0 {
            rows.push(PairCorrelationRow {
                slab,
                y,
                r: (k as f64 + 0.5) * t.dr,
                g: pairs as f64 / reference,
                pairs,
            });
        }
    };
    for k in 0..t.r_bins {
        let pairs: u64 = (0..slabs).map(|s| t.counts[s * t.r_bins + k]).sum();
        let reference: f64 = (0..slabs).map(|s| reference[s * t.r_bins + k]).sum();
        row(None, f64::NAN, k, pairs, reference);
    }
    for s in 0..slabs {
        for k in 0..t.r_bins {
            row(
                Some(s as u32),
                y_of(s),
                k,
                t.counts[s * t.r_bins + k],
                reference[s * t.r_bins + k],
            );
        }
    }
    rows
}

/// g(d+) of rows of one series (in increasing r, bins of equal width): the parabola (or, with
/// 3 points, the line) through the bins from r = d to 1.2 d (at least 4) at r = d; NaN without
/// 3 bins.
pub fn contact_value(rows: &[&PairCorrelationRow], dr: f64) -> f64 {
    let want = ((0.2 / dr).round() as usize).max(4);
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.r - 0.5 * dr >= 1.0 - 1e-9 && r.g.is_finite())
        .take(want)
        .map(|r| (r.r - 1.0, r.g))
        .collect();
    if points.len() < 3 {
        return f64::NAN;
    }
    let degree = if points.len() > 3 { 2 } else { 1 };
    polynomial_at_zero(&points, degree)
}

/// The constant term of the least-squares polynomial of `degree` (1 or 2) through `points`.
fn polynomial_at_zero(points: &[(f64, f64)], degree: usize) -> f64 {
    let m = degree + 1;
    let mut a = nalgebra::DMatrix::<f64>::zeros(points.len(), m);
    let mut b = nalgebra::DVector::<f64>::zeros(points.len());
    for (i, (x, y)) in points.iter().enumerate() {
        for j in 0..m {
            a[(i, j)] = x.powi(j as i32);
        }
        b[i] = *y;
    }
    let ata = a.transpose() * &a;
    let atb = a.transpose() * b;
    ata.lu().solve(&atb).map_or(f64::NAN, |c| c[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parabola_is_recovered_at_contact() {
        let rows: Vec<PairCorrelationRow> = (0..10)
            .map(|k| {
                let x = 0.01 * (k as f64 + 0.5);
                PairCorrelationRow {
                    slab: None,
                    y: f64::NAN,
                    r: 1.0 + x,
                    g: 2.0 - 3.0 * x + 4.0 * x * x,
                    pairs: 1,
                }
            })
            .collect();
        let refs: Vec<&PairCorrelationRow> = rows.iter().collect();
        assert!((contact_value(&refs, 0.01) - 2.0).abs() < 1e-9);
    }
}

row_as_tuple!(PairCorrelationRow { slab: Option<u32>, y: f64, r: f64, g: f64, pairs: u64 });
