//! The engine's checkpoint file format: versioned, length-prefixed and checksummed.
//!
//! Layout (little endian): magic `GRANFLOW-EDMD\0\0\0` (16 bytes), format version (u32),
//! payload length (u64), CRC-32 of the payload (u32), payload (postcard-encoded
//! [`EngineState`]). A truncated, corrupt, foreign or future-version file is rejected with a
//! message saying which check failed; it is never silently used.

use super::EdmdParams;
use crate::engine::{Counters, EngineError};
use serde::{Deserialize, Serialize};

const MAGIC: &[u8; 16] = b"GRANFLOW-EDMD\0\0\0";
/// Version of the payload layout; bump it when `EngineState` changes.
pub const FORMAT_VERSION: u32 = 1;
const HEADER_LEN: usize = 16 + 4 + 8 + 4;

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
    pub counters: Counters,
    pub wall_momentum: [[f64; 3]; 2],
    pub dissipated: f64,
    pub gravity_work: f64,
}

/// Serialise a state into checkpoint bytes.
pub fn encode(state: &EngineState) -> Vec<u8> {
    let payload = postcard::to_stdvec(state).expect("engine state serialises");
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// Check and decode checkpoint bytes.
pub fn decode(bytes: &[u8]) -> Result<EngineState, EngineError> {
    let fail = |why: String| Err(EngineError::Checkpoint(why));
    if bytes.len() < HEADER_LEN {
        return fail(format!(
            "file is {} bytes, shorter than the {HEADER_LEN}-byte header (truncated)",
            bytes.len()
        ));
    }
    if &bytes[..16] != MAGIC {
        return fail("not an EDMD checkpoint (wrong magic bytes)".into());
    }
    let version = u32::from_le_bytes(bytes[16..20].try_into().unwrap());
    if version != FORMAT_VERSION {
        return fail(format!(
            "format version {version}, this granflow reads version {FORMAT_VERSION}"
        ));
    }
    let len = u64::from_le_bytes(bytes[20..28].try_into().unwrap()) as usize;
    let crc = u32::from_le_bytes(bytes[28..32].try_into().unwrap());
    let payload = &bytes[HEADER_LEN..];
    if payload.len() != len {
        return fail(format!(
            "payload is {} bytes, header says {len} (truncated or padded)",
            payload.len()
        ));
    }
    if crc32fast::hash(payload) != crc {
        return fail("checksum mismatch (corrupt file)".into());
    }
    let state: EngineState = postcard::from_bytes(payload)
        .map_err(|e| EngineError::Checkpoint(format!("payload does not decode: {e}")))?;
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
