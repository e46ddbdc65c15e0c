//! The lattice gas behind the job boundary: the shipped sweep runs (shortened with
//! `--set`), survives SIGKILL at random moments and resumes to the same results as an
//! uninterrupted run, and gives its tables, a space-time picture per job and a phase diagram.

use crate::common::{BIN, kill_until_done};
use granflow::sweep::{load_sweep, store};
use polars::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::common::scratch;

fn shipped() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps/lga-density-window.ron")
}

/// Two densities (one inside the window, one above) at p = 0.5, 300 000 steps.
const SET: [&str; 8] = [
    "--set",
    "density=1.0,3.0",
    "--set",
    "dissipation=0.5",
    "--set",
    "steps=300000",
    "--set",
    "snapshot_interval=10",
];

fn run_args(results: &Path) -> Vec<String> {
    let mut args = vec![
        "run".to_string(),
        shipped().to_str().unwrap().to_string(),
        "--results".into(),
        results.to_str().unwrap().to_string(),
        "--threads".into(),
        "1".into(),
    ];
    args.extend(SET.iter().map(|s| s.to_string()));
    args
}

/// The comparable part of a result: everything except wall-clock figures and times.
fn deterministic(r: store::JobResult) -> String {
    ron::to_string(&r.without_wall_clock()).unwrap()
}

#[test]
fn the_shipped_lga_sweep_runs_resumes_after_kill_9_and_tabulates() {
    let dir = scratch("kill");
    let sets: Vec<String> = SET.chunks(2).map(|c| c[1].to_string()).collect();
    let sweep = load_sweep(&shipped(), &sets).unwrap();
    assert_eq!(sweep.plan.len(), 2);
    let reference = dir.join("reference");
    let out = Command::new(BIN)
        .args(run_args(&reference))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dirs = sweep.results_dir(&reference);

    let results = dir.join("results");
    let killed_dirs = sweep.results_dir(&results);
    let kills = kill_until_done(
        &sweep,
        &results,
        &run_args(&results),
        Duration::from_secs(120),
    );
    assert!(kills >= 2, "only {kills} kills");
    // the last rerun may have been killed before writing the tables: gather them
    let out = Command::new(BIN)
        .args(["gather", killed_dirs.tables.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for job in &sweep.plan {
        let a = store::read_result(&dirs.job_dir(&job.id)).unwrap();
        let b = store::read_result(&killed_dirs.job_dir(&job.id)).unwrap();
        assert_eq!(deterministic(a), deterministic(b), "job {}", job.id);
        let png = std::fs::read(killed_dirs.job_dir(&job.id).join("spacetime.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }

    // tables: the jobs table with the lattice summary, the spectra and space-time tables
    let read = |name: &str| {
        let mut f =
            std::fs::File::open(killed_dirs.tables.join(format!("{name}.parquet"))).unwrap();
        ParquetReader::new(&mut f).finish().unwrap()
    };
    let jobs = read("jobs");
    assert_eq!(jobs.height(), 2);
    for col in [
        "density",
        "dissipation",
        "label",
        "alpha",
        "peak_frequency",
        "wave_velocity",
        "final_steps",
        "rest_hops",
    ] {
        assert!(jobs.column(col).is_ok(), "jobs.parquet lacks {col}");
    }
    let spectra = read("spectra");
    assert!(spectra.height() > 100 && spectra.column("frequency").is_ok());
    let spacetime = read("spacetime");
    assert!(spacetime.height() > 100 && spacetime.column("count").is_ok());

    // and a phase diagram over the density
    let out = Command::new(BIN)
        .args([
            "phase-diagram",
            killed_dirs.tables.to_str().unwrap(),
            "--x",
            "density",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("waves"), "{text}");
    assert!(killed_dirs.tables.join("phase-density.png").exists());
}
