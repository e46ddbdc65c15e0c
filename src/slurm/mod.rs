//! Slurm scale-out: a sweep runs as job arrays whose tasks run the local runner's job code on
//! the same results directory (a shared file system); status from one batched squeue call.
//!
//! ```text
//! granflow slurm submit X.ron --> link.prepare (resolved sweep, plan order)
//!     --> split (T = ceil(n / J) tasks, arrays of <= MaxArraySize) --> script (one per array)
//!     --> sbatch --parsable --> record (slurm/submissions.json)
//! array task t --> granflow run <sweep copy> --job-range tJ:(t+1)J  (claims, resumes, skips done)
//! granflow status --> slurm_status: record + one squeue + job dirs + task exit records
//! ```
//! Layout inside `results/<sweep>/slurm/`: `scripts/submit<n>-array<k>.sbatch`,
//! `logs/<array>_<index>.log` (all attempts, appended), `tasks/<array>_<index>.exit`
//! (`<exit code> <restart count> <time>`), `submissions.json`.

pub mod config;
pub mod link;
pub mod record;
pub mod script;
pub mod split;
pub mod squeue;
pub mod status;
pub mod submit;

pub use link::{JobDirState, PreparedSweep, RunnerLink, SweepLink};
pub use script::SbatchOptions;
pub use status::{JobSlurmState, JobSlurmStatus, SlurmStatus, slurm_status_with};
pub use submit::{SubmitOptions, SubmitOutcome, submit};

use anyhow::Result;
use std::path::Path;

/// Slurm status of the sweep whose results directory is `results_dir` (`results/<sweep>/`);
/// `None` if it was never submitted to Slurm. One squeue call. For `granflow status`.
pub fn slurm_status(results_dir: &Path) -> Result<Option<SlurmStatus>> {
    slurm_status_with(&RunnerLink, results_dir)
}
