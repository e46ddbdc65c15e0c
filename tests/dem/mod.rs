//! The DEM engine (Debnath, Rao & Kumaran, J. Fluid Mech. 2022).

mod analysis;
mod channel;
mod collisions;
mod conservation;
mod determinism;
mod import;
mod lammps;
mod preparation;
mod support;
