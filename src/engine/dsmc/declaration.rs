//! The DSMC channel engine's declaration for the registry (the thesis' control parameters,
//! wall models and mixtures; clocks: steps and time) and its [`Engine`] boundary.

use super::{DsmcEngine, DsmcParams, WallModel};
use crate::engine::declare::{
    BuiltEngine, CounterDef, InId, ParamDefault, ParamKind, Problem, ranges,
};
use crate::engine::{
    Clock, Content, Counters, Engine, EngineDef, EngineError, ParamDef, ParamValue, Progress,
    Snapshot, StopAt, Values, envelope,
};

/// Version of the DSMC payload in the envelope.
const PAYLOAD_VERSION: u32 = 1;

/// The names of the wall models in sweep files.
pub const WALL_MODELS: &[&str] = &["thermal", "maxwell", "rough", "adiabatic", "periodic"];

/// The declaration of the `dsmc` engine.
pub static DECLARATION: EngineDef = EngineDef {
    name: "dsmc",
    title: "direct simulation Monte Carlo of dilute granular Poiseuille flow (Gupta 2017)",
    // 2: a mixture's NTC candidates of the species pairs in random order (monodisperse runs
    // are bitwise those of version 1)
    version: 2,
    params: PARAMS,
    alternatives: &[],
    clocks: &[Clock::Steps, Clock::Time],
    resolve,
    build,
    restore,
    size_name: "simulators",
    size: |v| (params_of(v, 0).cell_count() as f64 * number(v, "particles_per_cell")).round(),
    work,
    work_unit: "moves",
    work_rate: |_| 5e7,
    memory: |v| {
        let p = params_of(v, 0);
        // 48 bytes per simulator (state and sort buffers) and the per-cell sampling sums
        let n = p.cell_count() as f64 * p.particles_per_cell;
        64.0 * n + 4096.0 * p.cell_count() as f64 + 64e6
    },
    counters: &[
        CounterDef {
            name: "moves",
            doc: "simulator flights (one per simulator and step)",
        },
        CounterDef {
            name: "candidates",
            doc: "NTC candidate pairs",
        },
        CounterDef {
            name: "collisions",
            doc: "accepted collisions",
        },
        CounterDef {
            name: "wall_hits",
            doc: "simulators reaching a wall",
        },
        CounterDef {
            name: "bound_exceedances",
            doc: "candidates above their cell's g_max (raised for the rest of the cell)",
        },
        CounterDef {
            name: "samples",
            doc: "sampling steps",
        },
    ],
    ratios: &[],
    example: &[],
    example_run: (Clock::Steps, 20_000.0, 2_000.0),
};

fn positive(v: f64) -> bool {
    v > 0.0
}
fn knudsen(v: f64) -> bool {
    v > 0.0 && v <= 1e4
}
fn forcing(v: f64) -> bool {
    (0.0..=1e4).contains(&v)
}
fn step_fraction(v: f64) -> bool {
    v > 0.0 && v <= 1.0
}
fn cells(v: f64) -> bool {
    (0.0..=100_000.0).contains(&v)
}
fn fraction(v: f64) -> bool {
    (0.0..1.0).contains(&v)
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
        in_id: InId::Always,
    }
}

/// The thesis' control parameters (3.2.3), wall models (ch. 3-4), mixtures (ch. 5), and the
/// numerical ones; defaults: a molecular gas between thermal walls at Kn = 0.1, a-hat = 0.5.
const PARAMS: &[ParamDef] = &[
    param(
        "knudsen_number",
        "Kn",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.1),
        "0 < Kn <= 1e4",
        knudsen,
        "Kn = lambda / W, lambda = 1 / (sqrt 2 pi n d^2) set a priori",
    ),
    param(
        "forcing",
        "a-hat",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.5),
        "0 <= a-hat <= 1e4",
        forcing,
        "body force a-hat = a W / (2 k T_w / m) along the flow",
    ),
    param(
        "restitution",
        "e_n",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "[0, 1]",
        ranges::unit,
        "normal restitution of smooth inelastic hard spheres (e_11 in mixtures)",
    ),
    param(
        "wall_model",
        "wall",
        "-",
        ParamKind::Choice(WALL_MODELS),
        ParamDefault::Text("thermal"),
        "thermal, maxwell, rough, adiabatic or periodic",
        ranges::any,
        "thermal (diffuse at T_w), maxwell (accommodation), rough (beta_w), adiabatic, periodic (no walls)",
    ),
    param(
        "accommodation",
        "alpha",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "[0, 1]",
        ranges::unit,
        "diffuse fraction of the Maxwell wall",
    ),
    param(
        "wall_roughness",
        "beta_w",
        "1",
        ParamKind::Real,
        ParamDefault::Number(-0.9),
        "[-1, 1]",
        ranges::signed_unit,
        "bulk roughness of the rough wall, v_x' = -beta_w v_x (-1 smooth, 1 fully rough)",
    ),
    param(
        "cells",
        "n_c",
        "1",
        ParamKind::Integer,
        ParamDefault::Number(0.0),
        "0 (automatic: cell width <= lambda/3, at least 50) or 1 to 100000",
        cells,
        "layer cells across the channel",
    ),
    param(
        "particles_per_cell",
        "N_c",
        "1",
        ParamKind::Real,
        ParamDefault::Number(20.0),
        "0 < N_c <= 1e6",
        |v| positive(v) && v <= 1e6,
        "simulators per cell on average (sets N and the weight F_N)",
    ),
    param(
        "time_step",
        "dt",
        "tau_c",
        ParamKind::Real,
        ParamDefault::Number(0.1),
        "0 < dt <= 1 mean collision times",
        step_fraction,
        "time step in mean collision times of the gas at rest at T_w",
    ),
    param(
        "sample_every",
        "-",
        "steps",
        ParamKind::Integer,
        ParamDefault::Number(1.0),
        "a whole number >= 1",
        at_least_one,
        "steps between two samples of the cell moments",
    ),
    param(
        "species2_fraction",
        "x_2",
        "1",
        ParamKind::Real,
        ParamDefault::Number(0.0),
        "[0, 1) (0: monodisperse)",
        fraction,
        "number fraction of species 2",
    ),
    param(
        "mass_ratio",
        "m_2/m_1",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "a finite value > 0",
        positive,
        "mass of species 2 over species 1",
    ),
    param(
        "diameter_ratio",
        "d_2/d_1",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "a finite value > 0",
        positive,
        "diameter of species 2 over species 1",
    ),
    param(
        "restitution_12",
        "e_12",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "[0, 1]",
        ranges::unit,
        "restitution of unlike collisions",
    ),
    param(
        "restitution_22",
        "e_22",
        "1",
        ParamKind::Real,
        ParamDefault::Number(1.0),
        "[0, 1]",
        ranges::unit,
        "restitution of species-2 collisions",
    ),
];

