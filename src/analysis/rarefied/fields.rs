//! Cross-channel fields from summed raw moments (thesis eqs. 3.14-3.19, 5.6-5.11), normalised
//! as the thesis does (3.2.3): y by W about the centre, rho by rho_avg, u by
//! u_c = sqrt(2 k T_w / m_1) (and by sqrt(a W) for athermal walls, eq. 4.4), T by T_w,
//! P_ab by P_c = rho_avg u_c^2 / 2, q_a by q_c = rho_avg u_c^3 / 2.
//!
//! The peculiar velocity C = v - u uses each cell's mixture velocity u averaged over the whole
//! window (3.2.2), so central moments follow from the raw sums exactly:
//! sum m C_a C_b = S_ab - u_a S_b - u_b S_a + u_a u_b S, and
//! sum m C_a |C|^2 = S3_a - 2 u_b S_ab - u_a S_bb + 2 u_a u_b S_b + |u|^2 S_a - u_a |u|^2 S,
//! with S = sum m, S_a = sum m v_a, S_ab = sum m v_a v_b, S3_a = sum m v_a |v|^2.

use crate::engine::dsmc::sampling::{MOMENTS, Moments, moment as mo};

/// Constants of a run that turn moments into normalised fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    pub cells: usize,
    pub species: usize,
    /// [m_1, m_2]
    pub masses: [f64; 2],
    /// simulators of each species
    pub counts: [f64; 2],
    /// a (body-force acceleration, W = 1)
    pub acceleration: f64,
    /// Kn
    pub knudsen_number: f64,
}

impl Scales {
    /// u_c = sqrt(2 k T_w / m_1) with k T_w = m_1 = 1.
    pub const VELOCITY: f64 = std::f64::consts::SQRT_2;

    /// Total mass of the simulators, sum_s m_s N_s.
    pub fn total_mass(&self) -> f64 {
        (0..self.species)
            .map(|s| self.masses[s] * self.counts[s])
            .sum()
    }

    /// Total number of simulators.
    pub fn total_count(&self) -> f64 {
        self.counts[..self.species].iter().sum()
    }
}

/// Normalised fields of one layer cell.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CellFields {
    /// rho / rho_avg (mixture mass density)
    pub density: f64,
    /// u_x / u_c (mixture, mass-weighted, eq. 5.6)
    pub velocity: f64,
    /// T / T_w, T = sum m |C|^2 / (3 N) (eq. 3.17; mixtures: eq. 5.11)
    pub temperature: f64,
    /// P_ab / P_c (eq. 3.18)
    pub pxx: f64,
    pub pyy: f64,
    pub pzz: f64,
    pub pxy: f64,
    /// q_a / q_c (eq. 3.19)
    pub qx: f64,
    pub qy: f64,
    /// n_s / n_avg, number density of each species over the mean total number density
    pub species_density: [f64; 2],
    /// T_s / T_w, T_s = m_s <|v - u^m|^2> / 3 (eqs. 5.9-5.10)
    pub species_temperature: [f64; 2],
    /// u_x of each species / u_c
    pub species_velocity: [f64; 2],
}

impl CellFields {
    /// p / P_c = (P_xx + P_yy + P_zz) / 3.
    pub fn pressure(&self) -> f64 {
        (self.pxx + self.pyy + self.pzz) / 3.0
    }

    /// N1 = (P_xx - P_yy) / p (eq. 3.29).
    pub fn n1(&self) -> f64 {
        (self.pxx - self.pyy) / self.pressure()
    }

    /// N2 = (P_yy - P_zz) / p (eq. 3.30).
    pub fn n2(&self) -> f64 {
        (self.pyy - self.pzz) / self.pressure()
    }
}

/// Sum a window's moments: `moments[cell * species + s]` of every record, added.
pub fn add_moments(total: &mut [Moments], more: &[Moments]) {
    for (t, m) in total.iter_mut().zip(more) {
        for k in 0..MOMENTS {
            t[k] += m[k];
        }
    }
}

