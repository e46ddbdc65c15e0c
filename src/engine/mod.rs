//! The engine boundary: what every simulation engine offers to a job (advance, snapshot,
//! checkpoint/restore, counters), independent of how it moves particles.
//!
//! Units throughout: particle diameter d = 1, mass m = 1, gravity g = 1 (when switched on);
//! time is measured in sqrt(d/g).

pub mod dsmc;
pub mod edmd;
pub mod lga;

use serde::{Deserialize, Serialize};

/// The simulation box. x is the flow direction (periodic, gravity along +x), y is across the
/// channel (two flat walls at y = 0 and y = W, or periodic), z is the span (periodic).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoxGeometry {
    /// L, extent along x (flow), in particle diameters
    pub length: f64,
    /// W, extent along y (wall to wall), in particle diameters
    pub width: f64,
    /// H, extent along z (span), in particle diameters
    pub height: f64,
    /// true: flat walls at y = 0 and y = W; false: periodic in y (plain periodic box)
    pub walls: bool,
}

impl BoxGeometry {
    /// Extents as an array [L, W, H].
    pub fn extents(&self) -> [f64; 3] {
        [self.length, self.width, self.height]
    }

    /// Box volume L W H.
    pub fn volume(&self) -> f64 {
        self.length * self.width * self.height
    }
}

/// Event counters of a run (cumulative since the start of the run, kept across checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counters {
    /// particle-particle collisions (including TC-elastic ones)
    pub pair_collisions: u64,
    /// particle-wall collisions
    pub wall_collisions: u64,
    /// cell crossings (bookkeeping events)
    pub cell_crossings: u64,
    /// pair collisions made elastic by the TC model
    pub tc_elastic_collisions: u64,
    /// all events taken from the queue, including invalidated ones
    pub events: u64,
}

/// The thesis' clock and simulated time of a running engine.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    /// simulated time t, in sqrt(d/g)
    pub time: f64,
    /// collisions per particle = 2 x pair collisions / N (the thesis' clock)
    pub collisions_per_particle: f64,
    /// events processed so far
    pub events: u64,
}

/// A point of simulated progress at which an engine stops.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum StopAt {
    /// stop at the first event after which collisions per particle >= this value
    CollisionsPerParticle(f64),
    /// stop exactly at this simulated time
    Time(f64),
}

/// All particles brought to one time, with the run's counters and balances. This is what the
/// analysis consumes; it is engine-agnostic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// simulated time t of the snapshot
    pub time: f64,
    /// collisions per particle at the snapshot
    pub collisions_per_particle: f64,
    /// the box
    pub geometry: BoxGeometry,
    /// K = 4 I / (m d^2), the reduced moment of inertia (2/5 for solid spheres)
    pub inertia_factor: f64,
    /// g, gravitational acceleration along +x (0 when switched off)
    pub gravity: f64,
    /// particle centres r_i, wrapped into the box
    pub positions: Vec<[f64; 3]>,
    /// translational velocities c_i
    pub velocities: Vec<[f64; 3]>,
    /// angular velocities w_i
    pub angular_velocities: Vec<[f64; 3]>,
    /// event counters
    pub counters: Counters,
    /// translational kinetic energy sum m c^2 / 2
    pub translational_energy: f64,
    /// rotational kinetic energy sum I w^2 / 2
    pub rotational_energy: f64,
    /// cumulative impulse (momentum) delivered to the wall at y = 0 and to the wall at y = W
    pub wall_momentum: [[f64; 3]; 2],
    /// cumulative kinetic energy dissipated in collisions (pair + wall)
    pub energy_dissipated: f64,
    /// cumulative work done by gravity, m g sum of x-displacements
    pub gravity_work: f64,
}

impl Snapshot {
    /// Number of particles N.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

/// Errors an engine reports to the job that runs it.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// the parameters cannot be simulated (with the reason and what to change)
    #[error("invalid engine parameters: {0}")]
    InvalidParams(String),
    /// simulated time stopped advancing (inelastic collapse not cured by the TC model)
    #[error("simulation stalled: {0}")]
    Stalled(String),
    /// a checkpoint could not be read back
    #[error("checkpoint rejected: {0}")]
    Checkpoint(String),
}

/// A simulation engine as a job sees it.
pub trait Engine: Send {
    /// Number of particles N.
    fn particle_count(&self) -> usize;
    /// Simulated time, collisions per particle and events so far.
    fn progress(&self) -> Progress;
    /// Advance until `stop` is reached (deterministically: the stopping point depends only on
    /// the state, never on wall-clock time).
    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError>;
    /// Bring all particles to the current time and report them. Taking a snapshot is part of
    /// the deterministic trajectory (runs that snapshot at the same points agree bitwise).
    fn snapshot(&mut self) -> Snapshot;
    /// The whole engine state as a versioned, checksummed byte string. Only valid directly
    /// after `snapshot` (the deterministic synchronisation point).
    fn checkpoint(&self) -> Vec<u8>;
}

/// Which engine runs a job, with its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum EngineSpec {
    /// event-driven rough inelastic hard spheres (thesis ch. 2)
    Edmd(edmd::EdmdParams),
}

/// Build an engine in its initial state (placement and velocities from the seed).
pub fn build(spec: &EngineSpec) -> Result<Box<dyn Engine>, EngineError> {
    match spec {
        EngineSpec::Edmd(params) => Ok(Box::new(edmd::EdmdEngine::new(params.clone())?)),
    }
}

/// Rebuild an engine from a checkpoint written by [`Engine::checkpoint`].
pub fn restore(bytes: &[u8]) -> Result<Box<dyn Engine>, EngineError> {
    Ok(Box::new(edmd::EdmdEngine::restore(bytes)?))
}
