//! DSMC behind the job boundary: a shipped sweep runs (shortened with `--set`),
//! survives SIGKILL at random moments and resumes to bitwise the same results as an
//! uninterrupted run on another thread count, and gives its tables (the summary with errors,
//! the profiles), a curve plot and the minimum diagram.

use crate::common;

use crate::common::{granflow_ok, kill_until_done};
use granflow::sweep::{load_sweep, store};
use polars::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Duration;

fn shipped() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps/dsmc-walls.ron")
}

/// Thermal and Maxwell walls at Kn = 0.1 and 0.5, time 60 (about 170 M moves, 3 s, per job).
const SET: [&str; 12] = [
    "--set",
    "knudsen_number=0.1,0.5",
    "--set",
    "wall_model=thermal,maxwell",
    "--set",
    "particles_per_cell=200",
    "--set",
    "time=60",
    "--set",
    "snapshot_interval=0.5",
    "--set",
    "restitution=0.9",
];

fn run_args(results: &Path, threads: &str) -> Vec<String> {
    let mut args = vec![
        "run".to_string(),
        shipped().to_str().unwrap().to_string(),
        "--results".into(),
        results.to_str().unwrap().to_string(),
        "--threads".into(),
        threads.into(),
    ];
    args.extend(SET.iter().map(|s| s.to_string()));
    args
}

#[test]
fn the_shipped_dsmc_sweep_runs_resumes_after_kill_9_and_tabulates() {
    let dir = common::scratch("dsmc-sweep");
    let sets: Vec<String> = SET.chunks(2).map(|c| c[1].to_string()).collect();
    let sweep = load_sweep(&shipped(), &sets).unwrap();
    assert_eq!(sweep.plan.len(), 4);

    let reference = dir.join("reference");
    let args = run_args(&reference, "2");
    granflow_ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let dirs = sweep.results_dir(&reference);

    let results = dir.join("results");
    let killed = sweep.results_dir(&results);
    let kills = kill_until_done(
        &sweep,
        &results,
        &run_args(&results, "1"),
        Duration::from_secs(300),
    );
    assert!(kills >= 2, "only {kills} kills");
    granflow_ok(&["gather", killed.tables.to_str().unwrap()]);
    for job in &sweep.plan {
        let a = store::read_result(&dirs.job_dir(&job.id)).unwrap();
        let b = store::read_result(&killed.job_dir(&job.id)).unwrap();
        assert_eq!(
            ron::to_string(&a.without_wall_clock()).unwrap(),
            ron::to_string(&b.without_wall_clock()).unwrap(),
            "job {} after {kills} kills",
            job.id
        );
    }

    // the jobs table: the rarefied summary with errors; balances close (exact identities at
    // steady state: within 4 standard errors, or 1 % where the errors are tiny)
    let read = |name: &str| {
        let mut f = std::fs::File::open(killed.tables.join(format!("{name}.parquet"))).unwrap();
        ParquetReader::new(&mut f).finish().unwrap()
    };
    let jobs = read("jobs");
    assert_eq!(jobs.height(), 4);
    let f64s = |name: &str| -> Vec<f64> {
        let c = jobs.column(name).unwrap();
        (0..c.len())
            .map(|i| c.get(i).unwrap().try_extract::<f64>().unwrap())
            .collect()
    };
    let q = f64s("flow_rate");
    let q_err = f64s("flow_rate_error");
    for (v, e) in q.iter().zip(&q_err) {
        assert!(
            v.is_finite() && *v > 0.0 && *e > 0.0 && e < v,
            "Q = {v} +- {e}"
        );
    }
    for (b, e) in f64s("momentum_balance")
        .iter()
        .zip(f64s("momentum_balance_error"))
    {
        assert!(
            (b - 1.0).abs() < (4.0 * e).max(0.01),
            "momentum balance {b} +- {e}"
        );
    }
    // a Maxwell wall (half specular) lets the gas slip more: more flow than the thermal wall
    let wall_column = jobs.column("wall_model").unwrap();
    let wall: Vec<String> = (0..4)
        .map(|i| wall_column.get(i).unwrap().get_str().unwrap().to_string())
        .collect();
    let kn = f64s("knudsen_number");
    for k in [0.1, 0.5] {
        let at = |model: &str| {
            (0..4)
                .find(|&i| kn[i] == k && wall[i] == model)
                .map(|i| q[i])
                .unwrap()
        };
        assert!(at("maxwell") > at("thermal"), "Kn = {k}");
    }
    let profiles = read("profiles");
    assert!(
        profiles.height() >= 4 * 50 * 21,
        "{} profile rows",
        profiles.height()
    );
    for col in [
        "job_id",
        "quantity",
        "bin",
        "coordinate",
        "value",
        "standard_error",
    ] {
        assert!(profiles.column(col).is_ok(), "profiles.parquet lacks {col}");
    }
    let quantities: std::collections::BTreeSet<String> = profiles
        .column("quantity")
        .unwrap()
        .str()
        .unwrap()
        .iter()
        .flatten()
        .map(str::to_string)
        .collect();
    for q in ["density", "velocity", "temperature", "pxy", "qy"] {
        assert!(quantities.contains(q), "no {q} profile: {quantities:?}");
    }

    // the curve plot and the minimum diagram
    let out = granflow_ok(&[
        "plot",
        killed.tables.to_str().unwrap(),
        "--x",
        "knudsen_number",
        "--y",
        "flow_rate",
        "--by",
        "wall_model",
        "--log-x",
    ]);
    assert!(out.contains("wall_model = maxwell") && out.contains("wall_model = thermal"));
    let png = std::fs::read(
        killed
            .tables
            .join("plot-flow_rate-knudsen_number-by-wall_model.png"),
    )
    .unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let out = granflow_ok(&[
        "phase-diagram",
        killed.tables.to_str().unwrap(),
        "--x",
        "wall_model",
        "--minimum-of",
        "flow_rate",
        "--along",
        "knudsen_number",
    ]);
    // two points per curve cannot have an interior minimum
    assert!(
        out.contains("monotonic") && !out.contains(" minimum"),
        "{out}"
    );
}

#[test]
fn a_bad_plot_request_names_what_is_allowed() {
    let dir = common::scratch("dsmc-plot-bad");
    let results = dir.join("results");
    let out = std::process::Command::new(common::BIN)
        .args([
            "plot",
            shipped().to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
            "--x",
            "knudsen_number",
            "--y",
            "flow_rat",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("did you mean `flow_rate`?"), "{stderr}");
    let out = std::process::Command::new(common::BIN)
        .args([
            "plot",
            shipped().to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
            "--x",
            "wall_model",
            "--y",
            "flow_rate",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("use it as --by"), "{stderr}");
}
