//! The engine's checkpoint format: the EDMD state (postcard) sealed in the common
//! [`crate::engine::envelope`] (magic `GRANFLOW-EDMD`, format version, length, CRC-32). A
//! truncated, corrupt, foreign or future-version file is rejected with a message saying which
//! check failed; it is never silently used.

use super::{EdmdParams, NeighbourSearch, SearchPolicy};
use crate::engine::{EngineError, envelope};
use serde::{Deserialize, Serialize};

/// The name the envelope carries.
pub const ENGINE: &str = "edmd";
/// Version of the payload layout; bump it when `EngineState` changes. Version 1 (before this
/// one) lacked `suppressed_dissipation` and `stall_window`; it still reads, with the
/// suppressed total unknown (NaN) and the stall window starting at the checkpoint. (Version 2
/// existed only between commits of one session and is not read.) Version 3 lacked
/// `search`; it reads with the search chosen from the parameters, re-chosen from then on.
pub const FORMAT_VERSION: u32 = 4;

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
    /// the neighbour search in use and how it is chosen
    pub search: SearchPolicy,
}

/// The payload of format version 3 (frozen: it decodes checkpoints written before the
/// neighbour search was re-chosen during a run).
#[derive(Deserialize)]
struct EngineStateV3 {
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
    suppressed_dissipation: f64,
    stall_window: (u64, f64),
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
    envelope::seal_value(ENGINE, FORMAT_VERSION, state)
}

/// [`EngineState`] read from the engine's own arrays as it serialises: the same fields in the
/// same order, so the same bytes (tested against [`encode`] of the copied state), without a
/// copy of every particle (at 3e5 spheres that copy and its serialised twin were the peak of
/// a job's memory).
#[derive(Serialize)]
pub(crate) struct EngineStateView<'a> {
    pub params: &'a EdmdParams,
    pub now: f64,
    pub positions: ById<'a, [f64; 3]>,
    pub velocities: ById<'a, [f64; 3]>,
    pub angular_velocities: ById<'a, [f64; 3]>,
    pub last_collision: ById<'a, f64>,
    pub counters: EdmdCounters,
    pub wall_momentum: [[f64; 3]; 2],
    pub dissipated: f64,
    pub gravity_work: f64,
    pub suppressed_dissipation: f64,
    pub stall_window: (u64, f64),
    pub search: &'a SearchPolicy,
}

/// A per-particle quantity in id order, serialised as the `Vec` of it: `of(slot)` for the
/// slot of each id in turn.
pub(crate) struct ById<'a, T> {
    /// the storage slot of each particle id
    pub slots: &'a [u32],
    pub of: &'a dyn Fn(usize) -> T,
}

impl<T: Serialize> Serialize for ById<'_, T> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.slots.iter().map(|&s| (self.of)(s as usize)))
    }
}

/// Seal a view of the state as [`encode`] seals the state.
pub(crate) fn encode_view(view: &EngineStateView<'_>) -> Vec<u8> {
    envelope::seal_value(ENGINE, FORMAT_VERSION, view)
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
                search: SearchPolicy::adaptive(
                    NeighbourSearch::automatic(&v1.params),
                    &v1.counters,
                ),
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
        3 => {
            let v3: EngineStateV3 = postcard::from_bytes(payload).map_err(undecodable)?;
            EngineState {
                search: SearchPolicy::adaptive(
                    NeighbourSearch::automatic(&v3.params),
                    &v3.counters,
                ),
                params: v3.params,
                now: v3.now,
                positions: v3.positions,
                velocities: v3.velocities,
                angular_velocities: v3.angular_velocities,
                last_collision: v3.last_collision,
                counters: v3.counters,
                wall_momentum: v3.wall_momentum,
                dissipated: v3.dissipated,
                gravity_work: v3.gravity_work,
                suppressed_dissipation: v3.suppressed_dissipation,
                stall_window: v3.stall_window,
            }
        }
        FORMAT_VERSION => postcard::from_bytes(payload).map_err(undecodable)?,
        _ => {
            return fail(format!(
                "format version {version}, this granflow reads versions 1, 3 and {FORMAT_VERSION}"
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A state as a fresh dense run would checkpoint it.
    fn state() -> EngineState {
        let params = EdmdParams::channel(10.0, 10.0, 10.0, 0.35, 3);
        let n = params.particles;
        EngineState {
            search: SearchPolicy::fixed(NeighbourSearch::Cells),
            now: 1.5,
            positions: vec![[1.0, 2.0, 3.0]; n],
            velocities: vec![[0.5, 0.0, -0.5]; n],
            angular_velocities: vec![[0.0; 3]; n],
            last_collision: vec![f64::NEG_INFINITY; n],
            counters: EdmdCounters {
                pair_collisions: 10,
                events: 25,
                ..Default::default()
            },
            wall_momentum: [[0.0; 3]; 2],
            dissipated: 2.0,
            gravity_work: 3.0,
            suppressed_dissipation: 0.5,
            stall_window: (25, 1.5),
            params,
        }
    }

    #[test]
    fn the_search_policy_survives_a_checkpoint() {
        let mut s = state();
        s.search = SearchPolicy::adaptive(NeighbourSearch::Cells, &s.counters);
        assert_eq!(decode(&encode(&s)).unwrap(), s);
    }

    /// A version-3 payload (every field but the search, in the same order) still reads: the
    /// search is then the one the parameters choose, re-chosen from the checkpoint's counters.
    #[test]
    fn version_3_checkpoints_read_with_the_automatic_search() {
        let s = state();
        let v3 = (
            &s.params,
            s.now,
            &s.positions,
            &s.velocities,
            &s.angular_velocities,
            &s.last_collision,
            s.counters,
            s.wall_momentum,
            s.dissipated,
            s.gravity_work,
            s.suppressed_dissipation,
            s.stall_window,
        );
        let bytes = envelope::seal(ENGINE, 3, &postcard::to_stdvec(&v3).unwrap());
        let read = decode(&bytes).unwrap();
        let automatic = NeighbourSearch::automatic(&s.params);
        assert!(matches!(automatic, NeighbourSearch::Lists { .. }));
        assert_eq!(read.search, SearchPolicy::adaptive(automatic, &s.counters));
        assert_eq!(
            read,
            EngineState {
                search: read.search,
                ..s
            }
        );
    }
}
