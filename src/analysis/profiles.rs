//! Binwise profiles across the channel (thesis ch. 3, 25 bins over 0 <= y <= W by default):
//! phi(y), U_x(y), omega_z(y), T(y), theta(y), and the wall slip velocity.
//!
//! Per snapshot and bin the record keeps sums; the window average divides summed sums:
//! - phi(y) = (pi d^3 / 6) sum N_b / (S V_b), S snapshots, V_b = L H W / bins;
//! - U_x(y) = sum c_x / sum N_b, omega_z(y) = sum w_z / sum N_b;
//! - T(y) = sum |C|^2 / (3 sum (N_k - 1)), theta(y) = (I/m) sum |Omega|^2 / (3 sum (N_k - 1)),
//!   with C = c - <c>_k and Omega = w - <w>_k the fluctuations about the mean of the
//!   fluctuation cell k (the bin cut by the x and z cells of the grid: cellwise averaging, so
//!   density waves along x and z do not count as temperature) and N_k - 1 its degrees of
//!   freedom (the pooled, unbiased variance); I/m = K d^2 / 4.
//!
//! Non-dimensionalised as in the thesis: u / sqrt(g d), omega / sqrt(g / d), T / (g d),
//! theta / (g d) (with g = 0 the values are left in the simulation units).
//! The slip velocity is the mean of U_x in the two bins next to the walls (thesis 3.3); with
//! bins narrower than d/2 these are the outermost bins that hold centres.

use super::fields::{CellMoments, Grid, SPHERE_VOLUME};
use super::{ProfileRow, SnapshotRecord};
use crate::engine::Particles;
use serde::{Deserialize, Serialize};

/// Profile quantities, in the order of the rows.
pub const QUANTITIES: [&str; 5] = ["phi", "u_x", "omega_z", "T", "theta"];

/// Sums over one bin of one snapshot.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BinSums {
    /// N_b, centres in the bin
    pub count: u64,
    /// sum of c_x
    pub sum_ux: f64,
    /// sum of w_z
    pub sum_omega_z: f64,
    /// sum of |c - <c>_k|^2 over the bin's fluctuation cells
    pub sum_fluct_c2: f64,
    /// sum of |w - <w>_k|^2 over the bin's fluctuation cells
    pub sum_fluct_w2: f64,
    /// sum over the bin's fluctuation cells of (N_k - 1) for N_k >= 1
    pub dof: u64,
}

/// Bin of coordinate y for `bins` bins over [0, width].
fn bin_of(y: f64, width: f64, bins: usize) -> usize {
    let u = y / width * bins as f64;
    if u.is_nan() || u < 0.0 {
        0
    } else {
        (u as usize).min(bins - 1)
    }
}

/// The per-bin sums of one snapshot (fluctuation cells: x and z cells of `grid` x bins).
pub fn bin_sums(snapshot: &Particles, grid: &Grid, bins: usize) -> Vec<BinSums> {
    let bins = bins.max(1);
    let width = snapshot.geometry.width;
    let [n1, _, n3] = grid.n;
    let cells = n1 * bins * n3;
    let cell_of = |r: [f64; 3]| {
        (grid.index(0, r[0]) * bins + bin_of(r[1], width, bins)) * n3 + grid.index(2, r[2])
    };
    let idx: Vec<usize> = snapshot.positions.iter().map(|r| cell_of(*r)).collect();
    let moments = CellMoments::compute(snapshot, &idx, cells);
    let mut out = vec![BinSums::default(); bins];
    for k in 0..cells {
        let b = &mut out[(k / n3) % bins];
        b.count += moments.count[k];
        b.sum_ux += moments.sum_velocity[k][0];
        b.sum_omega_z += moments.sum_spin[k][2];
        b.sum_fluct_c2 += moments.fluctuation_c2[k];
        b.sum_fluct_w2 += moments.fluctuation_w2[k];
        b.dof += moments.count[k].saturating_sub(1);
    }
    out
}

/// Window-averaged, non-dimensionalised profiles of `records` and the slip velocity.
pub fn profiles(records: &[&SnapshotRecord]) -> (Vec<ProfileRow>, f64) {
    let Some(first) = records.first() else {
        return (Vec::new(), f64::NAN);
    };
    let bins = first.profile.len();
    let mut total = vec![BinSums::default(); bins];
    let mut snapshots = 0usize;
    for r in records.iter().filter(|r| r.profile.len() == bins) {
        snapshots += 1;
        for (t, b) in total.iter_mut().zip(&r.profile) {
            t.count += b.count;
            t.sum_ux += b.sum_ux;
            t.sum_omega_z += b.sum_omega_z;
            t.sum_fluct_c2 += b.sum_fluct_c2;
            t.sum_fluct_w2 += b.sum_fluct_w2;
            t.dof += b.dof;
        }
    }
    let [l, w, h] = first.box_extent;
    let g = first.gravity;
    let (u_scale, w_scale, t_scale) = if g > 0.0 {
        (g.sqrt(), g.sqrt(), g)
    } else {
        (1.0, 1.0, 1.0)
    };
    let bin_volume = l * w * h / bins.max(1) as f64;
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    let inertia = first.inertia_factor / 4.0;
    let mut rows = Vec::with_capacity(5 * bins);
    let mut ux = Vec::with_capacity(bins);
    for (b, t) in total.iter().enumerate() {
        let y = (b as f64 + 0.5) * w / bins as f64;
        let n = t.count as f64;
        let dof = 3.0 * t.dof as f64;
        let u = ratio(t.sum_ux, n) / u_scale;
        ux.push(u);
        let values = [
            (
                "phi",
                SPHERE_VOLUME * n / (snapshots.max(1) as f64 * bin_volume),
            ),
            ("u_x", u),
            ("omega_z", ratio(t.sum_omega_z, n) / w_scale),
            ("T", ratio(t.sum_fluct_c2, dof) / t_scale),
            ("theta", inertia * ratio(t.sum_fluct_w2, dof) / t_scale),
        ];
        for (q, v) in values {
            rows.push(ProfileRow {
                quantity: q.into(),
                bin: b as u32,
                y,
                value: v,
            });
        }
    }
    let order = |q: &str| {
        QUANTITIES
            .iter()
            .position(|&x| x == q)
            .unwrap_or(usize::MAX)
    };
    rows.sort_by_key(|r| (order(&r.quantity), r.bin));
    // the outermost bins that hold centres (with bins narrower than d/2 the outermost bins
    // are empty, as centres stay d/2 away from the walls)
    let filled: Vec<f64> = ux.iter().copied().filter(|u| u.is_finite()).collect();
    let slip = match filled.len() {
        0 => f64::NAN,
        k => 0.5 * (filled[0] + filled[k - 1]),
    };
    (rows, slip)
}
