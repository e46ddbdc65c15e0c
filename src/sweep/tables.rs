//! The Parquet tables of a results directory (written with polars): `jobs.parquet`,
//! `spectra.parquet`, `profiles.parquet`, `energy.parquet`. Columns are documented in
//! `results/README.md`. Written atomically (temp file + fsync + rename).

use super::execute::{self, JobResult};
use super::job::PARAMS;
use super::queue::{self, JobState};
use super::{Sweep, SweepDirs};
use polars::prelude::*;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// What [`gather`] wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GatherSummary {
    /// rows of jobs.parquet (every planned job)
    pub jobs: usize,
    /// of which done
    pub done: usize,
}

/// One planned job with its state and (when done) its result.
pub struct GatheredJob<'a> {
    pub job: &'a super::PlannedJob,
    pub state: JobState,
    pub result: Option<JobResult>,
}

/// Read the state and result of every job of the plan.
pub fn collect<'a>(sweep: &'a Sweep, dirs: &SweepDirs) -> Vec<GatheredJob<'a>> {
    sweep
        .plan
        .iter()
        .map(|job| {
            let dir = dirs.job_dir(&job.id);
            let mut state = queue::job_state(&dir);
            let result = if state == JobState::Done {
                match execute::read_result(&dir) {
                    Ok(r) => Some(r),
                    Err(e) => {
                        state = JobState::Failed(format!("unreadable result: {e:#}"));
                        None
                    }
                }
            } else {
                None
            };
            GatheredJob { job, state, result }
        })
        .collect()
}

/// Write the four tables of a sweep into its tables directory.
pub fn gather(sweep: &Sweep, dirs: &SweepDirs) -> anyhow::Result<GatherSummary> {
    let jobs = collect(sweep, dirs);
    std::fs::create_dir_all(&dirs.tables)?;
    write_parquet(&dirs.tables.join("jobs.parquet"), jobs_frame(&jobs)?)?;
    write_parquet(&dirs.tables.join("spectra.parquet"), spectra_frame(&jobs)?)?;
    write_parquet(
        &dirs.tables.join("profiles.parquet"),
        profiles_frame(&jobs)?,
    )?;
    write_parquet(&dirs.tables.join("energy.parquet"), energy_frame(&jobs)?)?;
    Ok(GatherSummary {
        jobs: jobs.len(),
        done: jobs.iter().filter(|j| j.result.is_some()).count(),
    })
}

fn write_parquet(path: &Path, mut df: DataFrame) -> anyhow::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        path.file_name()
            .map(|n| n.to_string_lossy())
            .unwrap_or_default(),
        std::process::id()
    ));
    {
        let file = std::fs::File::create(&tmp)?;
        ParquetWriter::new(&file)
            .with_compression(ParquetCompression::Uncompressed)
            .finish(&mut df)?;
        file.sync_all()?;
    }
    std::fs::rename(&tmp, path)?;
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// A column being built from JSON-like values; its type is fixed by the first non-null value.
enum Col {
    F64(Vec<Option<f64>>),
    I64(Vec<Option<i64>>),
    U64(Vec<Option<u64>>),
    Bool(Vec<Option<bool>>),
    Str(Vec<Option<String>>),
}

impl Col {
    fn into_column(self, name: &str) -> Column {
        let name: PlSmallStr = name.into();
        match self {
            Col::F64(v) => Column::new(name, v),
            Col::I64(v) => Column::new(name, v),
            Col::U64(v) => Column::new(name, v),
            Col::Bool(v) => Column::new(name, v),
            Col::Str(v) => Column::new(name, v),
        }
    }
}