fn number(values: &Values, name: &str) -> f64 {
    values
        .get(name)
        .and_then(ParamValue::as_f64)
        .unwrap_or(f64::NAN)
}

fn wall_model(values: &Values) -> WallModel {
    match values.get("wall_model").and_then(ParamValue::as_text) {
        Some("maxwell") => WallModel::Maxwell,
        Some("rough") => WallModel::Rough,
        Some("adiabatic") => WallModel::Adiabatic,
        Some("periodic") => WallModel::Periodic,
        _ => WallModel::Thermal,
    }
}

/// The engine parameters of resolved sweep values.
pub fn params_of(values: &Values, seed: u64) -> DsmcParams {
    DsmcParams {
        knudsen_number: number(values, "knudsen_number"),
        forcing: number(values, "forcing"),
        restitution: number(values, "restitution"),
        wall_model: wall_model(values),
        accommodation: number(values, "accommodation"),
        wall_roughness: number(values, "wall_roughness"),
        cells: number(values, "cells") as usize,
        particles_per_cell: number(values, "particles_per_cell"),
        time_step: number(values, "time_step"),
        sample_every: number(values, "sample_every") as u64,
        species2_fraction: number(values, "species2_fraction"),
        mass_ratio: number(values, "mass_ratio"),
        diameter_ratio: number(values, "diameter_ratio"),
        restitution_12: number(values, "restitution_12"),
        restitution_22: number(values, "restitution_22"),
        seed,
    }
}

/// The engine's own cross-checks (e.g. periodic walls need no forcing); its messages start
/// with the key.
fn resolve(values: &mut Values) -> Result<(), Problem> {
    params_of(values, 0).validate().map_err(|m| {
        let key = m
            .split([' ', '='])
            .next()
            .unwrap_or("knudsen_number")
            .to_string();
        Problem::new(&key, m)
    })
}

fn build(values: &Values, seed: u64) -> BuiltEngine {
    let engine = DsmcEngine::new(params_of(values, seed)).map_err(EngineError::InvalidParams)?;
    Ok(Box::new(engine))
}

fn restore(version: u32, payload: &[u8]) -> BuiltEngine {
    crate::engine::declare::check_payload_version("DSMC", version, PAYLOAD_VERSION)?;
    let engine = DsmcEngine::from_payload(payload).map_err(EngineError::Checkpoint)?;
    Ok(Box::new(engine))
}

/// Simulator moves of a run.
fn work(values: &Values, clock: Clock, length: f64) -> f64 {
    let p = params_of(values, 0);
    let n = p.cell_count() as f64 * p.particles_per_cell;
    let steps = match clock {
        Clock::Steps => length,
        Clock::Time => length / p.dt(),
        Clock::CollisionsPerParticle => f64::NAN,
    };
    n * steps
}

impl Engine for DsmcEngine {
    fn def(&self) -> &'static EngineDef {
        &DECLARATION
    }

    fn particle_count(&self) -> usize {
        self.species_counts().iter().sum()
    }

    fn progress(&self) -> Progress {
        Progress {
            time: self.time(),
            collisions_per_particle: 0.0,
            steps: self.steps(),
            events: self.counter_values().moves,
        }
    }

    fn advance(&mut self, stop: StopAt) -> Result<(), EngineError> {
        match stop {
            StopAt::Steps(n) => self.advance_to_step(n),
            StopAt::Time(t) => {
                let steps = (t / self.dt() - 1e-9).ceil().max(0.0) as u64;
                self.advance_to_step(steps)
            }
            StopAt::CollisionsPerParticle(_) => {
                return Err(DECLARATION.clock_error(stop.clock()));
            }
        }
        Ok(())
    }

    fn snapshot(&mut self) -> Snapshot {
        let sample = self.take_sample();
        Snapshot {
            progress: Engine::progress(self),
            counters: Counters::from_pairs(self.counters()),
            content: Content::Sample(Box::new(sample)),
        }
    }

    fn checkpoint(&self) -> Vec<u8> {
        envelope::seal(DECLARATION.name, PAYLOAD_VERSION, &self.to_payload())
    }
}
