//! `granflow gather results/<sweep>`: write the Parquet tables of a results directory from its
//! job directories alone.

use super::source::SweepSource;
use crate::sweep::tables;
use clap::Args;

#[derive(Debug, Args)]
pub struct GatherArgs {
    #[command(flatten)]
    pub source: SweepSource,
}

pub fn run(args: GatherArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let written = tables::gather(&sweep, &dirs)?;
    println!(
        "wrote jobs.parquet, spectra.parquet, profiles.parquet, energy.parquet in {}: {} jobs, {} done",
        dirs.tables.display(),
        written.jobs,
        written.done
    );
    Ok(())
}
