//! Direct simulation Monte Carlo (Bird) of the Boltzmann equation.
//!
//! - [`homogeneous`]: a spatially homogeneous gas of rough inelastic spheres (no positions),
//!   the exact solution of the Boltzmann equation without the Maxwellian closure of kinetic
//!   theory; it is the reference for the homogeneous cooling state where that closure is not
//!   accurate (nearly smooth spheres, beta <= 0).
//! - [`channel`]: the channel engine of Gupta's thesis (2017): smooth inelastic hard spheres
//!   (one or two species) driven by a body force between two walls, layer cells, Bird's
//!   no-time-counter collisions; [`params`] (control parameters), [`walls`] (flights and wall
//!   models), [`sampling`] (cell moments and balances).
//! - `declaration`: the channel engine as the registry sees it (`engine: "dsmc"`).
//! - [`kernel`]: what both share: the contact direction of a hard-sphere collision, the
//!   smooth inelastic collision rule, portable random deviates.

pub mod channel;
mod declaration;
pub mod homogeneous;
pub mod kernel;
mod params;
pub mod sampling;
mod walls;

pub use channel::{DsmcChecks, DsmcCounters, DsmcEngine, Sample, Simulator};
pub use declaration::{DECLARATION, WALL_MODELS, params_of};
pub use params::{DsmcParams, WallModel};
pub use sampling::{Balances, IntervalSums};
