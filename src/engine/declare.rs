//! The shape of an engine declaration ([`EngineDef`]): name, parameters ([`ParamDef`]: symbol,
//! unit, default, allowed range, doc, place in the job id), derived quantities, clocks, work and
//! memory estimates, counters, how to build and restore it (which analysis its snapshots feed
//! is said by `crate::registry`, which pairs them). Sweep files, validation, `--set`, `plan`, job ids, tables, `sim` flags and the
//! parameter tables are all generated from these declarations.

use super::{Engine, EngineError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// A parameter's value: a number (whole numbers too) or, for choices, a name.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ParamValue {
    Number(f64),
    Text(String),
}

impl<'de> Deserialize<'de> for ParamValue {
    /// A number or a name; anything else (a list where one value belongs, a map) is refused
    /// with what to write instead.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = ParamValue;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("one value: a number or a name in quotes")
            }
            fn visit_f64<E>(self, v: f64) -> Result<ParamValue, E> {
                Ok(ParamValue::Number(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<ParamValue, E> {
                Ok(ParamValue::Number(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<ParamValue, E> {
                Ok(ParamValue::Number(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<ParamValue, E> {
                Ok(ParamValue::Text(v.to_string()))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, _: A) -> Result<ParamValue, A::Error> {
                Err(serde::de::Error::custom(
                    "a list where one value belongs: give a single value here; to sweep a \
                     parameter, list its values under `axes`",
                ))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, _: A) -> Result<ParamValue, A::Error> {
                Err(serde::de::Error::custom(
                    "a structure where one value belongs: give a number or a name in quotes",
                ))
            }
        }
        d.deserialize_any(Visit)
    }
}

impl ParamValue {
    /// The number (None for a name).
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Number(v) => Some(*v),
            ParamValue::Text(_) => None,
        }
    }

    /// The name (None for a number).
    pub fn as_text(&self) -> Option<&str> {
        match self {
            ParamValue::Text(s) => Some(s),
            ParamValue::Number(_) => None,
        }
    }
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Number(v) => write!(f, "{v}"),
            ParamValue::Text(s) => write!(f, "\"{s}\""),
        }
    }
}

/// Parameter values by name (a job's resolved parameters, a sweep's fixed section or point).
pub type Values = BTreeMap<String, ParamValue>;

/// What kind of value a parameter takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// a finite real number
    Real,
    /// a whole number
    Integer,
    /// one of these names
    Choice(&'static [&'static str]),
}

/// A parameter's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamDefault {
    /// the sweep must give it
    Required,
    /// may be left out; the engine's `resolve` derives it (or asks for an alternative)
    Derived,
    /// this number
    Number(f64),
    /// this name (choices)
    Text(&'static str),
}

impl ParamDefault {
    /// The default as a value, when there is one.
    pub fn value(&self) -> Option<ParamValue> {
        match self {
            ParamDefault::Number(v) => Some(ParamValue::Number(*v)),
            ParamDefault::Text(s) => Some(ParamValue::Text((*s).to_string())),
            ParamDefault::Required | ParamDefault::Derived => None,
        }
    }
}

/// Whether a parameter enters the job id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InId {
    /// always, with its resolved value (the parameters of an engine's first id scheme)
    Always,
    /// only where it differs from its default (parameters added later: old ids stay valid)
    AwayFromDefault,
    /// never (it follows from others, e.g. phi from N and the box)
    Never,
}

/// One parameter of an engine.
#[derive(Clone, Copy, Debug)]
pub struct ParamDef {
    /// the key in sweep files, `--set`, tables and `sim --<key>` (with - for _)
    pub name: &'static str,
    /// the physics symbol
    pub symbol: &'static str,
    /// unit ("1" for dimensionless)
    pub unit: &'static str,
    pub kind: ParamKind,
    pub default: ParamDefault,
    /// the allowed range, as told to the user
    pub allowed: &'static str,
    /// the range check of a number (finiteness is checked before)
    pub check: fn(f64) -> bool,
    /// one line for the parameter table
    pub doc: &'static str,
    pub in_id: InId,
}

/// A parameter value that is not allowed: which key and why (the caller adds where).
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// the parameter concerned
    pub key: String,
    pub message: String,
}

impl Problem {
    pub fn new(key: &str, message: impl Into<String>) -> Self {
        Problem {
            key: key.to_string(),
            message: message.into(),
        }
    }
}

