//! The DEM engine's declaration for the registry (the paper's parameters, N from phi-bar, the
//! damping alternatives, the time-step rule; clocks: time and steps) and its [`Engine`]
//! boundary.

use super::engine::PAYLOAD_VERSION;
use super::params::{
    DEFAULT_RESTITUTION, DampingFrom, DemParams, REFERENCE_PAIR_MASS, SizeMix, WallDamping,
    damping_for_restitution, default_time_step,
};
use super::{DemEngine, Phase, prepare};
use crate::engine::declare::{
    BuiltEngine, CounterDef, InId, ParamDefault, ParamKind, Problem, ranges,
};
use crate::engine::{
    Clock, Content, Counters, Engine, EngineDef, EngineError, ParamDef, ParamValue,
    PreparationProgress, Progress, Snapshot, StopAt, Values, envelope,
};

/// The declaration of the `dem` engine.
pub static DECLARATION: EngineDef = EngineDef {
    name: "dem",
    title: "soft-sphere DEM of dense granular flow in a vertical channel (Debnath, Rao & Kumaran 2022)",
    // 2: every record carries the bond-order sums of its snapshot (Q6); trajectories are
    // bitwise those of version 1, but records of version 1 cannot give Q6 (and no longer
    // decode), so their jobs rerun from the start; 3: blocks of 256 particles instead of 512
    // (better balanced on two threads): the blocks' tallies (wall forces, gravity's work) are
    // summed in another grouping, so their last bits differ from version 2's
    version: 3,
    params: PARAMS,
    alternatives: &[&["restitution", "normal_damping"]],
    clocks: &[Clock::Time, Clock::Steps],
    resolve,
    build,
    restore,
    size_name: "N",
    size: |v| params_of(v, 0).particle_count() as f64,
    work,
    work_unit: "particle-steps",
    work_rate,
    memory: |v| {
        // measured peak RSS of dense channels: about 1.2 kB per particle (state, neighbour
        // rows, pair slots, build buffers) over a base of the binary and its buffers
        1200.0 * params_of(v, 0).particle_count() as f64 + 64e6
    },
    counters: &[
        CounterDef {
            name: "steps",
            doc: "flow steps (after the floor was removed)",
        },
        CounterDef {
            name: "prep_steps",
            doc: "preparation steps (raining and settling onto the floor)",
        },
        CounterDef {
            name: "contacts",
            doc: "pair-steps in contact",
        },
        CounterDef {
            name: "wall_contacts",
            doc: "particle-steps touching a wall (or the floor)",
        },
        CounterDef {
            name: "rebuilds",
            doc: "neighbour-list rebuilds",
        },
        CounterDef {
            name: "particle_steps",
            doc: "particle-steps (N per step, preparation included)",
        },
        CounterDef {
            name: "samples",
            doc: "samples of the bin sums",
        },
    ],
    ratios: &[],
    example: &[
        ("width_over_diameter", "10"),
        ("span_over_diameter", "5"),
        ("length_over_diameter", "10"),
        ("volume_fraction", "0.58"),
        ("normal_stiffness", "1e5"),
    ],
    example_run: (Clock::Time, 20.0, 2.0),
};

fn side(v: f64) -> bool {
    v >= 3.0
}
fn fraction(v: f64) -> bool {
    v > 0.0 && v < 0.7
}
fn restitution(v: f64) -> bool {
    v > 0.0 && v <= 1.0
}
fn friction(v: f64) -> bool {
    (0.0..=1e4).contains(&v)
}
fn skin(v: f64) -> bool {
    v > 0.0 && v <= 1.0
}
fn at_least_one(v: f64) -> bool {
    (1.0..=1e9).contains(&v)
}

#[allow(clippy::too_many_arguments)]
const fn param(
    name: &'static str,
    symbol: &'static str,
    unit: &'static str,
    kind: ParamKind,
    default: ParamDefault,
    allowed: &'static str,
    check: fn(f64) -> bool,
    doc: &'static str,
    in_id: InId,
) -> ParamDef {
    ParamDef {
        name,
        symbol,
        unit,
        kind,
        default,
        allowed,
        check,
        doc,
        in_id,
    }
}

