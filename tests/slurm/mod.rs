//! Slurm job arrays.

mod integration;
mod tasks;
