//! Sweeps on a real Slurm (the single-node cluster of `.ci/slurm-up.sh`).
//!
//! - `arrays_throttle_requeue_and_status_with_a_stand_in_runner`: the Slurm side alone (split
//!   arrays, `%K` throttle, logs, exit records, requeue, status) with a small bash stand-in for
//!   `granflow run --job-range` that has the runner's contract (skip done/failed jobs, resume
//!   from a checkpoint, record done atomically).
//! - `sweep_on_slurm_equals_local_run`: the real runner end to end: tables equal to a local
//!   run, cancel + requeue resumes from the checkpoint, a task whose jobs are done is a no-op.
//!
//! Without `sbatch` on PATH both print "SKIPPED: slurm not installed" and return.

use granflow::slurm::{
    self, JobDirState, JobSlurmState, PreparedSweep, SbatchOptions, SlurmStatus, SubmitOptions,
    SweepLink,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// One test at a time on the 2-CPU test cluster.
static CLUSTER: Mutex<()> = Mutex::new(());

fn slurm_installed(test: &str) -> bool {
    let found = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).any(|d| d.join("sbatch").is_file()))
        .unwrap_or(false);
    if !found {
        eprintln!("SKIPPED: slurm not installed (no sbatch on PATH): {test}");
    }
    found
}

use crate::common::scratch;

