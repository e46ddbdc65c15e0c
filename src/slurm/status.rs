//! Status of a Slurm-run sweep: each job's state from one batched squeue call, the job
//! directories, and the tasks' own exit records (no sacct).
//!
//! Per job, in this order: the job directory says done or failed -> that; else its task is in
//! squeue and active -> pending (with Slurm's reason) or running; else the task has ended ->
//! failed (exit code, Slurm state, log path) or unfinished (the task ended cleanly without
//! finishing the job, e.g. another runner held its lock).

use super::link::{JobDirState, SweepLink};
use super::record::{SubmissionLog, TaskRef};
use super::script::{task_exit_file, task_log};
use super::squeue::{self, QueueView};
use anyhow::Result;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// What a task recorded when its granflow command returned: `<exit code> <restart count> <time>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TaskExit {
    pub code: i32,
    pub restart_count: u32,
}

/// Read a task's exit record, if the task wrote one.
pub fn read_task_exit(path: &Path) -> Option<TaskExit> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut it = text.split_whitespace();
    let code = it.next()?.parse().ok()?;
    let restart_count = it.next()?.parse().ok()?;
    Some(TaskExit {
        code,
        restart_count,
    })
}

/// A job's state as seen through Slurm.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JobSlurmState {
    /// Waiting in Slurm; `reason` is squeue's (`JobArrayTaskLimit`, `Priority`, `BeginTime`...).
    Pending {
        reason: String,
    },
    /// Its task runs (`state` is RUNNING, COMPLETING, ...) on `nodes`.
    Running {
        state: String,
        nodes: String,
    },
    Done,
    /// The runner recorded an error, or the task ended without finishing the job.
    Failed {
        why: String,
        exit_code: Option<i32>,
    },
    /// The task ended with exit 0 but the job is not done (e.g. another runner holds it).
    Unfinished {
        why: String,
    },
    /// squeue could not be asked and the job directory says neither done nor failed.
    Unknown,
}

impl JobSlurmState {
    fn label(&self) -> &'static str {
        match self {
            Self::Pending { .. } => "pending",
            Self::Running { .. } => "running",
            Self::Done => "done",
            Self::Failed { .. } => "failed",
            Self::Unfinished { .. } => "unfinished",
            Self::Unknown => "unknown",
        }
    }
}

/// One job of a Slurm-run sweep.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JobSlurmStatus {
    pub job_id: String,
    pub task: TaskRef,
    pub state: JobSlurmState,
    /// The task's log (stdout and stderr, all attempts).
    pub log: PathBuf,
}

/// The Slurm view of a sweep, printable with `Display`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlurmStatus {
    pub sweep_dir: PathBuf,
    pub array_job_ids: Vec<String>,
    /// Jobs in the latest submission's plan order (then jobs only older submissions had).
    pub jobs: Vec<JobSlurmStatus>,
    /// Why squeue could not be asked, if it could not.
    pub queue_error: Option<String>,
}

impl SlurmStatus {
    /// Number of jobs per state label (`pending`, `running`, `done`, `failed`, ...).
    pub fn counts(&self) -> BTreeMap<&'static str, usize> {
        let mut c = BTreeMap::new();
        for j in &self.jobs {
            *c.entry(j.state.label()).or_insert(0) += 1;
        }
        c
    }

    /// True when no job is pending or running in Slurm (and squeue could be asked).
    pub fn is_settled(&self) -> bool {
        self.queue_error.is_none()
            && self.jobs.iter().all(|j| {
                !matches!(
                    j.state,
                    JobSlurmState::Pending { .. } | JobSlurmState::Running { .. }
                )
            })
    }
}

