//! `granflow status [SWEEP.ron | results/<sweep>]`: counts by state, per-job progress and
//! failures with their errors.

use super::out::{out, outln};
use super::source::SweepSource;
use crate::sweep::{store::JobState, tables};
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow status results/quick                      # counts by state, progress, failures
  granflow status sweeps/quick.ron --where restitution=0.7
  granflow status results/quick --json | jq '.counts'
  granflow status results/quick --verify             # every file of every job read whole")]
pub struct StatusArgs {
    #[command(flatten)]
    pub source: SweepSource,
    /// print one JSON object (counts by state and every job with its parameters, state,
    /// progress and label) instead of the text
    #[arg(long)]
    pub json: bool,
    /// read every done job's checkpoint and record log whole and check their CRC and digest
    /// (without it they are checked cheaply: which job they name, their lengths)
    #[arg(long)]
    pub verify: bool,
}

/// The machine-readable status: {"sweep", "engine", "tables", "counts", "jobs": [...]}.
fn status_json(
    sweep: &crate::sweep::Sweep,
    dirs: &crate::sweep::SweepDirs,
    jobs: &[tables::GatheredJob],
) -> serde_json::Value {
    use serde_json::json;
    let mut counts = serde_json::Map::new();
    for name in ["done", "running", "partial", "pending", "failed", "damaged"] {
        counts.insert(
            name.into(),
            json!(jobs.iter().filter(|j| j.state.name() == name).count()),
        );
    }
    let rows: Vec<serde_json::Value> = jobs
        .iter()
        .map(|j| {
            let run = &j.job.params.run;
            let dir = dirs.job(&j.job.id);
            let progress = match &j.state {
                JobState::Done => j.result.as_ref().map(|r| r.clock(run.clock())),
                JobState::Partial(p) => Some(p.on(run.clock())),
                JobState::Running => dir.checkpoint_progress().map(|p| p.on(run.clock())),
                _ => None,
            };
            let (error, label, probability) = match &j.state {
                JobState::Failed(e) => (Some(e.clone()), None, None),
                JobState::Damaged { reason, .. } => (Some(reason.clone()), None, None),
                _ => {
                    let label = j.result.as_ref().map(|r| r.analysis.shown_label());
                    let p = j
                        .result
                        .as_ref()
                        .and_then(|r| r.analysis.summary().get("label_probability").cloned());
                    (None, label, p)
                }
            };
            json!({
                "index": j.job.index,
                "id": j.job.id.0,
                "state": j.state.name(),
                "params": j.job.params.values,
                "seed": j.job.params.seed,
                "clock": run.clock().key(),
                "progress": progress,
                "target": run.length(),
                "label": label,
                "label_probability": probability,
                "error": error,
                "holder": matches!(j.state, JobState::Running)
                    .then(|| dir.holder())
                    .flatten(),
                "outdated": j.result.as_ref().and_then(|r| {
                    let def = j.job.params.def();
                    r.provenance
                        .outdated(def.version, crate::registry::analysis_of(def).version())
                        .map(|o| o.reason)
                }),
            })
        })
        .collect();
    json!({
        "sweep": sweep.name,
        "engine": sweep.spec.engine,
        "tables": dirs.tables,
        "counts": counts,
        "jobs": rows,
    })
}

