//! The Parquet tables of a results directory: `jobs.parquet` (one row per job: parameters,
//! state, the analysis summary, counters, final clocks) and the row tables the engine's
//! analysis declares (`spectra`, `profiles`, `energy` for the structure analysis), each keyed
//! by `job_id`. The schema follows from the declarations alone (the same whether no job or
//! every job is done; null where a value is not known or NaN); columns are documented in
//! `results/README.md`. A set is written into a new directory and switched to atomically;
//! [`parquet`] writes one file.

use super::store::{self, JobResult, JobState};
use super::{Sweep, SweepDirs};
use crate::analysis::columns::{Cell, ColumnKind, TableDef};
use crate::engine::declare::ParamKind;
use crate::engine::{Clock, EngineDef};
use parquet::Column;
use serde_json::Value;
use std::path::Path;

pub mod column_docs;
mod parquet;

/// What [`gather`] wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GatherSummary {
    /// rows of jobs.parquet (every planned job)
    pub jobs: usize,
    /// of which done
    pub done: usize,
    /// of which running (held by a live runner: another one, which writes the tables again
    /// when it ends)
    pub running: usize,
    /// the tables written (without `.parquet`), `jobs` first
    pub tables: Vec<String>,
}

impl GatherSummary {
    /// "4 jobs, 3 done" and, when some run elsewhere, "1 still running in another runner".
    pub fn counts(&self) -> String {
        let running = match self.running {
            0 => String::new(),
            n => format!(
                ", {n} still running in another runner (a run rewrites the tables when it \
                 ends; a --job-range or Slurm task does not: then `granflow gather`)"
            ),
        };
        format!("{} jobs, {} done{running}", self.jobs, self.done)
    }
}

/// One planned job with its state and (when done) its result.
pub struct GatheredJob<'a> {
    pub job: &'a super::PlannedJob,
    pub state: JobState,
    pub result: Option<JobResult>,
}

/// Read the state and result of every job of the plan, checking each job's files at a small
/// cost (see [`collect_checked`]).
pub fn collect<'a>(sweep: &'a Sweep, dirs: &SweepDirs) -> Vec<GatheredJob<'a>> {
    collect_checked(sweep, dirs, false)
}