fn run_ok(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{cmd:?} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Poll `status` (one squeue call each time) until `done` holds; panic after `timeout`.
fn wait_for(
    what: &str,
    timeout: Duration,
    mut status: impl FnMut() -> SlurmStatus,
    mut done: impl FnMut(&SlurmStatus) -> bool,
) -> SlurmStatus {
    let start = Instant::now();
    loop {
        let st = status();
        if done(&st) {
            return st;
        }
        assert!(
            start.elapsed() < timeout,
            "timed out waiting for {what}; last status:\n{st}"
        );
        std::thread::sleep(Duration::from_secs(1));
    }
}

fn squeue_state(array: &str, index: usize) -> String {
    let out = Command::new("squeue")
        .args(["--noheader", "--array", "--states=all", "--format=%T"])
        .arg(format!("--jobs={array}_{index}"))
        .output()
        .unwrap();
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Cancel a running array task and requeue it (as after preemption); it waits ~2 min to rerun.
fn cancel_and_requeue(array: &str, index: usize) {
    let task = format!("{array}_{index}");
    run_ok(Command::new("scancel").arg(&task));
    let start = Instant::now();
    while squeue_state(array, index) != "CANCELLED" {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{task} did not get cancelled"
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    run_ok(Command::new("scontrol").args(["requeue", &task]));
}

// ---------------------------------------------------------------------------------------------
// The Slurm side with a stand-in runner.

/// Stand-in for `granflow run <sweep> --results R --threads N --job-range A:B`: job i (id
/// `job<i>`) takes 6 steps of 1 s, checkpointing each step to `jobs/<id>/checkpoint`; it skips
/// done and failed jobs, resumes from the checkpoint, and job `job3` fails (exit 1 at the end).
const STAND_IN: &str = r#"#!/bin/bash
set -u
SWEEP_DIR=$(dirname "$2")
RANGE=""
while [ $# -gt 0 ]; do
  if [ "$1" = "--job-range" ]; then RANGE=$2; fi
  shift
done
A=${RANGE%%:*}; B=${RANGE##*:}
STATUS=0
for ((i=A; i<B; i++)); do
  D="$SWEEP_DIR/jobs/job$i"; mkdir -p "$D"
  if [ -e "$D/done" ] || [ -e "$D/failed" ]; then echo "job$i already finished: skipped"; continue; fi
  echo "RUN job$i"
  echo "start $(date +%s.%N)" >> "$D/timeline"
  STEP=0
  if [ -e "$D/checkpoint" ]; then STEP=$(cat "$D/checkpoint"); echo "job$i resuming from checkpoint step $STEP"; fi
  while [ "$STEP" -lt 6 ]; do sleep 1; STEP=$((STEP+1)); echo $STEP > "$D/checkpoint.tmp"; mv "$D/checkpoint.tmp" "$D/checkpoint"; done
  echo "end $(date +%s.%N)" >> "$D/timeline"
  if [ "$i" -eq 3 ]; then echo "deliberate failure" > "$D/failed"; STATUS=1; continue; fi
  echo "FINISH job$i"
  echo ok > "$D/done.tmp"; mv "$D/done.tmp" "$D/done"
done
exit $STATUS
"#;

struct StandInLink {
    jobs: usize,
}

impl SweepLink for StandInLink {
    fn prepare(
        &self,
        sweep_file: &Path,
        results: Option<&Path>,
        _sets: &[String],
    ) -> anyhow::Result<PreparedSweep> {
        let root = results.unwrap().to_path_buf();
        let sweep_dir = root.join("standin");
        std::fs::create_dir_all(sweep_dir.join("jobs"))?;
        let copy = sweep_dir.join("sweep.ron");
        std::fs::copy(sweep_file, &copy)?;
        Ok(PreparedSweep {
            name: "standin".into(),
            sweep_dir,
            results_arg: root,
            sweep_file: copy,
            job_ids: (0..self.jobs).map(|i| format!("job{i}")).collect(),
            refining: false,
            next_round: false,
        })
    }

    fn job_states(&self, sweep_dir: &Path, ids: &[String]) -> anyhow::Result<Vec<JobDirState>> {
        Ok(ids
            .iter()
            .map(|id| {
                let d = sweep_dir.join("jobs").join(id);
                if d.join("done").exists() {
                    JobDirState::Done
                } else if let Ok(e) = std::fs::read_to_string(d.join("failed")) {
                    JobDirState::Failed(e.trim().to_string())
                } else {
                    JobDirState::Unfinished
                }
            })
            .collect())
    }
}

/// (start, end) times of every run of every job, from the stand-in's timelines.
fn timelines(sweep_dir: &Path, jobs: usize) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    for i in 0..jobs {
        let text = std::fs::read_to_string(sweep_dir.join(format!("jobs/job{i}/timeline")))
            .unwrap_or_default();
        let mut start = None;
        for line in text.lines() {
            let (kind, t) = line.split_once(' ').unwrap();
            let t: f64 = t.parse().unwrap();
            match kind {
                "start" => start = Some(t),
                _ => spans.push((start.take().unwrap(), t)),
            }
        }
    }
    spans
}

fn max_overlap(spans: &[(f64, f64)]) -> usize {
    let mut events: Vec<(f64, i32)> = spans.iter().flat_map(|&(a, b)| [(a, 1), (b, -1)]).collect();
    events.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let (mut now, mut max) = (0i32, 0i32);
    for (_, d) in events {
        now += d;
        max = max.max(now);
    }
    max as usize
}

fn count_in_logs(sweep_dir: &Path, needle: &str) -> usize {
    let mut n = 0;
    for e in std::fs::read_dir(sweep_dir.join("slurm/logs")).unwrap() {
        let text = std::fs::read_to_string(e.unwrap().path()).unwrap();
        n += text.lines().filter(|l| *l == needle).count();
    }
    n
}

#[test]
fn arrays_throttle_requeue_and_status_with_a_stand_in_runner() {
    if !slurm_installed("arrays_throttle_requeue_and_status_with_a_stand_in_runner") {
        return;
    }
    let _cluster = CLUSTER.lock().unwrap_or_else(|e| e.into_inner());
    // A space in the path checks the quoting of the script's paths.
    let root = scratch("slurm stand-in");
    let stand_in = root.join("granflow-stand-in");
    std::fs::write(&stand_in, STAND_IN).unwrap();
    run_ok(Command::new("chmod").arg("+x").arg(&stand_in));
    let sweep_file = root.join("standin.ron");
    std::fs::write(&sweep_file, "(name: \"standin\")\n").unwrap();
    let jobs = 5;
    let link = StandInLink { jobs };
    let opts = SubmitOptions {
        sweep_file,
        results: Some(root.join("results")),
        sets: vec!["restitution=0.9".into()],
        sbatch: SbatchOptions {
            partition: None,
            time: Some("10:00".into()),
            cpus_per_task: 1,
            max_parallel: Some(2),
            extra: vec!["--job-name=granflow-test-standin".into()],
        },
        jobs_per_task: 1,
        granflow: Some(stand_in),
        // A cap of 2 tasks per array: 5 tasks -> arrays of 2, 2, 1, chained.
        max_array_size: Some(2),
        dry_run: false,
    };
    let out = slurm::submit(&link, &opts).unwrap();
    assert_eq!(out.array_job_ids.len(), 3, "{out:?}");
    let sweep_dir = out.sweep.sweep_dir.clone();
    let status = || {
        slurm::slurm_status_with(&link, &sweep_dir)
            .unwrap()
            .unwrap()
    };

    // Cancel job0's task once it has a checkpoint, then requeue it.
    let first = out.array_job_ids[0].clone();
    let start = Instant::now();
    while !sweep_dir.join("jobs/job0/checkpoint").exists() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "job0 never started:\n{}",
            status()
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    cancel_and_requeue(&first, 0);
    let st = status();
    assert!(
        matches!(st.jobs[0].state, JobSlurmState::Pending { .. }),
        "requeued task should be pending:\n{st}"
    );

    let st = wait_for(
        "the stand-in sweep",
        Duration::from_secs(600),
        status,
        |s| s.is_settled(),
    );
    eprintln!("{st}");
    let counts = st.counts();
    assert_eq!(counts.get("done"), Some(&4), "{st}");
    assert_eq!(counts.get("failed"), Some(&1), "{st}");
    let failed = &st.jobs[3];
    assert_eq!(failed.job_id, "job3");
    assert_eq!(
        failed.state,
        JobSlurmState::Failed {
            why: "deliberate failure".into(),
            exit_code: Some(1)
        }
    );
    assert!(failed.log.is_file(), "{}", failed.log.display());
    let text = st.to_string();
    assert!(text.contains(&failed.log.display().to_string()) && text.contains("exit code 1"));

    // Throttle: at most 2 jobs ever ran at once, across the three arrays.
    let spans = timelines(&sweep_dir, jobs);
    assert!(
        max_overlap(&spans) <= 2,
        "more than 2 tasks at once: {spans:?}"
    );
    // Requeue: one log, two attempts, the second resumed from job0's checkpoint.
    let log0 = std::fs::read_to_string(&st.jobs[0].log).unwrap();
    assert!(
        log0.contains(" attempt 1 ") && log0.contains(" attempt 2 "),
        "{log0}"
    );
    let second = &log0[log0.find(" attempt 2 ").unwrap()..];
    assert!(
        second.contains("job0 resuming from checkpoint step"),
        "{log0}"
    );
    // Every job finished exactly once (job3 failed once, never finished).
    for i in 0..jobs {
        let want = usize::from(i != 3);
        assert_eq!(
            count_in_logs(&sweep_dir, &format!("FINISH job{i}")),
            want,
            "job{i}"
        );
    }
    let runs_before = count_in_logs(&sweep_dir, "RUN job1");

    // Resubmitting the finished sweep: every task is a no-op and exits 0.
    let again = slurm::submit(&link, &opts).unwrap();
    let st = wait_for(
        "the no-op resubmission",
        Duration::from_secs(300),
        status,
        |s| {
            s.is_settled()
                && again.array_job_ids.iter().all(|a| {
                    (0..2).all(|i| !matches!(squeue_state(a, i).as_str(), "PENDING" | "RUNNING"))
                })
        },
    );
    assert!(
        st.jobs
            .iter()
            .all(|j| again.array_job_ids.contains(&j.task.array_job_id))
    );
    assert_eq!(st.counts().get("done"), Some(&4), "{st}");
    assert_eq!(count_in_logs(&sweep_dir, "RUN job1"), runs_before);
    for j in &st.jobs {
        let exit = slurm::status::read_task_exit(&slurm::script::task_exit_file(
            &sweep_dir,
            &j.task.array_job_id,
            j.task.index,
        ))
        .unwrap_or_else(|| panic!("no exit record for {}", j.job_id));
        assert_eq!(exit.code, 0, "no-op task of {} failed", j.job_id);
    }
    let _ = std::fs::remove_dir_all(&root);
}

// ---------------------------------------------------------------------------------------------
// The real runner.

/// The sweep run both locally and on Slurm: 4 jobs of some 5-10 s each (polled every second),
/// long enough for a task to be cancelled after its job wrote a checkpoint (one per snapshot).
const SWEEP_RON: &str = r#"(
    name: Some("slurmtest"),
    engine: "edmd",
    fixed: (
        width_over_diameter: Some(10.0),
        height_over_diameter: Some(10.0),
        volume_fraction: Some(0.15),
    ),
    axes: (length_over_width: Some([3.0, 4.0]), restitution: Some([0.7, 0.9])),
    seeds: [1],
    run: (collisions_per_particle: 8000.0, snapshot_interval: 200.0, checkpoint_every: 1),
)
"#;
/// Overrides applied to both runs.
const SETS: &[&str] = &[];
/// A job directory's own log (`sweep::queue::LOG_FILE`): "start", "resume at snapshot k",
/// "done", "failed: ..." lines.
const JOB_LOG: &str = "log.txt";

fn granflow() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_granflow"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn with_sets(mut c: Command) -> Command {
    for s in SETS {
        c.arg("--set").arg(s);
    }
    c
}

/// The sweep's results directory: the one directory under `root` holding `jobs/`.
fn sweep_dir_under(root: &Path) -> PathBuf {
    let dirs: Vec<PathBuf> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("jobs").is_dir())
        .collect();
    assert_eq!(
        dirs.len(),
        1,
        "expected one sweep directory under {}: {dirs:?}",
        root.display()
    );
    dirs.into_iter().next().unwrap()
}

fn files_with_mtimes(dir: &Path, out: &mut BTreeMap<PathBuf, std::time::SystemTime>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            files_with_mtimes(&p, out);
        } else {
            out.insert(
                p.clone(),
                std::fs::metadata(&p).unwrap().modified().unwrap(),
            );
        }
    }
}

