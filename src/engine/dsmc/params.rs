//! Validated parameters of one DSMC channel run (thesis 3.2.3 control parameters, ch. 4 wall
//! models, ch. 5 binary mixtures) and the quantities derived from them.
//!
//! Units: the channel width W = 1, the mass of species 1 m_1 = 1, k_B = 1 and the wall (or
//! reference) temperature T_w = 1; x (flow, body force along +x) and z are periodic and not
//! stored (thesis 3.2.1), y in [0, W] runs across the channel. The dilute gas depends on the
//! density and diameter only through n d^2 W, which the Knudsen number fixes a priori
//! (eqs. 3.20-3.21): n pi d_1^2 = 1 / (sqrt 2 Kn W).

use serde::{Deserialize, Serialize};

/// Automatic layer count: at least this many cells, so that the profiles resolve the Knudsen
/// layers even when the mean free path exceeds the width (cell width <= lambda / 3 alone would
/// give a single cell for Kn >= 1/3).
pub const MIN_AUTOMATIC_CELLS: usize = 50;

/// How a simulator that reaches a wall (y = 0 or y = W) leaves it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallModel {
    /// diffuse re-emission at T_w (eqs. 3.9-3.13): tangential components Gaussian with variance
    /// k T_w / m, normal component from the flux-weighted (Rayleigh) half-Maxwellian
    #[default]
    Thermal,
    /// Maxwell's wall: diffuse at T_w with probability alpha (`accommodation`), else specular
    Maxwell,
    /// athermal wall of bulk roughness beta_w (`wall_roughness`, eqs. 4.1-4.3):
    /// v_x' = -beta_w v_x, v_y' = -v_y, v_z' = -beta_w v_z (beta_w = -1 smooth, 1 fully rough)
    Rough,
    /// athermal adiabatic wall (eqs. 4.5-4.7): v_y' = -v_y, tangential components re-drawn from
    /// a Gaussian at the temperature of the layer cell next to the wall
    Adiabatic,
    /// no walls: y is periodic (homogeneous states and tests; needs forcing = 0)
    Periodic,
}

/// Everything that defines one DSMC channel run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DsmcParams {
    /// Kn = lambda / W, lambda = 1 / (sqrt 2 pi n d_1^2) set a priori from the mean total number
    /// density n (eqs. 3.20-3.21; for mixtures n = n_1 + n_2, thesis 5.4)
    pub knudsen_number: f64,
    /// a-hat = a W / (2 k T_w / m_1), the dimensionless body force along +x (eq. 3.4); for
    /// athermal walls T_w is the initial temperature and only Q-hat (eq. 4.4) is meaningful
    pub forcing: f64,
    /// e_n = e_11, normal restitution of smooth inelastic hard spheres, in [0, 1]
    pub restitution: f64,
    /// the wall model of both walls
    pub wall_model: WallModel,
    /// alpha, diffuse fraction of the Maxwell wall, in [0, 1] (used by `maxwell` only)
    pub accommodation: f64,
    /// beta_w, bulk roughness of the rough wall, in [-1, 1] (used by `rough` only)
    pub wall_roughness: f64,
    /// layer cells across y (collision and sampling cells coincide, thesis 3.2.2); 0: automatic,
    /// the fewest with cell width <= lambda / 3, at least [`MIN_AUTOMATIC_CELLS`]
    pub cells: usize,
    /// simulators per cell on average (N = round(cells x particles_per_cell); with the density
    /// fixed by Kn this sets the weight F_N = n V / N)
    pub particles_per_cell: f64,
    /// Delta t in mean collision times tau_c = lambda / sqrt(8 k T_w / (pi m)) of the gas at
    /// rest at T_w (for mixtures: the shortest species collision time), in (0, 1]
    pub time_step: f64,
    /// steps between two samples of the cell moments (1: every step)
    pub sample_every: u64,
    /// x_2, number fraction of species 2 (0: monodisperse), in [0, 1)
    pub species2_fraction: f64,
    /// m_2 / m_1
    pub mass_ratio: f64,
    /// d_2 / d_1
    pub diameter_ratio: f64,
    /// e_12, restitution of unlike collisions, in [0, 1]
    pub restitution_12: f64,
    /// e_22, restitution of species-2 collisions, in [0, 1]
    pub restitution_22: f64,
    /// seed of the portable random stream (PCG-64 MCG)
    pub seed: u64,
}

