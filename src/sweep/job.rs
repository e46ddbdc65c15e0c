//! Job identity: a job's resolved parameters ([`JobParams`]) and its id ([`JobId`]), the hash
//! of their canonical form, and the run settings ([`RunSettings`]).
//!
//! Canonical form (the id contract, documented in docs/sweeps.md, "Job ids"): a JSON object with keys
//! sorted, no whitespace, numbers in Rust's shortest round-trip notation:
//! `{"analysis":{..},"engine":"edmd","params":{..},"run":{..},"seed":S}` where `params` holds
//! the engine's declared parameters ([`crate::engine::EngineDef::params`]): those marked
//! [`InId::Always`] with their resolved value (even at the default), those marked
//! [`InId::AwayFromDefault`] only where they differ from the default, and never those marked
//! [`InId::Never`] (derived ones, like phi from N); `run` holds the run length on its clock
//! (`collisions_per_particle`, `steps` or `time`), `snapshot_interval` and, only when set,
//! `until_steady` (`{"window":W}`) and, only when set, `statistics` (the statistics settings
//! that differ from their defaults, `{}` when none does); `analysis` holds
//! only the analysis settings that differ from their defaults. The id is the first 16 hex
//! digits of SHA-256 of that text. So adding a new optional parameter (declared with
//! `AwayFromDefault`) or a new analysis setting leaves every existing id unchanged.

use crate::analysis::statistics::{StatisticsPlan, StatisticsSettings};
use crate::engine::declare::InId;
use crate::engine::{Clock, EngineDef, EngineError, ParamDef, ParamValue, Values};
use crate::registry;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::fmt;

/// Run length and snapshot cadence of a job, on one of the engine's clocks: exactly one of
/// `collisions_per_particle`, `steps` and `time` gives the length, and `snapshot_interval` is
/// in the same unit.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSettings {
    /// run length in collisions per particle
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collisions_per_particle: Option<f64>,
    /// run length in time steps
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<f64>,
    /// run length in simulated time
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// a snapshot (analysis record) every this much of the run's clock
    pub snapshot_interval: f64,
    /// write a checkpoint every this many snapshots (a deterministic cadence of simulated
    /// progress; it does not change results, so it is not part of the job id)
    #[serde(default = "default_checkpoint_every")]
    pub checkpoint_every: u32,
    /// stop before the run length (then a cap) once the run is steady: see [`UntilSteady`]
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_steady: Option<UntilSteady>,
    /// readings of `milestone_clock` at which the job records its structure (the `evolution`
    /// table); with `until_steady`, the run goes on at least to the last of them
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub milestones: Option<Vec<f64>>,
    /// also a milestone at every multiple of this reading
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub milestone_every: Option<f64>,
    /// the clock of the milestones (default: collisions per particle where the engine counts
    /// them, else the run's clock)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub milestone_clock: Option<Clock>,
    /// snapshots per milestone window (default [`DEFAULT_MILESTONE_WINDOW`])
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub milestone_window: Option<u32>,
    /// the thesis' statistics (VDFs, g(r), Lambda, velocity correlations, free paths, wall
    /// values): opt-in, see [`crate::analysis::statistics`]
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub statistics: Option<StatisticsSettings>,
}

/// Snapshots per milestone window unless the run says otherwise.
pub const DEFAULT_MILESTONE_WINDOW: u32 = 5;

/// Run until steady: after every snapshot the job asks its analysis, from the records alone,
/// whether the run is steady (the documented detector, balances included) over a window of at
/// least `window` (in the run's clock) with a label that holds a clear majority over it; if so
/// it stops there. The run length is the cap.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UntilSteady {
    /// the shortest steady window that ends a run, in the run's clock
    pub window: f64,
}

fn default_checkpoint_every() -> u32 {
    1
}

impl RunSettings {
    /// A run of `length` on `clock` with a snapshot every `interval`.
    pub fn new(clock: Clock, length: f64, interval: f64) -> Self {
        let mut run = RunSettings {
            snapshot_interval: interval,
            checkpoint_every: 1,
            ..Default::default()
        };
        run.set_length(clock, length);
        run
    }

    fn slot(&mut self, clock: Clock) -> &mut Option<f64> {
        match clock {
            Clock::CollisionsPerParticle => &mut self.collisions_per_particle,
            Clock::Steps => &mut self.steps,
            Clock::Time => &mut self.time,
        }
    }

    /// Set the run length on `clock` (clearing the others).
    pub fn set_length(&mut self, clock: Clock, length: f64) {
        for c in Clock::ALL {
            *self.slot(c) = None;
        }
        *self.slot(clock) = Some(length);
    }