/// The paper's channel and contact law (App. A) with its open choices as parameters.
const PARAMS: &[ParamDef] = &[
    param(
        "width_over_diameter",
        "W/d",
        "d_p",
        ParamKind::Real,
        ParamDefault::Required,
        "a finite value >= 4",
        side,
        "channel width, wall to wall (the paper's x; 60-150)",
        InId::Always,
    ),
    param(
        "span_over_diameter",
        "B/d",
        "d_p",
        ParamKind::Real,
        ParamDefault::Required,
        "a finite value > 2 (d_max + skin)",
        side,
        "spanwise extent, periodic (the paper's z; 40)",
        InId::Always,
    ),
    param(
        "length_over_diameter",
        "L/d",
        "d_p",
        ParamKind::Real,
        ParamDefault::Required,
        "a finite value > 2 (d_max + skin)",
        side,
        "length along the flow and gravity, periodic (the paper's y, H = 60 + Delta H)",
        InId::Always,
    ),
    param(
        "volume_fraction",
        "phi-bar",
        "1",
        ParamKind::Real,
        ParamDefault::Required,
        "0 < phi-bar < 0.7 (the settled packing must fit in L)",
        fraction,
        "mean volume fraction; N = round(phi-bar L W B / <pi d^3/6>)",
        InId::Always,
    ),
    param(
        "size_mix",
        "sizes",
        "-",
        ParamKind::Choice(SizeMix::NAMES),
        ParamDefault::Text("debnath"),
        "debnath or mono",
        ranges::any,
        "debnath: 30/40/30 % (by number) of d = 0.9/1.0/1.1 d_p; mono: all d_p",
        InId::Always,
    ),
    param(
        "normal_stiffness",
        "k_n",
        "rho_p g d_p^2",
        ParamKind::Real,
        ParamDefault::Number(1e6),
        "a finite value > 0",
        ranges::positive,
        "normal spring stiffness (the paper: 1e6; 1e5-1e8)",
        InId::Always,
    ),
    param(
        "stiffness_ratio",
        "k_t/k_n",
        "1",
        ParamKind::Real,
        ParamDefault::Number(2.0 / 7.0),
        "a finite value >= 0",
        ranges::non_negative,
        "tangential over normal stiffness (the paper: 2/7)",
        InId::Always,
    ),
    param(
        "restitution",
        "e_n",
        "1",
        ParamKind::Real,
        ParamDefault::Derived,
        "(0, 1]; give it or `normal_damping` (default 0.82)",
        restitution,
        "normal restitution of the d_p-d_p pair, which fixes xi_n (the paper: 0.82)",
        InId::Never,
    ),
    param(
        "normal_damping",
        "xi_n",
        "sqrt(g/d_p)",
        ParamKind::Real,
        ParamDefault::Derived,
        "a finite value >= 0; give it or `restitution`",
        ranges::non_negative,
        "normal damping rate, F_n = k_n delta - m_eff xi_n v_n (the paper's literal value: 180)",
        InId::Always,
    ),
    param(
        "damping_from",
        "-",
        "-",
        ParamKind::Choice(DampingFrom::NAMES),
        ParamDefault::Derived,
        "restitution or normal_damping (set from which one was given)",
        ranges::any,
        "which of `restitution` and `normal_damping` fixed xi_n (recorded, not a choice)",
        InId::Never,
    ),
    param(
        "tangential_damping_ratio",
        "xi_t/xi_n",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.5),
        "a finite value >= 0",
        ranges::non_negative,
        "tangential over normal damping (the paper: 1/2)",
        InId::Always,
    ),
    param(
        "friction",
        "mu_p",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.5),
        "0 <= mu <= 1e4",
        friction,
        "particle-particle Coulomb friction (the paper: 0.5)",
        InId::Always,
    ),
    param(
        "wall_friction",
        "mu_w",
        "1",
        ParamKind::Real,
        ParamDefault::Derived,
        "0 <= mu <= 1e4 (default: mu_p)",
        friction,
        "particle-wall Coulomb friction (the paper: as mu_p)",
        InId::Always,
    ),
    param(
        "wall_damping",
        "xi_w",
        "-",
        ParamKind::Choice(WallDamping::NAMES),
        ParamDefault::Text("pair_rate"),
        "pair_rate or pair_restitution",
        ranges::any,
        "the walls' damping. pair_restitution (the paper's \"same restitution\"): per size, the rate that gives each size the d_p pair's e_n against a wall; pair_rate (LAMMPS fix wall/gran given the pair's gamma_n, gamma_t; granflow's runs before this parameter): the pair's xi_n, xi_t with m_eff = m_i, e_n 0.72-0.79 by size at a pair e_n of 0.82",
        InId::AwayFromDefault,
    ),
    param(
        "settle_friction",
        "mu_s",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.0),
        "0 <= mu <= 1e4",
        friction,
        "friction while the rained particles compact on the floor, before mu_p and mu_w freeze them (not in the paper; 0 packs densest)",
        InId::Always,
    ),
    param(
        "gravity",
        "g",
        "g",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "a finite value > 0",
        ranges::positive,
        "gravitational acceleration along the flow (units d_p = rho_p = g = 1)",
        InId::Always,
    ),
    param(
        "time_step",
        "dt",
        "sqrt(d_p/g)",
        ParamKind::Real,
        ParamDefault::Derived,
        "> 0 with t_c >= 10 dt for every contact type (default 1.2e-4 (1e6/k_n)^(1/2))",
        ranges::positive,
        "time step (the paper: 1.2e-4 at k_n = 1e6)",
        InId::Always,
    ),
    param(
        "skin",
        "skin",
        "d_p",
        ParamKind::Real,
        ParamDefault::Number(0.1),
        "0 < skin <= 1",
        skin,
        "neighbour-list skin (speed only: trajectories do not depend on it)",
        InId::Never,
    ),
    param(
        "sample_every",
        "-",
        "steps",
        ParamKind::Integer,
        ParamDefault::Number(100.0),
        "a whole number >= 1",
        at_least_one,
        "steps between two samples of the bin sums",
        InId::Always,
    ),
];

