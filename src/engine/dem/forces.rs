//! The parallel kernels of a step: pair forces (each listed pair once, in parallel over fixed
//! blocks of pairs, into its slot) and the particle pass (each particle gathers its pairs'
//! forces in the tag order of its row, adds its wall and floor contacts and gravity, and
//! kicks and drifts), in parallel over fixed blocks of particles.
//!
//! Integration is LAMMPS' velocity Verlet (`fix nve/sphere`), per particle:
//!
//! ```text
//! v += (dt/2) F / m;   x += dt v;   w += (dt/2) tau / I      (initial half step)
//! F, tau = forces(x(t + dt), v(t + dt/2), w(t + dt/2))        (damping and history see the
//!                                                              half-step velocities)
//! v += (dt/2) F / m;   w += (dt/2) tau / I                    (final half step)
//! ```
//!
//! Between two steps that need no full-step state (no sample, no stop) the final half step of
//! one and the initial half step of the next are done in the same pass, as the same
//! operations in the same order. Every sum (a particle's forces, a block's tallies) runs in
//! an order fixed by tags and blocks, never by threads: the same bits on any number of
//! threads.

use super::bodies::Bodies;
use super::contact::{self, ContactLaw};
use super::domain::Domain;
use super::neighbours::{NEGATIVE, NeighbourList};
use rayon::prelude::*;

/// Particles per parallel task.
pub const PARTICLE_CHUNK: usize = 512;
/// Pairs per parallel task.
pub const PAIR_CHUNK: usize = 2048;

/// The flat boundaries: walls at y = 0 and y = W, and the preparation's floor normal to x.
#[derive(Clone, Copy, Debug)]
pub struct Boundaries {
    /// W
    pub width: f64,
    /// the law of both walls
    pub wall_law: ContactLaw,
    /// the floor's position along x (gravity pushes particles onto it), during preparation
    pub floor: Option<f64>,
    /// the floor's law
    pub floor_law: ContactLaw,
    /// g, the gravitational acceleration
    pub gravity: [f64; 3],
}

/// What the particle pass does after the forces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// forces only (LAMMPS' setup: histories are not advanced, velocities unchanged)
    Setup,
    /// the final half kick
    Final,
    /// the final half kick, then the next step's initial half kick and drift
    FinalAndNext,
}

/// A block's sums of one pass, added in block order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// force of the particles on each wall (minus the walls' force on the particles)
    pub on_walls: [[f64; 3]; 2],
    /// force of the particles on the floor
    pub on_floor: [f64; 3],
    /// particles touching a wall (and the floor)
    pub wall_contacts: u64,
    /// largest |x - x_build|^2 after a drift
    pub max_displacement2: f64,
    /// sum m g . v over the drifted particles (times dt: the work of gravity in the drift)
    pub gravity_power: f64,
}

impl Tally {
    /// Add a later block's tally.
    pub fn add(&mut self, o: &Tally) {
        for w in 0..2 {
            for k in 0..3 {
                self.on_walls[w][k] += o.on_walls[w][k];
            }
        }
        for k in 0..3 {
            self.on_floor[k] += o.on_floor[k];
        }
        self.wall_contacts += o.wall_contacts;
        self.max_displacement2 = self.max_displacement2.max(o.max_displacement2);
        self.gravity_power += o.gravity_power;
    }
}

/// Forces of all listed pairs at the current positions and velocities into their slots;
/// returns the number of touching pairs. `update`: advance the histories.
pub fn pair_forces(
    law: &ContactLaw,
    domain: &Domain,
    bodies: &Bodies,
    list: &mut NeighbourList,
    update: bool,
) -> u64 {
    let (x, v, w) = (&bodies.x, &bodies.v, &bodies.w);
    let (radius, mass) = (&bodies.radius, &bodies.mass);
    list.out
        .par_chunks_mut(PAIR_CHUNK)
        .zip(list.shear.par_chunks_mut(PAIR_CHUNK))
        .zip(list.touch.par_chunks_mut(PAIR_CHUNK))
        .zip(list.pairs.par_chunks(PAIR_CHUNK))
        .map(|(((outs, shears), touches), pairs)| {
            let mut touching = 0u64;
            for (((out, shear), touch), &[a, b]) in
                outs.iter_mut().zip(shears).zip(touches).zip(pairs)
            {
                let (a, b) = (a as usize, b as usize);
                // del = x_a - x_b, minimum image
                let del = domain.min_image([
                    x[a][0] - x[b][0],
                    x[a][1] - x[b][1],
                    x[a][2] - x[b][2],
                ]);
                let rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
                let radsum = radius[a] + radius[b];
                if rsq < radsum * radsum {
                    let c = contact::pair(
                        law,
                        del,
                        rsq,
                        (radius[a], radius[b]),
                        (v[a], v[b]),
                        (w[a], w[b]),
                        (mass[a], mass[b]),
                        shear,
                        update,
                    );
                    out.force = c.force;
                    out.tor = c.tor;
                    *touch = true;
                    touching += 1;
                } else if *touch {
                    // the contact ended: its history is dropped
                    *out = Default::default();
                    *shear = [0.0; 3];
                    *touch = false;
                }
            }
            touching
        })
        .sum()
}

