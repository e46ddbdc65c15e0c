//! `granflow gather results/<sweep>`: write the Parquet tables of a results directory from its
//! job directories alone.

use crate::sweep::{open_any, tables};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct GatherArgs {
    /// a results directory (results/<sweep>) or a sweep file
    pub sweep: PathBuf,
    /// results root when a sweep file is given
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// overrides, as given to `run`, when a sweep file is given
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

pub fn run(args: GatherArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = open_any(&args.sweep, &args.set, &args.results)?;
    let written = tables::gather(&sweep, &dirs)?;
    println!(
        "wrote jobs.parquet, spectra.parquet, profiles.parquet, energy.parquet in {}: {} jobs, {} done",
        dirs.tables.display(),
        written.jobs,
        written.done
    );
    Ok(())
}