fn number(values: &Values, name: &str) -> f64 {
    values
        .get(name)
        .and_then(ParamValue::as_f64)
        .unwrap_or(f64::NAN)
}

/// e_n of the d_p-d_p pair under damping xi_n (0 when overdamped).
fn reference_restitution(normal_damping: f64, normal_stiffness: f64) -> f64 {
    let w2 = normal_stiffness / REFERENCE_PAIR_MASS - 0.25 * normal_damping * normal_damping;
    if w2 <= 0.0 {
        return 0.0;
    }
    (-0.5 * normal_damping * std::f64::consts::PI / w2.sqrt()).exp()
}

/// The engine parameters of resolved values.
pub fn params_of(values: &Values, seed: u64) -> DemParams {
    let damping_from = match values.get("damping_from").and_then(ParamValue::as_text) {
        Some("normal_damping") => DampingFrom::NormalDamping,
        _ => DampingFrom::Restitution,
    };
    let g = number(values, "gravity");
    DemParams {
        width: number(values, "width_over_diameter"),
        span: number(values, "span_over_diameter"),
        length: number(values, "length_over_diameter"),
        volume_fraction: number(values, "volume_fraction"),
        size_mix: values
            .get("size_mix")
            .and_then(ParamValue::as_text)
            .and_then(SizeMix::from_name)
            .unwrap_or_default(),
        normal_stiffness: number(values, "normal_stiffness"),
        stiffness_ratio: number(values, "stiffness_ratio"),
        normal_damping: number(values, "normal_damping"),
        damping_from,
        tangential_damping_ratio: number(values, "tangential_damping_ratio"),
        friction: number(values, "friction"),
        wall_friction: number(values, "wall_friction"),
        wall_damping: values
            .get("wall_damping")
            .and_then(ParamValue::as_text)
            .and_then(WallDamping::from_name)
            .unwrap_or_default(),
        settle_friction: number(values, "settle_friction"),
        gravity: [g, 0.0, 0.0],
        time_step: number(values, "time_step"),
        skin: number(values, "skin"),
        sample_every: number(values, "sample_every") as u64,
        seed,
    }
}