impl ParamDef {
    /// Check one value against kind and range; the message names the parameter, the value
    /// and what is allowed.
    pub fn check_value(&self, value: &ParamValue) -> Result<(), String> {
        let out_of_range = |v: &dyn fmt::Display| {
            format!(
                "{} ({}) = {v} is out of range: allowed {}",
                self.name, self.symbol, self.allowed
            )
        };
        match (self.kind, value) {
            (ParamKind::Choice(choices), ParamValue::Text(s)) => {
                if choices.contains(&s.as_str()) {
                    Ok(())
                } else {
                    Err(format!(
                        "{} = \"{s}\" is not one of {}",
                        self.name,
                        quoted(choices)
                    ))
                }
            }
            (ParamKind::Choice(choices), ParamValue::Number(v)) => Err(format!(
                "{} = {v}: expected a name, one of {}",
                self.name,
                quoted(choices)
            )),
            (_, ParamValue::Text(s)) => Err(format!(
                "{} = \"{s}\": expected a number; allowed {}",
                self.name, self.allowed
            )),
            (kind, ParamValue::Number(v)) => {
                if !v.is_finite() {
                    return Err(format!(
                        "{} ({}) = {v} is not a finite number: allowed {}",
                        self.name, self.symbol, self.allowed
                    ));
                }
                if kind == ParamKind::Integer && v.fract() != 0.0 {
                    return Err(format!(
                        "{} ({}) = {v} is not a whole number: allowed {}",
                        self.name, self.symbol, self.allowed
                    ));
                }
                if (self.check)(*v) {
                    Ok(())
                } else {
                    Err(out_of_range(v))
                }
            }
        }
    }

    /// The value as the user would write it in a sweep file.
    pub fn parse_text(&self, text: &str) -> Result<ParamValue, String> {
        match self.kind {
            ParamKind::Choice(_) => Ok(ParamValue::Text(text.trim_matches('"').to_string())),
            _ => text
                .parse::<f64>()
                .map(ParamValue::Number)
                .map_err(|_| format!("`{text}` is not a number; allowed {}", self.allowed)),
        }
    }
}

fn quoted(choices: &[&str]) -> String {
    choices
        .iter()
        .map(|c| format!("\"{c}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A clock that drives a run: the unit of run lengths and snapshot intervals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Clock {
    /// collisions per particle, 2 x pair collisions / N (the 2008 thesis' clock)
    CollisionsPerParticle,
    /// time steps of a stepped engine
    Steps,
    /// simulated time
    Time,
}

impl Clock {
    /// Every clock, in the order the `run` section lists them.
    pub const ALL: [Clock; 3] = [Clock::CollisionsPerParticle, Clock::Steps, Clock::Time];

    /// The key of a run length on this clock in sweep files (`run: (steps: ...)`).
    pub fn key(self) -> &'static str {
        match self {
            Clock::CollisionsPerParticle => "collisions_per_particle",
            Clock::Steps => "steps",
            Clock::Time => "time",
        }
    }

    /// A short unit for progress lines.
    pub fn unit(self) -> &'static str {
        match self {
            Clock::CollisionsPerParticle => "cpp",
            Clock::Steps => "steps",
            Clock::Time => "t",
        }
    }

    /// The clock with this key.
    pub fn from_key(key: &str) -> Option<Clock> {
        Clock::ALL.into_iter().find(|c| c.key() == key)
    }
}

/// One counter an engine keeps.
#[derive(Clone, Copy, Debug)]
pub struct CounterDef {
    pub name: &'static str,
    pub doc: &'static str,
}

/// A ratio of two counters reported per job (e.g. the TC-elastic fraction).
#[derive(Clone, Copy, Debug)]
pub struct RatioDef {
    pub name: &'static str,
    pub numerator: &'static str,
    pub denominator: &'static str,
    pub doc: &'static str,
}

/// A built or restored engine.
pub type BuiltEngine = Result<Box<dyn Engine>, EngineError>;

/// Refuse a checkpoint payload of another layout version than the one this build reads
/// (`what`: the engine as a reader names it, e.g. "DSMC").
pub fn check_payload_version(what: &str, version: u32, reads: u32) -> Result<(), EngineError> {
    if version == reads {
        Ok(())
    } else {
        Err(EngineError::Checkpoint(format!(
            "{what} payload version {version}, this granflow reads version {reads}"
        )))
    }
}

/// Everything the rest of granflow needs to know about an engine, declared once.
pub struct EngineDef {
    /// the name in sweep files (`engine: "edmd"`) and checkpoints (at most 7 letters/digits)
    pub name: &'static str,
    /// one line: what it simulates and after whom
    pub title: &'static str,
    /// physics version: bump it when a change of the engine changes trajectories (results of
    /// older versions are then flagged as outdated; their ids stay)
    pub version: u32,
    /// the parameters, in expansion order (the last swept one varies fastest)
    pub params: &'static [ParamDef],
    /// groups of parameters of which at most one may be given (each derives the others, like
    /// phi and N): a later source (a point over `fixed`, `--set` over the file) replaces the
    /// whole group, and one source giving two of them is an error
    pub alternatives: &'static [&'static [&'static str]],
    /// the clocks a run length may use; the first is the default
    pub clocks: &'static [Clock],
    /// fill in derived parameters (e.g. N from phi and phi from N) and check what depends on
    /// several parameters (e.g. that phi can be placed in the box). Every declared parameter
    /// with a default is already present.
    pub resolve: fn(&mut Values) -> Result<(), Problem>,
    /// a fresh engine from resolved values and a seed
    pub build: fn(&Values, u64) -> BuiltEngine,
    /// an engine from a checkpoint payload of the given format version
    pub restore: fn(u32, &[u8]) -> BuiltEngine,
    /// what a job's size is called in `plan` and progress lines ("N", "sites")
    pub size_name: &'static str,
    /// the job's size (particles, sites) from resolved values
    pub size: fn(&Values) -> f64,
    /// estimated work of a run of `length` on `clock`, in `work_unit`s (the pool's sort key
    /// and `plan`'s estimate)
    pub work: fn(&Values, Clock, f64) -> f64,
    pub work_unit: &'static str,
    /// typical work units per second on one core for a job of these resolved values (for
    /// `plan`'s time estimate before any job of the sweep has run)
    pub work_rate: fn(&Values) -> f64,
    /// estimated memory of one running job, in bytes
    pub memory: fn(&Values) -> f64,
    /// the counters, in the order snapshots and tables list them
    pub counters: &'static [CounterDef],
    /// counter ratios reported per job
    pub ratios: &'static [RatioDef],
    /// values of the required parameters for `granflow sim` without flags (as text)
    pub example: &'static [(&'static str, &'static str)],
    /// run of `granflow sim` without a length: clock, length, report interval
    pub example_run: (Clock, f64, f64),
}

impl EngineDef {
    /// The declaration of a parameter.
    pub fn param(&self, name: &str) -> Option<&'static ParamDef> {
        self.params.iter().find(|d| d.name == name)
    }

