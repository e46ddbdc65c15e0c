//! Analysis of EDMD snapshots: structure classification, milestones, the thesis' statistics.

mod milestones;
mod statistics;
mod statistics_sweep;
mod structure;
