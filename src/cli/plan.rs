//! `granflow plan SWEEP.ron`: list the jobs of a sweep (index, id, state, N, estimated work,
//! swept parameters, seed) without running anything.

use super::out::outln;
use crate::sweep::{load_sweep, phase, store, tables};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow plan sweeps/thesis-fig5-25.ron            # jobs, N and estimated work
  granflow plan sweeps/quick.ron --set 'restitution=range(0.5,0.9,0.1)' --set seeds=1,2")]
pub struct PlanArgs {
    /// the sweep file (sweeps/*.ron)
    pub sweep: PathBuf,
    /// results root (to show each job's state)
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// override a fixed value or an axis: key=value, key=v1,v2,... or a range,
    /// key=linspace(start,stop,count) (also logspace, range; repeatable)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// only jobs whose parameters meet this condition (repeatable), e.g. --where restitution=0.7
    #[arg(long = "where", value_name = "CONDITION")]
    pub conditions: Vec<String>,
    /// threads the sweep will run on (for the wall-time estimate; default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
}

pub fn run(args: PlanArgs) -> anyhow::Result<()> {
    let base = load_sweep(&args.sweep, &args.set)?;
    let engine = base.engine();
    let dirs = base.results_dir(&args.results);
    // with the points its refinement added so far
    let mut sweep = crate::sweep::rounds::replay(&base, &dirs)?.sweep;
    crate::sweep::select::retain(&mut sweep.plan, &args.conditions, engine)?;
    let jobs = tables::collect(&sweep, &dirs);
    let mut swept = phase::swept_in(&sweep);
    if swept.is_empty()
        && let Some(first) = engine.params.first()
    {
        swept.push(first.name);
    }
    outln!(
        "sweep {}: {} jobs; tables in {}, jobs in {}",
        sweep.name,
        sweep.plan.len(),
        dirs.tables.display(),
        dirs.jobs.display()
    );
    if let Some(line) = crate::sweep::rounds::bound(&base) {
        outln!("{line}");
    }
    let mut header = format!(
        "{:>5}  {:<16}  {:<8}  {:>8}  {:>10}",
        "index", "id", "state", engine.size_name, "work"
    );
    for s in &swept {
        header.push_str(&format!("  {s:>w$}", w = s.len().max(8)));
    }
    header.push_str("  seed");
    outln!("{header}");
    let estimate = crate::sweep::estimate::estimate(&jobs, &|job| dirs.job_dir(&job.id));
    for (j, e) in jobs.iter().zip(&estimate.jobs) {
        let p = &j.job.params;
        let state = match &j.state {
            store::JobState::Partial(c) => {
                format!("{:.0}{}", c.on(p.run.clock()), p.run.clock().unit())
            }
            s => s.name().to_string(),
        };
        let work = if e.least < e.most {
            format!("{:.2e}-{:.2e}", e.least, e.most)
        } else {
            format!("{:.3e}", e.most)
        };
        let mut line = format!(
            "{:>5}  {:<16}  {:<8}  {:>8}  {:>10}",
            j.job.index,
            j.job.id.0,
            state,
            p.size(),
            work
        );
        for s in &swept {
            line.push_str(&format!(
                "  {:>w$}",
                p.values.get(*s).map_or("-".into(), phase::fmt_value),
                w = s.len().max(8)
            ));
        }
        line.push_str(&format!("  {}", p.seed));
        outln!("{line}");
    }
    if let Some(st) = &sweep.spec.run.statistics {
        let run = &sweep.spec.run;
        let plan = crate::analysis::statistics::StatisticsPlan::for_run(
            st.clone(),
            run.clock(),
            run.length(),
            run.until_steady.is_some(),
        );
        let sampled = (1..=run.snapshot_count())
            .filter(|&k| plan.samples(k, run.snapshot_target(k)))
            .count();
        outln!(
            "statistics: {} slabs, window {}, r_max {} d: {sampled} statistics snapshots per job \
             (of {}; each costs one pass over the pairs closer than r_max), free paths tallied \
             throughout",
            st.bins,
            st.window.map_or(
                "as the structure analysis' (steady window, else final third)".to_string(),
                |w| format!("the last {w} {}", run.clock().key())
            ),
            st.r_max,
            run.snapshot_count()
        );
    }
    let threads = args
        .threads
        .unwrap_or_else(|| crate::sweep::runner::RunOptions::default().threads);
    let remaining: f64 = estimate.jobs.iter().map(|e| e.remaining).sum();
    let (least, most): (f64, f64) = estimate
        .jobs
        .iter()
        .fold((0.0, 0.0), |(a, b), e| (a + e.least, b + e.most));
    let range = if most > least {
        format!("{least:.3e} to {most:.3e}")
    } else {
        format!("{most:.3e}")
    };
    outln!(
        "work: {range} {unit} in all, {remaining:.3e} still to do{}",
        if most > least {
            " (a run until steady stops between its steady window (or last milestone) and its cap)"
        } else {
            ""
        },
        unit = engine.work_unit,
    );
    outln!(
        "estimated time still to go: {} core-hours, about {} wall on {threads} threads (longest job first), at {}",
        format_args!("{:.1}", estimate.core_seconds() / 3600.0),
        humantime::format_duration(std::time::Duration::from_secs(
            estimate.wall_seconds(threads) as u64
        )),
        estimate.rate_basis
    );
    Ok(())
}
