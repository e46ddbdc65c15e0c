//! The sweep a reporting command reads: a results directory, or a sweep file with its results
//! root and overrides (shared by `status`, `gather` and `phase-diagram`).

use crate::sweep::{Sweep, SweepDirs, open_any};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct SweepSource {
    /// a results directory (results/<sweep>) or a sweep file
    pub sweep: PathBuf,
    /// results root when a sweep file is given
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// overrides, as given to `run`, when a sweep file is given
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl SweepSource {
    /// The sweep and its result directories.
    pub fn open(&self) -> anyhow::Result<(Sweep, SweepDirs)> {
        Ok(open_any(&self.sweep, &self.set, &self.results)?)
    }
}
