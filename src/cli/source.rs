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
    /// only jobs whose parameters meet this condition: KEY=V, KEY!=V, KEY<V, KEY<=V, KEY>V,
    /// KEY>=V (repeatable: all must hold), e.g. --where restitution=0.7
    #[arg(long = "where", value_name = "CONDITION")]
    pub conditions: Vec<String>,
}

impl SweepSource {
    /// The sweep and its result directories, its plan cut to the jobs that meet `--where`.
    pub fn open(&self) -> anyhow::Result<(Sweep, SweepDirs)> {
        let (mut sweep, dirs) = open_any(&self.sweep, &self.set, &self.results)?;
        let engine = sweep.engine();
        crate::sweep::select::retain(&mut sweep.plan, &self.conditions, engine)?;
        Ok((sweep, dirs))
    }
}
