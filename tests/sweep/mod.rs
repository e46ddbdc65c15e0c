//! The sweep orchestrator and its files.

mod cli;
mod exit_codes;
mod orchestrator;
pub(crate) mod refine;
mod registry;
mod store;
mod tables;
mod tamper;
