//! `granflow status [SWEEP.ron | results/<sweep>]`: counts by state, per-job progress and
//! failures with their errors.

use super::source::SweepSource;
use crate::sweep::{store, store::JobState, tables};
use clap::Args;

#[derive(Debug, Args)]
pub struct StatusArgs {
    #[command(flatten)]
    pub source: SweepSource,
}

pub fn run(args: StatusArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let jobs = tables::collect(&sweep, &dirs);
    let count = |name: &str| jobs.iter().filter(|j| j.state.name() == name).count();
    println!(
        "sweep {} ({} jobs) in {}",
        sweep.name,
        jobs.len(),
        dirs.tables.display()
    );
    println!(
        "  done {}  running {}  partial {}  pending {}  failed {}  damaged {}",
        count("done"),
        count("running"),
        count("partial"),
        count("pending"),
        count("failed"),
        count("damaged")
    );
    for j in &jobs {
        let run = &j.job.params.run;
        let (target, unit) = (run.length(), run.clock().unit());
        let line = match &j.state {
            JobState::Done => {
                let r = j.result.as_ref().expect("done jobs have results");
                let summary = r.analysis.summary();
                let (label, humps) = r.analysis.label();
                let p = summary.get("label_probability").and_then(|v| v.as_f64());
                let guard = summary
                    .get("collapse_guard_valid")
                    .and_then(|v| v.as_bool())
                    .unwrap_or(true);
                format!(
                    "done     {:.0}/{target:.0} {unit}  {}{}{}  {:.1} s  {:.2e} events/s{}",
                    r.clock(run.clock()),
                    crate::analysis::labels::label_key(label, humps),
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
                let c = c.on(run.clock());
                format!("partial  {c:.0}/{target:.0} {unit} (resumes from its checkpoint)")
            }
            JobState::Running => {
                let dir = dirs.job_dir(&j.job.id);
                match store::checkpoint_progress(&dir).map(|p| p.on(run.clock())) {
                    Some(c) => format!("running  {c:.0}/{target:.0} {unit} at the last checkpoint"),
                    None => "running  (claimed by a live runner)".to_string(),
                }
            }
            JobState::Pending => "pending".to_string(),
            JobState::Failed(e) => format!("FAILED   {e}"),
            JobState::Damaged { reason, .. } => {
                format!("DAMAGED  {reason} (set aside and recomputed by `run --retry-failed`)")
            }
        };
        println!("  [{:>3}] {}  {line}", j.job.index, j.job.id);
    }
    if let Some(slurm) = crate::slurm::slurm_status(&dirs.tables)? {
        print!("{slurm}");
    }
    Ok(())
}
