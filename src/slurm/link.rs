//! The seam between Slurm and the sweep runner: the two things `granflow slurm` needs to know
//! about a sweep, behind one trait so that the Slurm code is tested without the runner.
//!
//! - [`SweepLink::prepare`]: resolve the sweep file with its `--set` overrides, write the
//!   resolved sweep into the results directory (idempotent), and list the job ids in
//!   `granflow plan` order. Array task t runs the jobs at plan positions [t J, (t+1) J).
//! - [`SweepLink::job_states`]: whether each job's directory says done, failed (with its
//!   error) or neither.

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// A sweep ready to be run by array tasks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PreparedSweep {
    /// The sweep's name (`results/<name>/`).
    pub name: String,
    /// The sweep's results directory, `results/<sweep>/`, holding `jobs/<id>/`.
    pub sweep_dir: PathBuf,
    /// The value of `granflow run --results` that makes the runner use `sweep_dir`.
    pub results_arg: PathBuf,
    /// The resolved sweep file written into `sweep_dir` (what each task runs).
    pub sweep_file: PathBuf,
    /// Job ids in the deterministic plan order of `granflow plan` / `--job-range`.
    pub job_ids: Vec<String>,
}

/// What a job's directory says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JobDirState {
    Done,
    /// The runner recorded a failure, with its error message.
    Failed(String),
    /// Not started, or started (maybe with a checkpoint) but not finished.
    Unfinished,
}

/// What `granflow slurm` needs from the sweep runner.
pub trait SweepLink {
    /// Resolve, write the resolved sweep into its results directory, list the jobs.
    fn prepare(
        &self,
        sweep_file: &Path,
        results: Option<&Path>,
        sets: &[String],
    ) -> Result<PreparedSweep>;
    /// The states recorded in the job directories of these jobs (same order), for the sweep
    /// whose results directory (holding the resolved sweep) is `sweep_dir`.
    fn job_states(&self, sweep_dir: &Path, job_ids: &[String]) -> Result<Vec<JobDirState>>;
}

/// The real link, backed by the sweep runner (`crate::sweep`).
///
/// The sweep runner (`granflow run/plan/status/gather`, branch `sweep`) is being built in
/// parallel; until it is merged, both methods fail with a clear message. Wiring at merge:
/// `prepare` = parse + resolve the sweep with `sets`, write the resolved copy and job dirs as
/// `granflow run` does, return the plan order; `job_states` = the runner's own job-dir reader.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunnerLink;

const NOT_WIRED: &str = "granflow slurm needs the sweep runner (crate::sweep: plan order, \
    results directory, job states), which is not part of this build yet";

impl SweepLink for RunnerLink {
    fn prepare(
        &self,
        sweep_file: &Path,
        _results: Option<&Path>,
        _sets: &[String],
    ) -> Result<PreparedSweep> {
        bail!("{NOT_WIRED} (preparing {})", sweep_file.display())
    }

    fn job_states(&self, sweep_dir: &Path, _job_ids: &[String]) -> Result<Vec<JobDirState>> {
        bail!("{NOT_WIRED} (reading the jobs of {})", sweep_dir.display())
    }
}