/// Summary fields become columns by name (whatever fields the analysis reports); a field
/// that is NaN or missing is null.
fn summary_columns(jobs: &[GatheredJob]) -> Vec<(String, Col)> {
    let rows: Vec<Option<serde_json::Map<String, Value>>> = jobs
        .iter()
        .map(|j| {
            j.result
                .as_ref()
                .and_then(|r| match serde_json::to_value(&r.analysis.summary) {
                    Ok(Value::Object(m)) => Some(m),
                    _ => None,
                })
        })
        .collect();
    let mut names: Vec<String> = Vec::new();
    let mut kinds: BTreeMap<String, &'static str> = BTreeMap::new();
    for row in rows.iter().flatten() {
        for (k, v) in row {
            if !names.contains(k) {
                names.push(k.clone());
            }
            let kind = match v {
                Value::Bool(_) => "bool",
                Value::String(_) => "str",
                Value::Number(n) if n.is_u64() => "u64",
                Value::Number(n) if n.is_i64() => "i64",
                Value::Number(_) => "f64",
                _ => continue,
            };
            let entry = kinds.entry(k.clone()).or_insert(kind);
            if *entry != kind && (*entry == "u64" || *entry == "i64") && kind == "f64" {
                *entry = "f64";
            }
        }
    }
    names
        .into_iter()
        .map(|name| {
            let get = |row: &Option<serde_json::Map<String, Value>>| {
                row.as_ref().and_then(|m| m.get(&name)).cloned()
            };
            let col = match kinds.get(&name).copied().unwrap_or("f64") {
                "bool" => Col::Bool(
                    rows.iter()
                        .map(|r| get(r).and_then(|v| v.as_bool()))
                        .collect(),
                ),
                "str" => Col::Str(
                    rows.iter()
                        .map(|r| get(r).and_then(|v| v.as_str().map(str::to_string)))
                        .collect(),
                ),
                "u64" => Col::U64(
                    rows.iter()
                        .map(|r| get(r).and_then(|v| v.as_u64()))
                        .collect(),
                ),
                "i64" => Col::I64(
                    rows.iter()
                        .map(|r| get(r).and_then(|v| v.as_i64()))
                        .collect(),
                ),
                _ => Col::F64(
                    rows.iter()
                        .map(|r| get(r).and_then(|v| v.as_f64()))
                        .collect(),
                ),
            };
            (name, col)
        })
        .collect()
}

fn jobs_frame(jobs: &[GatheredJob]) -> anyhow::Result<DataFrame> {
    let n = jobs.len();
    let mut cols = vec![
        Column::new(
            "id".into(),
            jobs.iter().map(|j| j.job.id.0.clone()).collect::<Vec<_>>(),
        ),
        Column::new(
            "plan_index".into(),
            jobs.iter().map(|j| j.job.index as u64).collect::<Vec<_>>(),
        ),
        Column::new(
            "engine".into(),
            jobs.iter()
                .map(|j| j.job.params.engine.clone())
                .collect::<Vec<_>>(),
        ),
    ];
    for def in PARAMS {
        if def.integer {
            cols.push(Column::new(
                def.name.into(),
                jobs.iter()
                    .map(|j| j.job.params.get(def.name) as u64)
                    .collect::<Vec<_>>(),
            ));
        } else {
            cols.push(Column::new(
                def.name.into(),
                jobs.iter()
                    .map(|j| j.job.params.get(def.name))
                    .collect::<Vec<_>>(),
            ));
        }
    }
    cols.push(Column::new(
        "seed".into(),
        jobs.iter().map(|j| j.job.params.seed).collect::<Vec<_>>(),
    ));
    cols.push(Column::new(
        "run_length".into(),
        jobs.iter()
            .map(|j| j.job.params.run.collisions_per_particle)
            .collect::<Vec<_>>(),
    ));
    cols.push(Column::new(
        "snapshot_interval".into(),
        jobs.iter()
            .map(|j| j.job.params.run.snapshot_interval)
            .collect::<Vec<_>>(),
    ));
    cols.push(Column::new(
        "state".into(),
        jobs.iter().map(|j| j.state.name()).collect::<Vec<_>>(),
    ));
    cols.push(Column::new(
        "error".into(),
        jobs.iter()
            .map(|j| match &j.state {
                JobState::Failed(e) => Some(e.clone()),
                _ => None,
            })
            .collect::<Vec<_>>(),
    ));
    // a summary field that repeats a job column (e.g. `particles`) is left out: the job
    // column is the authority, and a table cannot hold two columns of one name
    for (name, col) in summary_columns(jobs) {
        if !cols.iter().any(|c| c.name().as_str() == name) {
            cols.push(col.into_column(&name));
        }
    }
    let r = |f: &dyn Fn(&JobResult) -> u64| -> Vec<Option<u64>> {
        jobs.iter().map(|j| j.result.as_ref().map(f)).collect()
    };
    let rf = |f: &dyn Fn(&JobResult) -> f64| -> Vec<Option<f64>> {
        jobs.iter().map(|j| j.result.as_ref().map(f)).collect()
    };
    cols.push(Column::new(
        "pair_collisions".into(),
        r(&|x| x.counters.pair_collisions),
    ));
    cols.push(Column::new(
        "wall_collisions".into(),
        r(&|x| x.counters.wall_collisions),
    ));
    cols.push(Column::new(
        "cell_crossings".into(),
        r(&|x| x.counters.cell_crossings),
    ));
    cols.push(Column::new(
        "tc_elastic_collisions".into(),
        r(&|x| x.counters.tc_elastic_collisions),
    ));
    cols.push(Column::new("events".into(), r(&|x| x.counters.events)));
    cols.push(Column::new(
        "tc_elastic_fraction".into(),
        rf(&|x| x.counters.tc_elastic_collisions as f64 / x.counters.pair_collisions.max(1) as f64),
    ));
    cols.push(Column::new(
        "collisions_per_particle".into(),
        rf(&|x| x.collisions_per_particle),
    ));
    cols.push(Column::new("time".into(), rf(&|x| x.time)));
    cols.push(Column::new("snapshots".into(), r(&|x| x.snapshots as u64)));
    cols.push(Column::new("wall_seconds".into(), rf(&|x| x.wall_seconds)));
    cols.push(Column::new(
        "events_per_second".into(),
        rf(&|x| x.events_per_second),
    ));
    Ok(DataFrame::new(n, cols)?)
}

