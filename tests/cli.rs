//! The researcher's side of the command line (issue 14): selection by parameter (`--where`)
//! for run, plan, status and gather; `status --json`; a phase diagram refuses an axis that
//! does not vary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_granflow");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

#[test]
fn where_selects_jobs_and_status_speaks_json() {
    let dir = scratch("where");
    let file = dir.join("w.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0], restitution: [0.7, 0.9]),\n run: (collisions_per_particle: 40, snapshot_interval: 20))",
    )
    .unwrap();
    let results = dir.join("results");
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    let out = granflow(&["run", f, "--results", r, "--where", "restitution=0.9"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = granflow(&["status", f, "--results", r, "--json"]);
    assert!(out.status.success());
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(status["counts"]["done"], 2);
    assert_eq!(status["counts"]["pending"], 2);
    for job in status["jobs"].as_array().unwrap() {
        let e = job["params"]["restitution"].as_f64().unwrap();
        assert_eq!(job["state"] == "done", e == 0.9, "{job}");
        if e == 0.9 {
            assert_eq!(job["progress"].as_f64(), Some(40.0));
            assert!(job["label"].is_string());
        }
    }
    // several conditions must all hold; comparisons
    let out = granflow(&[
        "status",
        f,
        "--results",
        r,
        "--json",
        "--where",
        "length_over_width>=2",
        "--where",
        "restitution!=0.7",
    ]);
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let jobs = status["jobs"].as_array().unwrap();
    assert_eq!(jobs.len(), 1);
    assert_eq!(jobs[0]["params"]["length_over_width"], 2.0);
    // plan shows the selection; a bad condition is bad input
    let out = granflow(&["plan", f, "--results", r, "--where", "restitution<0.8"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("2 jobs"));
    for bad in ["no_such=1", "restitution", "restitution>=high"] {
        let out = granflow(&["status", f, "--results", r, "--where", bad]);
        assert_eq!(out.status.code(), Some(2), "--where {bad}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--where"),
            "--where {bad}"
        );
    }
    let out = granflow(&["run", f, "--results", r, "--where", "restitution=0.5"]);
    assert_eq!(out.status.code(), Some(2));
    // the text status names each job by its swept parameters
    let out = granflow(&["status", f, "--results", r]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("L/W=2 e=0.9"), "{text}");
    // a phase diagram over a parameter that does not vary is refused
    let out = granflow(&["phase-diagram", f, "--results", r, "--x", "roughness"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not vary"));
}

/// A run without a terminal (piped, as in a Slurm log) prints a plain progress line per
/// running job at a fixed wall-clock interval, naming the job by its parameters.
#[test]
fn a_piped_run_prints_progress_lines() {
    let dir = scratch("progress");
    let file = dir.join("p.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 6.0, height_over_diameter: 6.0, volume_fraction: 0.15),\n axes: (length_over_width: [2.0]), run: (collisions_per_particle: 3000, snapshot_interval: 50))",
    )
    .unwrap();
    let results = dir.join("results");
    let out = Command::new(BIN)
        .args([
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ])
        .env("GRANFLOW_PROGRESS_SECONDS", "0")
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("running ")).collect();
    assert!(lines.len() >= 10, "{text}");
    assert!(
        lines[0].contains("/3000 cpp") && lines[0].contains("ETA"),
        "{}",
        lines[0]
    );
}

/// `granflow bench --json` keeps its keys (users' scripts read them), for every kind of
/// workload; numbers are measured (positive), not checked for speed.
#[test]
fn bench_json_keeps_its_keys() {
    let out = granflow(&[
        "bench",
        "--json",
        "--workload",
        "dsmc-kn1-6000-sampled",
        "--moves",
        "2e6",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(rows.len(), 1);
    let row = rows[0].as_object().unwrap();
    for key in [
        "workload",
        "n",
        "phi",
        "collisions_per_s",
        "events_per_s",
        "bytes_per_particle",
        "moves_per_s",
    ] {
        assert!(row.contains_key(key), "bench --json lacks `{key}`: {row:?}");
    }
    assert_eq!(row["n"], 6000);
    assert!(row["moves_per_s"].as_f64().unwrap() > 0.0);
    let out = granflow(&[
        "bench",
        "--json",
        "--workload",
        "lga-fig2",
        "--site-updates",
        "1e6",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert!(rows[0]["site_updates_per_s"].as_f64().unwrap() > 0.0);
    assert!(rows[0]["phi"].as_f64().is_some());
}
