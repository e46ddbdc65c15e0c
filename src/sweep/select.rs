//! Selection of jobs by parameter: `--where restitution=0.7`, `--where width_over_diameter>=30`,
//! `--where wall_model!=adiabatic`. Several conditions must all hold. Keys are the engine's
//! parameters and `seed`; numbers compare as numbers, names as names.

use super::BadInput;
use super::grid::PlannedJob;
use crate::engine::{EngineDef, ParamValue};

/// A comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// One condition `key op value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    pub key: String,
    pub op: Op,
    pub value: ParamValue,
}

/// Parse `key op value` against the engine's parameters (`seed` too). Errors name the
/// condition and what is allowed.
pub fn parse(text: &str, engine: &EngineDef) -> Result<Condition, BadInput> {
    // two-character operators first
    let ops = [
        (">=", Op::Ge),
        ("<=", Op::Le),
        ("!=", Op::Ne),
        ("==", Op::Eq),
        ("=", Op::Eq),
        (">", Op::Gt),
        ("<", Op::Lt),
    ];
    let Some((at, sym, op)) = ops
        .iter()
        .filter_map(|(sym, op)| text.find(sym).map(|at| (at, *sym, *op)))
        .min_by_key(|(at, sym, _)| (*at, std::cmp::Reverse(sym.len())))
    else {
        return Err(BadInput(format!(
            "--where {text}: expected KEY=VALUE, KEY!=VALUE, KEY<VALUE, KEY<=VALUE, KEY>VALUE or KEY>=VALUE"
        )));
    };
    let key = text[..at].trim();
    let raw = text[at + sym.len()..].trim();
    let value = if key == "seed" {
        raw.parse::<f64>()
            .map(ParamValue::Number)
            .map_err(|_| BadInput(format!("--where {text}: `{raw}` is not a seed")))?
    } else {
        let def = engine.param(key).ok_or_else(|| {
            BadInput(format!(
                "--where {text}: `{key}` is not a parameter of the {} engine; allowed: seed, {}",
                engine.name,
                engine.param_names()
            ))
        })?;
        def.parse_text(raw)
            .map_err(|m| BadInput(format!("--where {text}: {m}")))?
    };
    if matches!(value, ParamValue::Text(_)) && !matches!(op, Op::Eq | Op::Ne) {
        return Err(BadInput(format!(
            "--where {text}: names compare with = and != only"
        )));
    }
    Ok(Condition {
        key: key.to_string(),
        op,
        value,
    })
}

impl Condition {
    /// Whether a job meets the condition (a job without the key never does).
    pub fn holds(&self, job: &PlannedJob) -> bool {
        let seed = ParamValue::Number(job.params.seed as f64);
        let have = if self.key == "seed" {
            Some(&seed)
        } else {
            job.params.values.get(&self.key)
        };
        let Some(have) = have else {
            return false;
        };
        match (have, &self.value) {
            (ParamValue::Number(a), ParamValue::Number(b)) => match self.op {
                Op::Eq => a == b,
                Op::Ne => a != b,
                Op::Lt => a < b,
                Op::Le => a <= b,
                Op::Gt => a > b,
                Op::Ge => a >= b,
            },
            (ParamValue::Text(a), ParamValue::Text(b)) => match self.op {
                Op::Eq => a == b,
                Op::Ne => a != b,
                _ => false,
            },
            _ => false,
        }
    }
}

/// Keep the jobs that meet every condition (parsed from `texts`); the plan indices stay those
/// of the whole plan.
pub fn retain(
    plan: &mut Vec<PlannedJob>,
    texts: &[String],
    engine: &EngineDef,
) -> Result<(), BadInput> {
    let conditions = texts
        .iter()
        .map(|t| parse(t, engine))
        .collect::<Result<Vec<_>, _>>()?;
    plan.retain(|j| conditions.iter().all(|c| c.holds(j)));
    Ok(())
}