fn spectra_frame(jobs: &[GatheredJob]) -> anyhow::Result<DataFrame> {
    let (mut id, mut plane, mut k1, mut k2, mut power) = (vec![], vec![], vec![], vec![], vec![]);
    for j in jobs {
        for row in j.result.iter().flat_map(|r| &r.analysis.spectra) {
            id.push(j.job.id.0.clone());
            plane.push(row.plane.clone());
            k1.push(row.k1);
            k2.push(row.k2);
            power.push(row.power);
        }
    }
    let n = id.len();
    Ok(DataFrame::new(
        n,
        vec![
            Column::new("job_id".into(), id),
            Column::new("plane".into(), plane),
            Column::new("k1".into(), k1),
            Column::new("k2".into(), k2),
            Column::new("power".into(), power),
        ],
    )?)
}

fn profiles_frame(jobs: &[GatheredJob]) -> anyhow::Result<DataFrame> {
    let (mut id, mut quantity, mut bin, mut y, mut value) =
        (vec![], vec![], vec![], vec![], vec![]);
    for j in jobs {
        for row in j.result.iter().flat_map(|r| &r.analysis.profiles) {
            id.push(j.job.id.0.clone());
            quantity.push(row.quantity.clone());
            bin.push(row.bin);
            y.push(row.y);
            value.push(row.value);
        }
    }
    let n = id.len();
    Ok(DataFrame::new(
        n,
        vec![
            Column::new("job_id".into(), id),
            Column::new("quantity".into(), quantity),
            Column::new("bin".into(), bin),
            Column::new("y".into(), y),
            Column::new("value".into(), value),
        ],
    )?)
}

fn energy_frame(jobs: &[GatheredJob]) -> anyhow::Result<DataFrame> {
    let (mut id, mut cpp, mut time, mut tr, mut rot) = (vec![], vec![], vec![], vec![], vec![]);
    for j in jobs {
        for row in j.result.iter().flat_map(|r| &r.analysis.energy) {
            id.push(j.job.id.0.clone());
            cpp.push(row.collisions_per_particle);
            time.push(row.time);
            tr.push(row.translational);
            rot.push(row.rotational);
        }
    }
    let n = id.len();
    Ok(DataFrame::new(
        n,
        vec![
            Column::new("job_id".into(), id),
            Column::new("collisions_per_particle".into(), cpp),
            Column::new("time".into(), time),
            Column::new("translational_energy".into(), tr),
            Column::new("rotational_energy".into(), rot),
        ],
    )?)
}
