//! granflow's integration tests, one program (ripgrep's `tests/tests.rs` layout): cargo builds
//! and links one binary instead of one per file. A folder per part of the tool; each file's `//!`
//! line says what it checks and against which oracle.
//!
//! Run a part with a filter: `cargo test --release --test integration dem::` (or `edmd::cooling`).

/// The binary under test, scratch directories named after each test, the kill -9 loop.
mod common;

/// Structure analysis, milestones and the thesis' statistics (EDMD snapshots).
mod analysis;
/// The DEM engine: contact oracles, conservation, determinism, the channel, LAMMPS.
mod dem;
/// The DSMC engine: rarefied-gas oracles and the engine behind the job boundary.
mod dsmc;
/// The EDMD engine: collision, equilibrium and cooling oracles, channel balances, references.
mod edmd;
/// The engine boundary: a toy engine plugged in through the declaration path; layering.
mod engine;
/// The lattice gas: conservation, the bit-parallel kernel, the seed's oracles, sweeps.
mod lga;
/// Figures, the HTML report, the viewer files and the thesis-statement script's readings.
mod report;
/// Slurm job arrays on a real single-node cluster, and array tasks.
mod slurm;
/// The orchestrator: sweep files, ids, resume, the store, tampering, exit codes, tables.
mod sweep;
