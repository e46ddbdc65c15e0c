//! Event-driven molecular dynamics (EDMD) of rough inelastic hard spheres in a
//! gravity-driven channel (Malik 2008 thesis, ch. 2).
//!
//! - [`collision`]: the pure collision rules (what happens).
//! - [`motion`]: free flight under gravity and meeting times (when it happens).
//! - [`cells`], [`neighbours`], [`queue`]: the fast data structures (with a reference queue
//!   for tests);
//!   `search`: partner batches and prefetching for the neighbour search.
//! - [`setup`]: placement and initial velocities; [`checkpoint`]: the file format.
//! - [`EdmdEngine`]: the event loop; [`reference`]: a slow all-pairs engine for tests.

pub mod cells;
pub mod checkpoint;
pub mod collision;
mod engine;
pub mod motion;
pub mod neighbours;
mod params;
pub mod queue;
pub mod reference;
mod search;
pub mod setup;

pub use engine::{EdmdEngine, NeighbourSearch, PhysicalEvent};
pub use params::{EdmdParams, Placement, particles_for_volume_fraction};