/// Build the status from the submission log, squeue's view and the job directories.
pub fn build_status(
    link: &dyn SweepLink,
    sweep_dir: &Path,
    log: &SubmissionLog,
    queue: std::result::Result<&QueueView, String>,
) -> Result<SlurmStatus> {
    // The latest submission covering a job decides which task runs it.
    let mut task_of: BTreeMap<&str, TaskRef> = BTreeMap::new();
    let mut order: Vec<&str> = Vec::new();
    for s in log.submissions.iter().rev() {
        for (pos, id) in s.job_ids.iter().enumerate() {
            if task_of.contains_key(id.as_str()) {
                continue;
            }
            if let Some(t) = s.task_of(pos) {
                task_of.insert(id, t);
                order.push(id);
            }
        }
    }
    let queue_error = queue.as_ref().err().cloned();
    let ids: Vec<String> = order.iter().map(|s| s.to_string()).collect();
    let dir_states = link.job_states(sweep_dir, &ids)?;
    anyhow::ensure!(
        dir_states.len() == ids.len(),
        "job states: asked for {} jobs, got {}",
        ids.len(),
        dir_states.len()
    );
    let mut jobs = Vec::with_capacity(order.len());
    for (id, dir_state) in order.into_iter().zip(dir_states) {
        let task = task_of[id].clone();
        let log_path = task_log(sweep_dir, &task.array_job_id, task.index);
        let state = match dir_state {
            JobDirState::Done => JobSlurmState::Done,
            JobDirState::Failed(err) => JobSlurmState::Failed {
                why: err,
                exit_code: exit_of(sweep_dir, &task).map(|e| e.code),
            },
            JobDirState::Unfinished => match &queue {
                Err(_) => JobSlurmState::Unknown,
                Ok(view) => unfinished_job_state(sweep_dir, &task, view),
            },
        };
        jobs.push(JobSlurmStatus {
            job_id: id.to_string(),
            task,
            state,
            log: log_path,
        });
    }
    Ok(SlurmStatus {
        sweep_dir: sweep_dir.to_path_buf(),
        array_job_ids: log.array_job_ids(),
        jobs,
        queue_error,
    })
}

fn exit_of(sweep_dir: &Path, task: &TaskRef) -> Option<TaskExit> {
    read_task_exit(&task_exit_file(sweep_dir, &task.array_job_id, task.index))
}

/// A job whose directory says neither done nor failed: ask its task.
fn unfinished_job_state(sweep_dir: &Path, task: &TaskRef, view: &QueueView) -> JobSlurmState {
    let queued = view.get(&(task.array_job_id.clone(), task.index));
    if let Some(q) = queued {
        if q.state == "PENDING" || q.state == "REQUEUED" || q.state == "REQUEUE_HOLD" {
            return JobSlurmState::Pending {
                reason: q.reason.clone(),
            };
        }
        if squeue::is_active(&q.state) {
            return JobSlurmState::Running {
                state: q.state.clone(),
                nodes: q.nodes.clone(),
            };
        }
    }
    let exit = exit_of(sweep_dir, task);
    let slurm_end = queued.map(|q| format!("Slurm state {} ({})", q.state, q.reason));
    match (exit, slurm_end) {
        (Some(e), _) if e.code == 0 => JobSlurmState::Unfinished {
            why: "task exited 0 without finishing this job".into(),
        },
        (Some(e), end) => JobSlurmState::Failed {
            why: match end {
                Some(end) => format!("task exited with code {}; {end}", e.code),
                None => format!("task exited with code {}", e.code),
            },
            exit_code: Some(e.code),
        },
        (None, Some(end)) => JobSlurmState::Failed {
            why: format!("task ended without an exit record; {end}"),
            exit_code: None,
        },
        (None, None) => JobSlurmState::Failed {
            why: "task is no longer in squeue and left no exit record (killed: time limit, \
                  cancel, node failure?)"
                .into(),
            exit_code: None,
        },
    }
}

