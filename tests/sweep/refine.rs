//! Adaptive refinement behind `granflow run` (docs/sweeps.md, `refine`): rounds of ordinary
//! jobs, the `refinement_level` column, a rerun that computes nothing, `status --where` that
//! sees refined points, and a run killed with SIGKILL at many moments that ends with the same
//! points and results as an uninterrupted one, no job computed twice.

use crate::common::{BIN, kill_until_exit, scratch};
use granflow::sweep::{open_results, store};
use polars::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// Two Knudsen numbers, refined on the flow rate with a tolerance every pair exceeds, 2
/// levels: round 1 adds Kn = 1.25, round 2 adds 0.875 and 1.625 (DSMC, about 0.5 s a job).
/// Also the Slurm test's.
pub(crate) const SWEEP: &str = r#"(
    engine: "dsmc",
    fixed: (forcing: 0.5, wall_model: "thermal", particles_per_cell: 20.0),
    axes: (knudsen_number: [0.5, 2.0]),
    refine: (axes: ["knudsen_number"], levels: 2, budget: 10,
             quantity: Change(column: "flow_rate", relative: 1e-9)),
    run: (time: 20.0, snapshot_interval: 1.0),
)
"#;

fn sweep_file(dir: &Path) -> PathBuf {
    let path = dir.join("refined.ron");
    std::fs::write(&path, SWEEP).unwrap();
    path
}

fn run(file: &Path, results: &Path) -> String {
    let out = Command::new(BIN)
        .args(["run", file.to_str().unwrap(), "--results"])
        .arg(results)
        .args(["--threads", "1"])
        .output()
        .unwrap();
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    text
}

/// (Kn, level, job id) of every row of jobs.parquet, by Kn.
fn rows(tables: &Path) -> Vec<(f64, i64, String)> {
    let file = std::fs::File::open(tables.join("jobs.parquet")).unwrap();
    let df = ParquetReader::new(file).finish().unwrap();
    let kn = df.column("knudsen_number").unwrap().f64().unwrap().clone();
    let level = df
        .column("refinement_level")
        .unwrap()
        .i64()
        .unwrap()
        .clone();
    let id = df.column("job_id").unwrap().str().unwrap().clone();
    let mut out: Vec<(f64, i64, String)> = (0..df.height())
        .map(|i| {
            (
                kn.get(i).unwrap(),
                level.get(i).unwrap(),
                id.get(i).unwrap().to_string(),
            )
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

#[test]
fn rounds_add_midpoints_as_ordinary_jobs_and_a_rerun_computes_none() {
    let dir = scratch("refine-rounds");
    let file = sweep_file(&dir);
    let results = dir.join("results");
    let said = run(&file, &results);
    assert!(
        said.contains("refinement: 2 rounds adding 3 points (1 + 2), complete"),
        "{said}"
    );
    let tables = results.join("refined");
    let got: Vec<(f64, i64)> = rows(&tables).iter().map(|r| (r.0, r.1)).collect();
    assert_eq!(
        got,
        vec![(0.5, 0), (0.875, 2), (1.25, 1), (1.625, 2), (2.0, 0)]
    );
    // the refined sweep read back from its results: the same five jobs, plan order by round
    let (sweep, _) = open_results(&tables).unwrap();
    let levels: Vec<u32> = sweep.plan.iter().map(|j| j.level).collect();
    assert_eq!(levels, vec![0, 0, 1, 2, 2]);
    // a rerun runs nothing
    let again = run(&file, &results);
    assert!(
        again.contains("run finished: 0 done now (5 before)"),
        "{again}"
    );
    // --where sees refined points
    let out = Command::new(BIN)
        .args(["status"])
        .arg(&tables)
        .args(["--where", "knudsen_number<1.5"])
        .output()
        .unwrap();
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("(3 jobs)"), "{text}");
    assert!(
        text.contains("Kn=0.875") && text.contains("Kn=1.25"),
        "{text}"
    );
}

#[test]
fn a_refined_run_killed_at_any_moment_ends_with_the_same_points_and_results() {
    let dir = scratch("refine-kill");
    let file = sweep_file(&dir);
    let reference = dir.join("reference");
    run(&file, &reference);
    let want = rows(&reference.join("refined"));

    let results = dir.join("results");
    let args = [
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--threads",
        "1",
    ];
    // short first delays: the whole run takes ~0.3 s on a quiet machine, and the test needs
    // kills inside it (a delay of 150 ms growing by 97 ms gave only 2 there)
    let (kills, status) = kill_until_exit(
        &args,
        Duration::from_millis(30),
        Duration::from_millis(31),
        Duration::from_secs(300),
    );
    assert!(status.success(), "{status}");
    assert!(kills >= 3, "only {kills} kills");
    let got = rows(&results.join("refined"));
    assert_eq!(got, want, "the same points with the same ids");
    for (_, _, id) in &got {
        let job = results.join("refined/jobs").join(id);
        let log = std::fs::read_to_string(job.join(store::LOG_FILE)).unwrap();
        let events = store::log_events(&log);
        let starts = events.iter().filter(|e| e.starts_with("start")).count();
        let dones = events.iter().filter(|e| e.starts_with("done")).count();
        // a kill between checkpoint 0 and its `start` line leaves a `resume` line only
        assert!(
            starts <= 1 && dones == 1,
            "job {id} computed more than once:\n{log}"
        );
        let a = store::read_result(&job).unwrap().without_wall_clock();
        let b = store::read_result(&reference.join("refined/jobs").join(id))
            .unwrap()
            .without_wall_clock();
        assert_eq!(ron::to_string(&a).unwrap(), ron::to_string(&b).unwrap());
    }
}
