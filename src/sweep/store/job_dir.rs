//! [`JobDir`]: one job's directory, a path wrapped with what may be done to the files in it
//! (after ripgrep's `haystack.rs`). Runner, executor, `status` and `report` go through its
//! methods; every error names the file it is about. Reads and writes return
//! `anyhow::Result` (a caller that decides by kind sorts it with `JobError::from`); a claim
//! is `Ok(Claim)` or why not ([`NotClaimed`], an I/O error included).

use super::{
    Claim, JobCheckpoint, JobResult, JobState, NotClaimed, RESULT_FILE, claim, records, result,
};
use crate::sweep::grid::PlannedJob;
use crate::sweep::job::JobParams;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// One job's directory (`<results>/jobs/<id>/`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobDir {
    path: PathBuf,
}

impl JobDir {
    /// The job directory at `path` (nothing is created).
    pub fn new(path: impl Into<PathBuf>) -> Self {
        JobDir { path: path.into() }
    }

    /// Where it is.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Create it and write `params.json` once (an existing one is kept).
    pub fn init(&self, job: &PlannedJob) -> anyhow::Result<()> {
        super::init_job_dir(&self.path, job)
            .with_context(|| format!("preparing the job directory {}", self.path.display()))
    }

    /// The job's state from its files and lock ([`super::job_state_checked`]); `verify` reads
    /// and checks a result instead of trusting its presence.
    pub fn state(&self, verify: bool) -> JobState {
        super::job_state_checked(&self.path, verify)
    }

    /// Whether a result is there (done, by presence).
    pub fn is_done(&self) -> bool {
        self.path.join(RESULT_FILE).exists()
    }

    /// Check a done job's checkpoint and record log ([`super::check_done_files`]): the
    /// damaged file and why.
    pub fn check_done_files(&self, full: bool) -> Result<(), (&'static str, String)> {
        super::check_done_files(&self.path, full)
    }

    /// The checked parameters from `params.json`.
    pub fn params(&self) -> anyhow::Result<JobParams> {
        super::read_params(&self.path)
    }

    /// Set aside a damaged `params.json` and write it anew from the plan (false when another
    /// runner holds the job).
    pub fn repair_params(&self, job: &PlannedJob, reason: &str) -> anyhow::Result<bool> {
        super::repair_params(&self.path, job, reason)
    }

    /// Claim the job (non-blocking): the claim, or why not.
    pub fn claim(&self, retry_failed: bool) -> Result<Claim, NotClaimed> {
        claim::try_claim(&self.path, retry_failed).unwrap_or_else(|e| {
            Err(NotClaimed::Unreadable(format!(
                "{}: {e}",
                self.path.display()
            )))
        })
    }

    /// Who holds the claim (the lock file's text), if anyone said.
    pub fn holder(&self) -> Option<String> {
        claim::holder(&self.path)
    }

    /// The last checkpoint, if any.
    pub fn checkpoint(&self) -> anyhow::Result<Option<JobCheckpoint>> {
        super::read_checkpoint(&self.path)
    }

    /// Replace the checkpoint (atomically).
    pub fn write_checkpoint(&self, cp: &JobCheckpoint) -> anyhow::Result<()> {
        super::write_checkpoint(&self.path, cp)
    }

    /// The preparation checkpoint, if the job is in the middle of its preparation.
    pub fn preparation(&self) -> anyhow::Result<Option<super::PreparationCheckpoint>> {
        super::read_preparation(&self.path)
    }

    /// Replace the preparation checkpoint (atomically).
    pub fn write_preparation(&self, cp: &super::PreparationCheckpoint) -> anyhow::Result<()> {
        super::write_preparation(&self.path, cp)
    }

    /// Remove the preparation checkpoint (checkpoint 0 holds the job now).
    pub fn remove_preparation(&self) -> anyhow::Result<()> {
        super::remove_preparation(&self.path)
    }

    /// The progress of the last checkpoint, if one is readable.
    pub fn checkpoint_progress(&self) -> Option<crate::engine::Progress> {
        super::checkpoint_progress(&self.path)
    }

    /// The records written so far (a running or stopped job's).
    pub fn records_so_far(&self) -> anyhow::Result<Vec<crate::analysis::Record>> {
        records::records_so_far(&self.path)
    }

    /// The checked result.
    pub fn result(&self) -> anyhow::Result<JobResult> {
        result::read_result(&self.path)
    }

    /// Write the result (atomically); its checksum.
    pub fn write_result(&self, r: &JobResult) -> anyhow::Result<String> {
        result::write_result(&self.path, r)
    }

    /// Append `<UTC time> <event>` to the job's log.
    pub fn log(&self, event: &str) -> anyhow::Result<()> {
        super::log(&self.path, event)
            .with_context(|| format!("writing {}", self.path.join(super::LOG_FILE).display()))
    }

    /// Add the log's `done` line a runner stopped before writing.
    pub fn complete_done_log(&self) -> anyhow::Result<()> {
        super::complete_done_log(&self.path)
            .with_context(|| format!("writing {}", self.path.join(super::LOG_FILE).display()))
    }

    /// When the job first started, if its log says.
    pub fn first_start(&self) -> Option<String> {
        super::first_start(&self.path)
    }

    /// Record a failure.
    pub fn mark_failed(&self, error: &str) -> anyhow::Result<()> {
        super::mark_failed(&self.path, error)
            .with_context(|| format!("writing {}", self.path.join(super::FAILED_FILE).display()))
    }

    /// Retire an outdated result ([`super::retire_if_outdated`]); why, or None.
    pub fn retire_if_outdated(
        &self,
        engine_version: u32,
        analysis_version: u32,
    ) -> anyhow::Result<Option<String>> {
        super::retire_if_outdated(&self.path, engine_version, analysis_version)
    }
}

impl AsRef<Path> for JobDir {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}