/// A table's columns of scalar types (the tests' polars lacks `dtype-struct`, so the
/// list-of-struct columns of jobs.parquet are left out).
fn read_parquet(path: &Path) -> polars::prelude::DataFrame {
    use polars::prelude::*;
    let open = || std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let schema = ParquetReader::new(open()).schema().unwrap();
    let scalar: Vec<String> = schema
        .iter()
        .filter(|(_, f)| !f.dtype.is_nested())
        .map(|(name, _)| name.to_string())
        .collect();
    ParquetReader::new(open())
        .with_columns(Some(scalar))
        .finish()
        .unwrap()
}

/// Columns that must agree between two runs of the same jobs: the id, the labels and every
/// integer column (counts) except wall-clock ones.
fn comparable_columns(df: &polars::prelude::DataFrame) -> Vec<String> {
    df.columns()
        .iter()
        .filter(|c| {
            let name = c.name().to_lowercase();
            let integer = c.dtype().is_integer();
            let text = c.dtype() == &polars::prelude::DataType::String;
            let clock = ["wall", "time", "per_s", "rate", "elapsed"]
                .iter()
                .any(|w| name.contains(w));
            !clock
                && (integer
                    || (text
                        && (name.contains("id")
                            || name.contains("label")
                            || name.contains("state"))))
        })
        .map(|c| c.name().to_string())
        .collect()
}