/// Read the state and result of every job of the plan. A partial job's checkpoint and the
/// records it covers are read and checked (a resume needs them); a done job's result and
/// parameters file are read and checked, and its checkpoint and record log checked cheaply
/// (which job they name, their lengths), or read whole and checked against their CRC and
/// digest with `full` (`status --verify`).
pub fn collect_checked<'a>(sweep: &'a Sweep, dirs: &SweepDirs, full: bool) -> Vec<GatheredJob<'a>> {
    sweep
        .plan
        .iter()
        .map(|job| {
            let dir = dirs.job(&job.id);
            let mut state = dir.state(false);
            // a partial job's checkpoint and the records it covers are read and checked (a
            // resume needs them); a done job's result and parameters file
            if matches!(state, JobState::Partial(_)) {
                state = dir.state(true);
            }
            let result = if state == JobState::Done {
                let checked = dir
                    .result()
                    .map_err(|e| (store::RESULT_FILE, format!("{e:#}")))
                    .and_then(|r| {
                        dir.params()
                            .map(|_| r)
                            .map_err(|e| (store::PARAMS_FILE, format!("{e:#}")))
                    })
                    .and_then(|r| dir.check_done_files(full).map(|()| r));
                match checked {
                    Ok(r) => Some(r),
                    Err((file, reason)) => {
                        state = JobState::Damaged { file, reason };
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

/// The tables an engine's sweeps write and their columns with their types, in order (the
/// schema is fixed by the declarations: the same whether no job or every job is done).
pub fn schema(engine: &EngineDef) -> Vec<(String, Vec<(String, ColumnKind)>)> {
    schema_of(engine, false)
}

/// The tables of an engine's sweeps with statistics (`run.statistics`): the plain ones, the
/// statistics' columns of `jobs.parquet` and the statistics tables.
pub fn schema_with_statistics(engine: &EngineDef) -> Vec<(String, Vec<(String, ColumnKind)>)> {
    schema_of(
        engine,
        crate::registry::analysis_of(engine).supports_statistics(),
    )
}

fn schema_of(engine: &EngineDef, statistics: bool) -> Vec<(String, Vec<(String, ColumnKind)>)> {
    let columns = |cols: Vec<Column>| {
        cols.iter()
            .map(|c| (c.name().to_string(), c.kind()))
            .collect::<Vec<_>>()
    };
    let mut out = vec![(
        "jobs".to_string(),
        columns(jobs_table(engine, &[], statistics)),
    )];
    for table in tables_of(engine, statistics) {
        out.push((table.name.to_string(), columns(rows_table(table, &[]))));
    }
    out
}

/// The row tables a sweep writes: its analysis', and the statistics tables when it has them.
fn tables_of(engine: &EngineDef, statistics: bool) -> Vec<&'static TableDef> {
    let mut tables: Vec<&'static TableDef> = crate::registry::analysis_of(engine)
        .tables()
        .iter()
        .collect();
    if statistics {
        tables.extend(crate::analysis::statistics::tables::TABLES);
    }
    tables
}

/// Whether a sweep writes the statistics' tables and columns.
pub fn has_statistics(sweep: &Sweep) -> bool {
    sweep.spec.run.statistics.is_some()
        && crate::registry::analysis_of(sweep.engine()).supports_statistics()
}

/// Write the tables of a sweep into its tables directory: `jobs.parquet` and the row tables
/// of its engine's analysis.
pub fn gather(sweep: &Sweep, dirs: &SweepDirs) -> anyhow::Result<GatherSummary> {
    std::fs::create_dir_all(&dirs.tables)
        .map_err(|e| super::fs_error::PathError::new(&dirs.tables, e))?;
    // one gather at a time in a tables directory (two runners end together): a second one
    // waits, then reads the jobs anew, so the set it writes is no older than the first's, and
    // no generation directory is being written while one is cleaned up
    let _one_at_a_time = lock_gathering(&dirs.tables)?;
    let jobs = collect(sweep, dirs);
    write_set(sweep, &jobs, &dirs.tables, &[])
}

/// Write the tables of these jobs of a sweep into `tables` (created if missing) as a new set,
/// switched to atomically; `source` adds key-value metadata to every file (e.g. where
/// imported results came from). The caller holds the directory's gather lock where other
/// gathers may write into it.
pub fn write_set(
    sweep: &Sweep,
    jobs: &[GatheredJob],
    tables: &Path,
    source: &[(String, String)],
) -> anyhow::Result<GatherSummary> {
    let engine = super::spec::engine_of(&sweep.spec).expect("a loaded sweep names an engine");
    std::fs::create_dir_all(tables)?;
    // the set is written into a new generation directory, then switched to with one atomic
    // rename of the `tables` link: a kill leaves either the old set or the new one
    let generation = format!(
        ".tables-{}-{}-{}",
        crate::provenance::now().replace(':', ""),
        crate::provenance::host(),
        std::process::id()
    );
    let staging = tables.join(&generation);
    std::fs::create_dir_all(&staging)?;
    let mut metadata = file_metadata(sweep, &generation);
    metadata.extend(source.iter().cloned());
    let mut names = vec!["jobs".to_string()];
    let statistics = has_statistics(sweep);
    let written = (|| -> anyhow::Result<()> {
        let describe = |table: &'static str| {
            move |column: &str| {
                column_docs::lookup(table, engine.name, column).map(|d| parquet::FieldDoc {
                    unit: d.unit.clone(),
                    description: d.meaning.clone(),
                })
            }
        };
        parquet::write(
            &staging.join("jobs.parquet"),
            jobs_table(engine, jobs, statistics),
            &metadata,
            &describe("jobs"),
        )?;
        for table in tables_of(engine, statistics) {
            parquet::write(
                &staging.join(format!("{}.parquet", table.name)),
                rows_table(table, jobs),
                &metadata,
                &describe(table.name),
            )?;
            names.push(table.name.to_string());
        }
        Ok(())
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&staging);
        return Err(e);
    }
    switch_tables(tables, &generation, &names)?;
    Ok(GatherSummary {
        jobs: jobs.len(),
        done: jobs.iter().filter(|j| j.result.is_some()).count(),
        running: jobs.iter().filter(|j| j.state == JobState::Running).count(),
        tables: names,
    })
}

/// The name of the link to the current table set inside a tables directory; `<name>.parquet`
/// are links into it.
pub const TABLES_LINK: &str = "tables";

/// The file a gather holds an exclusive lock on while it writes and switches a set.
pub const GATHER_LOCK: &str = ".gather.lock";

/// Wait for the tables directory's gather lock (released when the file is dropped, or the
/// process ends). Where the file system has no working locks the gather goes on unlocked (as
/// `run --unsafe-no-locks` does: safe while one gather runs at a time).
pub fn lock_gathering(dir: &Path) -> anyhow::Result<std::fs::File> {
    let path = dir.join(GATHER_LOCK);
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(|e| super::fs_error::PathError::new(&path, e))?;
    let _ = file.lock();
    Ok(file)
}

/// Make `generation` the current set: a new link renamed over `tables` (atomic), the
/// `<name>.parquet` links made once, every other generation removed (the caller holds the
/// gather lock: they are earlier sets, or sets of gathers that were killed).
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

/// A JSON summary value as a cell of a column of `kind` (a value of another type is null).
fn json_cell(v: Option<&Value>, kind: ColumnKind) -> Cell {
    match (v, kind) {
        (Some(Value::Bool(b)), ColumnKind::Bool) => Cell::Bool(*b),
        (Some(Value::String(s)), ColumnKind::Str) => Cell::Str(s.clone()),
        (Some(Value::Number(n)), ColumnKind::I64) => n
            .as_i64()
            .or_else(|| n.as_u64().and_then(|u| i64::try_from(u).ok()))
            .map_or(Cell::Null, Cell::I64),
        (Some(Value::Number(n)), ColumnKind::F64) => n.as_f64().map_or(Cell::Null, Cell::F64),
        (Some(Value::Array(items)), ColumnKind::List(fields)) => Cell::List(
            items
                .iter()
                .map(|item| {
                    fields
                        .iter()
                        .map(|f| json_cell(item.get(f.name), f.kind))
                        .collect()
                })
                .collect(),
        ),
        _ => Cell::Null,
    }
}

/// The name in `jobs.parquet` of a clock's reading at the end of a job (`final_time`, ...):
/// `energy.parquet` has the clocks of each snapshot under the plain names.
pub fn final_clock_column(clock: Clock) -> String {
    format!("final_{}", clock.key())
}

/// The columns of `jobs.parquet`: plan, parameters, state, the analysis summary (null where a
/// job is not done), counters and their ratios, final clocks, cost.
fn jobs_table(engine: &EngineDef, jobs: &[GatheredJob], statistics: bool) -> Vec<Column> {
    let column = |name: &str, kind: ColumnKind, cell: &dyn Fn(&GatheredJob) -> Cell| {
        Column::from_cells(name, kind, jobs.iter().map(cell))
    };
    let done = |name: &str, kind: ColumnKind, cell: &dyn Fn(&JobResult) -> Cell| {
        Column::from_cells(
            name,
            kind,
            jobs.iter()
                .map(|j| j.result.as_ref().map_or(Cell::Null, cell)),
        )
    };
    let mut cols = vec![
        column("job_id", ColumnKind::Str, &|j| j.job.id.0.as_str().into()),
        column("plan_index", ColumnKind::I64, &|j| j.job.index.into()),
        column("refinement_level", ColumnKind::I64, &|j| {
            (j.job.level as usize).into()
        }),
        column("engine", ColumnKind::Str, &|j| {
            j.job.params.engine.as_str().into()
        }),
    ];
    for def in engine.params {
        let value = |j: &GatheredJob| j.job.params.values.get(def.name).cloned();
        cols.push(match def.kind {
            ParamKind::Integer => column(def.name, ColumnKind::I64, &|j| {
                value(j)
                    .and_then(|v| v.as_f64())
                    .map_or(Cell::Null, |v| Cell::I64(v as i64))
            }),
            ParamKind::Real => column(def.name, ColumnKind::F64, &|j| {
                value(j).and_then(|v| v.as_f64()).into()
            }),
            ParamKind::Choice(_) => column(def.name, ColumnKind::Str, &|j| {
                value(j)
                    .and_then(|v| v.as_text().map(str::to_string))
                    .into()
            }),
        });
    }
    cols.push(column("seed", ColumnKind::I64, &|j| {
        j.job.params.seed.into()
    }));
    cols.push(column("run_length", ColumnKind::F64, &|j| {
        j.job.params.run.length().into()
    }));
    cols.push(column("snapshot_interval", ColumnKind::F64, &|j| {
        j.job.params.run.snapshot_interval.into()
    }));
    cols.push(column("state", ColumnKind::Str, &|j| j.state.name().into()));
    cols.push(column("error", ColumnKind::Str, &|j| match &j.state {
        JobState::Failed(e) => e.as_str().into(),
        JobState::Damaged { reason, .. } => reason.as_str().into(),
        _ => Cell::Null,
    }));
    // a summary field that repeats a job column (e.g. `particles`) is left out: the job
    // column is the authority, and a table cannot hold two columns of one name
    let summaries: Vec<Option<serde_json::Map<String, Value>>> = jobs
        .iter()
        .map(|j| j.result.as_ref().map(|r| r.analysis.summary()))
        .collect();
    for (name, kind) in crate::registry::analysis_of(engine).summary_columns() {
        if cols.iter().any(|c| c.name() == name) {
            continue;
        }
        cols.push(Column::from_cells(
            name.as_str(),
            kind,
            summaries.iter().map(|s| match s {
                Some(s) => json_cell(s.get(&name), kind),
                None => Cell::Null,
            }),
        ));
    }
    if statistics {
        use crate::analysis::statistics::tables::summary_columns;
        for (name, kind) in summary_columns() {
            cols.push(Column::from_cells(
                name.as_str(),
                kind,
                summaries.iter().map(|s| match s {
                    Some(s) => json_cell(s.get(&name), kind),
                    None => Cell::Null,
                }),
            ));
        }
    }
    // null where a result does not have a counter (one imported from another code's output)
    for counter in engine.counters {
        cols.push(done(counter.name, ColumnKind::I64, &|x| {
            x.counters
                .value(counter.name)
                .map_or(Cell::Null, Cell::from)
        }));
    }
    for ratio in engine.ratios {
        cols.push(done(ratio.name, ColumnKind::F64, &|x| match (
            x.counters.value(ratio.numerator),
            x.counters.value(ratio.denominator),
        ) {
            (Some(a), Some(b)) => (a as f64 / b.max(1) as f64).into(),
            _ => Cell::Null,
        }));
    }
    for &clock in engine.clocks {
        let name = final_clock_column(clock);
        cols.push(match clock {
            Clock::CollisionsPerParticle => done(&name, ColumnKind::F64, &|x| {
                x.collisions_per_particle.into()
            }),
            Clock::Steps => done(&name, ColumnKind::I64, &|x| x.steps.into()),
            Clock::Time => done(&name, ColumnKind::F64, &|x| x.time.into()),
        });
    }
    cols.push(done("snapshots", ColumnKind::I64, &|x| x.snapshots.into()));
    cols.push(done("stop_reason", ColumnKind::Str, &|x| {
        x.stop_reason.as_str().into()
    }));
    cols.push(done("wall_seconds", ColumnKind::F64, &|x| {
        x.wall_seconds.into()
    }));
    cols.push(done("events_per_second", ColumnKind::F64, &|x| {
        x.events_per_second.into()
    }));
    // the build that computed each job (not the one that gathers): null where a result of an
    // older layout does not say
    let known = |s: &str| (!s.is_empty()).then(|| s.to_string()).into();
    cols.push(done("granflow_version", ColumnKind::Str, &|x| {
        known(&x.provenance.granflow)
    }));
    cols.push(done("granflow_commit", ColumnKind::Str, &|x| {
        known(&x.provenance.commit)
    }));
    cols
}

/// The columns of one of the analysis's row tables: `job_id` and the declared columns, the
/// rows of every done job.
fn rows_table(table: &TableDef, jobs: &[GatheredJob]) -> Vec<Column> {
    let mut id = Column::new("job_id", ColumnKind::Str);
    let mut cols: Vec<Column> = table
        .columns
        .iter()
        .map(|c| Column::new(c.name, c.kind))
        .collect();
    for j in jobs {
        for row in j.result.iter().flat_map(|r| r.analysis.rows(table.name)) {
            id.push(j.job.id.0.as_str().into());
            let mut cells = row.into_iter();
            for col in cols.iter_mut() {
                col.push(cells.next().unwrap_or(Cell::Null));
            }
        }
    }
    std::iter::once(id).chain(cols).collect()
}
