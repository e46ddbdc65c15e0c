//! The engine boundary: what every simulation engine offers to a job (advance, snapshot,
//! checkpoint/restore, counters), independent of how it moves particles, and the shape of the
//! declaration ([`declare`]) in which each engine states its parameters, clocks and counters
//! once. The engines import nothing above this layer; `crate::registry` lists them and pairs
//! each with its analysis.
//!
//! Units of the particle engines: particle diameter d = 1, mass m = 1, gravity g = 1 (when
//! switched on); time is measured in sqrt(d/g). The lattice gas counts sites and time steps.

pub mod declare;
pub mod dem;
pub mod dsmc;
pub mod edmd;
pub mod envelope;
pub mod free_paths;
pub mod lga;
pub(crate) mod prefetch;

use serde::{Deserialize, Serialize};
use std::any::Any;
use std::fmt;

pub use declare::{Clock, EngineDef, ParamDef, ParamValue, Values};
pub use free_paths::FreePathTally;

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

/// An engine's counters as named values, in the order its declaration lists them
/// (cumulative since the start of the run, kept across checkpoints).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counters(pub Vec<(String, u64)>);

impl Counters {
    /// The value of a counter (0 when the engine has no counter of that name).
    pub fn get(&self, name: &str) -> u64 {
        self.value(name).unwrap_or(0)
    }

    /// The value of a counter, None when the result has no counter of that name (e.g. one
    /// imported from another code's output, which counts fewer things).
    pub fn value(&self, name: &str) -> Option<u64> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// From (name, value) pairs.
    pub fn from_pairs<'a>(pairs: impl IntoIterator<Item = (&'a str, u64)>) -> Self {
        Counters(pairs.into_iter().map(|(n, v)| (n.to_string(), v)).collect())
    }
}

impl Serialize for Counters {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (name, value) in &self.0 {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Counters {
    /// Accepts a map `{"name": value}` and a struct `(name: value)` alike (results written
    /// before counters were named hold the struct form).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = Counters;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("named counters")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut m: A,
            ) -> Result<Counters, A::Error> {
                let mut out = Vec::new();
                while let Some((k, v)) = m.next_entry::<String, u64>()? {
                    out.push((k, v));
                }
                Ok(Counters(out))
            }
        }
        d.deserialize_any(Visit)
    }
}

/// Where a running engine is, on every clock it may be driven by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    /// simulated time t (sqrt(d/g) for particle engines; time steps for the lattice gas)
    pub time: f64,
    /// collisions per particle = 2 x pair collisions / N (the thesis' clock; 0 where the
    /// engine has no collisions to count)
    pub collisions_per_particle: f64,
    /// time steps taken (engines with a fixed step; 0 for event-driven ones)
    pub steps: u64,
    /// events processed so far (EDMD: all queue events; stepped engines: site or particle
    /// updates), the measure of work done
    pub events: u64,
}

impl Progress {
    /// The reading of one clock.
    pub fn on(&self, clock: Clock) -> f64 {
        match clock {
            Clock::CollisionsPerParticle => self.collisions_per_particle,
            Clock::Steps => self.steps as f64,
            Clock::Time => self.time,
        }
    }
}

/// A point of simulated progress at which an engine stops: a reading of one of its clocks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum StopAt {
    /// stop at the first event after which collisions per particle >= this value
    CollisionsPerParticle(f64),
    /// stop after this many time steps
    Steps(u64),
    /// stop exactly at this simulated time (stepped engines: at the first step reaching it)
    Time(f64),
}

impl StopAt {
    /// Stop when `clock` reads `value`.
    pub fn on(clock: Clock, value: f64) -> Self {
        match clock {
            Clock::CollisionsPerParticle => StopAt::CollisionsPerParticle(value),
            Clock::Steps => StopAt::Steps(value.ceil() as u64),
            Clock::Time => StopAt::Time(value),
        }
    }

    /// The clock it reads.
    pub fn clock(&self) -> Clock {
        match self {
            StopAt::CollisionsPerParticle(_) => Clock::CollisionsPerParticle,
            StopAt::Steps(_) => Clock::Steps,
            StopAt::Time(_) => Clock::Time,
        }
    }
}

