//! Event-driven molecular dynamics (EDMD) of rough inelastic hard spheres in a
//! gravity-driven channel (Malik 2008 thesis, ch. 2).

mod params;

pub use params::{EdmdParams, Placement};
mod engine;

pub use engine::EdmdEngine;