impl Default for DsmcParams {
    /// A molecular gas between thermal walls at Kn = 0.1, a-hat = 0.5, dt = 0.1 tau_c, 20
    /// simulators per cell, sampled every step, monodisperse.
    fn default() -> Self {
        DsmcParams {
            knudsen_number: 0.1,
            forcing: 0.5,
            restitution: 1.0,
            wall_model: WallModel::Thermal,
            accommodation: 1.0,
            wall_roughness: -0.9,
            cells: 0,
            particles_per_cell: 20.0,
            time_step: 0.1,
            sample_every: 1,
            species2_fraction: 0.0,
            mass_ratio: 1.0,
            diameter_ratio: 1.0,
            restitution_12: 1.0,
            restitution_22: 1.0,
            seed: 1,
        }
    }
}

impl DsmcParams {
    /// A monodisperse gas between thermal walls (thesis ch. 3).
    pub fn thermal(knudsen_number: f64, forcing: f64, restitution: f64, seed: u64) -> Self {
        DsmcParams {
            knudsen_number,
            forcing,
            restitution,
            seed,
            ..DsmcParams::default()
        }
    }

    /// Check ranges; the message names the key, its value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        let bad = |key: &str, value: &dyn std::fmt::Display, allowed: &str| {
            Err(format!(
                "{key} = {value} is out of range: allowed {allowed}"
            ))
        };
        let finite_in = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        if !(finite_in(self.knudsen_number, 0.0, 1e4) && self.knudsen_number > 0.0) {
            return bad("knudsen_number", &self.knudsen_number, "0 < Kn <= 1e4");
        }
        if !finite_in(self.forcing, 0.0, 1e4) {
            return bad("forcing", &self.forcing, "0 <= a-hat <= 1e4");
        }
        for (key, e) in [
            ("restitution", self.restitution),
            ("restitution_12", self.restitution_12),
            ("restitution_22", self.restitution_22),
        ] {
            if !finite_in(e, 0.0, 1.0) {
                return bad(key, &e, "0 <= e <= 1");
            }
        }
        if !finite_in(self.accommodation, 0.0, 1.0) {
            return bad("accommodation", &self.accommodation, "0 <= alpha <= 1");
        }
        if !finite_in(self.wall_roughness, -1.0, 1.0) {
            return bad("wall_roughness", &self.wall_roughness, "-1 <= beta_w <= 1");
        }
        if self.cells > 100_000 {
            return bad("cells", &self.cells, "0 (automatic) or 1 to 100000");
        }
        if !(finite_in(self.particles_per_cell, 0.0, 1e6) && self.particles_per_cell > 0.0) {
            return bad(
                "particles_per_cell",
                &self.particles_per_cell,
                "0 < value <= 1e6",
            );
        }
        if !(finite_in(self.time_step, 0.0, 1.0) && self.time_step > 0.0) {
            return bad(
                "time_step",
                &self.time_step,
                "0 < dt <= 1 mean collision times (a fraction of it: 0.05-0.2 is usual)",
            );
        }
        if self.sample_every == 0 {
            return bad("sample_every", &self.sample_every, "1 or more steps");
        }
        if !(finite_in(self.species2_fraction, 0.0, 1.0) && self.species2_fraction < 1.0) {
            return bad(
                "species2_fraction",
                &self.species2_fraction,
                "0 <= x_2 < 1 (0: monodisperse)",
            );
        }
        for (key, r) in [
            ("mass_ratio", self.mass_ratio),
            ("diameter_ratio", self.diameter_ratio),
        ] {
            if !(finite_in(r, 1e-3, 1e3)) {
                return bad(key, &r, "1e-3 to 1e3");
            }
        }
        let cells = self.cell_count();
        let n = self.species_counts();
        if n[0] + n[1] < 2 || n[0] == 0 || (self.species2_fraction > 0.0 && n[1] == 0) {
            return Err(format!(
                "particles_per_cell = {} gives {} simulators of species 1 and {} of species 2 \
                 in {cells} cells: allowed at least 2 in all and 1 of each species present",
                self.particles_per_cell, n[0], n[1]
            ));
        }
        if self.wall_model == WallModel::Periodic && self.forcing != 0.0 {
            return bad(
                "forcing",
                &self.forcing,
                "0 with wall_model = periodic (without walls a body force accelerates the gas \
                 for ever)",
            );
        }
        if self.forcing > 0.0 && !self.has_energy_sink() {
            return Err(format!(
                "wall_model = {:?} with elastic particles has no energy sink: the body force \
                 (forcing = {}) would heat the gas for ever; allowed: restitution < 1, a \
                 thermal wall, accommodation > 0 (maxwell) or -1 < wall_roughness < 1 (rough)",
                self.wall_model, self.forcing
            ));
        }
        Ok(())
    }

    /// Some mechanism removes energy: an inelastic collision that occurs, or a wall that
    /// thermalises or dissipates.
    fn has_energy_sink(&self) -> bool {
        let mixture = self.species2_fraction > 0.0;
        let inelastic = self.restitution < 1.0
            || (mixture && (self.restitution_12 < 1.0 || self.restitution_22 < 1.0));
        let wall = match self.wall_model {
            WallModel::Thermal => true,
            WallModel::Maxwell => self.accommodation > 0.0,
            WallModel::Rough => self.wall_roughness.abs() < 1.0,
            WallModel::Adiabatic | WallModel::Periodic => false,
        };
        inelastic || wall
    }

    /// Number of species: 2 when species2_fraction > 0, else 1.
    pub fn species(&self) -> usize {
        if self.species2_fraction > 0.0 { 2 } else { 1 }
    }

    /// Layer cells across the channel (resolving `cells = 0`).
    pub fn cell_count(&self) -> usize {
        if self.cells > 0 {
            return self.cells;
        }
        let needed = (3.0 / self.knudsen_number).ceil();
        (needed.min(100_000.0) as usize).max(MIN_AUTOMATIC_CELLS)
    }

    /// Simulators of each species: N = round(cells x particles_per_cell), N_2 = round(x_2 N).
    pub fn species_counts(&self) -> [usize; 2] {
        let total = (self.cell_count() as f64 * self.particles_per_cell).round() as usize;
        let second = (self.species2_fraction * total as f64).round() as usize;
        [total - second.min(total), second.min(total)]
    }

    /// Masses [m_1, m_2] = [1, mass_ratio].
    pub fn masses(&self) -> [f64; 2] {
        [1.0, self.mass_ratio]
    }

    /// Diameters [d_1, d_2] relative to d_1: [1, diameter_ratio].
    pub fn diameters(&self) -> [f64; 2] {
        [1.0, self.diameter_ratio]
    }

    /// Restitution of a pair of species (e_11, e_12, e_22).
    pub fn pair_restitution(&self, a: usize, b: usize) -> f64 {
        match (a.min(b), a.max(b)) {
            (0, 0) => self.restitution,
            (0, _) => self.restitution_12,
            _ => self.restitution_22,
        }
    }

    /// lambda = Kn W, the a priori mean free path.
    pub fn mean_free_path(&self) -> f64 {
        self.knudsen_number
    }

    /// n pi d_1^2 = 1 / (sqrt 2 lambda), the collision density of the real gas.
    pub fn collision_density(&self) -> f64 {
        1.0 / (std::f64::consts::SQRT_2 * self.mean_free_path())
    }

    /// a = 2 a-hat k T_w / (m_1 W), the body-force acceleration.
    pub fn acceleration(&self) -> f64 {
        2.0 * self.forcing
    }

    /// Mean collision time tau_c of the gas at rest at T_w with the a priori densities: for
    /// one species lambda / sqrt(8 k T_w / (pi m)); for a mixture the shortest of the species'
    /// 1 / nu_i, nu_i = sum_j n_j pi d_ij^2 sqrt(8 k T_w / (pi mu_ij)), mu_ij the reduced mass.
    pub fn collision_time(&self) -> f64 {
        let x = [1.0 - self.species2_fraction, self.species2_fraction];
        let m = self.masses();
        let d = self.diameters();
        let mut fastest: f64 = 0.0;
        for i in 0..self.species() {
            let mut rate = 0.0;
            for j in 0..self.species() {
                let dij = 0.5 * (d[i] + d[j]);
                let reduced = m[i] * m[j] / (m[i] + m[j]);
                rate += x[j]
                    * self.collision_density()
                    * dij
                    * dij
                    * (8.0 / (std::f64::consts::PI * reduced)).sqrt();
            }
            fastest = fastest.max(rate);
        }
        1.0 / fastest
    }

    /// Delta t = time_step x tau_c.
    pub fn dt(&self) -> f64 {
        self.time_step * self.collision_time()
    }

    /// Steps of the slowest relaxation of the mean flow, max(W^2 / (pi^2 nu), W / v-bar), with
    /// the hard-sphere kinematic viscosity nu = 0.499 lambda v-bar at T_w (Chapman-Enskog,
    /// second approximation) and v-bar = sqrt(8 k T_w / (pi m_1)): records of a job should span
    /// at least this many steps to be nearly independent samples.
    pub fn relaxation_steps(&self) -> u64 {
        let mean_speed = (8.0 / std::f64::consts::PI).sqrt();
        let viscous =
            1.0 / (std::f64::consts::PI.powi(2) * 0.499 * self.mean_free_path() * mean_speed);
        let ballistic = 1.0 / mean_speed;
        (viscous.max(ballistic) / self.dt()).ceil() as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_derived_values_follow_the_definitions() {
        let p = DsmcParams::default();
        p.validate().unwrap();
        assert_eq!(p.cell_count(), 50);
        assert_eq!(p.species_counts(), [1000, 0]);
        let v_bar = (8.0 / std::f64::consts::PI).sqrt();
        assert!((p.collision_time() - 0.1 / v_bar).abs() < 1e-15);
        let fine = DsmcParams::thermal(0.01, 0.5, 1.0, 1);
        assert_eq!(fine.cell_count(), 300);
        // a mixture of equal species has the monodisperse collision time
        let twin = DsmcParams {
            species2_fraction: 0.5,
            ..DsmcParams::default()
        };
        assert!((twin.collision_time() / p.collision_time() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn messages_name_key_value_and_range() {
        let cases: Vec<(DsmcParams, &str)> = vec![
            (
                DsmcParams {
                    knudsen_number: -1.0,
                    ..Default::default()
                },
                "knudsen_number = -1",
            ),
            (
                DsmcParams {
                    restitution_12: 1.5,
                    ..Default::default()
                },
                "restitution_12 = 1.5",
            ),
            (
                DsmcParams {
                    time_step: 2.0,
                    ..Default::default()
                },
                "time_step = 2",
            ),
            (
                DsmcParams {
                    wall_model: WallModel::Periodic,
                    ..Default::default()
                },
                "forcing = 0.5",
            ),
            (
                DsmcParams {
                    wall_model: WallModel::Adiabatic,
                    ..Default::default()
                },
                "no energy sink",
            ),
            (
                DsmcParams {
                    wall_model: WallModel::Rough,
                    wall_roughness: -1.0,
                    ..Default::default()
                },
                "no energy sink",
            ),
            (
                DsmcParams {
                    particles_per_cell: 0.01,
                    ..Default::default()
                },
                "particles_per_cell = 0.01",
            ),
        ];
        for (p, needle) in cases {
            let err = p.validate().unwrap_err();
            assert!(err.contains(needle), "{err:?} should contain {needle:?}");
            assert!(err.contains("allowed"), "{err:?}");
        }
        // a sink makes the athermal walls valid
        DsmcParams {
            wall_model: WallModel::Adiabatic,
            restitution: 0.9,
            ..Default::default()
        }
        .validate()
        .unwrap();
    }
}