/// xi_n from e_n or e_n from xi_n (recording which was given), mu_w = mu_p and the scaled
/// time step unless given, then the engine's own checks (the time-step rule among them).
fn resolve(values: &mut Values) -> Result<(), Problem> {
    let kn = number(values, "normal_stiffness");
    let given_e = values.contains_key("restitution");
    let given_xi = values.contains_key("normal_damping");
    let recorded = values
        .get("damping_from")
        .and_then(ParamValue::as_text)
        .map(str::to_string);
    let from = match (given_e, given_xi) {
        (true, true) => {
            return Err(Problem::new(
                "normal_damping",
                "`restitution` and `normal_damping` are both given: each follows from the \
                 other, give one",
            ));
        }
        (_, true) => DampingFrom::NormalDamping,
        _ => DampingFrom::Restitution,
    };
    if let Some(r) = &recorded
        && r != from.name()
    {
        return Err(Problem::new(
            "damping_from",
            format!(
                "damping_from = \"{r}\", but xi_n was fixed by `{}`: damping_from records which \
                 one was given (leave it out)",
                from.name()
            ),
        ));
    }
    match from {
        DampingFrom::Restitution => {
            let e = if given_e {
                number(values, "restitution")
            } else {
                DEFAULT_RESTITUTION
            };
            values.insert("restitution".into(), ParamValue::Number(e));
            values.insert(
                "normal_damping".into(),
                ParamValue::Number(damping_for_restitution(e, kn)),
            );
        }
        DampingFrom::NormalDamping => {
            let xi = number(values, "normal_damping");
            values.insert(
                "restitution".into(),
                ParamValue::Number(reference_restitution(xi, kn)),
            );
        }
    }
    values.insert(
        "damping_from".into(),
        ParamValue::Text(from.name().to_string()),
    );
    if !values.contains_key("wall_friction") {
        let mu = number(values, "friction");
        values.insert("wall_friction".into(), ParamValue::Number(mu));
    }
    if !values.contains_key("time_step") {
        values.insert(
            "time_step".into(),
            ParamValue::Number(default_time_step(kn)),
        );
    }
    params_of(values, 0).validate()
}

/// The engine before its preparation: a job settles the packing in checkpointed chunks
/// ([`Engine::prepare`]); `advance` finishes whatever is left first.
fn build(values: &Values, seed: u64) -> BuiltEngine {
    let engine =
        DemEngine::unprepared(params_of(values, seed)).map_err(EngineError::InvalidParams)?;
    Ok(Box::new(engine))
}

fn restore(version: u32, payload: &[u8]) -> BuiltEngine {
    let engine =
        DemEngine::from_payload_of_version(version, payload).map_err(EngineError::Checkpoint)?;
    Ok(Box::new(engine))
}

/// Typical particle-steps per second on one core at this job's N: the contact-rich benchmark
/// channels ran 17.6 M at N = 4052 and 7.2 M at N = 40 524 (docs/performance.md: the larger
/// working set no longer fits the cache), so the rate falls as a power of N between them and
/// is held at those values beyond.
fn work_rate(values: &Values) -> f64 {
    const SMALL: (f64, f64) = (4052.0, 1.76e7);
    const LARGE: (f64, f64) = (40524.0, 7.2e6);
    let n = params_of(values, 0).particle_count() as f64;
    let exponent = (LARGE.1 / SMALL.1).ln() / (LARGE.0 / SMALL.0).ln();
    SMALL.1 * (n.clamp(SMALL.0, LARGE.0) / SMALL.0).powf(exponent)
}

/// Particle-steps of a run, with an estimate of the preparation's: the settling takes about
/// five free-fall times from the top of the lattice (measured on small channels: 2-6).
fn work(values: &Values, clock: Clock, length: f64) -> f64 {
    let p = params_of(values, 0);
    let n = p.particle_count() as f64;
    let steps = match clock {
        Clock::Steps => length,
        Clock::Time => length / p.time_step,
        Clock::CollisionsPerParticle => f64::NAN,
    };
    let a = prepare::LATTICE_SPACING * p.max_diameter();
    let per_layer = ((p.width / a).floor() * (p.span / a).floor()).max(1.0);
    let height = (n / per_layer).ceil() * a;
    let prep_time = 5.0 * (2.0 * height / p.gravity[0]).sqrt();
    n * (steps + prep_time / p.time_step)
}