/// The fields of every cell from moments summed over `samples` samples.
pub fn cell_fields(moments: &[Moments], samples: f64, sc: &Scales) -> Vec<CellFields> {
    let cells = sc.cells as f64;
    let total_mass = sc.total_mass();
    let total_count = sc.total_count();
    let uc = Scales::VELOCITY;
    // P_c and q_c per sample per cell: rho_avg = M / cells in "mass per cell" units
    let pressure_scale = 0.5 * total_mass / cells * uc * uc;
    let flux_scale = 0.5 * total_mass / cells * uc * uc * uc;
    (0..sc.cells)
        .map(|c| {
            let run = &moments[c * sc.species..(c + 1) * sc.species];
            // mass-weighted raw sums of the mixture
            let mut s = [0.0; MOMENTS];
            for (k, m) in run.iter().enumerate() {
                for i in 0..MOMENTS {
                    s[i] += sc.masses[k] * m[i];
                }
            }
            let count: f64 = run.iter().map(|m| m[mo::COUNT]).sum();
            let mass = s[mo::COUNT];
            let u = if mass > 0.0 {
                [s[mo::VX] / mass, s[mo::VY] / mass, s[mo::VZ] / mass]
            } else {
                [0.0; 3]
            };
            let central2 = |a: usize, b: usize, raw: &Moments| {
                let first = [raw[mo::VX], raw[mo::VY], raw[mo::VZ]];
                raw[second_index(a, b)] - u[a] * first[b] - u[b] * first[a]
                    + u[a] * u[b] * raw[mo::COUNT]
            };
            let thermal = |raw: &Moments| (0..3).map(|a| central2(a, a, raw)).sum::<f64>();
            let heat = |a: usize| {
                let first = [s[mo::VX], s[mo::VY], s[mo::VZ]];
                let third = [s[mo::QX], s[mo::QY], s[mo::QZ]];
                let u2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
                let trace = s[mo::XX] + s[mo::YY] + s[mo::ZZ];
                let mut value = third[a] - u[a] * trace + u2 * first[a] - u[a] * u2 * mass;
                for b in 0..3 {
                    value += -2.0 * u[b] * s[second_index(a, b)] + 2.0 * u[a] * u[b] * first[b];
                }
                value
            };
            let per_cell_sample = |x: f64| x / samples;
            let mut f = CellFields {
                density: per_cell_sample(mass) * cells / total_mass,
                velocity: u[0] / uc,
                temperature: thermal(&s) / (3.0 * count),
                pxx: per_cell_sample(central2(0, 0, &s)) / pressure_scale,
                pyy: per_cell_sample(central2(1, 1, &s)) / pressure_scale,
                pzz: per_cell_sample(central2(2, 2, &s)) / pressure_scale,
                pxy: per_cell_sample(central2(0, 1, &s)) / pressure_scale,
                qx: per_cell_sample(0.5 * heat(0)) / flux_scale,
                qy: per_cell_sample(0.5 * heat(1)) / flux_scale,
                ..CellFields::default()
            };
            for (k, m) in run.iter().enumerate() {
                f.species_density[k] = per_cell_sample(m[mo::COUNT]) * cells / total_count;
                f.species_temperature[k] = sc.masses[k] * thermal(m) / (3.0 * m[mo::COUNT]);
                f.species_velocity[k] = m[mo::VX] / m[mo::COUNT] / uc;
            }
            f
        })
        .collect()
}

/// Index of sum v_a v_b in a cell's moments.
fn second_index(a: usize, b: usize) -> usize {
    match (a.min(b), a.max(b)) {
        (0, 0) => mo::XX,
        (1, 1) => mo::YY,
        (2, 2) => mo::ZZ,
        (0, 1) => mo::XY,
        (0, 2) => mo::XZ,
        _ => mo::YZ,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::dsmc::sampling::add_velocity;
    use nalgebra::Vector3;

    /// Fields of hand-made moments: two simulators per sample in one cell, velocities
    /// u +- c with u = (1, 0, 0) and c = (0.5, 1, -1): T = m |c|^2 / 3 = 0.75, P_xy from c_x c_y,
    /// q = 0 (symmetric), density 1 with one cell.
    #[test]
    fn central_moments_of_a_symmetric_pair() {
        let sc = Scales {
            cells: 1,
            species: 1,
            masses: [1.0, 1.0],
            counts: [2.0, 0.0],
            acceleration: 1.0,
            knudsen_number: 1.0,
        };
        let mut m = [[0.0; MOMENTS]];
        let u = Vector3::new(1.0, 0.0, 0.0);
        let c = Vector3::new(0.5, 1.0, -1.0);
        for _ in 0..3 {
            add_velocity(&mut m[0], &(u + c));
            add_velocity(&mut m[0], &(u - c));
        }
        let f = cell_fields(&m, 3.0, &sc)[0];
        assert!((f.density - 1.0).abs() < 1e-14);
        assert!((f.velocity - 1.0 / Scales::VELOCITY).abs() < 1e-14);
        assert!((f.temperature - 2.0 * c.norm_squared() / 6.0).abs() < 1e-14);
        // P_c = rho_avg u_c^2 / 2 = 2 (mass per cell) x 1
        assert!((f.pxy - 2.0 * c.x * c.y / 2.0).abs() < 1e-14);
        assert!((f.pzz - 2.0 * c.z * c.z / 2.0).abs() < 1e-14);
        assert!(f.qx.abs() < 1e-14 && f.qy.abs() < 1e-14);
    }

    /// A lone fast simulator on a cold bath carries the heat flux q = (1/2) sum m C |C|^2:
    /// checked against the direct sum over the velocities.
    #[test]
    fn heat_flux_equals_the_direct_sum() {
        let sc = Scales {
            cells: 1,
            species: 1,
            masses: [1.0, 1.0],
            counts: [4.0, 0.0],
            acceleration: 1.0,
            knudsen_number: 1.0,
        };
        let vs = [
            Vector3::new(3.0, 1.0, 0.0),
            Vector3::new(0.0, -1.0, 0.5),
            Vector3::new(0.5, 0.0, 0.0),
            Vector3::new(0.1, 0.2, -0.3),
        ];
        let mut m = [[0.0; MOMENTS]];
        for v in &vs {
            add_velocity(&mut m[0], v);
        }
        let u = vs.iter().sum::<Vector3<f64>>() / 4.0;
        let direct: Vector3<f64> = vs
            .iter()
            .map(|v| 0.5 * (v - u) * (v - u).norm_squared())
            .sum();
        let f = cell_fields(&m, 1.0, &sc)[0];
        let qc = 0.5 * 4.0 * Scales::VELOCITY.powi(3);
        assert!(
            (f.qx - direct.x / qc).abs() < 1e-13,
            "{} vs {}",
            f.qx,
            direct.x / qc
        );
        assert!((f.qy - direct.y / qc).abs() < 1e-13);
    }
}
