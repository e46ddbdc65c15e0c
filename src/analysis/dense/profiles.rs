//! Bin fields across the channel from summed DEM bin sums (Debnath, Rao & Kumaran 2022,
//! eqs. 2.1-2.5, dem.md A2), in the paper's axes: x wall-normal (our y), y along the flow
//! (our x), z the span.
//!
//! Conventions (the paper leaves them open):
//! - every field is a ratio of sums over the window's samples (not a mean of per-sample
//!   ratios): phi = sum (pi/6) d^3 / (S V), u_y = sum m v / sum m (eq. 2.1),
//!   Omega_z = sum I w / sum I (eq. 2.2), with S the samples and V the bin volume;
//! - fluctuations (T, eq. 2.3, and the kinetic stress, eq. 2.4) are about the
//!   *instantaneous* bin means, so a fluctuation of the whole flow in time (of u_cm) is no
//!   temperature: T = [sum m |v|^2 - sum_s |P_s|^2 / M_s + sum I |w|^2 - sum_s |S_s|^2 / J_s]
//!   / (6 N), N the particle-samples of the bin;
//! - stress sigma_ab, compressive positive, a the force component, b the branch vector:
//!   contact part sum F_a r_b / 2 over the contacts of the bin's particles, plus, in the wall
//!   bins, the wall contacts' F_a del_b; kinetic part sum m (v - v_bin)_a (v - v_bin)_b; both
//!   over S V. The paper's sigma_xy is the wall-normal force along flow-wise branches (our
//!   (y, x)), its sigma_yx the flow-wise force across wall-normal branches (our (x, y), the
//!   flux of flow momentum across planes parallel to the walls);
//! - dissipation rate per volume D (eq. 2.5, positive when dissipating): sum -F . v_s of the
//!   pair contacts whose midpoint is in the bin, plus the wall contacts' in the wall bins,
//!   over S V;
//! - shear rate du_y/dx: the derivative of the parabola through a bin's and its neighbours'
//!   (centre, u_y), one-sided differences in the wall bins (exact for a linear profile on the
//!   unequal bins); vorticity omega_z = du_y/dx; in our right-handed axes the paper's Omega_z
//!   is -w_z (the paper's axes are a reflection of ours);
//! - mu = |sigma_xy / sigma_xx|, I = d_p |du_y/dx| / sqrt(sigma_xx / rho_p), with
//!   d_p = rho_p = 1; shear production -sigma_yx du_y/dx (positive where the mean flow feeds
//!   the fluctuations);
//! - Q6: the global bond-orientational order of the bonds whose midpoint is in the bin, pooled
//!   over the snapshots (sums of Y_6m over every bond of every snapshot, then
//!   sqrt(4 pi / 13 sum_m |sum Y_6m|^2) / n_bonds; [`crate::engine::dem::bond_order`]); and
//!   the mean local q6 of the bonded particles with their centre in the bin.

use crate::engine::dem::sampling::SYM;
use crate::engine::dem::{BinSums, BondSums, Record};
use std::f64::consts::PI;

/// Summed sums of some records: what every field is computed from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Totals {
    /// S, samples of the bin sums
    pub samples: f64,
    pub bins: Vec<BinSums>,
    /// per wall, at the samples: sum F_a del_b over wall contacts (row-major)
    pub wall_stress: [[f64; 9]; 2],
    /// per wall, at the samples: sum -F . v_s over wall contacts
    pub wall_dissipation: [f64; 2],
    /// force evaluations and the sum of the particles' force on each wall over them
    pub force_steps: f64,
    pub wall_force: [[f64; 3]; 2],
    /// sum of u_cm (along the flow) over the samples
    pub com_velocity: f64,
    /// per bin: the bond-order sums of the records' snapshots
    pub bonds: Vec<BondSums>,
    /// the records summed
    pub records: usize,
}

impl Totals {
    /// The sums of `records` (all of the same run).
    pub fn of(records: &[&Record]) -> Totals {
        let mut t = Totals::default();
        for r in records {
            t.add(r);
        }
        t
    }

    fn add(&mut self, r: &Record) {
        let s = &r.sums;
        if self.bins.len() < s.bins.len() {
            self.bins.resize(s.bins.len(), BinSums::default());
        }
        for (a, b) in self.bins.iter_mut().zip(&s.bins) {
            add_bin(a, b);
        }
        if self.bonds.len() < r.bonds.len() {
            self.bonds.resize(r.bonds.len(), BondSums::default());
        }
        for (a, b) in self.bonds.iter_mut().zip(&r.bonds) {
            a.add(b);
        }
        self.samples += s.samples as f64;
        for w in 0..2 {
            for k in 0..9 {
                self.wall_stress[w][k] += s.wall_stress[w][k];
            }
            for k in 0..3 {
                self.wall_force[w][k] += s.wall_force[w][k];
            }
            self.wall_dissipation[w] += s.wall_dissipation[w];
        }
        self.force_steps += s.force_steps as f64;
        self.com_velocity += s.com_velocity[0];
        self.records += 1;
    }
}