/// Spheres brought to one time: what the particle analyses consume. Engines without spins
/// leave `angular_velocities` empty; 2D engines keep z = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Particles {
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
    /// angular velocities w_i (empty for smooth spheres)
    pub angular_velocities: Vec<[f64; 3]>,
    /// diameters d_i (empty: every sphere has the reference diameter d = 1)
    #[serde(default)]
    pub diameters: Vec<f64>,
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
    /// cumulative energy a collapse guard (EDMD's TC model) kept from being dissipated: what
    /// the collisions it altered would have dissipated in addition under the model's own
    /// collision law (0 for engines without one; NaN where unknown)
    pub suppressed_dissipation: f64,
}

impl Particles {
    /// Number of particles N.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Angular velocity of particle `p` (zero for smooth spheres, which carry none).
    #[inline]
    pub fn spin(&self, p: usize) -> [f64; 3] {
        self.angular_velocities.get(p).copied().unwrap_or([0.0; 3])
    }
}

/// A 2D lattice gas seen along its pipe: particles per row across the pipe and the total
/// momentum (what the lattice analyses consume; the full occupation is the engine's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lattice {
    /// L, sites along the pipe (periodic, along gravity)
    pub length: usize,
    /// W, sites across the pipe (between the walls)
    pub width: usize,
    /// particles in each row x = 0 .. L - 1 (all W sites and all states of the row)
    pub row_counts: Vec<u32>,
    /// total momentum in the engine's integer units (LGA: x along gravity in half lattice
    /// spacings, y in sqrt(3)/2)
    pub momentum: [i64; 2],
}

/// What a snapshot holds, by kind of engine.
#[derive(Debug)]
pub enum Content {
    /// spheres (hard-sphere MD)
    Particles(Particles),
    /// a lattice gas
    Lattice(Lattice),
    /// the engine's own sample, which only its analysis reads ([`Snapshot::sample`]): DSMC's
    /// cell moments and balances since the previous snapshot, DEM's bin sums and wall
    /// balances with its particles
    Sample(Box<dyn EngineSample>),
}

/// An engine's own snapshot content: a type of the engine's that its analysis downcasts
/// ([`Snapshot::sample`]); the rest of granflow sees only the particles it may carry.
pub trait EngineSample: SampleCopy + fmt::Debug + Send {
    /// The particles, where the sample carries them (viewers and particle analyses read them).
    fn particles(&self) -> Option<&Particles> {
        None
    }
    /// The particles, mutable (tests that build synthetic states).
    fn particles_mut(&mut self) -> Option<&mut Particles> {
        None
    }
}

/// Copy and comparison of a boxed sample (snapshots are `Clone` and `PartialEq`); every
/// `Clone + PartialEq` sample has them.
pub trait SampleCopy: Any {
    fn boxed_clone(&self) -> Box<dyn EngineSample>;
    fn same_as(&self, other: &dyn EngineSample) -> bool;
}

impl<T: EngineSample + Clone + PartialEq> SampleCopy for T {
    fn boxed_clone(&self) -> Box<dyn EngineSample> {
        Box::new(self.clone())
    }
    fn same_as(&self, other: &dyn EngineSample) -> bool {
        (other as &dyn Any).downcast_ref::<T>() == Some(self)
    }
}

impl Clone for Content {
    fn clone(&self) -> Self {
        match self {
            Content::Particles(p) => Content::Particles(p.clone()),
            Content::Lattice(l) => Content::Lattice(l.clone()),
            Content::Sample(s) => Content::Sample(s.boxed_clone()),
        }
    }
}

impl PartialEq for Content {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Content::Particles(a), Content::Particles(b)) => a == b,
            (Content::Lattice(a), Content::Lattice(b)) => a == b,
            (Content::Sample(a), Content::Sample(b)) => a.same_as(&**b),
            _ => false,
        }
    }
}

/// The state of an engine at one time, with its clocks and counters. Analyses consume it;
/// the content says which kind of analysis applies.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// clocks at the snapshot
    pub progress: Progress,
    /// the engine's counters, named as its declaration names them
    pub counters: Counters,
    /// particles or lattice
    pub content: Content,
}

impl Snapshot {
    /// Simulated time of the snapshot.
    pub fn time(&self) -> f64 {
        self.progress.time
    }

