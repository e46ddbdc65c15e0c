//! The lattice gas behind the job boundary (issue 12): the shipped sweep runs (shortened with
//! `--set`), survives SIGKILL at random moments and resumes to the same results as an
//! uninterrupted run, and gives its tables, a space-time picture per job and a phase diagram.

use granflow::sweep::{load_sweep, store};
use polars::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_granflow");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("lga-sweep-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

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
fn deterministic(mut r: store::JobResult) -> String {
    r.wall_seconds = 0.0;
    r.events_per_second = 0.0;
    r.provenance.started.clear();
    r.provenance.finished.clear();
    r.checksum.clear();
    ron::to_string(&r).unwrap()
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
    let mut kills = 0u64;
    let started = Instant::now();
    while !sweep
        .plan
        .iter()
        .all(|j| killed_dirs.job_dir(&j.id).join(store::RESULT_FILE).exists())
    {
        let mut child = Command::new(BIN)
            .args(run_args(&results))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(150 + 97 * kills));
        if child.try_wait().unwrap().is_none() {
            child.kill().unwrap();
            kills += 1;
        }
        child.wait().unwrap();
        assert!(started.elapsed() < Duration::from_secs(120), "no progress");
    }
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
        "steps",
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
