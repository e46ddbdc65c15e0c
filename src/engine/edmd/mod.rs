//! Event-driven molecular dynamics (EDMD) of rough inelastic hard spheres in a
//! gravity-driven channel (Malik 2008 thesis, ch. 2).
//!
//! - [`collision`]: the pure collision rules (what happens).
//! - [`motion`]: free flight under gravity and meeting times (when it happens).
//! - [`cells`], [`neighbours`], [`queue`]: the fast data structures (with a reference queue
//!   for tests); `images` (periodic image codes), `search` (the buffers that keep candidates
//!   without a branch), `huge` (large arrays on huge pages) and `prefetch` (cache hints)
//!   serve them.
//! - [`setup`]: placement and initial velocities; [`start`]: the thermalised start (a random
//!   packing run elastic and without gravity); [`checkpoint`]: the file format.
//! - [`EdmdEngine`] (`engine/`): the struct and its construction (`mod.rs`), `rebuild`,
//!   `cell_search` and `list_search` (event prediction; `lanes`: the contact test's first pass
//!   for two partners at once), `event_loop`, `collide` (what an event does), `stall`
//!   (inelastic-collapse check), `boundary` (the [`crate::engine::Engine`] trait);
//!   [`reference`]: a slow all-pairs engine for tests.

pub mod cells;
pub mod checkpoint;
pub mod collision;
mod declaration;
mod engine;
mod huge;
mod images;
pub mod motion;
pub mod neighbours;
mod params;
pub mod queue;
pub mod reference;
mod search;
pub mod search_policy;
pub mod setup;
pub mod start;

pub use checkpoint::EdmdCounters;
pub use declaration::{DECLARATION, geometry, lattice_capacity, params_of};
pub use engine::{EdmdEngine, NeighbourSearch, PhysicalEvent};
pub use params::{EdmdParams, Placement, particles_for_volume_fraction};
pub use search_policy::SearchPolicy;
