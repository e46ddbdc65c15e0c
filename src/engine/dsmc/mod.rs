//! Direct simulation Monte Carlo (Bird) of the Boltzmann equation for rough inelastic spheres.
//!
//! - [`homogeneous`]: a spatially homogeneous gas (no positions), the exact solution of the
//!   Boltzmann equation without the Maxwellian closure of kinetic theory; it is the reference
//!   for the homogeneous cooling state where that closure is not accurate (nearly smooth
//!   spheres, beta <= 0).

pub mod homogeneous;
