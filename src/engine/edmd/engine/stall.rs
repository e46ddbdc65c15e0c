//! Stall check: inelastic collapse detected as simulated time that stops advancing.

use super::*;

impl EdmdEngine {
    /// Stall check, after every event: a window of 100 events per particle that covers less
    /// simulated time than the TC time t_c (or 1e-9 without the TC model) means inelastic
    /// collapse. Windows follow each other through the run (across snapshots and
    /// checkpoints: they are part of the state).
    #[inline]
    pub(super) fn stall_check(&mut self) -> Result<(), EngineError> {
        let (start_events, start_time) = self.stall_window;
        if self.counters.events < start_events + self.stall_window() {
            return Ok(());
        }
        self.stall_window = (self.counters.events, self.now);
        let span = self.now - start_time;
        let floor = if self.params.tc > 0.0 {
            self.params.tc
        } else {
            1e-9
        };
        if span < floor {
            return Err(EngineError::Stalled(format!(
                "{} events ({} per particle) advanced simulated time by only {span:.3e} at t = {:.6} \
                 (collisions per particle {:.1}): inelastic collapse. The TC model time is tc = {:e}; \
                 increase tc (e.g. to {:e}) or raise the restitution",
                self.stall_window(),
                self.stall_window() / self.kin.len() as u64,
                self.now,
                self.collisions_per_particle(),
                self.params.tc,
                if self.params.tc > 0.0 {
                    self.params.tc * 10.0
                } else {
                    1e-4
                },
            )));
        }
        Ok(())
    }

    pub(super) fn stall_window(&self) -> u64 {
        100 * self.kin.len() as u64
    }
}
