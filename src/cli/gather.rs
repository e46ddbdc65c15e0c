//! `granflow gather results/<sweep>`: write the Parquet tables of a results directory from its
//! job directories alone.

use super::out::outln;
use super::source::SweepSource;
use crate::sweep::tables;
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow gather results/quick                      # (re)write results/quick/*.parquet
  granflow gather sweeps/quick.ron --results /scratch/me/results")]
pub struct GatherArgs {
    #[command(flatten)]
    pub source: SweepSource,
}

pub fn run(args: GatherArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let written = tables::gather(&sweep, &dirs)?;
    let names: Vec<String> = written
        .tables
        .iter()
        .map(|n| format!("{n}.parquet"))
        .collect();
    outln!(
        "wrote {} in {}: {} jobs, {} done{}",
        names.join(", "),
        dirs.tables.display(),
        written.jobs,
        written.done,
        if args.source.conditions.is_empty() {
            String::new()
        } else {
            format!(
                " (the jobs --where {} selects)",
                args.source.conditions.join(" ")
            )
        }
    );
    Ok(())
}
