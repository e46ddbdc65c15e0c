//! How a job ends in error, by kind, so that whoever runs it decides by kind and not by reading
//! messages: a [`JobError::Resource`] error (the disk, not the job) leaves the job resumable and
//! stops the run from starting jobs; every other kind fails the job with its message.
//!
//! The messages are those the job's `failed` file and the run's `FAILED` line show.

use crate::analysis::AnalysisError;
use crate::engine::EngineError;

/// Why a job stopped without a result.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// parameters the engine cannot simulate (or drive by the run's clock), or analysis settings
    /// the analysis refuses: the job would fail the same way again
    #[error("{0}")]
    BadInput(String),
    /// a full disk, a quota, a file-size limit, a failing device or a read-only file system
    /// met while reading or writing the job's files: the job stays resumable
    #[error("{0:#}")]
    Resource(anyhow::Error),
    /// simulated time stopped advancing (inelastic collapse not cured by the TC model)
    #[error("simulation stalled: {0}")]
    Collapse(String),
    /// the engine failed otherwise (a checkpoint it cannot read back, one of another engine)
    #[error("{0}")]
    Engine(String),
    /// the analysis could not record a snapshot or analyse the records
    #[error("{0}")]
    Analysis(String),
    /// a job file could not be read or written for a reason that is not a resource error
    /// (a damaged checkpoint or record log, a missing file)
    #[error("{0:#}")]
    Store(anyhow::Error),
}

impl JobError {
    /// Whether the job stays resumable (a resource error) rather than failed.
    pub fn is_resource(&self) -> bool {
        matches!(self, JobError::Resource(_))
    }
}

impl From<EngineError> for JobError {
    fn from(e: EngineError) -> Self {
        match e {
            EngineError::Stalled(why) => JobError::Collapse(why),
            EngineError::InvalidParams(_) | EngineError::Clock { .. } => {
                JobError::BadInput(e.to_string())
            }
            EngineError::Checkpoint(_) => JobError::Engine(e.to_string()),
        }
    }
}

impl From<AnalysisError> for JobError {
    fn from(e: AnalysisError) -> Self {
        match e {
            AnalysisError::Settings(_) => JobError::BadInput(e.to_string()),
            AnalysisError::Content(_) | AnalysisError::Records(_) => {
                JobError::Analysis(e.to_string())
            }
        }
    }
}

/// A store error (the job's files): a resource error when an OS error of the disk is in it,
/// else a store error. The one place where a store error is sorted by kind.
impl From<anyhow::Error> for JobError {
    fn from(e: anyhow::Error) -> Self {
        if super::fs_error::is_resource_error(&e) {
            JobError::Resource(e)
        } else {
            JobError::Store(e)
        }
    }
}

impl From<std::io::Error> for JobError {
    fn from(e: std::io::Error) -> Self {
        JobError::from(anyhow::Error::new(e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fs::PathError;
    use std::path::Path;

    #[test]
    fn errors_sort_by_kind_with_their_messages() {
        let full: std::io::Error =
            PathError::new(Path::new("/r/x"), std::io::Error::from_raw_os_error(28)).into();
        let e = JobError::from(anyhow::Error::new(full).context("writing the checkpoint"));
        assert!(e.is_resource(), "{e:?}");
        assert!(e.to_string().starts_with("writing the checkpoint: "), "{e}");
        assert!(e.to_string().contains("/r/x"), "{e}");

        let missing = JobError::from(std::io::Error::from_raw_os_error(2));
        assert!(matches!(missing, JobError::Store(_)), "{missing:?}");

        let stalled = JobError::from(EngineError::Stalled("no time passed".into()));
        assert!(matches!(stalled, JobError::Collapse(_)));
        assert_eq!(stalled.to_string(), "simulation stalled: no time passed");

        let bad = JobError::from(EngineError::InvalidParams("N > capacity".into()));
        assert!(matches!(bad, JobError::BadInput(_)));
        assert_eq!(bad.to_string(), "invalid engine parameters: N > capacity");

        let settings = JobError::from(AnalysisError::Settings("grid > 0".into()));
        assert!(matches!(settings, JobError::BadInput(_)));
        let records = JobError::from(AnalysisError::Records("no sample".into()));
        assert!(matches!(records, JobError::Analysis(_)));
        assert_eq!(records.to_string(), "no sample");
    }
}
