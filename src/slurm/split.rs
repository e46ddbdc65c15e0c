//! Cutting a sweep into array tasks and the tasks into job arrays that respect `MaxArraySize`.
//!
//! With n jobs in plan order and J jobs per task, task t runs the jobs [t J, min((t+1) J, n)),
//! so there are T = ceil(n / J) tasks. Slurm caps the array *index* at MaxArraySize - 1, so the
//! tasks are cut into arrays of at most MaxArraySize tasks; each array's script adds its first
//! task number to `SLURM_ARRAY_TASK_ID`.

use serde::{Deserialize, Serialize};
use std::ops::Range;

/// One job array: its tasks are the global tasks `first_task .. first_task + tasks`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArrayChunk {
    /// Global task number of array index 0.
    pub first_task: usize,
    /// Number of array tasks (indices 0 ..= tasks - 1).
    pub tasks: usize,
}

/// Number of tasks T = ceil(n / J) for n jobs and J jobs per task.
pub fn task_count(jobs: usize, jobs_per_task: usize) -> usize {
    assert!(jobs_per_task > 0, "jobs per task must be positive");
    jobs.div_ceil(jobs_per_task)
}

/// The jobs (indices in plan order) that global task `task` runs.
pub fn task_jobs(task: usize, jobs_per_task: usize, jobs: usize) -> Range<usize> {
    let start = (task * jobs_per_task).min(jobs);
    start..(start + jobs_per_task).min(jobs)
}

/// Cut `tasks` tasks into arrays of at most `max_array_size` tasks each.
pub fn split_into_arrays(tasks: usize, max_array_size: usize) -> Vec<ArrayChunk> {
    assert!(max_array_size > 0, "MaxArraySize must be positive");
    (0..tasks)
        .step_by(max_array_size)
        .map(|first_task| ArrayChunk {
            first_task,
            tasks: max_array_size.min(tasks - first_task),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_job_belongs_to_exactly_one_task_and_every_task_to_one_array() {
        for jobs in [1usize, 2, 7, 12, 1001, 1002, 2500] {
            for jpt in [1usize, 2, 3, 10] {
                for max in [1usize, 2, 5, 1001] {
                    let tasks = task_count(jobs, jpt);
                    let arrays = split_into_arrays(tasks, max);
                    let mut seen = vec![0u32; jobs];
                    let mut next_task = 0;
                    for a in &arrays {
                        assert!(a.tasks >= 1 && a.tasks <= max, "{a:?} max {max}");
                        assert_eq!(a.first_task, next_task);
                        next_task += a.tasks;
                        for t in a.first_task..a.first_task + a.tasks {
                            let r = task_jobs(t, jpt, jobs);
                            assert!(!r.is_empty(), "task {t} has no job");
                            for j in r {
                                seen[j] += 1;
                            }
                        }
                    }
                    assert_eq!(next_task, tasks);
                    assert!(
                        seen.iter().all(|&c| c == 1),
                        "jobs {jobs} jpt {jpt} max {max}"
                    );
                }
            }
        }
    }

    #[test]
    fn max_array_size_caps_the_index() {
        // MaxArraySize 1001 allows indices 0..=1000: 1001 tasks fit in one array, 1002 do not.
        assert_eq!(split_into_arrays(1001, 1001).len(), 1);
        assert_eq!(
            split_into_arrays(1002, 1001),
            vec![
                ArrayChunk {
                    first_task: 0,
                    tasks: 1001
                },
                ArrayChunk {
                    first_task: 1001,
                    tasks: 1
                }
            ]
        );
        assert!(split_into_arrays(0, 1001).is_empty());
    }
}
