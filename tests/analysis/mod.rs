//! Analysis of EDMD snapshots: structure classification, milestones, the thesis' statistics.

mod classifier;
mod milestones;
mod statistics;
mod statistics_sweep;
mod structure;
/// Synthetic coarse-grained density fields of known structure (support for `classifier`).
mod synthetic;
