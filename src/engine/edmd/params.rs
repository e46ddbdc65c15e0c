//! Validated parameters of one EDMD run.

use crate::engine::{BoxGeometry, EngineError};
use serde::{Deserialize, Serialize};

/// How the initial configuration is placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Placement {
    /// random sequential placement where it works, else a randomly displaced lattice
    #[default]
    Auto,
    /// random sequential placement without overlap
    Random,
    /// a lattice filling the box (simple cubic where it leaves room between spheres, else a
    /// checkerboard, fcc-like, one), with small random displacements
    Lattice,
    /// an fcc lattice (the box must hold whole unit cells, as in the benchmark workloads)
    Fcc,
    /// a random packing, then this many collisions per particle elastic, smooth and without
    /// gravity before the run starts (see [`super::start`]): a fluid at rest on average. Last
    /// in the list, so that checkpoints written before it decode unchanged.
    Thermalised { collisions_per_particle: u32 },
}

/// Everything that defines one EDMD run (units d = m = g = 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdmdParams {
    /// the box (walls at y = 0, W or periodic)
    pub geometry: BoxGeometry,
    /// N, number of spheres
    pub particles: usize,
    /// g, gravity along +x (1 for the channel, 0 switches it off)
    pub gravity: f64,
    /// e, normal restitution of particle-particle collisions, in [0, 1]
    pub restitution: f64,
    /// beta, tangential restitution of particle-particle collisions, in [-1, 1]
    pub roughness: f64,
    /// e_w, normal restitution of particle-wall collisions, in [0, 1]
    pub wall_restitution: f64,
    /// beta_w, tangential restitution of particle-wall collisions, in [-1, 1]
    pub wall_roughness: f64,
    /// K = 4 I / (m d^2): 2/5 solid sphere, 2/3 thin shell
    pub inertia_factor: f64,
    /// t_c of the TC model: a pair collision in which either partner collided within the last
    /// t_c is elastic in the normal direction (0 switches the model off)
    pub tc: f64,
    /// kT of the initial Gaussian translational and rotational velocities
    pub initial_temperature: f64,
    /// initial placement
    pub placement: Placement,
    /// seed of the portable RNG used for placement and velocities
    pub seed: u64,
}

impl EdmdParams {
    /// Default TC time t_c, in sqrt(d/g): small against the mean free time (~0.1-1) of the
    /// channel flows, large against the time between collisions in a collapsing cluster.
    pub const DEFAULT_TC: f64 = 1e-4;

    /// The thesis channel with the given box and volume fraction (e = 0.7, beta = 0.1,
    /// e_w = beta_w = 0.99, K = 2/5, g = 1).
    pub fn channel(length: f64, width: f64, height: f64, volume_fraction: f64, seed: u64) -> Self {
        let geometry = BoxGeometry {
            length,
            width,
            height,
            walls: true,
        };
        EdmdParams {
            particles: particles_for_volume_fraction(&geometry, volume_fraction),
            geometry,
            gravity: 1.0,
            restitution: 0.7,
            roughness: 0.1,
            wall_restitution: 0.99,
            wall_roughness: 0.99,
            inertia_factor: 0.4,
            tc: Self::DEFAULT_TC,
            initial_temperature: 0.01,
            placement: Placement::Auto,
            seed,
        }
    }

    /// A plain periodic box of elastic smooth spheres without gravity.
    pub fn periodic_elastic(side: f64, particles: usize, temperature: f64, seed: u64) -> Self {
        EdmdParams {
            geometry: BoxGeometry {
                length: side,
                width: side,
                height: side,
                walls: false,
            },
            particles,
            gravity: 0.0,
            restitution: 1.0,
            roughness: -1.0,
            wall_restitution: 1.0,
            wall_roughness: -1.0,
            inertia_factor: 0.4,
            tc: 0.0,
            initial_temperature: temperature,
            placement: Placement::Auto,
            seed,
        }
    }

    /// Volume fraction phi = N (pi/6) / (L W H).
    pub fn volume_fraction(&self) -> f64 {
        self.particles as f64 * std::f64::consts::PI / 6.0 / self.geometry.volume()
    }

    /// Check ranges; the message names the parameter, its value and what is allowed.
    pub fn validate(&self) -> Result<(), EngineError> {
        let bad = |name: &str, value: f64, allowed: &str| {
            Err(EngineError::InvalidParams(format!(
                "{name} = {value} is out of range: allowed {allowed}"
            )))
        };
        let g = &self.geometry;
        for (name, v) in [
            ("length", g.length),
            ("width", g.width),
            ("height", g.height),
        ] {
            if !(v.is_finite() && v >= 3.0) {
                return bad(
                    name,
                    v,
                    "a finite box side of at least 3 particle diameters",
                );
            }
        }
        if self.particles == 0 {
            return Err(EngineError::InvalidParams(
                "particles = 0: at least one sphere is needed".into(),
            ));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad("restitution (e)", self.restitution, "[0, 1]");
        }
        if !(-1.0..=1.0).contains(&self.roughness) {
            return bad("roughness (beta)", self.roughness, "[-1, 1]");
        }
        if !(0.0..=1.0).contains(&self.wall_restitution) {
            return bad("wall_restitution (e_w)", self.wall_restitution, "[0, 1]");
        }
        if !(-1.0..=1.0).contains(&self.wall_roughness) {
            return bad("wall_roughness (beta_w)", self.wall_roughness, "[-1, 1]");
        }
        if !(self.inertia_factor.is_finite()
            && self.inertia_factor > 0.0
            && self.inertia_factor <= 1.0)
        {
            return bad(
                "inertia_factor (K)",
                self.inertia_factor,
                "(0, 1] (2/5 solid, 2/3 shell)",
            );
        }
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return bad("gravity (g)", self.gravity, "a finite value >= 0");
        }
        if !(self.tc.is_finite() && self.tc >= 0.0) {
            return bad(
                "tc",
                self.tc,
                "a finite time >= 0 (0 switches the TC model off)",
            );
        }
        if !(self.initial_temperature.is_finite() && self.initial_temperature > 0.0) {
            return bad(
                "initial_temperature",
                self.initial_temperature,
                "a finite value > 0",
            );
        }
        Ok(())
    }
}

/// N = round(phi L W H / (pi d^3 / 6)).
pub fn particles_for_volume_fraction(geometry: &BoxGeometry, volume_fraction: f64) -> usize {
    (volume_fraction * geometry.volume() / (std::f64::consts::PI / 6.0)).round() as usize
}