    /// The lengths given, by clock.
    fn given(&self) -> Vec<(Clock, f64)> {
        [
            (Clock::CollisionsPerParticle, self.collisions_per_particle),
            (Clock::Steps, self.steps),
            (Clock::Time, self.time),
        ]
        .into_iter()
        .filter_map(|(c, v)| v.map(|v| (c, v)))
        .collect()
    }

    /// The run's clock (valid after [`RunSettings::validate`]).
    pub fn clock(&self) -> Clock {
        self.given()
            .first()
            .map_or(Clock::CollisionsPerParticle, |g| g.0)
    }

    /// The run length on its clock.
    pub fn length(&self) -> f64 {
        self.given().first().map_or(f64::NAN, |g| g.1)
    }

    /// Check against an engine's clocks: one length, finite and > 0, on a clock the engine
    /// has; 0 < interval <= length with at most 1e6 snapshots; checkpoint_every >= 1. The
    /// error names the key.
    pub fn validate(&self, engine: &EngineDef) -> Result<(), (&'static str, String)> {
        let given = self.given();
        let &[(clock, length)] = given.as_slice() else {
            let key = given.get(1).map_or("snapshot_interval", |g| g.0.key());
            return Err((
                key,
                format!(
                    "give exactly one run length: one of {} (the {} engine's clocks)",
                    engine.clock_names(),
                    engine.name
                ),
            ));
        };
        if !engine.has_clock(clock) {
            return Err((
                clock.key(),
                format!(
                    "the {} engine cannot measure a run in `{}`; allowed: {}",
                    engine.name,
                    clock.key(),
                    engine.clock_names()
                ),
            ));
        }
        if !(length.is_finite() && length > 0.0) {
            return Err((
                clock.key(),
                format!(
                    "{} is out of range: allowed a finite value > 0",
                    super::readable::readable_number(length)
                ),
            ));
        }
        if clock == Clock::Steps && length.fract() != 0.0 {
            return Err((
                clock.key(),
                format!("{length} is not a whole number of steps"),
            ));
        }
        let interval = self.snapshot_interval;
        if clock == Clock::Steps && interval.fract() != 0.0 {
            return Err((
                "snapshot_interval",
                format!(
                    "{interval} is not a whole number of steps: allowed a whole number from 1 to \
                     steps ({length})"
                ),
            ));
        }
        let n = super::readable::readable_number;
        if !(interval.is_finite() && interval > 0.0 && interval <= length) {
            return Err((
                "snapshot_interval",
                format!(
                    "{} is out of range: allowed 0 < snapshot_interval <= {} ({})",
                    n(interval),
                    clock.key(),
                    n(length)
                ),
            ));
        }
        if length / interval > 1e6 {
            return Err((
                "snapshot_interval",
                format!(
                    "snapshot_interval = {} and {} = {} make {} snapshots: allowed at most 1e6 \
                     (raise the interval or shorten the run)",
                    n(interval),
                    clock.key(),
                    n(length),
                    n((length / interval).ceil())
                ),
            ));
        }
        if self.until_steady.is_some() && !registry::analysis_of(engine).supports_until_steady() {
            return Err((
                "until_steady",
                format!(
                    "the {} engine's analysis has no steady-state rule: give a run length only",
                    engine.name
                ),
            ));
        }
        if let Some(u) = &self.until_steady
            && !(u.window.is_finite() && u.window > 0.0 && u.window <= length)
        {
            return Err((
                "until_steady",
                format!(
                    "window = {} is out of range: allowed 0 < window <= {} ({length}), in {}",
                    u.window,
                    clock.key(),
                    clock.key()
                ),
            ));
        }
        if let Some(st) = &self.statistics {
            if !registry::analysis_of(engine).supports_statistics() {
                return Err((
                    "statistics",
                    format!(
                        "the {} engine's snapshots carry no particles: the statistics need \
                         particles with velocities (engines whose snapshots carry them: {})",
                        engine.name,
                        registry::engines_analysed_by(|a| a.supports_statistics())
                    ),
                ));
            }
            st.validate().map_err(|(key, m)| {
                (
                    "statistics",
                    format!("{key}: {m}; keys: {}", crate::analysis::statistics::KEYS),
                )
            })?;
            if let Some(w) = st.window
                && w > length
            {
                return Err((
                    "statistics",
                    format!(
                        "window = {w} is out of range: allowed 0 < window <= {} ({length}), in {}",
                        clock.key(),
                        clock.key()
                    ),
                ));
            }
        }
        if self.checkpoint_every == 0 {
            return Err((
                "checkpoint_every",
                "0 is out of range: allowed a whole number >= 1 (snapshots between checkpoints)"
                    .into(),
            ));
        }
        self.validate_milestones(engine)
    }

