//! `granflow run SWEEP.ron`: run the jobs of a sweep that are not done yet on a rayon pool,
//! write the tables, and show the phase diagram when every job is done.

use crate::sweep::runner::{RunOptions, run_sweep};

/// println! that survives a closed stdout.
macro_rules! say {
    ($($arg:tt)*) => { crate::sweep::say(&format!($($arg)*)) };
}
use crate::sweep::{BadInput, load_sweep, phase, tables};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow run sweeps/quick.ron                      # resumable: run it again after a stop
  granflow run sweeps/quick.ron --threads 2 --set collisions_per_particle=2000
  granflow run sweeps/quick.ron --set 'restitution=linspace(0.5,0.9,5)' --where length_over_width=1
  granflow run sweeps/quick.ron --retry-failed")]
pub struct RunArgs {
    /// the sweep file (sweeps/*.ron)
    pub sweep: PathBuf,
    /// results root: tables in DIR/<sweep>/ (DIR/<sweep>/runs/<overrides>/ with --set), jobs in DIR/<sweep>/jobs/
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// worker threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
    /// override a fixed value or an axis: key=value, key=v1,v2,... or a range,
    /// key=linspace(start,stop,count) (also logspace, range; repeatable)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// only jobs whose plan index (order of `granflow plan`) lies in [START, END); with
    /// --job-ids, the lines [START, END) of that file
    #[arg(long, value_name = "START:END")]
    pub job_range: Option<String>,
    /// run the jobs listed in FILE (one id per line; a Slurm submission writes it) from their
    /// job directories' params.json, whatever the sweep file says now
    #[arg(long, value_name = "FILE")]
    pub job_ids: Option<PathBuf>,
    /// run failed jobs again (from their last checkpoint), and set aside and recompute
    /// damaged ones
    #[arg(long)]
    pub retry_failed: bool,
    /// run again the done jobs whose result was made by another version of the engine (from
    /// the start) or of the analysis (only the analysis, from the records of the job's last
    /// checkpoint); the old files are kept as `<name>.outdated-<time>`
    #[arg(long)]
    pub rerun_outdated: bool,
    /// run even where the results file system has no working file locks (Lustre `noflock`,
    /// some FUSE mounts): safe only while a single runner works on the sweep at a time
    #[arg(long)]
    pub unsafe_no_locks: bool,
    /// only jobs whose parameters meet this condition: KEY=V, KEY!=V, KEY<V, KEY<=V, KEY>V,
    /// KEY>=V (repeatable: all must hold), e.g. --where width_over_diameter>=30
    #[arg(long = "where", value_name = "CONDITION")]
    pub conditions: Vec<String>,
}

/// Parse `START:END` (either side may be empty: 0 and the plan length).
pub fn parse_job_range(text: &str, plan_len: usize) -> Result<(usize, usize), BadInput> {
    let bad = || {
        BadInput(format!(
            "--job-range {text}: expected START:END with 0 <= START < END (plan indices, END exclusive; the plan has {plan_len} jobs)"
        ))
    };
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let a = if a.trim().is_empty() {
        0
    } else {
        a.trim().parse().map_err(|_| bad())?
    };
    let b = if b.trim().is_empty() {
        plan_len
    } else {
        b.trim().parse().map_err(|_| bad())?
    };
    if a >= b {
        // END is exclusive: START:START selects nothing, which is never what was meant
        return Err(bad());
    }
    if a >= plan_len {
        return Err(BadInput(format!(
            "--job-range {text}: selects no job (the plan has {plan_len} jobs, indices 0 to {})",
            plan_len.saturating_sub(1)
        )));
    }
    Ok((a, b.min(plan_len)))
}

/// The jobs of an id list (lines [range) of `file`) as a plan, each from its job directory's
/// `params.json` (positions in the list as plan indices).
fn plan_of_ids(
    file: &std::path::Path,
    range: Option<&str>,
    dirs: &crate::sweep::SweepDirs,
) -> anyhow::Result<Vec<crate::sweep::PlannedJob>> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| BadInput(format!("--job-ids {}: {e}", file.display())))?;
    let ids: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let (a, b) = match range {
        Some(r) => parse_job_range(r, ids.len())?,
        None => (0, ids.len()),
    };
    ids[a..b]
        .iter()
        .enumerate()
        .map(|(k, id)| {
            let id = crate::sweep::JobId(id.to_string());
            let params = dirs.job(&id).params()?;
            anyhow::ensure!(
                params.id() == id,
                "{}: params.json does not give the id {id}",
                dirs.job_dir(&id).display()
            );
            Ok(crate::sweep::PlannedJob {
                index: a + k,
                id,
                params,
                swept: Vec::new(),
                level: 0,
            })
        })
        .collect()
}

pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let mut sweep = load_sweep(&args.sweep, &args.set)?;
    let by_ids = args.job_ids.is_some();
    let job_range = match (&args.job_ids, &args.job_range) {
        (Some(file), range) => {
            let swept = phase::swept_in(&sweep);
            sweep.plan = plan_of_ids(file, range.as_deref(), &sweep.results_dir(&args.results))?;
            for job in &mut sweep.plan {
                job.swept = swept.clone();
            }
            None
        }
        (None, Some(t)) => Some(parse_job_range(t, sweep.plan.len())?),
        (None, None) => None,
    };
    let engine = sweep.engine();
    // --where picks the jobs to run; the tables and the diagram stay those of the whole sweep
    let whole = (!args.conditions.is_empty()).then(|| sweep.clone());
    crate::sweep::select::retain(&mut sweep.plan, &args.conditions, engine)?;
    if sweep.plan.is_empty() {
        return Err(BadInput("--where selects no job of the sweep".into()).into());
    }
    if args.threads == Some(0) {
        return Err(BadInput("--threads 0: allowed a whole number >= 1".into()).into());
    }
    // the input is good: only now may anything be created
    crate::sweep::check_results_root(&args.results)?;
    if args.unsafe_no_locks {
        crate::sweep::store::allow_claims_without_locks();
        say!(
            "warning: --unsafe-no-locks: claims are not exclusive; run no other runner on this sweep"
        );
    } else {
        match crate::sweep::store::check_locking(&args.results) {
            Ok(Some(warning)) => say!("{warning}"),
            Ok(None) => {}
            Err(refusal) => return Err(BadInput(refusal).into()),
        }
    }
    let dirs = sweep.results_dir(&args.results);
    let opts = RunOptions {
        threads: args
            .threads
            .unwrap_or_else(|| RunOptions::default().threads),
        retry_failed: args.retry_failed,
        rerun_outdated: args.rerun_outdated,
        job_range,
        // a --job-range run is one slice of a sweep (a Slurm array task): writing the whole
        // sweep's tables from every slice would cost O(jobs) per task; `gather` does it once
        write_tables: job_range.is_none() && !by_ids && whole.is_none(),
        write_resolved: !by_ids,
    };
    let summary = run_sweep(&sweep, &dirs, &opts)?;
    if let Some(err) = &summary.halted {
        return Err(crate::sweep::fs_error::ResourceStop(format!(
            "the run stopped on a resource error: {err}. No job was marked failed: free space \
             (or fix the device) and run the same command again; the stopped jobs resume from \
             their last checkpoint (exit code {})",
            crate::sweep::fs_error::EXIT_RESOURCE
        ))
        .into());
    }
    // with the points its refinement added (none without a `refine` section)
    let (sweep, whole) = if job_range.is_none() && !by_ids {
        let refined = |s: &crate::sweep::Sweep| crate::sweep::rounds::replay(s, &dirs);
        (
            refined(&sweep)?.sweep,
            whole.map(|w| refined(&w)).transpose()?.map(|r| r.sweep),
        )
    } else {
        (sweep, whole)
    };
    let selected: std::collections::HashSet<String> =
        sweep.plan.iter().map(|j| j.id.0.clone()).collect();
    let sweep = match whole {
        Some(whole) if job_range.is_none() && !by_ids => {
            let written = tables::gather(&whole, &dirs)?;
            say!(
                "tables of the whole sweep: {} in {}",
                written.counts(),
                dirs.tables.display()
            );
            whole
        }
        _ => sweep,
    };
    let jobs = tables::collect(&sweep, &dirs);
    let failed: Vec<_> = jobs
        .iter()
        .filter(|j| {
            matches!(j.state.name(), "failed" | "damaged") && selected.contains(&j.job.id.0)
        })
        .collect();
    let failures = failed.len();
    if !failed.is_empty() {
        say!(
            "{} failed jobs (see `granflow status {}`; rerun with --retry-failed):",
            failed.len(),
            dirs.tables.display()
        );
        for j in &failed {
            match &j.state {
                crate::sweep::store::JobState::Failed(e) => {
                    say!("  {} [{}]: {e}", j.job.id, j.job.index)
                }
                crate::sweep::store::JobState::Damaged { reason, .. } => {
                    say!("  {} [{}]: damaged: {reason}", j.job.id, j.job.index)
                }
                _ => {}
            }
        }
    }
    if job_range.is_some() || by_ids {
        say!(
            "slice done; run `granflow gather {}` for the tables and the phase diagram",
            dirs.tables.display()
        );
    } else if jobs.iter().all(|j| j.result.is_some()) {
        let swept = phase::swept_in(&sweep);
        if let Some(&x) = swept.first() {
            let y = swept.get(1).copied();
            let mut diagram =
                phase::PhaseDiagram::build(sweep.engine(), &jobs, x, y).map_err(BadInput)?;
            diagram.frame.title =
                phase::title(&sweep, &[x].into_iter().chain(y).collect::<Vec<_>>());
            let (png, svg) = super::phase_diagram::write_plots(&diagram, &dirs.tables)?;
            say!(
                "\nphase diagram ({}):\n{}",
                dirs.tables.display(),
                diagram.table()
            );
            say!("plots: {} {}", png.display(), svg.display());
        }
    } else if summary.busy > 0 {
        say!(
            "some jobs are held by another runner; run `granflow gather {}` when it is done",
            dirs.tables.display()
        );
    }
    anyhow::ensure!(
        failures == 0,
        "{failures} jobs failed (the others are done; rerun with --retry-failed)"
    );
    Ok(())
}