    /// The particles, for engines whose snapshots carry them.
    pub fn particles(&self) -> Option<&Particles> {
        match &self.content {
            Content::Particles(p) => Some(p),
            Content::Sample(s) => s.particles(),
            Content::Lattice(_) => None,
        }
    }

    /// The particles, mutable (tests that build synthetic states).
    pub fn particles_mut(&mut self) -> Option<&mut Particles> {
        match &mut self.content {
            Content::Particles(p) => Some(p),
            Content::Sample(s) => s.particles_mut(),
            Content::Lattice(_) => None,
        }
    }

    /// The lattice, for lattice engines.
    pub fn lattice(&self) -> Option<&Lattice> {
        match &self.content {
            Content::Lattice(l) => Some(l),
            _ => None,
        }
    }

    /// The engine's own sample, when the snapshot holds one of type `T` (an analysis asks for
    /// its engine's type, e.g. `dsmc::Sample`).
    pub fn sample<T: EngineSample>(&self) -> Option<&T> {
        match &self.content {
            Content::Sample(s) => (&**s as &dyn Any).downcast_ref(),
            _ => None,
        }
    }
}

/// A preparation in progress ([`Engine::preparation`]): steps done, the most it may take, and
/// the quantity whose fall ends it.
#[derive(Clone, Debug, PartialEq)]
pub struct PreparationProgress {
    /// the stage it is in (e.g. "compaction", "freezing")
    pub stage: &'static str,
    /// steps done so far
    pub steps: u64,
    /// the most steps it may take before it is given up as failed
    pub max_steps: u64,
    /// what ends the stage, with its value now and the value that ends it (e.g. "kinetic
    /// energy per particle 3.1e-4, ends below 1.0e-6 m_p g d_p")
    pub measure: String,
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
    /// the engine cannot be driven by this clock
    #[error("the {engine} engine has no clock `{clock}`; its clocks: {allowed}")]
    Clock {
        engine: &'static str,
        clock: &'static str,
        allowed: String,
    },
}

/// A simulation engine as a job sees it.
pub trait Engine: Send {
    /// Its declaration (name, parameters, clocks, counters, analysis).
    fn def(&self) -> &'static EngineDef;
    /// Number of particles N (lattice gas: particles on the lattice).
    fn particle_count(&self) -> usize;
    /// Clocks and events so far.
    fn progress(&self) -> Progress;
    /// Advance until `stop` is reached (deterministically: the stopping point depends only on
    /// the state, never on wall-clock time).
    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError>;
    /// Bring the state to the current time and report it. Taking a snapshot is part of the
    /// deterministic trajectory (runs that snapshot at the same points agree bitwise).
    fn snapshot(&mut self) -> Snapshot;
    /// The whole engine state as bytes sealed in an [`envelope`] that names the engine. Only
    /// valid directly after `snapshot` (the deterministic synchronisation point).
    fn checkpoint(&self) -> Vec<u8>;
    /// Start tallying free paths between collisions ([`free_paths`]) over `slabs` slabs
    /// across y, from now on (statistics runs; nothing is tallied otherwise). Not part of the
    /// state: a job switches it on again after a restore. False when the engine has no
    /// collisions to measure (the default).
    fn record_free_paths(&mut self, _slabs: usize) -> bool {
        false
    }
    /// How far the preparation of the initial state has come, while the engine is still
    /// preparing it (DEM: the particles settling onto a floor before the flow starts); None
    /// when the engine has no preparation or it is over (the default).
    fn preparation(&self) -> Option<PreparationProgress> {
        None
    }
    /// Go on with the preparation for at most `steps` of its steps (none left: nothing to do).
    /// Where a preparation is split into calls does not change its result by a bit (each
    /// engine that prepares tests this), so a job may checkpoint after any call
    /// ([`Engine::checkpoint`] is valid there too) and resume.
    fn prepare(&mut self, _steps: u64) -> Result<(), EngineError> {
        Ok(())
    }
    /// The free paths ended since the last call (or since recording started), leaving an
    /// empty tally; None when the engine does not record them. A job takes them right after
    /// every snapshot, so that a checkpoint (taken there) never holds any.
    fn take_free_paths(&mut self) -> Option<FreePathTally> {
        None
    }
}