    /// Milestones need the structure analysis (its records carry both clocks); readings finite,
    /// > 0 and increasing; a window of 1 to 1000 snapshots.
    fn validate_milestones(&self, engine: &EngineDef) -> Result<(), (&'static str, String)> {
        let given = self.milestones.is_some() || self.milestone_every.is_some();
        if !given {
            for (key, set) in [
                ("milestone_clock", self.milestone_clock.is_some()),
                ("milestone_window", self.milestone_window.is_some()),
            ] {
                if set {
                    return Err((
                        key,
                        "given without `milestones` or `milestone_every`".into(),
                    ));
                }
            }
            return Ok(());
        }
        if registry::analysis_of(engine) != crate::analysis::AnalysisKind::Structure {
            return Err((
                "milestones",
                format!(
                    "the {} engine's analysis records no structure at milestones (only engines with the structure analysis do: {})",
                    engine.name,
                    registry::engines_analysed_by(|a| a == crate::analysis::AnalysisKind::Structure)
                ),
            ));
        }
        if let Some(clock) = self.milestone_clock
            && clock == Clock::Steps
        {
            return Err((
                "milestone_clock",
                "\"steps\": allowed \"collisions_per_particle\" or \"time\"".into(),
            ));
        }
        if let Some(list) = &self.milestones {
            if list.is_empty() {
                return Err(("milestones", "empty: give at least one reading".into()));
            }
            for (i, &m) in list.iter().enumerate() {
                if !(m.is_finite() && m > 0.0) {
                    return Err((
                        "milestones",
                        format!("{m} is out of range: allowed finite readings > 0"),
                    ));
                }
                if i > 0 && m <= list[i - 1] {
                    return Err((
                        "milestones",
                        format!(
                            "{m} follows {}: give the readings in increasing order",
                            list[i - 1]
                        ),
                    ));
                }
            }
        }
        if let Some(every) = self.milestone_every
            && !(every.is_finite() && every > 0.0)
        {
            return Err((
                "milestone_every",
                format!("{every} is out of range: allowed a finite reading > 0"),
            ));
        }
        if let Some(w) = self.milestone_window
            && !(1..=1000).contains(&w)
        {
            return Err((
                "milestone_window",
                format!("{w} is out of range: allowed 1 to 1000 snapshots"),
            ));
        }
        Ok(())
    }

    /// The milestone plan of this run for `engine` (None without milestones).
    pub fn milestone_plan(
        &self,
        engine: &EngineDef,
    ) -> Option<crate::analysis::milestones::MilestonePlan> {
        if self.milestones.is_none() && self.milestone_every.is_none() {
            return None;
        }
        let clock =
            self.milestone_clock
                .unwrap_or(if engine.has_clock(Clock::CollisionsPerParticle) {
                    Clock::CollisionsPerParticle
                } else {
                    self.clock()
                });
        Some(crate::analysis::milestones::MilestonePlan {
            clock,
            readings: self.milestones.clone().unwrap_or_default(),
            every: self.milestone_every.unwrap_or(0.0),
            window: self.milestone_window.unwrap_or(DEFAULT_MILESTONE_WINDOW) as usize,
        })
    }

    /// Whether a run at `progress` has passed its last listed milestone (runs until steady
    /// decide only after it; true without listed milestones).
    pub fn past_milestones(&self, engine: &EngineDef, progress: &crate::engine::Progress) -> bool {
        match (self.milestone_plan(engine), &self.milestones) {
            (Some(plan), Some(list)) => list
                .last()
                .is_none_or(|&last| progress.on(plan.clock) >= last),
            _ => true,
        }
    }

    /// Number of snapshots after the initial one: ceil(run length / interval).
    pub fn snapshot_count(&self) -> u32 {
        (self.length() / self.snapshot_interval).ceil() as u32
    }

    /// The clock reading of snapshot k (k = 0 is the initial state).
    pub fn snapshot_target(&self, k: u32) -> f64 {
        (k as f64 * self.snapshot_interval).min(self.length())
    }
}

/// Everything that defines one job, resolved (defaults filled in, derived values computed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobParams {
    /// the engine name (a name of the registry)
    pub engine: String,
    /// every declared parameter of the engine by name, resolved (derived ones included)
    pub values: Values,
    /// seed of the engine's RNG
    pub seed: u64,
    /// run length and snapshots
    pub run: RunSettings,
    /// the analysis settings, resolved (all keys)
    pub analysis: Value,
}

/// A job's id: 16 hex digits of the SHA-256 of its canonical parameters.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct JobId(pub String);

