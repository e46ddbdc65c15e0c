//! Soft-sphere DEM of dense granular flow in a vertical channel (Debnath, Rao & Kumaran, J.
//! Fluid Mech. 2022; `../shared/spec/dem.md`): frictional spheres with the linear
//! spring-dashpot law and tangential history of LAMMPS' `gran/hooke/history`, falling under
//! gravity between two flat frictional walls.
//!
//! **Axes.** granflow's convention: x along the flow and gravity (+x), periodic, length L;
//! y wall to wall, walls at y = 0 and y = W; z the span, periodic, width B. The paper's axes
//! differ: its x is wall-normal (our y), its y is the flow (our x), its z the span (our z).
//! So the paper's u_y is our u_x, its H our L, and its sigma_xy (wall-normal force component,
//! flow-wise branch vector) our sigma_yx: the first index of a contact stress is the force
//! component ([`sampling`]).
//!
//! **Units.** d_p = rho_p = g = 1; a sphere of diameter d has m = (pi/6) d^3, I = m d^2 / 10.
//!
//! **Decisions** (where the paper is silent or inconsistent, dem.md A1-A2):
//! - damping: xi_n follows from e_n = 0.82 for the d_p-d_p pair by default (xi_n = 246.4 at
//!   k_n = 1e6), or is given (`normal_damping`, the paper's literal 180); every record
//!   carries e_n and t_c of each pair type and of the wall ([`params::ContactType`]);
//! - the wall is a particle of infinite mass: m_eff = m_i, the same k_n, k_t, xi_n, xi_t, and
//!   mu_w (= mu_p by default), as LAMMPS' `fix wall/gran`;
//! - sliding rescales the history so that the spring gives the Coulomb cap, as LAMMPS does;
//!   a tensile net normal force is not clipped;
//! - sizes: exact counts of the mix (30/40/30 % of 0.9/1.0/1.1 d_p), shuffled by the seed;
//! - preparation: rain from a lattice onto a floor at x = L with `settle_friction` (0 by
//!   default, the densest pouring), settled below 1e-8 m_p g d_p per particle, then the floor
//!   is removed and x made periodic ([`prepare`]).
//!
//! **Modules.** [`params`] (validated parameters, contact types, the time-step rule),
//! [`contact`] (the contact law, shared by everything), [`bodies`] (struct-of-arrays storage),
//! [`domain`] (periodicity), [`neighbours`] (cell list, neighbour list, histories across
//! rebuilds), [`forces`] (the parallel pair and particle passes, velocity Verlet),
//! [`prepare`] (the lattice and the settling), [`sampling`] (bins and interval sums),
//! [`bond_order`] (the bond-orientational sums behind Q6, taken at each snapshot),
//! [`engine`] (the step loop, snapshots, checkpoints), [`lammps`] (LAMMPS data, input and
//! dump files), [`imported`] (a LAMMPS dump's frames as records for the analysis), [`reference`] (all pairs, one thread:
//! what the tests hold the engine to, bit for bit), `declaration` (the registry's view).
//!
//! **Determinism.** Each pair is evaluated once, by its owner (its lower tag), into its slot;
//! a particle's force is minus the sum of its lower-tag partners' pair forces (tag order)
//! plus the sum of its owned pairs' forces (tag order), then wall, floor and gravity. No sum depends on the number of threads, the working order, the cell size, the
//! skin or the rebuild times, so runs agree bitwise on any number of threads, with any skin,
//! and after any checkpoint and restore.

pub mod bodies;
pub mod bond_order;
mod contact;
mod contact_lanes;
mod declaration;
mod domain;
mod engine;
mod forces;
pub mod imported;
pub mod lammps;
pub mod neighbours;
pub mod params;
mod prepare;
pub mod reference;
pub mod sampling;
pub mod scan_lanes;
mod simd;

pub use bodies::BodyState;
pub use bond_order::BondSums;
pub use declaration::{DECLARATION, params_of};
pub use engine::{DemCounters, DemEngine, Phase, Record, RunConstants, Sample, Totals};
pub use neighbours::KeptContact;
pub use params::{ContactType, DampingFrom, DemParams, SizeMix, WallDamping};
pub use sampling::{BinSums, Bins, IntervalSums};
