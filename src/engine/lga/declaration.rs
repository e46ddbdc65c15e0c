//! The lattice gas's declaration for the registry (parameters of Peng & Herrmann 1994, the
//! time-step clock, site-update estimates, counters) and its [`Engine`] boundary.

use super::state::PAYLOAD_VERSION;
use super::{LgaEngine, LgaParams};
use crate::engine::declare::{
    BuiltEngine, CounterDef, InId, ParamDefault, ParamKind, Problem, ranges,
};
use crate::engine::{
    Clock, Content, Counters, Engine, EngineDef, EngineError, Lattice, ParamDef, ParamValue,
    Progress, Snapshot, StopAt, Values, envelope,
};

/// The declaration of the `lga` engine.
pub static DECLARATION: EngineDef = EngineDef {
    name: "lga",
    title: "lattice-gas automaton of granular flow in a vertical pipe (Peng & Herrmann 1994)",
    version: 1,
    params: PARAMS,
    alternatives: &[],
    clocks: &[Clock::Steps],
    resolve,
    build,
    restore,
    size_name: "particles",
    size: |v| number(v, "density") * number(v, "length") * number(v, "width"),
    work,
    work_unit: "site updates",
    work_rate: |_| 1e9,
    memory: |v| 256.0 * number(v, "length") * number(v, "width") + 64e6,
    counters: &[
        CounterDef {
            name: "head_on",
            doc: "rule (1): head-on pairs turned",
        },
        CounterDef {
            name: "dissipative_pairs",
            doc: "rule (2), dissipative branch: pair -> rest + moving",
        },
        CounterDef {
            name: "three_body",
            doc: "rule (3), dissipative branch: triple -> rest + head-on pair",
        },
        CounterDef {
            name: "rest_head_on",
            doc: "rule (4): head-on pair + rest particle -> three rest particles",
        },
        CounterDef {
            name: "rest_pairs",
            doc: "rule (5): pair + rest particle -> two rest particles + moving",
        },
        CounterDef {
            name: "blocked_rest_collisions",
            doc: "rules (4)-(5) not applied: too few sites left for the extra rest particles",
        },
        CounterDef {
            name: "rest_hops",
            doc: "hops of extra rest particles",
        },
        CounterDef {
            name: "hop_fallbacks",
            doc: "extra rest particles placed by the fallback after 1024 hops",
        },
        CounterDef {
            name: "gravity_starts",
            doc: "rule (6): rest particles that started moving along gravity",
        },
        CounterDef {
            name: "gravity_kicks",
            doc: "rule (6): moving particles next to a rest particle turned by +v1",
        },
        CounterDef {
            name: "wall_collisions",
            doc: "rule (7): particles reflected by a wall",
        },
        CounterDef {
            name: "wall_bounce_backs",
            doc: "rule (7): of those, bounced back",
        },
    ],
    ratios: &[],
    example: &[],
    example_run: (Clock::Steps, 100_000.0, 10_000.0),
};

fn sites(v: f64) -> bool {
    (1.0..=super::params::MAX_SITES as f64).contains(&v)
}
fn occupancy(v: f64) -> bool {
    (0.0..=6.0).contains(&v)
}

#[allow(clippy::too_many_arguments)] // one argument per column of the parameter table
const fn param(
    name: &'static str,
    symbol: &'static str,
    unit: &'static str,
    kind: ParamKind,
    default: f64,
    allowed: &'static str,
    check: fn(f64) -> bool,
    doc: &'static str,
) -> ParamDef {
    ParamDef {
        name,
        symbol,
        unit,
        kind,
        default: ParamDefault::Number(default),
        allowed,
        check,
        doc,
        in_id: InId::Always,
    }
}

