//! Grid expansion: a validated sweep spec becomes the ordered list of jobs (the plan).
//!
//! Plan order (relied on by `--job-range`): the grid first, as the cartesian product of the
//! axes in the order of the engine's parameter declaration with the last axis varying fastest
//! and seeds innermost; then the extra points in file order, each once per seed.

use super::job::{JobId, JobParams};
use super::spec::{Source, SpecError, SweepSpec, engine_of};
use crate::engine::{EngineDef, ParamValue, Values};
use std::collections::HashMap;

/// One job of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedJob {
    /// position in the plan order (0-based)
    pub index: usize,
    /// the job id (hash of the canonical parameters)
    pub id: JobId,
    /// resolved parameters
    pub params: JobParams,
    /// the parameters its sweep varies (filled by [`super::load_sweep`]; a job's figures name
    /// them with the chosen values, never as "at their defaults")
    pub swept: Vec<&'static str>,
    /// its refinement level: 0 on the base grid, `k` for a point added by refinement at
    /// 1/2^k of the base spacing (see [`super::refine`])
    pub level: u32,
}

/// Where a set of values came from, for error messages.
#[derive(Clone, Copy)]
enum From {
    Grid,
    Point(usize),
}

/// Put `value` for `key` into `values`, replacing `key`'s alternatives (a point's N replaces
/// the fixed phi).
fn put(values: &mut Values, alternatives: &[&str], key: &str, value: ParamValue) {
    for alt in alternatives {
        values.remove(*alt);
    }
    values.insert(key.to_string(), value);
}

/// The most memory one job may need, in bytes: `GRANFLOW_MAX_JOB_MEMORY_GB` if set, else the
/// machine's memory (Linux: MemTotal of /proc/meminfo; elsewhere 64 GB).
pub fn job_memory_limit() -> f64 {
    if let Some(gb) = std::env::var("GRANFLOW_MAX_JOB_MEMORY_GB")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        return gb * 1e9;
    }
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(64e9, |kb| kb * 1024.0)
}

/// Refuse a job whose estimated memory exceeds [`job_memory_limit`], saying how much it needs.
pub fn check_job_memory(engine: &EngineDef, values: &Values) -> Result<(), String> {
    let memory = (engine.memory)(values);
    let limit = job_memory_limit();
    if memory > limit {
        return Err(format!(
            "a job needs about {:.0} GB of memory ({} = {:.3e}), more than the limit of {:.1} GB \
             (the machine's memory; set GRANFLOW_MAX_JOB_MEMORY_GB to change it)",
            memory / 1e9,
            engine.size_name,
            (engine.size)(values),
            limit / 1e9
        ));
    }
    Ok(())
}

/// Most jobs one sweep may plan: a plan holds every job's parameters in memory (a few kB each)
/// and every job gets a directory, so a grid whose axes multiply past this is refused before
/// it is expanded.
pub const MAX_JOBS: usize = 100_000;

