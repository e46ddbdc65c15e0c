//! `granflow gather results/<sweep>`: write the Parquet tables of a results directory from its
//! job directories alone. With `--where` the selected jobs' tables go into a directory of
//! their own (`where/<conditions>/` under the sweep's tables), so the sweep's tables stay whole.

use super::out::outln;
use super::source::SweepSource;
use crate::sweep::{SweepDirs, override_tag, tables};
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow gather results/quick                      # (re)write results/quick/*.parquet
  granflow gather results/quick --where restitution=0.7   # into results/quick/where/restitution=0.7/
  granflow gather sweeps/quick.ron --results /scratch/me/results")]
pub struct GatherArgs {
    #[command(flatten)]
    pub source: SweepSource,
}

/// Where the tables of the jobs `--where` selects go: `<tables>/where/<conditions>/` (the
/// job directories stay the sweep's).
pub fn selection_dirs(dirs: &SweepDirs, conditions: &[String]) -> SweepDirs {
    SweepDirs {
        tables: dirs.tables.join("where").join(override_tag(conditions)),
        jobs: dirs.jobs.clone(),
    }
}

pub fn run(args: GatherArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let conditions = &args.source.conditions;
    let dirs = if conditions.is_empty() {
        dirs
    } else {
        selection_dirs(&dirs, conditions)
    };
    let written = tables::gather(&sweep, &dirs)?;
    let names: Vec<String> = written
        .tables
        .iter()
        .map(|n| format!("{n}.parquet"))
        .collect();
    outln!(
        "wrote {} in {}: {}{}",
        names.join(", "),
        dirs.tables.display(),
        written.counts(),
        if conditions.is_empty() {
            String::new()
        } else {
            format!(
                " (the jobs --where {} selects; the sweep's own tables are left as they were)",
                conditions.join(" ")
            )
        }
    );
    Ok(())
}