/// The force of the nearer wall (LAMMPS fix wall/gran with yplane 0 W) on a particle at y,
/// if it touches: (wall index, del from the wall point, rsq).
#[inline(always)]
pub fn nearer_wall(y: f64, radius: f64, width: f64) -> (usize, [f64; 3], bool) {
    let del1 = y - 0.0;
    let del2 = width - y;
    let (wall, dy) = if del1 < del2 { (0, del1) } else { (1, -del2) };
    let rsq = dy * dy;
    (wall, [0.0, dy, 0.0], rsq <= radius * radius)
}

/// The particle pass: gather each particle's forces (pairs in its row's tag order, then the
/// nearer wall, the floor, gravity), store F and tau, then kick (and drift) as `pass` says.
/// `record_wall`: keep each particle's wall force (for sampling). Returns the blocks' tallies
/// in `tallies` and their sum.
#[allow(clippy::too_many_arguments)]
pub fn particle_pass(
    pair_law: &ContactLaw,
    bounds: &Boundaries,
    domain: &Domain,
    bodies: &mut Bodies,
    list: &NeighbourList,
    pass: Pass,
    record_wall: bool,
    tallies: &mut Vec<Tally>,
) -> Tally {
    let update = pass != Pass::Setup;
    let dt = pair_law.dt;
    let Bodies {
        radius,
        mass,
        kick_v,
        kick_w,
        x,
        v,
        w,
        force,
        torque,
        x_build,
        wall_shear,
        floor_shear,
        wall_force,
        ..
    } = bodies;
    let (radius, mass, kick_v, kick_w, x_build) = (&*radius, &*mass, &*kick_v, &*kick_w, &*x_build);
    let outs = &list.out;
    x.par_chunks_mut(PARTICLE_CHUNK)
        .zip(v.par_chunks_mut(PARTICLE_CHUNK))
        .zip(w.par_chunks_mut(PARTICLE_CHUNK))
        .zip(force.par_chunks_mut(PARTICLE_CHUNK))
        .zip(torque.par_chunks_mut(PARTICLE_CHUNK))
        .zip(wall_shear.par_chunks_mut(PARTICLE_CHUNK))
        .zip(floor_shear.par_chunks_mut(PARTICLE_CHUNK))
        .zip(wall_force.par_chunks_mut(PARTICLE_CHUNK))
        .enumerate()
        .map(|(c, (((((((xs, vs), ws), fs), ts), wss), fss), wfs))| {
            let mut tally = Tally::default();
            for k in 0..xs.len() {
                let i = c * PARTICLE_CHUNK + k;
                let (r, m) = (radius[i], mass[i]);
                // F = sum over the row (tag order) of +-F_pair; tau -= R_i tor
                let mut f = [0.0f64; 3];
                let mut t = [0.0f64; 3];
                for &e in list.row(i) {
                    let o = &outs[(e & !NEGATIVE) as usize];
                    // +1 or -1 (exact: the product is the force or its negation)
                    let sign = 1.0 - 2.0 * (e >> 31) as f64;
                    for d in 0..3 {
                        f[d] += sign * o.force[d];
                        t[d] -= r * o.tor[d];
                    }
                }
                // the nearer wall
                let (wall, del, touching) = nearer_wall(xs[k][1], r, bounds.width);
                if touching {
                    let cw = contact::wall(
                        &bounds.wall_law,
                        del,
                        del[1] * del[1],
                        r,
                        vs[k],
                        ws[k],
                        m,
                        &mut wss[k],
                        update,
                    );
                    for d in 0..3 {
                        f[d] += cw.force[d];
                        t[d] -= r * cw.tor[d];
                        tally.on_walls[wall][d] -= cw.force[d];
                    }
                    tally.wall_contacts += 1;
                    if record_wall {
                        wfs[k] = cw.force;
                    }
                } else {
                    if wss[k] != [0.0; 3] {
                        wss[k] = [0.0; 3];
                    }
                    if record_wall {
                        wfs[k] = [0.0; 3];
                    }
                }
                // the floor (preparation): a wall normal to x at x = floor
                if let Some(floor) = bounds.floor {
                    let dx = -(floor - xs[k][0]);
                    let rsq = dx * dx;
                    if rsq <= r * r {
                        let cf = contact::wall(
                            &bounds.floor_law,
                            [dx, 0.0, 0.0],
                            rsq,
                            r,
                            vs[k],
                            ws[k],
                            m,
                            &mut fss[k],
                            update,
                        );
                        for d in 0..3 {
                            f[d] += cf.force[d];
                            t[d] -= r * cf.tor[d];
                            tally.on_floor[d] -= cf.force[d];
                        }
                        tally.wall_contacts += 1;
                    } else if fss[k] != [0.0; 3] {
                        fss[k] = [0.0; 3];
                    }
                }
                // gravity, m g
                for d in 0..3 {
                    f[d] += m * bounds.gravity[d];
                }
                fs[k] = f;
                ts[k] = t;
                if pass == Pass::Setup {
                    continue;
                }
                // final half step: v += (dt/2) F/m, w += (dt/2) tau/I
                for d in 0..3 {
                    vs[k][d] += kick_v[i] * f[d];
                    ws[k][d] += kick_w[i] * t[d];
                }
                if pass == Pass::FinalAndNext {
                    drift(
                        domain,
                        bounds,
                        dt,
                        (kick_v[i], kick_w[i], m),
                        (&mut xs[k], &mut vs[k], &mut ws[k]),
                        (&f, &t),
                        &x_build[i],
                        &mut tally,
                    );
                }
            }
            tally
        })
        .collect_into_vec(tallies);
    let mut sum = Tally::default();
    for t in tallies.iter() {
        sum.add(t);
    }
    sum
}