impl Engine for DemEngine {
    fn def(&self) -> &'static EngineDef {
        &DECLARATION
    }

    fn particle_count(&self) -> usize {
        DemEngine::particle_count(self)
    }

    fn progress(&self) -> Progress {
        Progress {
            time: self.time(),
            collisions_per_particle: 0.0,
            steps: self.steps(),
            events: self.counters().particle_steps,
        }
    }

    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        let target = match stop {
            StopAt::Steps(n) => n,
            StopAt::Time(t) => (t / self.dt() - 1e-9).ceil().max(0.0) as u64,
            StopAt::CollisionsPerParticle(_) => {
                return Err(DECLARATION.clock_error(stop.clock()));
            }
        };
        self.advance_to_step(target)
            .map_err(EngineError::InvalidParams)
    }

    fn snapshot(&mut self) -> Snapshot {
        let sample = self.take_sample();
        Snapshot {
            progress: Engine::progress(self),
            counters: Counters::from_pairs(self.counter_pairs()),
            content: Content::Sample(Box::new(sample)),
        }
    }

    fn checkpoint(&self) -> Vec<u8> {
        envelope::seal(DECLARATION.name, PAYLOAD_VERSION, &self.to_payload())
    }

    fn preparation(&self) -> Option<PreparationProgress> {
        let Phase::Preparing(p) = self.phase() else {
            return None;
        };
        let (stage, ends_below) = if p.freezing {
            ("freezing", p.threshold)
        } else {
            ("compaction", p.compact_threshold)
        };
        Some(PreparationProgress {
            stage,
            steps: p.steps,
            max_steps: p.max_steps,
            measure: format!(
                "kinetic energy per particle {:.2e}, ends below {ends_below:.2e}",
                p.last_energy
            ),
        })
    }

    fn prepare(&mut self, steps: u64) -> Result<(), EngineError> {
        DemEngine::prepare(self, steps)
            .map(|_| ())
            .map_err(EngineError::InvalidParams)
    }
}

impl DemEngine {
    /// The counters by their declared names, in declaration order.
    pub fn counter_pairs(&self) -> Vec<(&'static str, u64)> {
        let c = self.counters();
        vec![
            ("steps", c.steps),
            ("prep_steps", c.prep_steps),
            ("contacts", c.contacts),
            ("wall_contacts", c.wall_contacts),
            ("rebuilds", c.rebuilds),
            ("particle_steps", c.particle_steps),
            ("samples", c.samples),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of a dem-small-like channel with N particles' worth of length.
    fn channel(length: f64) -> Values {
        let mut values = Values::new();
        for (k, v) in [
            ("width_over_diameter", 20.0),
            ("span_over_diameter", 20.0),
            ("length_over_diameter", length),
            ("volume_fraction", 0.6),
        ] {
            values.insert(k.into(), ParamValue::Number(v));
        }
        DECLARATION.resolve_values(&values).unwrap()
    }

    #[test]
    fn the_typical_rate_falls_with_size_between_the_measured_ones() {
        let (small, large) = (channel(5.0), channel(200.0));
        let n = |v: &Values| params_of(v, 0).particle_count() as f64;
        assert!(
            n(&small) < 4052.0 && n(&large) > 40524.0,
            "{} {}",
            n(&small),
            n(&large)
        );
        // held at the measured rates beyond the measured sizes
        assert!((work_rate(&small) - 1.76e7).abs() < 1.0);
        assert!((work_rate(&large) - 7.2e6).abs() < 1.0);
        // and falling in between
        let (a, b) = (channel(40.0), channel(80.0));
        assert!(n(&a) > 4052.0 && n(&b) < 40524.0, "{} {}", n(&a), n(&b));
        assert!(1.76e7 > work_rate(&a) && work_rate(&a) > work_rate(&b) && work_rate(&b) > 7.2e6);
    }
}