/// Status of a Slurm-run sweep through the given link; `None` if it was never submitted.
pub fn slurm_status_with(link: &dyn SweepLink, sweep_dir: &Path) -> Result<Option<SlurmStatus>> {
    let Some(log) = SubmissionLog::read(sweep_dir)? else {
        return Ok(None);
    };
    let queue = squeue::query(&log.array_job_ids()).map_err(|e| format!("{e:#}"));
    build_status(link, sweep_dir, &log, queue.as_ref().map_err(|e| e.clone())).map(Some)
}

impl fmt::Display for SlurmStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Slurm: array job(s) {} ({} jobs)",
            self.array_job_ids.join(", "),
            self.jobs.len()
        )?;
        if let Some(e) = &self.queue_error {
            writeln!(
                f,
                "  squeue unavailable ({e}); states from the job directories only"
            )?;
        }
        let counts = self.counts();
        let order = [
            "pending",
            "running",
            "done",
            "failed",
            "unfinished",
            "unknown",
        ];
        let parts: Vec<String> = order
            .iter()
            .filter_map(|k| counts.get(k).map(|n| format!("{n} {k}")))
            .collect();
        writeln!(f, "  {}", parts.join(", "))?;
        for j in &self.jobs {
            let task = format!(
                "task {} ({}_{})",
                j.task.task, j.task.array_job_id, j.task.index
            );
            match &j.state {
                JobSlurmState::Done => continue,
                JobSlurmState::Pending { reason } => {
                    writeln!(f, "  pending    {}  {task}: {reason}", j.job_id)?
                }
                JobSlurmState::Running { state, nodes } => {
                    writeln!(f, "  running    {}  {task}: {state} on {nodes}", j.job_id)?
                }
                JobSlurmState::Failed { why, exit_code } => {
                    let code = exit_code
                        .map(|c| format!(", exit code {c}"))
                        .unwrap_or_default();
                    writeln!(
                        f,
                        "  failed     {}  {task}{code}: {why}; log {}",
                        j.job_id,
                        j.log.display()
                    )?
                }
                JobSlurmState::Unfinished { why } => writeln!(
                    f,
                    "  unfinished {}  {task}: {why}; log {}",
                    j.job_id,
                    j.log.display()
                )?,
                JobSlurmState::Unknown => writeln!(f, "  unknown    {}  {task}", j.job_id)?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::record::{Submission, SubmittedArray};
    use super::super::split::ArrayChunk;
    use super::super::squeue::parse_squeue;
    use super::*;
    use crate::slurm::link::PreparedSweep;

    /// Job states from a fixed table.
    struct TableLink(BTreeMap<String, JobDirState>);
    impl SweepLink for TableLink {
        fn prepare(&self, _: &Path, _: Option<&Path>, _: &[String]) -> Result<PreparedSweep> {
            unreachable!()
        }
        fn job_states(&self, _: &Path, ids: &[String]) -> Result<Vec<JobDirState>> {
            Ok(ids
                .iter()
                .map(|id| self.0.get(id).cloned().unwrap_or(JobDirState::Unfinished))
                .collect())
        }
    }

    #[test]
    fn maps_squeue_job_dirs_and_exit_records_onto_jobs() {
        let dir = std::env::temp_dir().join(format!("granflow-status-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("slurm/tasks")).unwrap();
        // Jobs a..f, one per task, array 40 (tasks 0-3) and 41 (tasks 4-5).
        let ids: Vec<String> = "abcdef".chars().map(|c| c.to_string()).collect();
        let log = SubmissionLog {
            submissions: vec![Submission {
                submitted_at: 0,
                jobs_per_task: 1,
                job_ids: ids.clone(),
                sets: vec![],
                arrays: vec![
                    SubmittedArray {
                        array_job_id: "40".into(),
                        script: "s0".into(),
                        chunk: ArrayChunk {
                            first_task: 0,
                            tasks: 4,
                        },
                    },
                    SubmittedArray {
                        array_job_id: "41".into(),
                        script: "s1".into(),
                        chunk: ArrayChunk {
                            first_task: 4,
                            tasks: 2,
                        },
                    },
                ],
            }],
        };
        let link = TableLink(BTreeMap::from([
            ("a".to_string(), JobDirState::Done),
            (
                "b".to_string(),
                JobDirState::Failed("phi not placeable".into()),
            ),
        ]));
        // c: running; d: pending (throttled); e: gone from squeue, exit record 3; f: gone, exit 0.
        std::fs::write(
            dir.join("slurm/tasks/41_0.exit"),
            "3 0 2026-11-23T12:00:00\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("slurm/tasks/41_1.exit"),
            "0 1 2026-11-23T12:00:00\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("slurm/tasks/40_1.exit"),
            "1 0 2026-11-23T12:00:00\n",
        )
        .unwrap();
        let view = parse_squeue(
            "40|0|COMPLETED|None|n1\n40|1|FAILED|NonZeroExitCode|n1\n\
             40|2|RUNNING|None|n2\n40|3|PENDING|JobArrayTaskLimit|\n",
        )
        .unwrap();
        let st = build_status(&link, &dir, &log, Ok(&view)).unwrap();
        let states: Vec<_> = st
            .jobs
            .iter()
            .map(|j| (j.job_id.as_str(), j.state.clone()))
            .collect();
        assert_eq!(states[0], ("a", JobSlurmState::Done));
        assert_eq!(
            states[1],
            (
                "b",
                JobSlurmState::Failed {
                    why: "phi not placeable".into(),
                    exit_code: Some(1)
                }
            )
        );
        assert_eq!(
            states[2],
            (
                "c",
                JobSlurmState::Running {
                    state: "RUNNING".into(),
                    nodes: "n2".into()
                }
            )
        );
        assert_eq!(
            states[3],
            (
                "d",
                JobSlurmState::Pending {
                    reason: "JobArrayTaskLimit".into()
                }
            )
        );
        assert!(matches!(
            &states[4].1,
            JobSlurmState::Failed {
                exit_code: Some(3),
                ..
            }
        ));
        assert!(matches!(&states[5].1, JobSlurmState::Unfinished { .. }));
        assert_eq!(st.jobs[4].log, dir.join("slurm/logs/41_0.log"));
        assert!(!st.is_settled());
        let text = st.to_string();
        assert!(
            text.contains("1 pending, 1 running, 1 done, 2 failed, 1 unfinished"),
            "{text}"
        );
        assert!(text.contains("slurm/logs/41_0.log"), "{text}");
        assert!(text.contains("exit code 3"), "{text}");
        // Without squeue, unfinished jobs are unknown and the status says why.
        let st = build_status(&link, &dir, &log, Err("no squeue".into())).unwrap();
        assert_eq!(st.jobs[2].state, JobSlurmState::Unknown);
        assert!(st.to_string().contains("squeue unavailable (no squeue)"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_later_submission_takes_over_its_jobs() {
        let sub = |array: &str| Submission {
            submitted_at: 0,
            jobs_per_task: 2,
            job_ids: vec!["x".into(), "y".into()],
            sets: vec![],
            arrays: vec![SubmittedArray {
                array_job_id: array.into(),
                script: "s".into(),
                chunk: ArrayChunk {
                    first_task: 0,
                    tasks: 1,
                },
            }],
        };
        let log = SubmissionLog {
            submissions: vec![sub("7"), sub("9")],
        };
        let view = parse_squeue("9|0|RUNNING|None|n\n").unwrap();
        let link = TableLink(BTreeMap::new());
        let st = build_status(&link, Path::new("/nonexistent"), &log, Ok(&view)).unwrap();
        assert_eq!(st.jobs.len(), 2);
        assert!(st.jobs.iter().all(|j| j.task.array_job_id == "9"));
        assert!(
            st.jobs
                .iter()
                .all(|j| matches!(j.state, JobSlurmState::Running { .. }))
        );
    }
}
