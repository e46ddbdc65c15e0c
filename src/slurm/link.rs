//! The seam between Slurm and the sweep runner: the two things `granflow slurm` needs to know
//! about a sweep, behind one trait so that the Slurm code is tested without the runner.
//!
//! - [`SweepLink::prepare`]: resolve the sweep file with its `--set` overrides, write the
//!   resolved sweep into the results directory (idempotent), and list the job ids in
//!   `granflow plan` order. Array task t runs the jobs at plan positions [t J, (t+1) J).
//! - [`SweepLink::job_states`]: whether each job's directory says done, failed (with its
//!   error) or neither.

use anyhow::Result;
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
    /// Job ids in the deterministic plan order of `granflow plan` / `--job-range` (of a
    /// refined sweep: those not done yet).
    pub job_ids: Vec<String>,
    /// the sweep has a `refine` section
    pub refining: bool,
    /// a refined sweep whose refinement is not complete: a one-task job after the arrays
    /// submits the next round ([`super::script::NextRoundScript`])
    pub next_round: bool,
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

/// The real link, backed by the sweep runner (`crate::sweep`): the same resolution, results
/// directories and job-directory states as `granflow run`.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunnerLink;

/// The results root of `granflow run` when `--results` is not given.
pub const DEFAULT_RESULTS_ROOT: &str = "results";

impl SweepLink for RunnerLink {
    fn prepare(
        &self,
        sweep_file: &Path,
        results: Option<&Path>,
        sets: &[String],
    ) -> Result<PreparedSweep> {
        use crate::sweep::{RESOLVED_SWEEP_FILE, load_sweep};
        let base = load_sweep(sweep_file, sets)?;
        let root = results.unwrap_or(Path::new(DEFAULT_RESULTS_ROOT));
        let dirs = base.results_dir(root);
        base.write_resolved(&dirs)?;
        // with the points its refinement added so far (none without a `refine` section)
        let refined = crate::sweep::rounds::replay(&base, &dirs)?;
        let sweep = &refined.sweep;
        for job in &sweep.plan {
            dirs.job(&job.id).init(job)?;
        }
        let mut plan: Vec<_> = sweep.plan.iter().collect();
        plan.sort_by_key(|j| j.index);
        let refining = base.spec.refine.is_some();
        if refining {
            // a round's submission runs the jobs not done yet (the earlier rounds' are)
            plan.retain(|j| !dirs.job(&j.id).is_done());
        }
        Ok(PreparedSweep {
            name: sweep.name.clone(),
            sweep_file: dirs.tables.join(RESOLVED_SWEEP_FILE),
            sweep_dir: dirs.tables,
            results_arg: root.to_path_buf(),
            job_ids: plan.iter().map(|j| j.id.0.clone()).collect(),
            refining,
            next_round: refining && !refined.complete,
        })
    }

    fn job_states(&self, sweep_dir: &Path, job_ids: &[String]) -> Result<Vec<JobDirState>> {
        use crate::sweep::{JobId, open_results, store};
        let (_, dirs) = open_results(sweep_dir)?;
        Ok(job_ids
            .iter()
            .map(|id| match dirs.job(&JobId(id.clone())).state(false) {
                store::JobState::Done => JobDirState::Done,
                store::JobState::Failed(e) => JobDirState::Failed(e),
                store::JobState::Damaged { reason, .. } => {
                    JobDirState::Failed(format!("damaged: {reason}"))
                }
                _ => JobDirState::Unfinished,
            })
            .collect())
    }
}
