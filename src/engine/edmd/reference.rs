//! A slow, simple reference engine for tests: all particles are kept at one time, every step
//! checks all pairs (and all their periodic images) and both walls for the earliest event,
//! then moves everyone to it (Allen & Tildesley's naive algorithm). It shares only the pure
//! collision rules and contact-time formula with the fast engine.

use super::collision::{self, ContactLaw, SphereVelocity};
use super::motion::{fly, pair_contact_time};
use super::{EdmdParams, PhysicalEvent};
use crate::engine::EngineError;
use nalgebra::Vector3;

/// The all-pairs engine.
pub struct ReferenceEngine {
    params: EdmdParams,
    now: f64,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    angular: Vec<[f64; 3]>,
    last_collision: Vec<f64>,
    /// physical events processed, in order
    pub events: Vec<PhysicalEvent>,
}

enum Next {
    Pair(usize, usize),
    Wall(usize, bool),
}

impl ReferenceEngine {
    /// Same initial state as the fast engine with the same parameters.
    pub fn new(params: EdmdParams) -> Result<Self, EngineError> {
        params.validate()?;
        let start = super::setup::initial_state(&params)?;
        let n = params.particles;
        Ok(ReferenceEngine {
            params,
            now: 0.0,
            positions: start.positions,
            velocities: start.velocities,
            angular: start.angular_velocities,
            last_collision: vec![f64::NEG_INFINITY; n],
            events: Vec::new(),
        })
    }

    /// Continue from a snapshot of any engine (the TC model's memory of past collisions is
    /// not in a snapshot: use with tc = 0).
    pub fn from_snapshot(params: EdmdParams, snapshot: &crate::engine::Snapshot) -> Self {
        let p = snapshot
            .particles()
            .expect("an EDMD snapshot carries particles");
        let n = p.len();
        ReferenceEngine {
            params,
            now: snapshot.time(),
            positions: p.positions.clone(),
            velocities: p.velocities.clone(),
            angular: p.angular_velocities.clone(),
            last_collision: vec![f64::NEG_INFINITY; n],
            events: Vec::new(),
        }
    }

    /// Process `count` physical events.
    pub fn run_events(&mut self, count: usize) {
        for _ in 0..count {
            self.step();
        }
    }

    fn step(&mut self) {
        let n = self.positions.len();
        let g = &self.params.geometry;
        let ext = g.extents();
        let periodic = [true, !g.walls, true];
        let mut best = f64::INFINITY;
        let mut next = None;
        if g.walls {
            for i in 0..n {
                let (y, vy) = (self.positions[i][1], self.velocities[i][1]);
                let hit = if vy > 0.0 {
                    Some(((g.width - 0.5 - y) / vy, true))
                } else if vy < 0.0 {
                    Some(((0.5 - y) / vy, false))
                } else {
                    None
                };
                if let Some((t, upper)) = hit {
                    let t = t.max(0.0);
                    if t < best {
                        best = t;
                        next = Some(Next::Wall(i, upper));
                    }
                }
            }
        }
        for i in 0..n {
            for j in i + 1..n {
                for sx in -1i32..=1 {
                    for sy in -1i32..=1 {
                        for sz in -1i32..=1 {
                            let s = [sx, sy, sz];
                            if (0..3).any(|a| !periodic[a] && s[a] != 0) {
                                continue;
                            }
                            let shift: [f64; 3] = std::array::from_fn(|a| s[a] as f64 * ext[a]);
                            let r: [f64; 3] = std::array::from_fn(|a| {
                                self.positions[i][a] - (self.positions[j][a] + shift[a])
                            });
                            let v: [f64; 3] = std::array::from_fn(|a| {
                                self.velocities[i][a] - self.velocities[j][a]
                            });
                            if let Some(t) = pair_contact_time(r, v)
                                && t < best
                            {
                                best = t;
                                next = Some(Next::Pair(i, j));
                            }
                        }
                    }
                }
            }
        }
        let Some(next) = next else { return };
        // everyone flies to the event
        let gravity = self.params.gravity;
        for i in 0..n {
            let (r, c) = fly(self.positions[i], self.velocities[i], gravity, best);
            self.positions[i] = r;
            self.velocities[i] = c;
            for a in 0..3 {
                if periodic[a] {
                    self.positions[i][a] = self.positions[i][a].rem_euclid(ext[a]);
                }
            }
        }
        self.now += best;
        let law = ContactLaw {
            restitution: self.params.restitution,
            roughness: self.params.roughness,
            inertia_factor: self.params.inertia_factor,
        };
        match next {
            Next::Pair(i, j) => {
                // the image separation at contact (positions were wrapped, so recompute it)
                let mut r = Vector3::zeros();
                for a in 0..3 {
                    let mut d = self.positions[i][a] - self.positions[j][a];
                    if periodic[a] {
                        d -= ext[a] * (d / ext[a]).round();
                    }
                    r[a] = d;
                }
                let k = -r / r.norm();
                let tc = self.params.tc;
                let elastic = tc > 0.0
                    && (self.now - self.last_collision[i] < tc
                        || self.now - self.last_collision[j] < tc);
                let law = if elastic {
                    ContactLaw {
                        restitution: 1.0,
                        ..law
                    }
                } else {
                    law
                };
                let out = collision::pair_collision(&self.sphere(i), &self.sphere(j), &k, &law);
                self.set_sphere(i, out.first);
                self.set_sphere(j, out.second);
                self.last_collision[i] = self.now;
                self.last_collision[j] = self.now;
                self.events.push(PhysicalEvent::Pair {
                    time: self.now,
                    first: i as u32,
                    second: j as u32,
                });
            }
            Next::Wall(i, upper) => {
                let k = Vector3::new(0.0, if upper { 1.0 } else { -1.0 }, 0.0);
                let wall_law = ContactLaw {
                    restitution: self.params.wall_restitution,
                    roughness: self.params.wall_roughness,
                    inertia_factor: self.params.inertia_factor,
                };
                let out = collision::wall_collision(&self.sphere(i), &k, &wall_law);
                self.set_sphere(i, out.sphere);
                self.last_collision[i] = self.now;
                self.events.push(PhysicalEvent::Wall {
                    time: self.now,
                    particle: i as u32,
                    upper,
                });
            }
        }
    }

    fn sphere(&self, i: usize) -> SphereVelocity {
        SphereVelocity {
            linear: self.velocities[i].into(),
            angular: self.angular[i].into(),
        }
    }

    fn set_sphere(&mut self, i: usize, s: SphereVelocity) {
        self.velocities[i] = s.linear.into();
        self.angular[i] = s.angular.into();
    }
}
