//! The Parquet tables of a results directory (written with polars): `jobs.parquet` (one row per
//! job: parameters, state, the analysis summary, counters) and the row tables the engine's
//! analysis declares (`spectra`, `profiles`, `energy` for the structure analysis). Columns are
//! documented in `results/README.md`. Written atomically (temp file + fsync + rename).

use super::store::{self, JobResult, JobState};
use super::{Sweep, SweepDirs};
use crate::analysis::columns::{Cell, ColumnKind};
use crate::engine::declare::ParamKind;
use crate::engine::{Clock, EngineDef};
use polars::prelude::*;
use serde_json::Value;
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
            let mut state = store::job_state(&dir);
            let result = if state == JobState::Done {
                match store::read_result(&dir) {
                    Ok(r) => Some(r),
                    Err(e) => {
                        state = JobState::Damaged {
                            file: store::RESULT_FILE,
                            reason: format!("{e:#}"),
                        };
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

/// The tables an engine's sweeps write and their columns, in order (the schema is fixed by the
/// declarations: the same whether no job or every job is done).
pub fn schema(engine: &EngineDef) -> anyhow::Result<Vec<(String, Vec<String>)>> {
    let names = |df: &DataFrame| {
        df.get_column_names()
            .iter()
            .map(|n| n.to_string())
            .collect::<Vec<_>>()
    };
    let mut out = vec![("jobs".to_string(), names(&jobs_frame(engine, &[])?))];
    for table in engine.analysis.tables() {
        out.push((table.name.to_string(), names(&rows_frame(table, &[])?)));
    }
    Ok(out)
}

/// Write the tables of a sweep into its tables directory: `jobs.parquet` and the row tables
/// of its engine's analysis.
pub fn gather(sweep: &Sweep, dirs: &SweepDirs) -> anyhow::Result<GatherSummary> {
    let jobs = collect(sweep, dirs);
    let engine = super::spec::engine_of(&sweep.spec).expect("a loaded sweep names an engine");
    std::fs::create_dir_all(&dirs.tables)?;
    // one gather at a time per tables directory (two runners that end together both gather):
    // a gather removes the generations it did not write, which must not be another's set in
    // the making. The lock dies with its process; where the file system has no locks, gathers
    // are not serialised (as claims under --unsafe-no-locks).
    let lock_path = dirs.tables.join(GATHER_LOCK);
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .write(true)
        .truncate(false)
        .open(&lock_path)
        .map_err(|e| anyhow::anyhow!("{}: {e}", lock_path.display()))?;
    let _ = lock.lock();
    // the set is written into a new generation directory, then switched to with one atomic
    // rename of the `tables` link: a kill leaves either the old set or the new one
    let generation = format!(
        ".tables-{}-{}-{}",
        crate::provenance::now().replace(':', ""),
        crate::provenance::host(),
        std::process::id()
    );
    let staging = dirs.tables.join(&generation);
    std::fs::create_dir_all(&staging)?;
    let metadata = file_metadata(sweep, &generation);
    let mut names = vec!["jobs".to_string()];
    let written = (|| -> anyhow::Result<()> {
        write_parquet(
            &staging.join("jobs.parquet"),
            jobs_frame(engine, &jobs)?,
            &metadata,
        )?;
        for table in engine.analysis.tables() {
            write_parquet(
                &staging.join(format!("{}.parquet", table.name)),
                rows_frame(table, &jobs)?,
                &metadata,
            )?;
            names.push(table.name.to_string());
        }
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&staging);
        return Err(e);
    }
    switch_tables(&dirs.tables, &generation, &names)?;
    Ok(GatherSummary {
        jobs: jobs.len(),
        done: jobs.iter().filter(|j| j.result.is_some()).count(),
    })
}

/// The lock file that serialises gathers into one tables directory.
pub const GATHER_LOCK: &str = ".gather.lock";

/// The name of the link to the current table set inside a tables directory; `<name>.parquet`
/// are links into it.
pub const TABLES_LINK: &str = "tables";

/// Make `generation` the current set: a new link renamed over `tables` (atomic), the
/// `<name>.parquet` links made once, earlier generations removed.
fn switch_tables(dir: &Path, generation: &str, names: &[String]) -> anyhow::Result<()> {
    let link = dir.join(TABLES_LINK);
    let tmp = dir.join(format!(".{TABLES_LINK}.tmp-{}", std::process::id()));
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(generation, &tmp)?;
    std::fs::rename(&tmp, &link)?;
    for name in names {
        let file = dir.join(format!("{name}.parquet"));
        let target = Path::new(TABLES_LINK).join(format!("{name}.parquet"));
        if std::fs::read_link(&file).ok().as_deref() != Some(target.as_path()) {
            // a plain file of an older granflow, or a missing link: replace it by the link
            let _ = std::fs::remove_file(&file);
            std::os::unix::fs::symlink(&target, &file)?;
        }
    }
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    for entry in std::fs::read_dir(dir)?.flatten() {
        let n = entry.file_name().to_string_lossy().into_owned();
        if n.starts_with(".tables-") && n != generation {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
    Ok(())
}

/// Key-value metadata of every table of a set: provenance and the sweep they come from.
fn file_metadata(sweep: &Sweep, generation: &str) -> Vec<(String, String)> {
    let config =
        ron::ser::PrettyConfig::default().extensions(ron::extensions::Extensions::IMPLICIT_SOME);
    vec![
        ("granflow.version".into(), crate::provenance::VERSION.into()),
        ("granflow.commit".into(), crate::provenance::COMMIT.into()),
        ("granflow.host".into(), crate::provenance::host()),
        ("granflow.written".into(), crate::provenance::now()),
        (
            "granflow.table_set".into(),
            generation.trim_start_matches('.').into(),
        ),
        ("granflow.sweep".into(), sweep.name.clone()),
        ("granflow.engine".into(), sweep.spec.engine.clone()),
        (
            "granflow.sweep_ron".into(),
            ron::ser::to_string_pretty(&sweep.spec, config).unwrap_or_default(),
        ),
    ]
}

fn write_parquet(
    path: &Path,
    mut df: DataFrame,
    metadata: &[(String, String)],
) -> anyhow::Result<()> {
    let file = std::fs::File::create(path)?;
    ParquetWriter::new(&file)
        .with_compression(ParquetCompression::Uncompressed)
        .with_key_value_metadata(Some(KeyValueMetadata::from_static(metadata.to_vec())))
        .finish(&mut df)?;
    file.sync_all()?;
    Ok(())
}

/// A column being built, by type.
enum Col {
    F64(Vec<Option<f64>>),
    U32(Vec<Option<u32>>),
    I64(Vec<Option<i64>>),
    U64(Vec<Option<u64>>),
    Bool(Vec<Option<bool>>),
    Str(Vec<Option<String>>),
}

impl Col {
    fn new(kind: ColumnKind) -> Self {
        match kind {
            ColumnKind::F64 => Col::F64(Vec::new()),
            ColumnKind::U32 => Col::U32(Vec::new()),
            ColumnKind::U64 => Col::U64(Vec::new()),
            ColumnKind::I64 => Col::I64(Vec::new()),
            ColumnKind::Bool => Col::Bool(Vec::new()),
            ColumnKind::Str => Col::Str(Vec::new()),
        }
    }

    /// Append a cell (a cell of another type, or NaN, is null).
    fn push(&mut self, cell: Cell) {
        match (self, cell) {
            (Col::F64(v), Cell::F64(x)) => v.push((!x.is_nan()).then_some(x)),
            (Col::F64(v), Cell::U32(x)) => v.push(Some(x as f64)),
            (Col::F64(v), Cell::U64(x)) => v.push(Some(x as f64)),
            (Col::U32(v), Cell::U32(x)) => v.push(Some(x)),
            (Col::U64(v), Cell::U64(x)) => v.push(Some(x)),
            (Col::U64(v), Cell::U32(x)) => v.push(Some(x as u64)),
            (Col::I64(v), Cell::I64(x)) => v.push(Some(x)),
            (Col::Bool(v), Cell::Bool(x)) => v.push(Some(x)),
            (Col::Str(v), Cell::Str(x)) => v.push(Some(x)),
            (col, _) => col.push_null(),
        }
    }

    fn push_null(&mut self) {
        match self {
            Col::F64(v) => v.push(None),
            Col::U32(v) => v.push(None),
            Col::U64(v) => v.push(None),
            Col::I64(v) => v.push(None),
            Col::Bool(v) => v.push(None),
            Col::Str(v) => v.push(None),
        }
    }

    fn into_column(self, name: &str) -> Column {
        let name: PlSmallStr = name.into();
        match self {
            Col::F64(v) => Column::new(name, v),
            Col::U32(v) => Column::new(name, v),
            Col::I64(v) => Column::new(name, v),
            Col::U64(v) => Column::new(name, v),
            Col::Bool(v) => Column::new(name, v),
            Col::Str(v) => Column::new(name, v),
        }
    }
}

/// A JSON summary value as a cell of a column of `kind`.
fn json_cell(v: Option<&Value>, kind: ColumnKind) -> Cell {
    match (v, kind) {
        (Some(Value::Bool(b)), ColumnKind::Bool) => Cell::Bool(*b),
        (Some(Value::String(s)), ColumnKind::Str) => Cell::Str(s.clone()),
        (Some(Value::Number(n)), ColumnKind::U64) => n.as_u64().map_or(Cell::Null, Cell::U64),
        (Some(Value::Number(n)), ColumnKind::I64) => n.as_i64().map_or(Cell::Null, Cell::I64),
        (Some(Value::Number(n)), ColumnKind::F64) => n.as_f64().map_or(Cell::Null, Cell::F64),
        _ => Cell::Null,
    }
}

/// The `jobs.parquet` frame: plan, parameters, state, the analysis summary (null where a job
/// is not done), counters and their ratios, final clocks, cost.
fn jobs_frame(engine: &EngineDef, jobs: &[GatheredJob]) -> anyhow::Result<DataFrame> {
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
    for def in engine.params {
        let value = |j: &GatheredJob| j.job.params.values.get(def.name).cloned();
        cols.push(match def.kind {
            ParamKind::Integer => Column::new(
                def.name.into(),
                jobs.iter()
                    .map(|j| value(j).and_then(|v| v.as_f64()).map(|v| v as u64))
                    .collect::<Vec<_>>(),
            ),
            ParamKind::Real => Column::new(
                def.name.into(),
                jobs.iter()
                    .map(|j| value(j).and_then(|v| v.as_f64()))
                    .collect::<Vec<_>>(),
            ),
            ParamKind::Choice(_) => Column::new(
                def.name.into(),
                jobs.iter()
                    .map(|j| value(j).and_then(|v| v.as_text().map(str::to_string)))
                    .collect::<Vec<_>>(),
            ),
        });
    }
    cols.push(Column::new(
        "seed".into(),
        jobs.iter().map(|j| j.job.params.seed).collect::<Vec<_>>(),
    ));
    cols.push(Column::new(
        "run_length".into(),
        jobs.iter()
            .map(|j| j.job.params.run.length())
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
                JobState::Damaged { reason, .. } => Some(reason.clone()),
                _ => None,
            })
            .collect::<Vec<_>>(),
    ));
    // a summary field that repeats a job column (e.g. `particles`) is left out: the job
    // column is the authority, and a table cannot hold two columns of one name
    let summaries: Vec<Option<serde_json::Map<String, Value>>> = jobs
        .iter()
        .map(|j| j.result.as_ref().map(|r| r.analysis.summary()))
        .collect();
    for (name, kind) in engine.analysis.summary_columns() {
        if cols.iter().any(|c| c.name().as_str() == name) {
            continue;
        }
        let mut col = Col::new(kind);
        for s in &summaries {
            match s {
                Some(s) => col.push(json_cell(s.get(&name), kind)),
                None => col.push_null(),
            }
        }
        cols.push(col.into_column(&name));
    }
    let r = |f: &dyn Fn(&JobResult) -> u64| -> Vec<Option<u64>> {
        jobs.iter().map(|j| j.result.as_ref().map(f)).collect()
    };
    let rf = |f: &dyn Fn(&JobResult) -> f64| -> Vec<Option<f64>> {
        jobs.iter().map(|j| j.result.as_ref().map(f)).collect()
    };
    for counter in engine.counters {
        cols.push(Column::new(
            counter.name.into(),
            r(&|x| x.counters.get(counter.name)),
        ));
    }
    for ratio in engine.ratios {
        cols.push(Column::new(
            ratio.name.into(),
            rf(&|x| {
                x.counters.get(ratio.numerator) as f64
                    / x.counters.get(ratio.denominator).max(1) as f64
            }),
        ));
    }
    for clock in engine.clocks {
        cols.push(match clock {
            Clock::CollisionsPerParticle => {
                Column::new(clock.key().into(), rf(&|x| x.collisions_per_particle))
            }
            Clock::Steps => Column::new(clock.key().into(), r(&|x| x.steps)),
            Clock::Time => Column::new(clock.key().into(), rf(&|x| x.time)),
        });
    }
    cols.push(Column::new("snapshots".into(), r(&|x| x.snapshots as u64)));
    cols.push(Column::new(
        "stop_reason".into(),
        jobs.iter()
            .map(|j| j.result.as_ref().map(|x| x.stop_reason.clone()))
            .collect::<Vec<_>>(),
    ));
    cols.push(Column::new("wall_seconds".into(), rf(&|x| x.wall_seconds)));
    cols.push(Column::new(
        "events_per_second".into(),
        rf(&|x| x.events_per_second),
    ));
    Ok(DataFrame::new(n, cols)?)
}

/// One of the analysis's row tables: `job_id` and the declared columns, rows of every done job.
fn rows_frame(
    table: &crate::analysis::columns::TableDef,
    jobs: &[GatheredJob],
) -> anyhow::Result<DataFrame> {
    let mut id = Vec::new();
    let mut cols: Vec<Col> = table.columns.iter().map(|c| Col::new(c.kind)).collect();
    for j in jobs {
        for row in j.result.iter().flat_map(|r| r.analysis.rows(table.name)) {
            id.push(j.job.id.0.clone());
            for (col, cell) in cols.iter_mut().zip(row) {
                col.push(cell);
            }
        }
    }
    let n = id.len();
    let mut columns = vec![Column::new("job_id".into(), id)];
    columns.extend(
        cols.into_iter()
            .zip(table.columns)
            .map(|(c, def)| c.into_column(def.name)),
    );
    Ok(DataFrame::new(n, columns)?)
}
