//! `granflow plan SWEEP.ron`: list the jobs of a sweep (index, id, state, N, estimated work,
//! swept parameters, seed) without running anything.

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
}

pub fn run(args: PlanArgs) -> anyhow::Result<()> {
    let mut sweep = load_sweep(&args.sweep, &args.set)?;
    let engine = sweep.engine();
    crate::sweep::select::retain(&mut sweep.plan, &args.conditions, engine)?;
    let dirs = sweep.results_dir(&args.results);
    let jobs = tables::collect(&sweep, &dirs);
    let mut swept = phase::swept_in(&sweep);
    if swept.is_empty()
        && let Some(first) = engine.params.first()
    {
        swept.push(first.name);
    }
    println!(
        "sweep {}: {} jobs; tables in {}, jobs in {}",
        sweep.name,
        sweep.plan.len(),
        dirs.tables.display(),
        dirs.jobs.display()
    );
    let mut header = format!(
        "{:>5}  {:<16}  {:<8}  {:>8}  {:>10}",
        "index", "id", "state", engine.size_name, "work"
    );
    for s in &swept {
        header.push_str(&format!("  {s:>w$}", w = s.len().max(8)));
    }
    header.push_str("  seed");
    println!("{header}");
    let mut total_work = 0.0;
    for j in &jobs {
        let p = &j.job.params;
        total_work += p.estimated_work();
        let state = match &j.state {
            store::JobState::Partial(c) => {
                format!("{:.0}{}", c.on(p.run.clock()), p.run.clock().unit())
            }
            s => s.name().to_string(),
        };
        let mut line = format!(
            "{:>5}  {:<16}  {:<8}  {:>8}  {:>10.3e}",
            j.job.index,
            j.job.id.0,
            state,
            p.size(),
            p.estimated_work()
        );
        for s in &swept {
            line.push_str(&format!(
                "  {:>w$}",
                p.values.get(*s).map_or("-".into(), phase::fmt_value),
                w = s.len().max(8)
            ));
        }
        line.push_str(&format!("  {}", p.seed));
        println!("{line}");
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
        println!(
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
    println!(
        "estimated work: {total_work:.3e} {unit} (about {:.0} core-seconds at {:.1e} {unit}/s)",
        total_work / engine.work_rate,
        engine.work_rate,
        unit = engine.work_unit,
    );
    Ok(())
}