/// a += b, field by field.
pub fn add_bin(a: &mut BinSums, b: &BinSums) {
    a.count += b.count;
    a.volume += b.volume;
    a.mass += b.mass;
    a.inertia += b.inertia;
    a.dissipation += b.dissipation;
    a.contacts += b.contacts;
    for k in 0..3 {
        a.momentum[k] += b.momentum[k];
        a.spin_momentum[k] += b.spin_momentum[k];
    }
    for k in 0..6 {
        a.momentum_flux[k] += b.momentum_flux[k];
        a.spin_flux[k] += b.spin_flux[k];
        a.mean_momentum_flux[k] += b.mean_momentum_flux[k];
        a.mean_spin_flux[k] += b.mean_spin_flux[k];
    }
    for k in 0..9 {
        a.contact_stress[k] += b.contact_stress[k];
    }
}

/// The channel's geometry as the fields need it.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    /// bin edges across the channel, 0 .. W
    pub edges: Vec<f64>,
    /// L B, the bins' cross-section parallel to the walls
    pub area: f64,
}

impl Geometry {
    pub fn of(r: &Record) -> Geometry {
        Geometry {
            edges: r.constants.bin_edges.clone(),
            area: r.constants.length * r.constants.span,
        }
    }

    /// W
    pub fn width(&self) -> f64 {
        self.edges.last().copied().unwrap_or(0.0)
    }

    /// Bin centres (distance from the wall at x = 0).
    pub fn centres(&self) -> Vec<f64> {
        self.edges.windows(2).map(|e| 0.5 * (e[0] + e[1])).collect()
    }

    fn volume(&self, bin: usize) -> f64 {
        (self.edges[bin + 1] - self.edges[bin]) * self.area
    }
}

/// The paper's index of our axis: paper (x, y, z) = our (y, x, z).
const PAPER: [usize; 3] = [1, 0, 2];

/// The fields of one bin (paper axes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BinFields {
    /// phi
    pub volume_fraction: f64,
    /// u_y, mass-weighted (eq. 2.1)
    pub velocity: f64,
    /// Omega_z, moment-of-inertia weighted (eq. 2.2, paper's sign)
    pub spin: f64,
    /// T, eq. 2.3 (energy per degree of freedom)
    pub temperature: f64,
    /// sigma_ab, contact + kinetic, compressive positive, paper axes (a force, b branch)
    pub stress: [[f64; 3]; 3],
    /// D, eq. 2.5
    pub dissipation: f64,
    /// du_y/dx
    pub shear_rate: f64,
    /// Q6 of the bonds with their midpoint in the bin (NaN: none)
    pub q6: f64,
    /// mean local q6 of the bonded particles with their centre in the bin (NaN: none)
    pub local_q6: f64,
}

impl BinFields {
    /// mu = |sigma_xy / sigma_xx|
    pub fn friction(&self) -> f64 {
        (self.stress[0][1] / self.stress[0][0]).abs()
    }

    /// I = d_p |du_y/dx| / sqrt(sigma_xx / rho_p)
    pub fn inertial_number(&self) -> f64 {
        self.shear_rate.abs() / self.stress[0][0].sqrt()
    }

    /// Omega_z / omega_z (1/2 when the particles turn with the material)
    pub fn spin_over_vorticity(&self) -> f64 {
        self.spin / self.shear_rate
    }

    /// d_p (du_y/dx) / sqrt(T)
    pub fn shear_over_sqrt_temperature(&self) -> f64 {
        self.shear_rate / self.temperature.sqrt()
    }

    /// -sigma_yx du_y/dx
    pub fn shear_production(&self) -> f64 {
        -self.stress[1][0] * self.shear_rate
    }
}

/// The index of the symmetric product (a, b) in [`SYM`] order.
fn sym(a: usize, b: usize) -> usize {
    let (a, b) = (a.min(b), a.max(b));
    SYM.iter()
        .position(|&p| p == (a, b))
        .expect("a symmetric pair")
}