fn sorted_rows(df: &polars::prelude::DataFrame, cols: &[String]) -> Vec<String> {
    let mut rows: Vec<String> = (0..df.height())
        .map(|i| {
            cols.iter()
                .map(|c| format!("{}={}", c, df.column(c).unwrap().get(i).unwrap()))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    rows.sort();
    rows
}

#[test]
fn sweep_on_slurm_equals_local_run() {
    if !slurm_installed("sweep_on_slurm_equals_local_run") {
        return;
    }
    let _cluster = CLUSTER.lock().unwrap_or_else(|e| e.into_inner());
    let root = scratch("slurm-sweep");
    let sweep_file = root.join("slurmtest.ron");
    std::fs::write(&sweep_file, SWEEP_RON).unwrap();

    // 1. The local run, and its tables.
    let local_root = root.join("local");
    let mut c = granflow();
    c.arg("run")
        .arg(&sweep_file)
        .arg("--results")
        .arg(&local_root)
        .args(["--threads", "2"]);
    run_ok(&mut with_sets(c));
    let local_dir = sweep_dir_under(&local_root);
    run_ok(granflow().arg("gather").arg(&local_dir));

    // 2. The same sweep on Slurm, at most 2 tasks at once.
    let slurm_root = root.join("slurm");
    let mut c = granflow();
    c.args(["slurm", "submit"])
        .arg(&sweep_file)
        .args(["--max-parallel", "2", "--cpus-per-task", "1"])
        .args(["--time", "60:00", "--results"])
        .arg(&slurm_root);
    let printed = run_ok(&mut with_sets(c));
    let arrays: Vec<String> = printed
        .lines()
        .filter_map(|l| l.strip_prefix("submitted array job "))
        .map(str::to_string)
        .collect();
    assert_eq!(arrays.len(), 1, "{printed}");
    let sweep_dir = sweep_dir_under(&slurm_root);
    let status = || {
        slurm::slurm_status(&sweep_dir)
            .unwrap()
            .expect("submitted sweep")
    };
    let n_jobs = status().jobs.len();
    assert!(
        n_jobs >= 3,
        "the test sweep should have a handful of jobs, has {n_jobs}"
    );

    // 3. Cancel a running task once its job has written a checkpoint; requeue it.
    let has_checkpoint = |id: &str| {
        std::fs::read_dir(sweep_dir.join("jobs").join(id)).is_ok_and(|rd| {
            rd.filter_map(Result::ok)
                .any(|e| e.file_name().to_string_lossy().contains("checkpoint"))
        })
    };
    let st = wait_for(
        "a running job with a checkpoint",
        Duration::from_secs(600),
        status,
        |s| {
            s.jobs.iter().any(|j| {
                matches!(j.state, JobSlurmState::Running { .. }) && has_checkpoint(&j.job_id)
            })
        },
    );
    let victim = st
        .jobs
        .iter()
        .find(|j| matches!(j.state, JobSlurmState::Running { .. }) && has_checkpoint(&j.job_id))
        .unwrap()
        .clone();
    cancel_and_requeue(&victim.task.array_job_id, victim.task.index);

    // 4. Wait for everything (the requeued task waits ~2 min before it runs again).
    let st = wait_for("the Slurm sweep", Duration::from_secs(1800), status, |s| {
        s.is_settled()
    });
    eprintln!("{st}");
    assert_eq!(
        st.counts().get("done"),
        Some(&n_jobs),
        "not all jobs done:\n{st}"
    );
    let task_log = std::fs::read_to_string(&victim.log).unwrap();
    assert!(
        task_log.contains(" attempt 1 ") && task_log.contains(" attempt 2 "),
        "the requeued task did not run twice:\n{task_log}"
    );
    // Each job started once, finished once; the victim resumed from its checkpoint in between.
    for j in &st.jobs {
        let log = std::fs::read_to_string(sweep_dir.join("jobs").join(&j.job_id).join(JOB_LOG))
            .unwrap_or_default();
        // the event word of each line, without its time and details
        let lines: Vec<&str> = granflow::sweep::store::log_events(&log)
            .into_iter()
            .map(|e| e.split(' ').next().unwrap_or(""))
            .collect();
        let at = |p: &dyn Fn(&str) -> bool| lines.iter().position(|l| p(l));
        assert_eq!(
            lines.iter().filter(|l| **l == "start").count(),
            1,
            "{}: {log}",
            j.job_id
        );
        assert_eq!(
            lines.iter().filter(|l| **l == "done").count(),
            1,
            "{}: {log}",
            j.job_id
        );
        if j.job_id == victim.job_id {
            let start = at(&|l| l == "start").unwrap();
            let resume = at(&|l| l == "resume").unwrap_or_else(|| {
                panic!(
                    "{} did not resume from its checkpoint:\n{log}\n{task_log}",
                    j.job_id
                )
            });
            assert!(
                start < resume && resume < at(&|l| l == "done").unwrap(),
                "{log}"
            );
        }
    }

    // 5. Tables: complete and equal to the local run's.
    run_ok(granflow().arg("gather").arg(&sweep_dir));
    for table in ["jobs", "spectra", "profiles", "energy"] {
        let local = read_parquet(&local_dir.join(format!("{table}.parquet")));
        let remote = read_parquet(&sweep_dir.join(format!("{table}.parquet")));
        assert_eq!(
            local.height(),
            remote.height(),
            "{table}.parquet row counts"
        );
        if table == "jobs" {
            assert_eq!(
                remote.height(),
                n_jobs,
                "jobs.parquet: one row per job, exactly once"
            );
            let cols = comparable_columns(&local);
            assert!(!cols.is_empty(), "no comparable columns in jobs.parquet");
            assert_eq!(
                sorted_rows(&local, &cols),
                sorted_rows(&remote, &cols),
                "{cols:?}"
            );
        }
    }

    // 6. Tasks whose jobs are done are no-ops: resubmit, nothing in jobs/ is rewritten.
    let mut before = BTreeMap::new();
    files_with_mtimes(&sweep_dir.join("jobs"), &mut before);
    let mut c = granflow();
    c.args(["slurm", "submit"])
        .arg(&sweep_file)
        .args(["--max-parallel", "2", "--results"])
        .arg(&slurm_root);
    let printed = run_ok(&mut with_sets(c));
    let again: Vec<String> = printed
        .lines()
        .filter_map(|l| l.strip_prefix("submitted array job "))
        .map(str::to_string)
        .collect();
    let st = wait_for(
        "the no-op resubmission",
        Duration::from_secs(600),
        status,
        |s| {
            s.is_settled()
                && s.jobs.iter().all(|j| {
                    again.contains(&j.task.array_job_id)
                        && slurm::status::read_task_exit(&slurm::script::task_exit_file(
                            &sweep_dir,
                            &j.task.array_job_id,
                            j.task.index,
                        ))
                        .is_some()
                })
        },
    );
    for j in &st.jobs {
        let exit = slurm::status::read_task_exit(&slurm::script::task_exit_file(
            &sweep_dir,
            &j.task.array_job_id,
            j.task.index,
        ))
        .unwrap();
        assert_eq!(
            exit.code,
            0,
            "no-op task for {} failed; log {}",
            j.job_id,
            j.log.display()
        );
    }
    let mut after = BTreeMap::new();
    files_with_mtimes(&sweep_dir.join("jobs"), &mut after);
    assert_eq!(
        before, after,
        "a task rewrote files of a job that was already done"
    );
    let _ = std::fs::remove_dir_all(&root);
}

/// A refined sweep on Slurm: each round is further arrays, submitted by a one-task job after
/// the arrays before (no process on the login node); it ends with the jobs, ids and levels of
/// the local run, every job computed once, and nothing left in the queue.
#[test]
fn a_refined_sweep_runs_its_rounds_as_further_arrays() {
    if !slurm_installed("a_refined_sweep_runs_its_rounds_as_further_arrays") {
        return;
    }
    let _cluster = CLUSTER.lock().unwrap_or_else(|e| e.into_inner());
    let root = scratch("slurm-refine");
    let sweep_file = root.join("refined.ron");
    std::fs::write(&sweep_file, crate::sweep::refine::SWEEP).unwrap();
    let local_root = root.join("local");
    run_ok(
        granflow()
            .arg("run")
            .arg(&sweep_file)
            .arg("--results")
            .arg(&local_root)
            .args(["--threads", "1"]),
    );
    let slurm_root = root.join("slurm");
    let printed = run_ok(
        granflow()
            .args(["slurm", "submit"])
            .arg(&sweep_file)
            .args(["--cpus-per-task", "1", "--time", "30:00", "--results"])
            .arg(&slurm_root),
    );
    assert!(
        printed.contains("computes the refinement's next round"),
        "{printed}"
    );
    let sweep_dir = sweep_dir_under(&slurm_root);
    let queued = || {
        let out = Command::new("squeue")
            .args(["-h", "-o", "%j", "-n"])
            .arg("granflow-refined,granflow-refined-next")
            .output()
            .unwrap();
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    };
    let start = Instant::now();
    loop {
        let (sweep, dirs) = granflow::sweep::open_results(&sweep_dir).unwrap();
        let done = sweep.plan.iter().all(|j| dirs.job(&j.id).is_done());
        if sweep.plan.len() == 5 && done && queued().is_empty() {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(900),
            "the rounds did not end: {} jobs, queue: {}",
            sweep.plan.len(),
            queued()
        );
        std::thread::sleep(Duration::from_secs(2));
    }
    let plan = |dir: &Path| -> Vec<(String, u32)> {
        let (sweep, _) = granflow::sweep::open_results(dir).unwrap();
        sweep
            .plan
            .iter()
            .map(|j| (j.id.0.clone(), j.level))
            .collect()
    };
    assert_eq!(plan(&sweep_dir), plan(&sweep_dir_under(&local_root)));
    // three submissions: the base grid and one per round
    let log = slurm::record::SubmissionLog::read(&sweep_dir)
        .unwrap()
        .unwrap();
    assert_eq!(log.submissions.len(), 3, "{log:?}");
    for (id, _) in plan(&sweep_dir) {
        let text = std::fs::read_to_string(sweep_dir.join("jobs").join(&id).join(JOB_LOG)).unwrap();
        let events = granflow::sweep::store::log_events(&text);
        let count = |w: &str| {
            events
                .iter()
                .filter(|e| e.split(' ').next() == Some(w))
                .count()
        };
        assert_eq!((count("start"), count("done")), (1, 1), "{id}: {text}");
    }
    // the last round's job gathered the tables
    assert!(sweep_dir.join("jobs.parquet").exists());
}
