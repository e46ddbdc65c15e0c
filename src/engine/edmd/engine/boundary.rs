//! The engine boundary: the state as plain data, and the [`Engine`] trait (advance, snapshot,
//! checkpoint).

use super::*;

impl EdmdEngine {
    /// Position and velocity of the particle in slot `s` brought from its local time to `now`
    /// (not stored: the state and the checkpoint read them so).
    fn flown_to_now(&self, s: usize) -> ([f64; 3], [f64; 3]) {
        let k = &self.kin[s];
        fly(
            k.position,
            k.velocity,
            self.params.gravity,
            self.now - k.time,
        )
    }

    /// Current state as plain data (particles at their local times brought to `now`): the
    /// reference for [`EdmdEngine::checkpoint_bytes`].
    #[cfg(test)]
    pub(super) fn state(&self) -> EngineState {
        let positions = self.by_id(|s| self.flown_to_now(s).0);
        let velocities = self.by_id(|s| self.flown_to_now(s).1);
        EngineState {
            params: self.params.clone(),
            now: self.now,
            positions,
            velocities,
            angular_velocities: self.by_id(|s| self.own[s].angular),
            last_collision: self.by_id(|s| self.own[s].last_collision),
            counters: self.counters,
            wall_momentum: self.wall_momentum,
            dissipated: self.dissipated,
            gravity_work: self.gravity_work,
            suppressed_dissipation: self.suppressed_dissipation,
            stall_window: self.stall_window,
            search: self.policy,
        }
    }

    /// The checkpoint bytes of the current state: `checkpoint::encode(&self.state())` (the
    /// reference, which the tests compare with), serialised straight from the engine's
    /// arrays in id order.
    pub(super) fn checkpoint_bytes(&self) -> Vec<u8> {
        let mut slots = vec![0u32; self.ids.len()];
        for (slot, &id) in self.ids.iter().enumerate() {
            slots[id as usize] = slot as u32;
        }
        let (position, velocity) = (
            |s: usize| self.flown_to_now(s).0,
            |s: usize| self.flown_to_now(s).1,
        );
        let (angular, last) = (
            |s: usize| self.own[s].angular,
            |s: usize| self.own[s].last_collision,
        );
        let by_id = |of| checkpoint::ById { slots: &slots, of };
        checkpoint::encode_view(&checkpoint::EngineStateView {
            params: &self.params,
            now: self.now,
            positions: by_id(&position),
            velocities: by_id(&velocity),
            angular_velocities: by_id(&angular),
            last_collision: checkpoint::ById {
                slots: &slots,
                of: &last,
            },
            counters: self.counters,
            wall_momentum: self.wall_momentum,
            dissipated: self.dissipated,
            gravity_work: self.gravity_work,
            suppressed_dissipation: self.suppressed_dissipation,
            stall_window: self.stall_window,
            search: &self.policy,
        })
    }
}

impl EdmdEngine {
    /// The particles of a snapshot taken now (tests and benchmarks of this engine, which know
    /// that its snapshots carry particles).
    pub fn particles_now(&mut self) -> Particles {
        match self.snapshot().content {
            Content::Particles(p) => p,
            _ => unreachable!("EDMD snapshots carry particles"),
        }
    }
}

impl Engine for EdmdEngine {
    fn def(&self) -> &'static EngineDef {
        &super::super::DECLARATION
    }

    fn particle_count(&self) -> usize {
        self.kin.len()
    }

    fn progress(&self) -> Progress {
        Progress {
            time: self.now,
            collisions_per_particle: self.collisions_per_particle(),
            steps: 0,
            events: self.counters.events,
        }
    }

    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        match stop {
            StopAt::Steps(_) => return Err(self.def().clock_error(stop.clock())),
            StopAt::CollisionsPerParticle(target) => {
                let target_pairs = (target * self.kin.len() as f64 / 2.0).ceil() as u64;
                while self.counters.pair_collisions < target_pairs {
                    if !self.step() {
                        break;
                    }
                    self.stall_check()?;
                }
            }
            StopAt::Time(t_stop) => {
                while let Some((t, _)) = self.queue.peek() {
                    if t > t_stop {
                        break;
                    }
                    self.step();
                    self.stall_check()?;
                }
                if t_stop > self.now {
                    self.now = t_stop;
                    self.synchronised = false;
                }
            }
        }
        Ok(())
    }

    fn snapshot(&mut self) -> Snapshot {
        self.rebuild();
        self.synchronised = true;
        let k_over_4 = self.params.inertia_factor / 4.0; // I = K m d^2 / 4
        let translational_energy = self
            .kin
            .iter()
            .map(|k| 0.5 * dot(k.velocity, k.velocity))
            .sum();
        let rotational_energy = self
            .own
            .iter()
            .map(|o| 0.5 * k_over_4 * dot(o.angular, o.angular))
            .sum();
        Snapshot {
            progress: self.progress(),
            counters: self.counters.named(),
            content: Content::Particles(Particles {
                geometry: self.params.geometry,
                inertia_factor: self.params.inertia_factor,
                gravity: self.params.gravity,
                positions: self.by_id(|s| self.kin[s].position),
                velocities: self.by_id(|s| self.kin[s].velocity),
                angular_velocities: self.by_id(|s| self.own[s].angular),
                diameters: Vec::new(),
                translational_energy,
                rotational_energy,
                wall_momentum: self.wall_momentum,
                energy_dissipated: self.dissipated,
                gravity_work: self.gravity_work,
                suppressed_dissipation: self.suppressed_dissipation,
            }),
        }
    }

    fn checkpoint(&self) -> Vec<u8> {
        assert!(
            self.synchronised,
            "a checkpoint is only taken directly after a snapshot"
        );
        self.checkpoint_bytes()
    }

    fn record_free_paths(&mut self, slabs: usize) -> bool {
        let g = self.params.geometry;
        self.free_paths = Some(Box::new(crate::engine::FreePathTally::new(
            slabs, g.width, !g.walls,
        )));
        true
    }

    fn take_free_paths(&mut self) -> Option<crate::engine::FreePathTally> {
        let paths = self.free_paths.as_deref_mut()?;
        let empty = paths.emptied();
        Some(std::mem::replace(paths, empty))
    }
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::StopAt;

    /// The checkpoint serialised from the arrays is the copied state's, byte for byte, in a
    /// cell-search and a list-search channel whose particles have been re-sorted.
    #[test]
    fn the_streamed_checkpoint_is_the_copied_states() {
        for (phi, seed) in [(0.15, 42), (0.40, 7)] {
            let params = EdmdParams::channel(10.0, 10.0, 10.0, phi, seed);
            let mut e = EdmdEngine::new(params).unwrap();
            for k in 1..=3 {
                e.advance(StopAt::CollisionsPerParticle(20.0 * k as f64))
                    .unwrap();
                e.snapshot();
                assert!(
                    e.ids.iter().enumerate().any(|(s, &id)| s as u32 != id),
                    "storage order is id order: the test would not see a wrong permutation"
                );
                assert_eq!(
                    e.checkpoint_bytes(),
                    checkpoint::encode(&e.state()),
                    "phi = {phi}, {} cpp",
                    20 * k
                );
            }
        }
    }
}