/// The fields of every bin from summed sums.
pub fn fields(t: &Totals, g: &Geometry) -> Vec<BinFields> {
    let n = t.bins.len();
    let mut out: Vec<BinFields> = t
        .bins
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let sv = t.samples * g.volume(k);
            let wall = if k == 0 {
                Some(0)
            } else if k + 1 == n {
                Some(1)
            } else {
                None
            };
            // ours (a, c): contact + wall contacts + kinetic, over S V
            let ours = |a: usize, c: usize| {
                let s = sym(a, c);
                let kinetic = b.momentum_flux[s] - b.mean_momentum_flux[s];
                let walls = wall.map_or(0.0, |w| t.wall_stress[w][3 * a + c]);
                (b.contact_stress[3 * a + c] + walls + kinetic) / sv
            };
            let stress: [[f64; 3]; 3] =
                std::array::from_fn(|a| std::array::from_fn(|c| ours(PAPER[a], PAPER[c])));
            let fluct: f64 = (0..3)
                .map(|a| {
                    let s = sym(a, a);
                    b.momentum_flux[s] - b.mean_momentum_flux[s] + b.spin_flux[s]
                        - b.mean_spin_flux[s]
                })
                .sum();
            BinFields {
                volume_fraction: b.volume / sv,
                velocity: b.momentum[0] / b.mass,
                spin: -b.spin_momentum[2] / b.inertia,
                temperature: fluct / (6.0 * b.count),
                stress,
                dissipation: (b.dissipation + wall.map_or(0.0, |w| t.wall_dissipation[w])) / sv,
                shear_rate: f64::NAN,
                q6: t.bonds.get(k).map_or(f64::NAN, BondSums::q6),
                local_q6: t.bonds.get(k).map_or(f64::NAN, BondSums::mean_local_q6),
            }
        })
        .collect();
    let u: Vec<f64> = out.iter().map(|f| f.velocity).collect();
    for (f, d) in out.iter_mut().zip(derivative(&g.centres(), &u)) {
        f.shear_rate = d;
    }
    out
}

/// df/dx at each point: the derivative at x_k of the parabola through its neighbours
/// (x_{k-1}, x_k, x_{k+1}), one-sided differences at the ends.
pub fn derivative(x: &[f64], f: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            if n < 2 {
                f64::NAN
            } else if k == 0 {
                (f[1] - f[0]) / (x[1] - x[0])
            } else if k + 1 == n {
                (f[k] - f[k - 1]) / (x[k] - x[k - 1])
            } else {
                let (h1, h2) = (x[k] - x[k - 1], x[k + 1] - x[k]);
                (h1 * h1 * (f[k + 1] - f[k]) + h2 * h2 * (f[k] - f[k - 1])) / (h1 * h2 * (h1 + h2))
            }
        })
        .collect()
}

/// How a quantity is read off a bin's fields.
pub type Reading = fn(&BinFields) -> f64;

/// The profiled quantities: name and how to read it off a bin's fields (names of the long
/// profiles table).
pub const QUANTITIES: &[(&str, Reading)] = &[
    ("volume_fraction", |f| f.volume_fraction),
    ("velocity", |f| f.velocity),
    ("spin", |f| f.spin),
    ("temperature", |f| f.temperature),
    ("stress_xx", |f| f.stress[0][0]),
    ("stress_yy", |f| f.stress[1][1]),
    ("stress_zz", |f| f.stress[2][2]),
    ("stress_xy", |f| f.stress[0][1]),
    ("stress_yx", |f| f.stress[1][0]),
    ("dissipation", |f| f.dissipation),
    ("shear_rate", |f| f.shear_rate),
    ("spin_over_vorticity", BinFields::spin_over_vorticity),
    (
        "shear_over_sqrt_temperature",
        BinFields::shear_over_sqrt_temperature,
    ),
    ("shear_production", BinFields::shear_production),
    ("mu", BinFields::friction),
    ("inertial_number", BinFields::inertial_number),
    ("q6", |f| f.q6),
    ("local_q6", |f| f.local_q6),
];

/// Mean of mirror bins (k and n-1-k) of an even profile, from the wall to the centre; an odd
/// one (`odd`: the shear rate) is folded as (f_k - f_{n-1-k}) / 2.
pub fn fold(values: &[f64], odd: bool) -> Vec<f64> {
    let n = values.len();
    (0..n.div_ceil(2))
        .map(|k| {
            let m = values[n - 1 - k];
            0.5 * (values[k] + if odd { -m } else { m })
        })
        .collect()
}

/// The volume of a sphere of diameter d.
pub fn sphere_volume(d: f64) -> f64 {
    PI / 6.0 * d * d * d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_derivative_of_a_linear_profile_is_its_slope_on_unequal_bins() {
        let x = [0.75, 2.0, 3.0, 4.0, 5.25];
        let f: Vec<f64> = x.iter().map(|x| 3.0 - 2.5 * x).collect();
        for d in derivative(&x, &f) {
            assert!((d + 2.5).abs() < 1e-12, "{d}");
        }
        // a parabola: exact at the interior points
        let f: Vec<f64> = x.iter().map(|x| x * x).collect();
        let d = derivative(&x, &f);
        for k in 1..4 {
            assert!((d[k] - 2.0 * x[k]).abs() < 1e-12, "{k}: {}", d[k]);
        }
    }

    #[test]
    fn folding_averages_mirror_bins() {
        assert_eq!(fold(&[1.0, 2.0, 3.0, 6.0, 5.0], false), vec![3.0, 4.0, 3.0]);
        assert_eq!(fold(&[1.0, 2.0, -2.0, -1.0], true), vec![1.0, 2.0]);
    }
}
