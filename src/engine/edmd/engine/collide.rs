//! Processing events: cell crossings, pair collisions (with the TC model) and wall collisions.

use super::*;

impl EdmdEngine {
    /// Move particle `i` into the next cell along `axis`, wrapping across the periodic seam;
    /// returns the new cell's coordinates.
    pub(super) fn cross_cell(&mut self, i: usize, axis: usize, upper: bool) -> [usize; 3] {
        self.counters.cell_crossings += 1;
        let from = self.kin[i].cell as usize;
        let mut coords = self.cells.coords(from);
        let ax = self.cells.axes[axis];
        let (next, shift) = ax
            .neighbour(coords[axis], if upper { 1 } else { -1 })
            .expect("crossing stays in the box");
        // a wrapped neighbour carries the shift that brings it next to the old cell; the
        // particle itself moves the opposite way
        self.kin[i].position[axis] -= shift;
        coords[axis] = next;
        let to = self.cells.index(coords);
        self.cells.relocate(i as u32, from, to);
        self.kin[i].cell = to as u32;
        coords
    }

    /// Minimum-image separation r_i - r_j of two particles at the same time.
    pub(super) fn separation(&self, i: usize, j: usize) -> Vector3<f64> {
        let g = &self.params.geometry;
        let ext = g.extents();
        let mut r = [0.0; 3];
        for a in 0..3 {
            let mut d = self.kin[i].position[a] - self.kin[j].position[a];
            if a != 1 || !g.walls {
                if d > 0.5 * ext[a] {
                    d -= ext[a];
                } else if d < -0.5 * ext[a] {
                    d += ext[a];
                }
            }
            r[a] = d;
        }
        Vector3::from(r)
    }

    /// Pair collision of i and j (both at `now`), with the TC model.
    pub(super) fn collide_pair(&mut self, i: usize, j: usize) {
        let t = self.now;
        if let Some(paths) = self.free_paths.as_deref_mut() {
            let g = self.params.gravity;
            for p in [i, j] {
                let tau = t - self.own[p].last_collision;
                if tau.is_finite() {
                    let k = &self.kin[p];
                    paths.add_flight(k.position[1], k.velocity, tau, g, false);
                }
            }
        }
        let r = self.separation(i, j);
        let k = -r / r.norm(); // unit vector from i to j
        let tc = self.params.tc;
        let tc_elastic = tc > 0.0
            && (t - self.own[i].last_collision < tc || t - self.own[j].last_collision < tc);
        let first = SphereVelocity {
            linear: self.kin[i].velocity.into(),
            angular: self.own[i].angular.into(),
        };
        let second = SphereVelocity {
            linear: self.kin[j].velocity.into(),
            angular: self.own[j].angular.into(),
        };
        let law = if tc_elastic {
            self.counters.tc_elastic_collisions += 1;
            // what constant e would have dissipated in addition: (m/4)(1 - e^2) g_n^2
            let e = self.pair_law.restitution;
            let g_n = k.dot(&collision::contact_velocity(&first, &second, &k));
            self.suppressed_dissipation += 0.25 * (1.0 - e * e) * g_n * g_n;
            ContactLaw {
                restitution: 1.0,
                ..self.pair_law
            }
        } else {
            self.pair_law
        };
        let out = collision::pair_collision(&first, &second, &k, &law);
        self.kin[i].velocity = out.first.linear.into();
        self.kin[j].velocity = out.second.linear.into();
        self.own[i].angular = out.first.angular.into();
        self.own[j].angular = out.second.angular.into();
        self.kin[i].collisions += 1;
        self.kin[j].collisions += 1;
        self.own[i].last_collision = t;
        self.own[j].last_collision = t;
        self.dissipated += out.dissipated;
        self.counters.pair_collisions += 1;
        if let Some(log) = &mut self.log {
            let (a, b) = (self.ids[i], self.ids[j]);
            log.push(PhysicalEvent::Pair {
                time: t,
                first: a.min(b),
                second: a.max(b),
            });
        }
    }

    /// Collision of particle i with the wall at y = W (upper) or y = 0.
    pub(super) fn collide_wall(&mut self, i: usize, upper: bool) {
        let w = self.params.geometry.width;
        // at contact the centre is a from the wall; round-off never lets it sink in
        let y = &mut self.kin[i].position[1];
        *y = if upper {
            y.min(w - collision::RADIUS)
        } else {
            y.max(collision::RADIUS)
        };
        if let Some(paths) = self.free_paths.as_deref_mut() {
            let tau = self.now - self.own[i].last_collision;
            if tau.is_finite() {
                let k = &self.kin[i];
                paths.add_flight(k.position[1], k.velocity, tau, self.params.gravity, true);
            }
        }
        let k = Vector3::new(0.0, if upper { 1.0 } else { -1.0 }, 0.0);
        let sphere = SphereVelocity {
            linear: self.kin[i].velocity.into(),
            angular: self.own[i].angular.into(),
        };
        let out = collision::wall_collision(&sphere, &k, &self.wall_law);
        self.kin[i].velocity = out.sphere.linear.into();
        self.own[i].angular = out.sphere.angular.into();
        self.kin[i].collisions += 1;
        self.own[i].last_collision = self.now;
        let side = &mut self.wall_momentum[upper as usize];
        for a in 0..3 {
            side[a] += out.impulse[a];
        }
        self.dissipated += out.dissipated;
        self.counters.wall_collisions += 1;
        if let Some(log) = &mut self.log {
            log.push(PhysicalEvent::Wall {
                time: self.now,
                particle: self.ids[i],
                upper,
            });
        }
    }
}