    /// The parameter names, comma separated (for error messages).
    pub fn param_names(&self) -> String {
        self.params
            .iter()
            .map(|d| d.name)
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Whether runs may be measured on `clock`.
    pub fn has_clock(&self, clock: Clock) -> bool {
        self.clocks.contains(&clock)
    }

    /// The alternatives of `key` (the other members of its group), if it is in one.
    pub fn alternatives_of(&self, key: &str) -> Vec<&'static str> {
        self.alternatives
            .iter()
            .filter(|g| g.contains(&key))
            .flat_map(|g| g.iter().copied().filter(|k| *k != key))
            .collect()
    }

    /// The clock keys, comma separated.
    pub fn clock_names(&self) -> String {
        self.clocks
            .iter()
            .map(|c| c.key())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The error for a clock this engine does not have.
    pub fn clock_error(&self, clock: Clock) -> EngineError {
        EngineError::Clock {
            engine: self.name,
            clock: clock.key(),
            allowed: self.clock_names(),
        }
    }

    /// Fill in defaults, check every value, then derive and cross-check (`resolve`).
    pub fn resolve_values(&self, given: &Values) -> Result<Values, Problem> {
        let mut values = given.clone();
        for (key, value) in &values {
            let def = self.param(key).ok_or_else(|| {
                Problem::new(key, format!("not a parameter of the {} engine", self.name))
            })?;
            def.check_value(value).map_err(|m| Problem::new(key, m))?;
        }
        for def in self.params {
            if !values.contains_key(def.name) {
                match def.default.value() {
                    Some(v) => {
                        values.insert(def.name.to_string(), v);
                    }
                    None if def.default == ParamDefault::Required => {
                        return Err(Problem::new(
                            def.name,
                            format!(
                                "`{}` ({}) is not given: set it in `fixed`, `axes`, `linked` or every point",
                                def.name, def.symbol
                            ),
                        ));
                    }
                    None => {}
                }
            }
        }
        for group in self.alternatives {
            let present: Vec<&str> = group
                .iter()
                .copied()
                .filter(|k| given.contains_key(*k))
                .collect();
            if present.len() > 1 {
                return Err(Problem::new(
                    present[1],
                    format!(
                        "`{}` and `{}` are both given: each follows from the other, give one",
                        present[0], present[1]
                    ),
                ));
            }
        }
        (self.resolve)(&mut values)?;
        Ok(values)
    }

    /// The parameter table of this engine in docs/parameters.md (markdown), generated from the declaration.
    pub fn markdown_table(&self) -> String {
        let mut out = String::from(
            "| key | symbol | unit | default | allowed | meaning |\n| --- | --- | --- | --- | --- | --- |\n",
        );
        for d in self.params {
            let default = match d.default {
                ParamDefault::Required => "required".to_string(),
                ParamDefault::Derived => "derived".to_string(),
                ParamDefault::Number(v) => format!("{v}"),
                ParamDefault::Text(s) => format!("\"{s}\""),
            };
            out.push_str(&format!(
                "| `{}` | {} | {} | {} | {} | {} |\n",
                d.name, d.symbol, d.unit, default, d.allowed, d.doc
            ));
        }
        out
    }
}

impl fmt::Debug for EngineDef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "EngineDef({})", self.name)
    }
}

impl PartialEq for EngineDef {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

/// Range checks shared by declarations.
pub mod ranges {
    pub fn positive(v: f64) -> bool {
        v > 0.0
    }
    pub fn non_negative(v: f64) -> bool {
        v >= 0.0
    }
    pub fn unit(v: f64) -> bool {
        (0.0..=1.0).contains(&v)
    }
    pub fn signed_unit(v: f64) -> bool {
        (-1.0..=1.0).contains(&v)
    }
    pub fn any(_: f64) -> bool {
        true
    }
}
