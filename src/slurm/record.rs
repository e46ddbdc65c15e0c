//! `results/<sweep>/slurm/submissions.json`: which arrays run which jobs, so that status can map
//! an array task back to its jobs from the results directory alone.
//!
//! Every `granflow slurm submit` appends one [`Submission`]; a later submission of the same
//! sweep (e.g. after failures) takes over the jobs it covers. The file is rewritten atomically
//! (temp file, fsync, rename) under an exclusive lock on `slurm/.lock`.

use super::split::{ArrayChunk, task_jobs};
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::fs::{self, OpenOptions};
use std::path::{Path, PathBuf};

/// One job array of a submission.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubmittedArray {
    /// Slurm's array job id (`SLURM_ARRAY_JOB_ID`).
    pub array_job_id: String,
    /// The sbatch script, relative to the sweep's results directory.
    pub script: PathBuf,
    /// Which global tasks this array holds.
    pub chunk: ArrayChunk,
}

/// One `granflow slurm submit`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Submission {
    /// Seconds since the Unix epoch.
    pub submitted_at: u64,
    /// J, jobs per task.
    pub jobs_per_task: usize,
    /// The plan's job ids in plan order (task t runs `job_ids[t J .. (t+1) J]`).
    pub job_ids: Vec<String>,
    /// `--set` overrides of this submission.
    pub sets: Vec<String>,
    pub arrays: Vec<SubmittedArray>,
}

/// Where one job is run in Slurm.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TaskRef {
    pub array_job_id: String,
    /// Index inside the array (`SLURM_ARRAY_TASK_ID`).
    pub index: usize,
    /// Global task number.
    pub task: usize,
}

impl Submission {
    /// The array task that runs the job at `position` in plan order.
    pub fn task_of(&self, position: usize) -> Option<TaskRef> {
        let task = position / self.jobs_per_task;
        self.arrays.iter().find_map(|a| {
            (task >= a.chunk.first_task && task < a.chunk.first_task + a.chunk.tasks).then(|| {
                TaskRef {
                    array_job_id: a.array_job_id.clone(),
                    index: task - a.chunk.first_task,
                    task,
                }
            })
        })
    }

    /// The job ids that global task `task` runs.
    pub fn jobs_of_task(&self, task: usize) -> &[String] {
        &self.job_ids[task_jobs(task, self.jobs_per_task, self.job_ids.len())]
    }
}

/// All submissions of a sweep, oldest first.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SubmissionLog {
    pub submissions: Vec<Submission>,
}

/// `results/<sweep>/slurm/`.
pub fn slurm_dir(sweep_dir: &Path) -> PathBuf {
    sweep_dir.join("slurm")
}

/// `results/<sweep>/slurm/submissions.json`.
pub fn log_path(sweep_dir: &Path) -> PathBuf {
    slurm_dir(sweep_dir).join("submissions.json")
}

impl SubmissionLog {
    /// Read the log; `None` if the sweep was never submitted to Slurm.
    pub fn read(sweep_dir: &Path) -> Result<Option<Self>> {
        let path = log_path(sweep_dir);
        let text = match fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
        };
        let log: Self = serde_json::from_str(&text)
            .with_context(|| format!("parsing {} (Slurm submission record)", path.display()))?;
        for (i, s) in log.submissions.iter().enumerate() {
            if s.jobs_per_task == 0 {
                bail!("{}: submission {i} has jobs_per_task = 0", path.display());
            }
        }
        Ok(Some(log))
    }

    /// All array job ids, oldest first.
    pub fn array_job_ids(&self) -> Vec<String> {
        self.submissions
            .iter()
            .flat_map(|s| s.arrays.iter().map(|a| a.array_job_id.clone()))
            .collect()
    }
}

/// Append a submission to the sweep's log (locked, atomic rewrite).
pub fn append(sweep_dir: &Path, submission: Submission) -> Result<()> {
    let dir = slurm_dir(sweep_dir);
    fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let lock_path = dir.join(".lock");
    let lock = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&lock_path)
        .with_context(|| format!("opening {}", lock_path.display()))?;
    fs4::FileExt::lock(&lock).with_context(|| format!("locking {}", lock_path.display()))?;
    let mut log = SubmissionLog::read(sweep_dir)?.unwrap_or_default();
    log.submissions.push(submission);
    let text = serde_json::to_string_pretty(&log)?;
    write_atomically(&log_path(sweep_dir), text.as_bytes())
    // The lock is released when `lock` is dropped.
}

/// Write `bytes` to `path` through a temp file in the same directory, fsync, rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    crate::sweep::write_atomic(path, bytes).with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn submission(ids: &[&str], jpt: usize, arrays: &[(&str, usize, usize)]) -> Submission {
        Submission {
            submitted_at: 1,
            jobs_per_task: jpt,
            job_ids: ids.iter().map(|s| s.to_string()).collect(),
            sets: vec![],
            arrays: arrays
                .iter()
                .map(|&(id, first_task, tasks)| SubmittedArray {
                    array_job_id: id.into(),
                    script: format!("slurm/{id}.sbatch").into(),
                    chunk: ArrayChunk { first_task, tasks },
                })
                .collect(),
        }
    }

    #[test]
    fn maps_jobs_to_tasks_across_split_arrays() {
        // 5 jobs, 2 per task -> tasks 0,1,2; MaxArraySize 2 -> arrays 10 (tasks 0,1), 11 (task 2).
        let s = submission(&["a", "b", "c", "d", "e"], 2, &[("10", 0, 2), ("11", 2, 1)]);
        let refs: Vec<_> = (0..5)
            .map(|p| s.task_of(p).map(|t| (t.array_job_id, t.index, t.task)))
            .collect();
        assert_eq!(
            refs,
            vec![
                Some(("10".into(), 0, 0)),
                Some(("10".into(), 0, 0)),
                Some(("10".into(), 1, 1)),
                Some(("10".into(), 1, 1)),
                Some(("11".into(), 0, 2)),
            ]
        );
        assert_eq!(s.jobs_of_task(2), ["e".to_string()]);
        assert_eq!(s.task_of(6), None);
    }

    #[test]
    fn append_round_trips_and_keeps_order() {
        let dir = std::env::temp_dir().join(format!("granflow-record-test-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        assert_eq!(SubmissionLog::read(&dir).unwrap(), None);
        append(&dir, submission(&["a"], 1, &[("10", 0, 1)])).unwrap();
        append(&dir, submission(&["a"], 1, &[("12", 0, 1)])).unwrap();
        let log = SubmissionLog::read(&dir).unwrap().unwrap();
        assert_eq!(
            log.array_job_ids(),
            vec!["10".to_string(), "12".to_string()]
        );
        fs::write(log_path(&dir), "{ not json").unwrap();
        let err = SubmissionLog::read(&dir).unwrap_err();
        assert!(format!("{err:#}").contains("submissions.json"));
        let _ = fs::remove_dir_all(&dir);
    }
}
