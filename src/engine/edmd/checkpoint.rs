//! The engine's checkpoint format: the EDMD state (postcard) sealed in the common
//! [`crate::engine::envelope`] (magic `GRANFLOW-EDMD`, format version, length, CRC-32). A
//! truncated, corrupt, foreign or future-version file is rejected with a message saying which
//! check failed; it is never silently used.

use super::EdmdParams;
use crate::engine::{EngineError, envelope};
use serde::{Deserialize, Serialize};

/// The name the envelope carries.
pub const ENGINE: &str = "edmd";
/// Version of the payload layout; bump it when `EngineState` changes. Version 1 (before this
/// one) lacked `suppressed_dissipation` and `stall_window`; it still reads, with the
/// suppressed total unknown (NaN) and the stall window starting at the checkpoint. (Version 2
/// existed only between commits of one session and is not read.)
pub const FORMAT_VERSION: u32 = 3;

/// Event counters of a run (cumulative since the start of the run, kept across checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EdmdCounters {
    /// particle-particle collisions (including TC-elastic ones)
    pub pair_collisions: u64,
    /// particle-wall collisions
    pub wall_collisions: u64,
    /// cell crossings (bookkeeping events)
    pub cell_crossings: u64,
    /// pair collisions made elastic by the TC model
    pub tc_elastic_collisions: u64,
    /// all events taken from the queue, including invalidated ones
    pub events: u64,
}

impl EdmdCounters {
    /// As named counters (the names of the declaration's counter list).
    pub fn named(&self) -> crate::engine::Counters {
        crate::engine::Counters::from_pairs([
            ("pair_collisions", self.pair_collisions),
            ("wall_collisions", self.wall_collisions),
            ("cell_crossings", self.cell_crossings),
            ("tc_elastic_collisions", self.tc_elastic_collisions),
            ("events", self.events),
        ])
    }
}
/// Everything needed to continue a run, at one synchronised time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EngineState {
    pub params: EdmdParams,
    /// simulated time of the state
    pub now: f64,
    pub positions: Vec<[f64; 3]>,
    pub velocities: Vec<[f64; 3]>,
    pub angular_velocities: Vec<[f64; 3]>,
    /// time of each particle's last collision (TC model)
    pub last_collision: Vec<f64>,
    pub counters: EdmdCounters,
    pub wall_momentum: [[f64; 3]; 2],
    pub dissipated: f64,
    pub gravity_work: f64,
    /// cumulative energy the TC model kept from being dissipated (NaN: unknown, for runs
    /// resumed from a version-1 checkpoint)
    pub suppressed_dissipation: f64,
    /// start of the current stall-check window: (event count, simulated time)
    pub stall_window: (u64, f64),
}

/// The payload of format version 1 (frozen: it decodes checkpoints written before the TC
/// model's suppressed dissipation was tracked).
#[derive(Deserialize)]
struct EngineStateV1 {
    params: EdmdParams,
    now: f64,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    angular_velocities: Vec<[f64; 3]>,
    last_collision: Vec<f64>,
    counters: EdmdCounters,
    wall_momentum: [[f64; 3]; 2],
    dissipated: f64,
    gravity_work: f64,
}

/// Serialise a state into checkpoint bytes.
pub fn encode(state: &EngineState) -> Vec<u8> {
    let payload = postcard::to_stdvec(state).expect("engine state serialises");
    envelope::seal(ENGINE, FORMAT_VERSION, &payload)
}

/// Check and decode checkpoint bytes.
pub fn decode(bytes: &[u8]) -> Result<EngineState, EngineError> {
    let sealed = envelope::open(bytes)?;
    if sealed.engine != ENGINE {
        return Err(EngineError::Checkpoint(format!(
            "not an EDMD checkpoint (written by the {} engine)",
            sealed.engine
        )));
    }
    decode_payload(sealed.version, sealed.payload)
}

/// Decode a payload taken out of its envelope.
pub fn decode_payload(version: u32, payload: &[u8]) -> Result<EngineState, EngineError> {
    let fail = |why: String| Err(EngineError::Checkpoint(why));
    let undecodable =
        |e: postcard::Error| EngineError::Checkpoint(format!("payload does not decode: {e}"));
    let state: EngineState = match version {
        1 => {
            let v1: EngineStateV1 = postcard::from_bytes(payload).map_err(undecodable)?;
            EngineState {
                params: v1.params,
                now: v1.now,
                positions: v1.positions,
                velocities: v1.velocities,
                angular_velocities: v1.angular_velocities,
                last_collision: v1.last_collision,
                counters: v1.counters,
                wall_momentum: v1.wall_momentum,
                dissipated: v1.dissipated,
                gravity_work: v1.gravity_work,
                suppressed_dissipation: f64::NAN,
                stall_window: (v1.counters.events, v1.now),
            }
        }
        FORMAT_VERSION => postcard::from_bytes(payload).map_err(undecodable)?,
        _ => {
            return fail(format!(
                "format version {version}, this granflow reads versions 1 and {FORMAT_VERSION}"
            ));
        }
    };
    let n = state.params.particles;
    if [
        state.positions.len(),
        state.velocities.len(),
        state.angular_velocities.len(),
        state.last_collision.len(),
    ]
    .iter()
    .any(|&len| len != n)
    {
        return fail(format!("particle arrays do not match N = {n}"));
    }
    Ok(state)
}