impl fmt::Display for JobId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl JobParams {
    /// The engine's declaration (the registry holds every engine a valid job can name).
    pub fn def(&self) -> &'static EngineDef {
        registry::find(&self.engine).expect("a job names a registered engine")
    }

    /// Value of a numeric parameter (NaN when it is absent or a name).
    pub fn get(&self, name: &str) -> f64 {
        self.values
            .get(name)
            .and_then(ParamValue::as_f64)
            .unwrap_or(f64::NAN)
    }

    /// The job's size as its engine counts it (N for particle engines).
    pub fn size(&self) -> f64 {
        (self.def().size)(&self.values)
    }

    /// Build the job's engine in its initial state.
    pub fn build_engine(&self) -> Result<Box<dyn crate::engine::Engine>, EngineError> {
        (self.def().build)(&self.values, self.seed)
    }

    /// Estimated work of the job in its engine's work units (the sort key of the pool).
    pub fn estimated_work(&self) -> f64 {
        (self.def().work)(&self.values, self.run.clock(), self.run.length())
    }

    /// The canonical text that the id hashes (see the module docs).
    pub fn canonical(&self) -> String {
        canonical_with(self.def().params, self)
    }

    /// The job id.
    pub fn id(&self) -> JobId {
        id_of_canonical(&self.canonical())
    }

    /// The analysis of this job's engine with the job's settings, the run's milestones and its
    /// statistics, when the run asks for them.
    pub fn analyser(&self) -> Result<crate::analysis::Analyser, crate::analysis::AnalysisError> {
        let mut analyser = registry::analysis_of(self.def()).analyser(&self.analysis)?;
        if let crate::analysis::Analyser::Structure(settings) = &mut analyser {
            settings.milestones = self.run.milestone_plan(self.def());
        }
        Ok(match &self.run.statistics {
            Some(s) => analyser.with_statistics(StatisticsPlan::for_run(
                s.clone(),
                self.run.clock(),
                self.run.length(),
                self.run.until_steady.is_some(),
            )),
            None => analyser,
        })
    }
}

/// The canonical form over a given parameter table (the table is an argument so that tests can
/// show that extending it leaves ids unchanged).
pub fn canonical_with(table: &[ParamDef], job: &JobParams) -> String {
    let mut params = BTreeMap::new();
    for def in table {
        let Some(v) = job.values.get(def.name) else {
            continue;
        };
        let keep = match def.in_id {
            InId::Always => true,
            InId::AwayFromDefault => def.default.value().as_ref() != Some(v),
            InId::Never => false,
        };
        if keep {
            params.insert(def.name.to_string(), param_json(v));
        }
    }
    let defaults = registry::find(&job.engine)
        .map(|e| registry::analysis_of(e).default_settings())
        .unwrap_or(Value::Null);
    let mut analysis = BTreeMap::new();
    if let Value::Object(now) = &job.analysis {
        for (k, v) in now {
            if defaults.get(k) != Some(v) {
                analysis.insert(k.clone(), v.clone());
            }
        }
    }
    let mut run = BTreeMap::new();
    run.insert(job.run.clock().key().to_string(), number(job.run.length()));
    run.insert(
        "snapshot_interval".to_string(),
        number(job.run.snapshot_interval),
    );
    if let Some(u) = &job.run.until_steady {
        let rule: serde_json::Map<String, Value> = [("window".to_string(), number(u.window))]
            .into_iter()
            .collect();
        run.insert("until_steady".to_string(), Value::Object(rule));
    }
    if let Some(s) = &job.run.statistics {
        run.insert("statistics".to_string(), Value::Object(s.non_default()));
    }
    let mut top = BTreeMap::new();
    top.insert(
        "analysis".to_string(),
        Value::Object(analysis.into_iter().collect()),
    );
    top.insert("engine".to_string(), Value::String(job.engine.clone()));
    top.insert(
        "params".to_string(),
        Value::Object(params.into_iter().collect()),
    );
    top.insert("run".to_string(), Value::Object(run.into_iter().collect()));
    top.insert("seed".to_string(), Value::from(job.seed));
    let mut out = String::new();
    write_canonical(&Value::Object(top.into_iter().collect()), &mut out);
    out
}

fn param_json(v: &ParamValue) -> Value {
    match v {
        ParamValue::Number(x) => number(*x),
        ParamValue::Text(s) => Value::String(s.clone()),
    }
}

/// The id of a canonical text: the first 16 hex digits of its SHA-256.
pub fn id_of_canonical(canonical: &str) -> JobId {
    let digest = Sha256::digest(canonical.as_bytes());
    JobId(crate::provenance::hex(&digest[..8]))
}

fn number(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// Compact JSON with object keys sorted, whatever map type serde_json was built with.
fn write_canonical(v: &Value, out: &mut String) {
    match v {
        Value::Object(map) => {
            let sorted: BTreeMap<&String, &Value> = map.iter().collect();
            out.push('{');
            for (i, (k, v)) in sorted.into_iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String(k.clone()).to_string());
                out.push(':');
                write_canonical(v, out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                write_canonical(item, out);
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}
