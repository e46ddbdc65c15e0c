//! The event-driven engine (placeholder until the engine lands).

use super::EdmdParams;
use crate::engine::{Engine, EngineError, Progress, Snapshot, StopAt};

/// Event-driven engine for rough inelastic hard spheres.
pub struct EdmdEngine {
    params: EdmdParams,
}

impl EdmdEngine {
    pub fn new(params: EdmdParams) -> Result<Self, EngineError> {
        params.validate()?;
        Ok(EdmdEngine { params })
    }
    pub fn restore(_bytes: &[u8]) -> Result<Self, EngineError> {
        todo!()
    }
}

impl Engine for EdmdEngine {
    fn particle_count(&self) -> usize {
        self.params.particles
    }
    fn progress(&self) -> Progress {
        todo!()
    }
    fn advance(&mut self, _stop: StopAt) -> Result<(), EngineError> {
        todo!()
    }
    fn snapshot(&mut self) -> Snapshot {
        todo!()
    }
    fn checkpoint(&self) -> Vec<u8> {
        todo!()
    }
}