/// The seed's parameters; the defaults are its Fig. 2 run (L = 220, W = 11, rho = 1,
/// p = g = b = 0.5).
const PARAMS: &[ParamDef] = &[
    param(
        "length",
        "L",
        "sites",
        ParamKind::Integer,
        220.0,
        "a whole number >= 1 (sites along the pipe, periodic)",
        sites,
        "pipe length along gravity (the seed: 220 for spectra, 2200 for pictures)",
    ),
    param(
        "width",
        "W",
        "sites",
        ParamKind::Integer,
        11.0,
        "a whole number >= 1 (sites across the pipe)",
        sites,
        "pipe width between the two walls (the seed: 11)",
    ),
    param(
        "density",
        "rho",
        "particles per site",
        ParamKind::Real,
        1.0,
        "[0, 6] (only the six moving states are filled at the start)",
        occupancy,
        "mean density; each moving state occupied with probability rho / 6 at the start",
    ),
    param(
        "dissipation",
        "p",
        "1",
        ParamKind::Real,
        0.5,
        "[0, 1]",
        ranges::unit,
        "probability of the dissipative branch of rules (2) and (3)",
    ),
    param(
        "gravity_probability",
        "g",
        "1",
        ParamKind::Real,
        0.5,
        "[0, 1]",
        ranges::unit,
        "probability of the gravity rule (6)",
    ),
    param(
        "bounce_back",
        "b",
        "1",
        ParamKind::Real,
        0.5,
        "[0, 1] (0: smooth walls)",
        ranges::unit,
        "probability that a particle hitting a wall is bounced back, rule (7)",
    ),
];

fn number(values: &Values, name: &str) -> f64 {
    values
        .get(name)
        .and_then(ParamValue::as_f64)
        .unwrap_or(f64::NAN)
}

/// The engine parameters of resolved sweep values.
pub fn params_of(values: &Values, seed: u64) -> LgaParams {
    LgaParams {
        length: number(values, "length") as usize,
        width: number(values, "width") as usize,
        density: number(values, "density"),
        dissipation: number(values, "dissipation"),
        gravity: number(values, "gravity_probability"),
        bounce_back: number(values, "bounce_back"),
        seed,
    }
}

/// The lattice must fit the engine's bound on sites.
fn resolve(values: &mut Values) -> Result<(), Problem> {
    let sites = number(values, "length") * number(values, "width");
    if sites > super::params::MAX_SITES as f64 {
        return Err(Problem::new(
            "length",
            format!(
                "L W = {sites} sites is too large: allowed at most {}",
                super::params::MAX_SITES
            ),
        ));
    }
    Ok(())
}

fn build(values: &Values, seed: u64) -> BuiltEngine {
    let engine = LgaEngine::new(params_of(values, seed)).map_err(EngineError::InvalidParams)?;
    Ok(Box::new(engine))
}

fn restore(version: u32, payload: &[u8]) -> BuiltEngine {
    crate::engine::declare::check_payload_version("lattice-gas", version, PAYLOAD_VERSION)?;
    let engine = LgaEngine::from_payload(payload).map_err(EngineError::Checkpoint)?;
    Ok(Box::new(engine))
}

/// Site updates of a run: L W x steps.
fn work(values: &Values, clock: Clock, length: f64) -> f64 {
    let sites = number(values, "length") * number(values, "width");
    match clock {
        Clock::Steps | Clock::Time => sites * length,
        Clock::CollisionsPerParticle => f64::NAN,
    }
}

impl Engine for LgaEngine {
    fn def(&self) -> &'static EngineDef {
        &DECLARATION
    }

    fn particle_count(&self) -> usize {
        LgaEngine::particle_count(self) as usize
    }

    fn progress(&self) -> Progress {
        let p = self.params();
        Progress {
            time: self.step() as f64,
            collisions_per_particle: 0.0,
            steps: self.step(),
            events: self.step() * (p.length * p.width) as u64,
        }
    }

    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        match stop {
            StopAt::Steps(n) => self.advance_to(n),
            // one time step is one unit of time
            StopAt::Time(t) => self.advance_to(t.ceil().max(0.0) as u64),
            StopAt::CollisionsPerParticle(_) => {
                return Err(DECLARATION.clock_error(stop.clock()));
            }
        }
        Ok(())
    }

    fn snapshot(&mut self) -> Snapshot {
        let p = self.params();
        Snapshot {
            progress: Engine::progress(self),
            counters: Counters::from_pairs(self.counters()),
            content: Content::Lattice(Lattice {
                length: p.length,
                width: p.width,
                row_counts: self.bin_counts(1),
                momentum: self.momentum(),
            }),
        }
    }

    fn checkpoint(&self) -> Vec<u8> {
        envelope::seal(DECLARATION.name, PAYLOAD_VERSION, &self.to_payload())
    }
}
