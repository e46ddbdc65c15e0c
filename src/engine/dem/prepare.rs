//! The preparation (paper §2, Fig. 2): the particles, with sizes drawn from the mix, start on
//! a loose lattice above a temporary flat floor normal to x (gravity, along +x, pushes them
//! onto it, at x = L), with small random velocities; they rain onto it and settle under the
//! run's contact law in two stages:
//! 1. *compaction*: friction `settle_friction` (0 by default) for pairs, walls and floor,
//!    until the kinetic energy per particle is below [`COMPACT_ENERGY`] m_p g d_p (1e-4) or
//!    for at most 10 + 5 sqrt(2 h / g) time units (h the lattice's height): a frictionless
//!    rain packs densely, as the paper's fill (a settled packing of about 0.63) needs;
//! 2. *freezing*: the run's friction (mu_p, mu_w), until the kinetic energy per particle is
//!    below [`SETTLE_ENERGY`] m_p g d_p (1e-6): friction stops the slow creep of a
//!    frictionless packing, which would otherwise take many times longer to come to rest.
//!
//! Then the floor is removed and x made periodic with period L. The settled packing fills part
//! of L and the rest is empty space that the flow closes (the paper's Delta H); a packing
//! taller than L is refused. With `settle_friction` = mu_p = mu_w both stages are the run's
//! law throughout (the literal reading of the paper).
//!
//! Everything is drawn from one PCG-64 stream seeded by the job's seed, so the preparation is
//! a deterministic function of the parameters; it runs in the engine's own steps and is
//! checkpointed like the run.
//!
//! Lattice: simple cubic with spacing at least 1.1 d_max; across y, floor(W / 1.1 d_max)
//! sites spaced W / n_y (so that every site is at least 0.55 d_max from a wall), along z
//! floor(B / 1.1 d_max) sites spaced B / n_z, layers of spacing 1.1 d_max from the floor
//! upwards (x decreasing), filled layer by layer; the N sizes (exact counts of the mix) are
//! shuffled onto the first N sites; each velocity component is uniform in
//! [-0.1, 0.1] sqrt(g d_p) less the mean (no net momentum: with frictionless settling a
//! common drift along z would never stop), spins zero.

use super::bodies::BodyState;
use super::params::{DemParams, sphere_mass};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Settled when the kinetic energy (translation and rotation) per particle is below this, in
/// units of m_p g d_p (m_p = pi/6, the reference sphere's mass): an rms speed of about
/// 2e-3 sqrt(g d_p). Not lower: with friction, rattlers rolling without slip along grooves of
/// the packing (the law has no rolling resistance) keep about 1e-8 for ever.
pub const SETTLE_ENERGY: f64 = 1e-6;
/// The compaction stage ends when the kinetic energy per particle is below this (m_p g d_p).
pub const COMPACT_ENERGY: f64 = 1e-4;
/// Steps between two checks of the settling criterion.
pub const SETTLE_CHECK_EVERY: u64 = 100;
/// Lattice spacing over the largest diameter.
pub const LATTICE_SPACING: f64 = 1.1;
/// Largest initial velocity component, sqrt(g d_p).
pub const INITIAL_SPEED: f64 = 0.1;

/// The state of a preparation in progress.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Preparation {
    /// x of the floor (= L)
    pub floor: f64,
    /// the largest number of steps it may take: 50 + 10 sqrt(2 h / g) time units for a
    /// lattice of height h (the free fall from its top, ten times over, and margin)
    pub max_steps: u64,
    /// the longest compaction: 10 + 5 sqrt(2 h / g) time units
    pub compact_max_steps: u64,
    /// kinetic energy per particle that ends the compaction
    pub compact_threshold: f64,
    /// in the freezing stage (the run's friction)
    pub freezing: bool,
    /// kinetic energy per particle below which the packing has settled
    pub threshold: f64,
    /// steps done
    pub steps: u64,
    /// kinetic energy per particle at the last check
    pub last_energy: f64,
}

/// The particles on their lattice (canonical order = site order, from the floor upwards),
/// and the preparation that will settle them.
pub fn lattice(params: &DemParams) -> Result<(Vec<BodyState>, Preparation), String> {
    let n = params.particle_count();
    let d_max = params.max_diameter();
    let a = LATTICE_SPACING * d_max;
    let ny = (params.width / a).floor() as usize;
    let nz = (params.span / a).floor() as usize;
    if ny == 0 || nz == 0 {
        return Err(format!(
            "the channel ({} x {}) holds no lattice site of spacing {a}",
            params.width, params.span
        ));
    }
    let (sy, sz) = (params.width / ny as f64, params.span / nz as f64);
    let layers = n.div_ceil(ny * nz);
    let mut rng = Pcg64Mcg::seed_from_u64(params.seed);
    // exact counts of each size, shuffled onto the sites (Fisher-Yates)
    let mut diameters = Vec::with_capacity(n);
    for (&(d, _), count) in params
        .size_mix
        .components()
        .iter()
        .zip(params.size_mix.counts(n))
    {
        diameters.extend(std::iter::repeat_n(d, count));
    }
    for i in (1..n).rev() {
        let j = rng.random_range(0..=i);
        diameters.swap(i, j);
    }
    let floor = params.length;
    let mut states = Vec::with_capacity(n);
    'sites: for layer in 0..layers {
        for iy in 0..ny {
            for iz in 0..nz {
                if states.len() == n {
                    break 'sites;
                }
                let position = [
                    floor - (layer as f64 + 0.5) * a,
                    (iy as f64 + 0.5) * sy,
                    (iz as f64 + 0.5) * sz,
                ];
                let mut velocity = [0.0; 3];
                for c in &mut velocity {
                    *c = INITIAL_SPEED * (2.0 * rng.random::<f64>() - 1.0);
                }
                states.push(BodyState::fresh(
                    diameters[states.len()],
                    position,
                    velocity,
                    [0.0; 3],
                ));
            }
        }
    }
    // no net momentum: with frictionless settling nothing would ever stop a common drift
    // along the periodic z (or along x before the floor is reached)
    let total_mass: f64 = states.iter().map(|s| sphere_mass(s.diameter)).sum();
    for k in 0..3 {
        let p: f64 = states
            .iter()
            .map(|s| sphere_mass(s.diameter) * s.velocity[k])
            .sum();
        for s in &mut states {
            s.velocity[k] -= p / total_mass;
        }
    }
    let g = params.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    if params.gravity[0] <= 0.0 {
        return Err(format!(
            "the preparation needs gravity along +x towards its floor (gravity = {:?})",
            params.gravity
        ));
    }
    let height = layers as f64 * a;
    let fall = (2.0 * height / g).sqrt();
    let cap_time = 50.0 + 10.0 * fall;
    let compact_time = 10.0 + 5.0 * fall;
    let reference_mass = std::f64::consts::PI / 6.0;
    Ok((
        states,
        Preparation {
            floor,
            max_steps: (cap_time / params.time_step).ceil() as u64,
            compact_max_steps: (compact_time / params.time_step).ceil() as u64,
            compact_threshold: COMPACT_ENERGY * reference_mass * g,
            freezing: false,
            threshold: SETTLE_ENERGY * reference_mass * g,
            steps: 0,
            last_energy: f64::NAN,
        },
    ))
}