pub fn run(args: StatusArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let jobs = tables::collect_checked(&sweep, &dirs, args.verify);
    if args.json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&status_json(&sweep, &dirs, &jobs))?
        );
        return damaged_error(&jobs);
    }
    let count = |name: &str| jobs.iter().filter(|j| j.state.name() == name).count();
    outln!(
        "sweep {} ({} jobs) in {}",
        sweep.name,
        jobs.len(),
        dirs.tables.display()
    );
    outln!(
        "  done {}  running {}  partial {}  pending {}  failed {}  damaged {}",
        count("done"),
        count("running"),
        count("partial"),
        count("pending"),
        count("failed"),
        count("damaged")
    );
    let mut swept = crate::sweep::phase::swept_in(&sweep);
    if sweep.spec.seeds.len() > 1 {
        swept.push("seed");
    }
    for j in &jobs {
        let run = &j.job.params.run;
        let (target, unit) = (run.length(), run.clock().unit());
        let line = match &j.state {
            JobState::Done => {
                let r = j.result.as_ref().expect("done jobs have results");
                let summary = r.analysis.summary();
                let p = summary.get("label_probability").and_then(|v| v.as_f64());
                let guard = summary
                    .get("collapse_guard_valid")
                    .and_then(|v| v.as_bool())
                    .unwrap_or(true);
                let def = j.job.params.def();
                let outdated = r
                    .provenance
                    .outdated(def.version, crate::registry::analysis_of(def).version())
                    .map_or(String::new(), |o| {
                        format!("  OUTDATED ({}; `run --rerun-outdated`)", o.reason)
                    });
                format!(
                    "done     {:.0}/{target:.0} {unit}  {}{}{}  {:.1} s  {:.2e} events/s{}{outdated}",
                    r.clock(run.clock()),
                    r.analysis.shown_label(),
                    p.map_or(String::new(), |p| format!(" (p = {p:.2})")),
                    if guard {
                        ""
                    } else {
                        "  COLLAPSE GUARD BEYOND VALIDITY"
                    },
                    r.wall_seconds,
                    r.events_per_second,
                    if r.stop_reason.is_empty() {
                        String::new()
                    } else {
                        format!("  [{}]", r.stop_reason)
                    }
                )
            }
            JobState::Partial(c) => {
                let dir = dirs.job(&j.job.id);
                match preparing_at(&dir) {
                    Some(steps) => format!(
                        "partial  preparing, step {steps} (resumes from its preparation checkpoint)"
                    ),
                    None => {
                        let c = c.on(run.clock());
                        format!("partial  {c:.0}/{target:.0} {unit} (resumes from its checkpoint)")
                    }
                }
            }
            JobState::Running => {
                let dir = dirs.job(&j.job.id);
                let by = dir.holder().map_or(String::new(), |h| format!("  [{h}]"));
                match (
                    dir.checkpoint_progress().map(|p| p.on(run.clock())),
                    preparing_at(&dir),
                ) {
                    (Some(c), _) => {
                        format!("running  {c:.0}/{target:.0} {unit} at the last checkpoint{by}")
                    }
                    (None, Some(steps)) => {
                        format!("running  preparing, step {steps} at the last checkpoint{by}")
                    }
                    (None, None) => format!("running  (claimed by a live runner){by}"),
                }
            }
            JobState::Pending => "pending".to_string(),
            JobState::Failed(e) => format!("FAILED   {e}"),
            JobState::Damaged { reason, .. } => {
                format!("DAMAGED  {reason} (set aside and recomputed by `run --retry-failed`)")
            }
        };
        let point = crate::sweep::phase::point_text(sweep.engine(), &j.job.params, &swept);
        outln!("  [{:>3}] {}  {point}  {line}", j.job.index, j.job.id);
    }
    if let Some(slurm) = crate::slurm::slurm_status(&dirs.tables)? {
        out!("{slurm}");
    }
    damaged_error(&jobs)
}

/// The command fails (exit 1) when a job's files are damaged, after reporting everything: a
/// script that checks `status` must not read a damaged sweep as healthy.
fn damaged_error(jobs: &[tables::GatheredJob]) -> anyhow::Result<()> {
    let damaged: Vec<&str> = jobs
        .iter()
        .filter(|j| matches!(j.state, JobState::Damaged { .. }))
        .map(|j| j.job.id.0.as_str())
        .collect();
    anyhow::ensure!(
        damaged.is_empty(),
        "{} damaged jobs ({}): `granflow run --retry-failed` sets their damaged files aside and \
         recomputes them",
        damaged.len(),
        damaged.join(", ")
    );
    Ok(())
}

/// The preparation's steps at a job's preparation checkpoint, when it is in the middle of its
/// preparation (no checkpoint yet).
fn preparing_at(dir: &crate::sweep::store::JobDir) -> Option<u64> {
    if dir.checkpoint_progress().is_some() {
        return None;
    }
    dir.preparation().ok().flatten().map(|p| p.steps)
}