/// A count as people write it: digits in groups of three (`1 000 000`); beyond 10^15 in
/// scientific notation.
pub fn grouped(n: f64) -> String {
    if n >= 1e15 {
        return format!("{n:.3e}");
    }
    let digits = format!("{n:.0}");
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// Refuse a sweep whose plan would exceed [`MAX_JOBS`], naming each axis with its length and
/// the product, before anything is expanded (a product of three 1000-value ranges is 10^9
/// jobs: expanding it would take minutes and gigabytes).
fn check_plan_size(spec: &SweepSpec, engine: &EngineDef, src: &Source) -> Result<(), SpecError> {
    let axes: Vec<(&str, usize)> = engine
        .params
        .iter()
        .filter_map(|d| spec.axes.0.get(d.name).map(|v| (d.name, v.len())))
        .collect();
    let grid: f64 = axes.iter().map(|(_, n)| *n as f64).product();
    let seeds = spec.seeds.len() as f64;
    let jobs = (grid + spec.points.len() as f64) * seeds;
    if jobs <= MAX_JOBS as f64 {
        return Ok(());
    }
    let lengths: Vec<String> = axes.iter().map(|(_, n)| grouped(*n as f64)).collect();
    let names: Vec<&str> = axes.iter().map(|(name, _)| *name).collect();
    let points = if spec.points.is_empty() {
        String::new()
    } else {
        format!(" + {} extra points", spec.points.len())
    };
    Err(src.error_at(
        None,
        "axes",
        0,
        format!(
            "the axes multiply to {} = {} grid points ({}){points}, x {} = {} jobs: \
             allowed at most {} jobs in one sweep; take fewer values, or split the sweep \
             into several files",
            lengths.join(" x "),
            grouped(grid),
            names.join(" x "),
            if spec.seeds.len() == 1 {
                "1 seed".to_string()
            } else {
                format!("{} seeds", spec.seeds.len())
            },
            grouped(jobs),
            grouped(MAX_JOBS as f64)
        ),
    ))
}

/// Expand a validated spec into the plan.
pub(crate) fn expand(spec: &SweepSpec, src: &Source) -> Result<Vec<PlannedJob>, SpecError> {
    let engine = engine_of(spec).expect("validated: the engine exists");
    check_plan_size(spec, engine, src)?;
    let analyser = crate::registry::analysis_of(engine)
        .analyser(&spec.analysis)
        .map_err(|m| src.error_at(None, "analysis", 0, m.to_string()))?;
    let analysis = analyser.settings();
    let fixed = &spec.fixed.0;
    let axes: Vec<(&str, &Vec<ParamValue>)> = engine
        .params
        .iter()
        .filter_map(|d| spec.axes.0.get(d.name).map(|v| (d.name, v)))
        .collect();
    let mut points: Vec<(From, Values)> = Vec::new();
    let combos: usize = axes.iter().map(|(_, v)| v.len()).product();
    for mut i in 0..combos {
        let mut values = fixed.clone();
        let mut picks = vec![None; axes.len()];
        for (k, (_, vals)) in axes.iter().enumerate().rev() {
            picks[k] = Some(vals[i % vals.len()].clone());
            i /= vals.len();
        }
        for (k, (name, _)) in axes.iter().enumerate() {
            values.insert(name.to_string(), picks[k].take().expect("picked"));
        }
        points.push((From::Grid, values));
    }
    for (i, point) in spec.points.iter().enumerate() {
        let mut values = fixed.clone();
        for (k, v) in &point.0 {
            put(&mut values, &engine.alternatives_of(k), k, v.clone());
        }
        points.push((From::Point(i), values));
    }
    let mut plan = Vec::new();
    let mut seen: HashMap<JobId, usize> = HashMap::new();
    for (from, mut values) in points {
        let at = |key: &str, message: String| match from {
            From::Grid => {
                let section = if spec.axes.0.contains_key(key) {
                    Some("axes")
                } else if spec.fixed.0.contains_key(key) {
                    Some("fixed")
                } else if spec.linked.iter().any(|l| l.param == key) {
                    Some("linked")
                } else {
                    None
                };
                match section {
                    Some(s) => src.error_at(Some(s), key, 0, message),
                    None => src.error_at(None, "fixed", 0, message),
                }
            }
            From::Point(i) => {
                src.error_at(None, "points", 0, format!("point {}: {message}", i + 1))
            }
        };
        for link in &spec.linked {
            let explicit =
                matches!(from, From::Point(i) if spec.points[i].0.contains_key(&link.param));
            if !explicit
                && let Some(followed) = values.get(&link.follows).and_then(ParamValue::as_f64)
            {
                put(
                    &mut values,
                    &engine.alternatives_of(&link.param),
                    &link.param,
                    ParamValue::Number(link.factor * followed),
                );
            }
        }
        let values = engine
            .resolve_values(&values)
            .map_err(|p| at(&p.key, super::readable::readable_numbers(&p.message)))?;
        check_job_memory(engine, &values).map_err(|m| at("fixed", m))?;
        let probe = JobParams {
            engine: spec.engine.clone(),
            values,
            seed: 0,
            run: spec.run.clone(),
            analysis: analysis.clone(),
        };
        for &seed in &spec.seeds {
            let params = JobParams {
                seed,
                ..probe.clone()
            };
            let id = params.id();
            if let Some(&other) = seen.get(&id) {
                let first = engine.params.first().map_or("fixed", |d| d.name);
                return Err(at(
                    first,
                    format!(
                        "duplicate point: it resolves to the same job ({id}, seed {seed}) as job {} of the plan; \
                         each point may appear once",
                        other
                    ),
                ));
            }
            seen.insert(id.clone(), plan.len());
            plan.push(PlannedJob {
                index: plan.len(),
                id,
                params,
                swept: Vec::new(),
                level: 0,
            });
        }
    }
    Ok(plan)
}
