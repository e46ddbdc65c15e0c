//! The statistics behind the job boundary: a sweep with `run.statistics` runs,
//! survives SIGKILL at random moments and resumes to bitwise the same results as an
//! uninterrupted run on another thread count, draws the statistics figures per job and the
//! comparisons in the report, and a sweep without the block keeps its job ids (its tables are
//! checked by tests/sweep/tables.rs). The shipped thesis sweeps pass `plan`.

use crate::common::{granflow_ok, kill_until_done, scratch};
use granflow::sweep::{load_sweep, store};
use std::path::Path;
use std::time::Duration;

const SWEEP: &str = "(engine: \"edmd\",
  fixed: (length_over_width: 1.0, width_over_diameter: 10.0, height_over_diameter: 10.0,
          volume_fraction: 0.12, wall_restitution: 1.0, wall_roughness: 1.0),
  axes: (restitution: [0.8, 0.95], roughness: [-0.99, 0.0]),
  run: (collisions_per_particle: 1500, snapshot_interval: 30, checkpoint_every: 1,
        statistics: (bins: 5, window: 1000, r_max: 3.0)))";

#[test]
fn a_statistics_sweep_resumes_after_kill_9_to_the_same_results_and_draws() {
    let dir = scratch("statistics-sweep");
    let file = dir.join("stats.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    assert_eq!(sweep.plan.len(), 4);
    for job in &sweep.plan {
        let canonical = job.params.canonical();
        assert!(
            canonical.contains("\"statistics\":{\"bins\":5,\"r_max\":3.0,\"window\":1000.0}"),
            "{canonical}"
        );
    }
    let f = file.to_str().unwrap();
    let reference = dir.join("reference");
    granflow_ok(&[
        "run",
        f,
        "--results",
        reference.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    let results = dir.join("results");
    let args: Vec<String> = [
        "run",
        f,
        "--results",
        results.to_str().unwrap(),
        "--threads",
        "1",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let kills = kill_until_done(&sweep, &results, &args, Duration::from_secs(300));
    assert!(kills >= 2, "only {kills} kills");
    let (a_dirs, b_dirs) = (sweep.results_dir(&reference), sweep.results_dir(&results));
    for job in &sweep.plan {
        let a = store::read_result(&a_dirs.job_dir(&job.id)).unwrap();
        let b = store::read_result(&b_dirs.job_dir(&job.id)).unwrap();
        assert_eq!(
            ron::to_string(&a.without_wall_clock()).unwrap(),
            ron::to_string(&b.without_wall_clock()).unwrap(),
            "job {} after {kills} kills",
            job.id
        );
        let granflow::analysis::Analysis::Structure(analysis) = &a.analysis else {
            panic!("an EDMD job has the structure analysis");
        };
        let s = analysis.statistics.as_ref().expect("statistics");
        assert!(s.summary.statistics_snapshots >= 30, "{:?}", s.summary);
        assert!(s.summary.free_paths > 0 && s.summary.mean_free_path > 0.0);
        assert!(!s.vdf.is_empty() && !s.pair_correlation.is_empty());
        assert!(!s.orientation.is_empty() && !s.velocity_correlation.is_empty());
        for name in [
            "vdf",
            "pair_correlation",
            "orientation",
            "velocity_correlation",
            "knudsen",
        ] {
            let png = a_dirs
                .job_dir(&job.id)
                .join("figures")
                .join(format!("{name}.png"));
            assert!(png.is_file(), "{}", png.display());
        }
    }
    // `gather` names every table it wrote, the statistics' among them, and each is there
    let said = granflow_ok(&["gather", b_dirs.tables.to_str().unwrap()]);
    for name in [
        "jobs",
        "vdf",
        "vdf_moments",
        "pair_correlation",
        "orientation",
        "velocity_correlation",
        "free_paths",
    ] {
        let file = format!("{name}.parquet");
        assert!(said.contains(&file), "gather does not name {file}: {said}");
        assert!(b_dirs.tables.join(&file).is_file(), "{file} missing");
    }
    // the report compares the jobs: wall slip and Lambda(0) against e, one curve per beta
    granflow_ok(&["report", b_dirs.tables.to_str().unwrap()]);
    let page = std::fs::read_to_string(b_dirs.tables.join("report.html")).unwrap();
    for id in [
        "id=\"statistics\"",
        "id=\"statistics-slip_velocity\"",
        "id=\"statistics-lambda_centre\"",
    ] {
        assert!(page.contains(id), "the report lacks {id}");
    }
    for job in &sweep.plan {
        assert!(page.contains(&format!("id=\"job-{}-vdf\"", job.id)));
    }
    // `plot` knows the statistics' columns
    let out = granflow_ok(&[
        "plot",
        b_dirs.tables.to_str().unwrap(),
        "--x",
        "restitution",
        "--y",
        "slip_rotational",
    ]);
    assert!(out.contains("roughness = -0.99"), "{out}");
}

/// Without the block a job's canonical text, id and analysis settings are what they were.
#[test]
fn a_sweep_without_statistics_keeps_its_ids() {
    let dir = scratch("statistics-plain");
    let file = dir.join("plain.ron");
    std::fs::write(
        &file,
        SWEEP.replace(
            ",\n        statistics: (bins: 5, window: 1000, r_max: 3.0)",
            "",
        ),
    )
    .unwrap();
    let plain = load_sweep(&file, &[]).unwrap();
    for job in &plain.plan {
        let canonical = job.params.canonical();
        assert!(!canonical.contains("statistics"), "{canonical}");
        assert_eq!(
            job.id,
            granflow::sweep::job::id_of_canonical(&canonical),
            "{canonical}"
        );
        assert!(job.params.analyser().unwrap().free_path_slabs().is_none());
    }
    // the same point with statistics is another job
    std::fs::write(&file, SWEEP).unwrap();
    let with = load_sweep(&file, &[]).unwrap();
    for (a, b) in plain.plan.iter().zip(&with.plan) {
        assert_ne!(a.id, b.id);
    }
}

/// The shipped thesis sweeps are accepted by `plan`, with the estimate and the statistics line.
#[test]
fn the_thesis_sweeps_plan() {
    let results = scratch("statistics-plan");
    for (name, jobs) in [
        ("thesis-ch3", 15),
        ("thesis-ch4-dilute", 12),
        ("thesis-ch4-dense", 13),
    ] {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("sweeps/{name}.ron"));
        let out = granflow_ok(&[
            "plan",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ]);
        assert!(out.contains(&format!("{jobs} jobs")), "{name}: {out}");
        assert!(out.contains("estimated time still to go"), "{name}: {out}");
        assert!(out.contains("statistics: 25 slabs"), "{name}: {out}");
    }
}
