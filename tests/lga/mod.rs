//! The lattice gas (Peng & Herrmann 1994).

mod engine;
mod sweep;
