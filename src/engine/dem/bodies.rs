//! Particle storage: a struct of arrays in the engine's working order (sorted by cell at every
//! neighbour-list rebuild), each particle carrying its tag, its index in the canonical order
//! (the order of checkpoints, snapshots and the reference). Nothing computed depends on the
//! working order: every sum runs in an order fixed by tags.

use serde::{Deserialize, Serialize};

/// One particle's state in canonical form (what checkpoints and the reference hold).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyState {
    /// d, diameter
    pub diameter: f64,
    /// x, centre
    pub position: [f64; 3],
    /// v, velocity
    pub velocity: [f64; 3],
    /// w, angular velocity
    pub spin: [f64; 3],
    /// F, force of the last force evaluation
    pub force: [f64; 3],
    /// tau, torque of the last force evaluation
    pub torque: [f64; 3],
    /// the wall-contact history s (zero when not touching a wall)
    pub wall_shear: [f64; 3],
    /// the temporary floor's contact history (preparation only)
    pub floor_shear: [f64; 3],
    /// the position at the last neighbour-list build
    pub position_at_build: [f64; 3],
}

impl BodyState {
    /// A particle of diameter d at x with velocity v and spin w, before any force evaluation:
    /// no force, torque or contact history, its list-build position x.
    pub fn fresh(
        diameter: f64,
        position: [f64; 3],
        velocity: [f64; 3],
        spin: [f64; 3],
    ) -> BodyState {
        BodyState {
            diameter,
            position,
            velocity,
            spin,
            force: [0.0; 3],
            torque: [0.0; 3],
            wall_shear: [0.0; 3],
            floor_shear: [0.0; 3],
            position_at_build: position,
        }
    }
}

/// The particles as arrays in working order.
#[derive(Clone, Debug, Default)]
pub struct Bodies {
    /// canonical index of each particle
    pub tag: Vec<u32>,
    /// R = d / 2
    pub radius: Vec<f64>,
    /// m = (4 pi / 3) R^3 (rho = 1)
    pub mass: Vec<f64>,
    /// dt / (2 m): the half kick of v per unit force (LAMMPS' dtfm)
    pub kick_v: Vec<f64>,
    /// dt / (2 I) = (dt / 2 / 0.4) / (R^2 m): the half kick of w per unit torque (LAMMPS'
    /// dtirotate)
    pub kick_w: Vec<f64>,
    /// x
    pub x: Vec<[f64; 3]>,
    /// v
    pub v: Vec<[f64; 3]>,
    /// w
    pub w: Vec<[f64; 3]>,
    /// F
    pub force: Vec<[f64; 3]>,
    /// tau
    pub torque: Vec<[f64; 3]>,
    /// x at the last list build
    pub x_build: Vec<[f64; 3]>,
    /// wall history s_w
    pub wall_shear: Vec<[f64; 3]>,
    /// floor history (preparation)
    pub floor_shear: Vec<[f64; 3]>,
    /// force of the wall on the particle at the last evaluation that recorded it (sampling
    /// steps; zero when not touching)
    pub wall_force: Vec<[f64; 3]>,
}

/// Reused buffers of a permutation.
#[derive(Clone, Debug, Default)]
pub struct PermuteBuffers {
    v3: Vec<[f64; 3]>,
    v1: Vec<f64>,
    u: Vec<u32>,
}

fn apply<T: Copy>(data: &mut Vec<T>, order: &[u32], buf: &mut Vec<T>) {
    buf.clear();
    buf.extend(order.iter().map(|&o| data[o as usize]));
    std::mem::swap(data, buf);
}

impl Bodies {
    /// Particles from canonical states (tag = index), with the kick factors of step `dt`.
    pub fn from_states(states: &[BodyState], dt: f64) -> Bodies {
        let mut b = Bodies::default();
        for (tag, s) in states.iter().enumerate() {
            let radius = 0.5 * s.diameter;
            let mass = super::params::sphere_mass(s.diameter);
            b.tag.push(tag as u32);
            b.radius.push(radius);
            b.mass.push(mass);
            b.x.push(s.position);
            b.v.push(s.velocity);
            b.w.push(s.spin);
            b.force.push(s.force);
            b.torque.push(s.torque);
            b.x_build.push(s.position_at_build);
            b.wall_shear.push(s.wall_shear);
            b.floor_shear.push(s.floor_shear);
            b.wall_force.push([0.0; 3]);
        }
        b.kick_v = vec![0.0; b.len()];
        b.kick_w = vec![0.0; b.len()];
        b.set_time_step(dt);
        b
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.tag.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tag.is_empty()
    }

    /// The kick factors of step dt, as LAMMPS' fix nve/sphere forms them: dtf = dt / 2,
    /// dtfm = dtf / m, dtirotate = (dtf / 0.4) / (R^2 m).
    pub fn set_time_step(&mut self, dt: f64) {
        let dtf = 0.5 * dt;
        let dtfrotate = dtf / 0.4;
        for i in 0..self.len() {
            self.kick_v[i] = dtf / self.mass[i];
            self.kick_w[i] = dtfrotate / (self.radius[i] * self.radius[i] * self.mass[i]);
        }
    }

    /// The states in canonical (tag) order.
    pub fn states(&self) -> Vec<BodyState> {
        let mut out = vec![None; self.len()];
        for i in 0..self.len() {
            out[self.tag[i] as usize] = Some(BodyState {
                diameter: 2.0 * self.radius[i],
                position: self.x[i],
                velocity: self.v[i],
                spin: self.w[i],
                force: self.force[i],
                torque: self.torque[i],
                wall_shear: self.wall_shear[i],
                floor_shear: self.floor_shear[i],
                position_at_build: self.x_build[i],
            });
        }
        out.into_iter()
            .map(|s| s.expect("tags are a permutation"))
            .collect()
    }

    /// One per-particle array in tag order.
    pub fn by_tag<T: Copy + Default>(&self, data: &[T]) -> Vec<T> {
        let mut out = vec![T::default(); self.len()];
        for (i, &t) in self.tag.iter().enumerate() {
            out[t as usize] = data[i];
        }
        out
    }

    /// Reorder: the particle now at position k is the one at `order[k]`.
    pub fn permute(&mut self, order: &[u32], buf: &mut PermuteBuffers) {
        apply(&mut self.tag, order, &mut buf.u);
        for a in [
            &mut self.radius,
            &mut self.mass,
            &mut self.kick_v,
            &mut self.kick_w,
        ] {
            apply(a, order, &mut buf.v1);
        }
        for a in [
            &mut self.x,
            &mut self.v,
            &mut self.w,
            &mut self.force,
            &mut self.torque,
            &mut self.x_build,
            &mut self.wall_shear,
            &mut self.floor_shear,
            &mut self.wall_force,
        ] {
            apply(a, order, &mut buf.v3);
        }
    }
}
