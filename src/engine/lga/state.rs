//! What the lattice gas counts (rule applications, hops, gravity and wall events) and the
//! checkpoint payload that both implementations can be restored from.

use super::params::LgaParams;
use serde::{Deserialize, Serialize};

/// Cumulative event counts since step 0 (kept across checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counters {
    /// rule (1): head-on pairs turned
    pub head_on: u64,
    /// rule (2), dissipative branch: pair -> rest + moving
    pub dissipative_pairs: u64,
    /// rule (3), dissipative branch: triple -> rest + head-on pair
    pub three_body: u64,
    /// rule (4): head-on pair + rest particle -> three rest particles
    pub rest_head_on: u64,
    /// rule (5): pair + rest particle -> two rest particles + moving
    pub rest_pairs: u64,
    /// rules (4)-(5) not applied because fewer sites without a rest particle were left than
    /// extra rest particles to place (the site keeps its state)
    pub blocked_rest_collisions: u64,
    /// hops of extra rest particles
    pub rest_hops: u64,
    /// extra rest particles placed by the fallback after `MAX_HOPS` hops
    pub hop_fallbacks: u64,
    /// rule (6): rest particles that started moving along gravity (v1)
    pub gravity_starts: u64,
    /// rule (6): moving particles next to a rest particle turned by +v1 (v3 -> v2, v5 -> v6)
    pub gravity_kicks: u64,
    /// rule (7): particles reflected by a wall
    pub wall_collisions: u64,
    /// rule (7): of those, bounced back (the rest were reflected specularly)
    pub wall_bounce_backs: u64,
}

impl Counters {
    /// The counters as (name, value), in declaration order.
    pub fn named(&self) -> Vec<(&'static str, u64)> {
        vec![
            ("head_on", self.head_on),
            ("dissipative_pairs", self.dissipative_pairs),
            ("three_body", self.three_body),
            ("rest_head_on", self.rest_head_on),
            ("rest_pairs", self.rest_pairs),
            ("blocked_rest_collisions", self.blocked_rest_collisions),
            ("rest_hops", self.rest_hops),
            ("hop_fallbacks", self.hop_fallbacks),
            ("gravity_starts", self.gravity_starts),
            ("gravity_kicks", self.gravity_kicks),
            ("wall_collisions", self.wall_collisions),
            ("wall_bounce_backs", self.wall_bounce_backs),
        ]
    }
}

/// Version of [`Payload`]; bump on any change of its layout or meaning.
pub const PAYLOAD_VERSION: u32 = 1;

/// The full state of a run, independent of the kernel's memory layout.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Payload {
    /// [`PAYLOAD_VERSION`]
    pub version: u32,
    pub params: LgaParams,
    /// time steps done
    pub step: u64,
    pub counters: Counters,
    /// momentum given to the particles by the walls so far (units of `rules::MOMENTUM`)
    pub wall_impulse: [i64; 2],
    /// 7-bit state of every site, in site order (see `rules::Geometry::index`)
    pub occupation: Vec<u8>,
}

impl Payload {
    /// Serialise with postcard.
    pub fn to_bytes(&self) -> Vec<u8> {
        postcard::to_stdvec(self).expect("serialising a lattice-gas state cannot fail")
    }

    /// Read and check a payload: version, parameters, number and range of site states.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        let p: Payload = postcard::from_bytes(bytes)
            .map_err(|e| format!("lattice-gas state cannot be read: {e}"))?;
        if p.version != PAYLOAD_VERSION {
            return Err(format!(
                "lattice-gas state has format version {}, this build reads version {PAYLOAD_VERSION}",
                p.version
            ));
        }
        p.params.validate()?;
        let sites = p.params.length * p.params.width;
        if p.occupation.len() != sites {
            return Err(format!(
                "lattice-gas state holds {} sites, its parameters need L W = {sites}",
                p.occupation.len()
            ));
        }
        if let Some(s) = p.occupation.iter().position(|&o| o > super::rules::FULL) {
            return Err(format!(
                "lattice-gas state of site {s} is {}, above the 7-bit maximum 127",
                p.occupation[s]
            ));
        }
        Ok(p)
    }
}
