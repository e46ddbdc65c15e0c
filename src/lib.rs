//! granflow: event-driven simulation, density-wave analysis and sweep orchestration for
//! gravity-driven granular channel flow ("granular Poiseuille flow").
//!
//! Architecture (data flow):
//! ```text
//! sweeps/*.ron --parse/validate--> sweep::SweepSpec --expand--> [job params] --id = hash--> results/<sweep>/jobs/<id>/
//!     job queue (claim, lock) --> rayon pool --> engine::Engine::advance ... snapshots --> analysis
//!     --> per-job outputs (atomic writes) --> gather --> results/<sweep>/*.parquet --> phase diagram
//! ```
//! - [`fs`]: atomic writes and I/O errors with their path (the bottom layer).
//! - [`engine`]: the engine boundary and the engines ([`engine::edmd`], [`engine::lga`],
//!   [`engine::dsmc`], [`engine::dem`]); imports nothing above itself.
//! - [`analysis`]: fields, spectra, profiles, steady-state detection, classification, and the
//!   thesis' chapter 3-4 statistics ([`analysis::statistics`], opt-in per sweep).
//! - [`registry`]: the one list of engines, each paired with the analysis its snapshots feed.
//! - [`sweep`]: sweep files, grids, job ids, the resumable queue, tables, phase diagrams.
//! - [`slurm`]: job arrays on a Slurm cluster running the same job code; status via squeue.
//! - [`provenance`]: which code made a result (version, commit, engine and analysis versions).
//! - [`job_figures`]: a job's figures, one file per analysis.
//! - [`report`]: the one-file HTML report of a sweep.
//! - [`cli`]: the command-line front end.

// Loops over the three components (`for d in 0..3 { f[d] += m g[d] }`) and over axes are
// written with their index, as the equations are; clippy's iterator form would hide that.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod cli;
pub mod engine;
pub mod figure;
pub mod fs;
pub mod job_figures;
pub mod provenance;
pub mod registry;
pub mod report;
pub mod slurm;
pub mod sweep;