/// The initial half step of one particle: v += (dt/2) F/m, x += dt v (wrapped), w += (dt/2)
/// tau/I; tallies the displacement since the list build and the work rate of gravity.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn drift(
    domain: &Domain,
    bounds: &Boundaries,
    dt: f64,
    (kv, kw, m): (f64, f64, f64),
    (x, v, w): (&mut [f64; 3], &mut [f64; 3], &mut [f64; 3]),
    (f, t): (&[f64; 3], &[f64; 3]),
    x_build: &[f64; 3],
    tally: &mut Tally,
) {
    for d in 0..3 {
        v[d] += kv * f[d];
    }
    for d in 0..3 {
        x[d] += dt * v[d];
    }
    domain.wrap(x);
    for d in 0..3 {
        w[d] += kw * t[d];
    }
    let g = &bounds.gravity;
    tally.gravity_power += m * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2]);
    let s = domain.min_image([x[0] - x_build[0], x[1] - x_build[1], x[2] - x_build[2]]);
    tally.max_displacement2 = tally
        .max_displacement2
        .max(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
}

/// The initial half step of every particle (when it could not be fused with the previous
/// step's final one).
pub fn kick_drift(
    domain: &Domain,
    bounds: &Boundaries,
    dt: f64,
    bodies: &mut Bodies,
    tallies: &mut Vec<Tally>,
) -> Tally {
    let Bodies {
        mass,
        kick_v,
        kick_w,
        x,
        v,
        w,
        force,
        torque,
        x_build,
        ..
    } = bodies;
    let (mass, kick_v, kick_w, force, torque, x_build) =
        (&*mass, &*kick_v, &*kick_w, &*force, &*torque, &*x_build);
    x.par_chunks_mut(PARTICLE_CHUNK)
        .zip(v.par_chunks_mut(PARTICLE_CHUNK))
        .zip(w.par_chunks_mut(PARTICLE_CHUNK))
        .enumerate()
        .map(|(c, ((xs, vs), ws))| {
            let mut tally = Tally::default();
            for k in 0..xs.len() {
                let i = c * PARTICLE_CHUNK + k;
                drift(
                    domain,
                    bounds,
                    dt,
                    (kick_v[i], kick_w[i], mass[i]),
                    (&mut xs[k], &mut vs[k], &mut ws[k]),
                    (&force[i], &torque[i]),
                    &x_build[i],
                    &mut tally,
                );
            }
            tally
        })
        .collect_into_vec(tallies);
    let mut sum = Tally::default();
    for t in tallies.iter() {
        sum.add(t);
    }
    sum
}
