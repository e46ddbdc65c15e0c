//! The reference integrator: the same physics as the engine with none of its machinery: all
//! pairs tried every step (O(N^2)), particles in tag order, histories in a map keyed by tags,
//! one thread. Tests run it beside the engine and require the same bits step after step
//! (positions, velocities, spins, forces, torques, wall and pair histories): the engine's
//! cell list, neighbour list, skin, rebuilds, reordering, history carry-over, row gather and
//! parallel blocks must then be exact stand-ins for "every pair, summed in tag order".
//!
//! Both use the contact rule of [`super::contact`] and sum a particle's forces in the same
//! order (each pair evaluated once, oriented from the lower tag): minus the forces of its
//! pairs with lower-tag partners by ascending tag, plus the sum of the forces of its pairs
//! with higher-tag partners by ascending tag, then the nearer wall, the floor, gravity; and
//! both kick and drift with the same operations. That fixed order is what makes bitwise
//! agreement a fair requirement.

use super::bodies::BodyState;
use super::contact::{self, ContactForce, ContactLaw};
use super::domain::Domain;
use super::forces::{Boundaries, nearer_wall};
use super::neighbours::KeptContact;
use super::params::sphere_mass;
use std::collections::BTreeMap;

/// A system integrated the simple way.
#[derive(Clone, Debug)]
pub struct Reference {
    pub law: ContactLaw,
    pub bounds: Boundaries,
    pub domain: Domain,
    /// particles in tag order
    pub bodies: Vec<BodyState>,
    /// histories of the touching pairs, (lower tag, higher tag) -> s
    pub contacts: BTreeMap<(u32, u32), [f64; 3]>,
}

impl Reference {
    /// From the engine's canonical state and laws.
    pub fn new(
        law: ContactLaw,
        bounds: Boundaries,
        domain: Domain,
        bodies: Vec<BodyState>,
        contacts: &[KeptContact],
    ) -> Self {
        Reference {
            law,
            bounds,
            domain,
            bodies,
            contacts: contacts.iter().map(|c| ((c.0, c.1), c.2)).collect(),
        }
    }

    /// The touching pairs as (owner tag, other tag, s), sorted.
    pub fn contact_list(&self) -> Vec<KeptContact> {
        self.contacts.iter().map(|(k, s)| (k.0, k.1, *s)).collect()
    }

    /// One velocity-Verlet step.
    pub fn step(&mut self) {
        let dt = self.law.dt;
        let dtf = 0.5 * dt;
        // initial half step: v += (dt/2) F/m, x += dt v, w += (dt/2) tau/I
        for b in &mut self.bodies {
            let (kv, kw) = kicks(b.diameter, dtf);
            for k in 0..3 {
                b.velocity[k] += kv * b.force[k];
            }
            for k in 0..3 {
                b.position[k] += dt * b.velocity[k];
            }
            self.domain.wrap(&mut b.position);
            for k in 0..3 {
                b.spin[k] += kw * b.torque[k];
            }
        }
        self.forces();
        // final half step
        for b in &mut self.bodies {
            let (kv, kw) = kicks(b.diameter, dtf);
            for k in 0..3 {
                b.velocity[k] += kv * b.force[k];
                b.spin[k] += kw * b.torque[k];
            }
        }
    }

    /// Forces and torques at the current positions and (half-step) velocities.
    fn forces(&mut self) {
        let n = self.bodies.len();
        // every pair once, from the lower tag
        let mut pair: BTreeMap<(usize, usize), ContactForce> = BTreeMap::new();
        for i in 0..n {
            for j in i + 1..n {
                let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
                let del = self.domain.min_image([
                    bi.position[0] - bj.position[0],
                    bi.position[1] - bj.position[1],
                    bi.position[2] - bj.position[2],
                ]);
                let rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
                let (ri, rj) = (0.5 * bi.diameter, 0.5 * bj.diameter);
                let radsum = ri + rj;
                let key = (i as u32, j as u32);
                if rsq < radsum * radsum {
                    let shear = self.contacts.entry(key).or_insert([0.0; 3]);
                    let c = contact::pair(
                        &self.law,
                        del,
                        rsq,
                        (ri, rj),
                        (bi.velocity, bj.velocity),
                        (bi.spin, bj.spin),
                        (sphere_mass(bi.diameter), sphere_mass(bj.diameter)),
                        shear,
                        true,
                    );
                    pair.insert((i, j), c);
                } else {
                    self.contacts.remove(&key);
                }
            }
        }
        // each particle: (its pairs with lower tags, in tag order) + (its pairs with higher
        // tags, in tag order), then the nearer wall, the floor, gravity
        for i in 0..n {
            let r = 0.5 * self.bodies[i].diameter;
            let m = sphere_mass(self.bodies[i].diameter);
            let mut f = [0.0f64; 3];
            let mut t = [0.0f64; 3];
            for j in 0..i {
                if let Some(c) = pair.get(&(j, i)) {
                    for d in 0..3 {
                        f[d] -= c.force[d];
                        t[d] -= r * c.tor[d];
                    }
                }
            }
            let mut fo = [0.0f64; 3];
            let mut to = [0.0f64; 3];
            for j in i + 1..n {
                if let Some(c) = pair.get(&(i, j)) {
                    for d in 0..3 {
                        fo[d] += c.force[d];
                        to[d] -= r * c.tor[d];
                    }
                }
            }
            for d in 0..3 {
                f[d] += fo[d];
                t[d] += to[d];
            }
            let b = &mut self.bodies[i];
            let (_, del, touching) = nearer_wall(b.position[1], r, self.bounds.width);
            if touching {
                let c = contact::wall(
                    self.bounds.wall_laws.of(r),
                    del,
                    del[1] * del[1],
                    r,
                    b.velocity,
                    b.spin,
                    m,
                    &mut b.wall_shear,
                    true,
                );
                for d in 0..3 {
                    f[d] += c.force[d];
                    t[d] -= r * c.tor[d];
                }
            } else {
                b.wall_shear = [0.0; 3];
            }
            if let Some(floor) = self.bounds.floor {
                let dx = -(floor - b.position[0]);
                if dx * dx <= r * r {
                    let c = contact::wall(
                        self.bounds.floor_laws.of(r),
                        [dx, 0.0, 0.0],
                        dx * dx,
                        r,
                        b.velocity,
                        b.spin,
                        m,
                        &mut b.floor_shear,
                        true,
                    );
                    for d in 0..3 {
                        f[d] += c.force[d];
                        t[d] -= r * c.tor[d];
                    }
                } else {
                    b.floor_shear = [0.0; 3];
                }
            }
            for d in 0..3 {
                f[d] += m * self.bounds.gravity[d];
            }
            b.force = f;
            b.torque = t;
        }
    }
}

/// (dt/2)/m and (dt/2)/I as LAMMPS forms them.
fn kicks(diameter: f64, dtf: f64) -> (f64, f64) {
    let r = 0.5 * diameter;
    let m = sphere_mass(diameter);
    (dtf / m, (dtf / 0.4) / (r * r * m))
}
