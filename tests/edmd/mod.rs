//! The EDMD engine of rough inelastic hard spheres (Malik 2008).

mod channel;
mod checkpoint;
mod collisions;
mod cooling;
mod dense_flow;
mod equilibrium;
mod reference;
