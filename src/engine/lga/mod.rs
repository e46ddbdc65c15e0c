//! The lattice-gas automaton of Peng & Herrmann (PRE 49, R1796, 1994) for granular flow in
//! a vertical pipe: a triangular lattice L sites long (periodic, along gravity) and W sites
//! wide between two walls, seven Boolean states per site (six moving, one rest), updated in
//! parallel by a collision step and a propagation step.
//!
//! Modules: [`params`] (rho, p, g, b, L, W, seed), [`rules`] (lattice, velocities and the
//! site rules in the seed's notation, with the reading of its bond indices), [`rng`] (the
//! counter-based random stream), [`kernel`] (the bit-parallel engine [`LgaEngine`]),
//! [`reference`] (one site at a time, the test oracle), [`state`] (counters, checkpoint
//! payload), `declaration` (the registry's view and the [`crate::engine::Engine`] boundary).
//!
//! **One time step** (step t -> t + 1; all random decisions are keyed by (seed, t, purpose,
//! site), see [`rng`]):
//! 1. *Collisions* (1)-(5) at every site, on the state after the previous propagation (see
//!    [`rules`] for the table). Rules (4) and (5) leave two or one *extra* rest particles.
//! 2. *Hops.* The extra rest particles are placed one after another, sites in site order
//!    (index y L + x) and, at a site of rule (4), the first extra before the second: each
//!    hops to a uniformly chosen neighbour inside the pipe (4 neighbours next to a wall, 6
//!    elsewhere), again and again, until it reaches a site without a rest particle, where it
//!    stays. A hop may return to a site already visited. The walk is bounded: after
//!    `MAX_HOPS` = 1024 hops the particle goes to the first site without a rest particle
//!    after the walk's last site in site order (counted as `hop_fallbacks`). Before the
//!    hops of a site, if fewer sites without a rest particle are left than it has extras, its
//!    rule (4)/(5) is not applied and the site keeps its state (counted as
//!    `blocked_rest_collisions`), so that mass is conserved and nothing can loop forever.
//! 3. *Gravity* (6) on the state after the hops, every site in parallel, three independent
//!    decisions of probability g that read the state before this rule: a rest particle
//!    starts to move along gravity (v1) if v1 is empty; at a site with a rest particle, v3
//!    turns into v3 + v1 = v2 if v2 is empty and v5 into v5 + v1 = v6 if v6 is empty (the
//!    only moving velocities for which "v + unit vector along gravity" is again a lattice
//!    velocity; v4 + v1 = 0 is the rest state, which is occupied). Each event adds v1 to the
//!    momentum. Gravity acts only through rest particles, as the seed's rule says; with
//!    p = 0 the initial state has none and no rule creates one, so gravity never acts.
//! 4. *Walls* (7) and *propagation.* Every particle moves to the neighbour its velocity points
//!    to. A particle at a wall column moving towards the wall (v5, v6 at y = 0; v2, v3 at
//!    y = W - 1) instead stays at its site and turns inwards: bounced back (v -> -v) with
//!    probability b, else specularly reflected (v5 <-> v3, v6 <-> v2 at y = 0; v2 <-> v6,
//!    v3 <-> v5 at y = W - 1); the wall lies half a bond beyond the wall column. The
//!    state it turns into receives no other particle in that step. One decision per wall
//!    site serves both particles that may hit the wall there (with two particles the
//!    outcome is the same either way), so each particle is bounced back with probability b.
//!
//! **Initial state:** every moving state of every site occupied with probability rho / 6
//! (no rest particles), so 0 <= rho <= 6.
//!
//! **Units.** Momentum: x (along gravity) in halves of the lattice spacing, y in units of
//! sqrt(3)/2, so v1 = (2, 0), v2 = (1, 1) (see [`rules::MOMENTUM`]). Probabilities are
//! realised as multiples of 2^-32.

mod declaration;
pub mod kernel;
mod params;
mod reference;
pub mod rng;
pub mod rules;
pub mod state;

pub use declaration::{DECLARATION, params_of};
pub use kernel::LgaEngine;
pub use params::LgaParams;
pub use reference::LgaReference;
pub use state::Counters;
