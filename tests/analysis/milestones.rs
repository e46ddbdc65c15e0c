//! Milestones (the thesis dates its structures in collisions per particle): a run records its
//! structure at the readings its sweep lists, into `evolution.parquet` (read back with pyarrow
//! and DuckDB); a run killed between milestones ends with the same table; a run until steady
//! goes on at least to its last milestone; milestones are refused where they cannot be kept.

use crate::common::{BIN, granflow_ok, kill_until_done, scratch};
use granflow::analysis::Analysis;
use granflow::sweep::{load_sweep, store};
use std::process::Command;
use std::time::Duration;

const SWEEP: &str = "(engine: \"edmd\", fixed: (width_over_diameter: 6.0, height_over_diameter: 4.0, volume_fraction: 0.15),
  axes: (length_over_width: [1.0, 2.0]),
  run: (collisions_per_particle: 600, snapshot_interval: 10, milestones: [100, 250, 595], milestone_every: 200, milestone_window: 3))";

fn milestones_of(dir: &std::path::Path) -> Vec<granflow::analysis::milestones::MilestoneRow> {
    match store::read_result(dir).unwrap().analysis {
        Analysis::Structure(a) => a.milestones,
        other => panic!("not a structure analysis: {other:?}"),
    }
}

#[test]
fn milestones_are_recorded_read_back_and_survive_kill_9() {
    let dir = scratch("milestones");
    let file = dir.join("m.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let f = file.to_str().unwrap();
    let straight = dir.join("straight");
    granflow_ok(&[
        "run",
        f,
        "--results",
        straight.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&straight);
    for job in &sweep.plan {
        let rows = milestones_of(&dirs.job_dir(&job.id));
        // the listed readings and the multiples of 200 up to the end (600)
        let readings: Vec<f64> = rows.iter().map(|r| r.milestone).collect();
        assert_eq!(
            readings,
            [100.0, 200.0, 250.0, 400.0, 595.0, 600.0],
            "{}",
            job.id
        );
        for r in &rows {
            assert_eq!(r.clock, "collisions_per_particle");
            assert_eq!(r.window_snapshots, 3);
            // the nearest record is within one snapshot interval of the reading
            assert!(
                (r.collisions_per_particle - r.milestone).abs() <= 10.0 + 1.0,
                "{r:?}"
            );
            assert!(!r.structure.is_empty() && (0.0..=1.0).contains(&r.probability));
            assert!(r.translational > 0.0);
            for plane in ["xy", "xz", "yz"] {
                assert_eq!(
                    r.peaks.iter().filter(|p| p.plane == plane).count(),
                    2,
                    "{plane}: {r:?}"
                );
            }
        }
        // the evolution figure: the trace above a row of density maps per milestone (six
        // rows of 300 CSS pixels under a 380-pixel trace, at 96 dpi, plus the heading)
        let png = dirs.job_dir(&job.id).join("figures/evolution.png");
        let bytes = std::fs::read(&png).unwrap_or_else(|e| panic!("{}: {e}", png.display()));
        assert_eq!(&bytes[1..4], b"PNG");
        let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        assert!(
            height >= 380 + 6 * 300,
            "{}: height {height}",
            png.display()
        );
    }

    // read back with pyarrow and DuckDB
    let script = r#"
import sys, duckdb, pyarrow.parquet as pq
d = sys.argv[1]
t = pq.read_table(d + "/evolution.parquet")
assert t.num_rows == 12, t.num_rows
assert t.column_names[:3] == ["job_id", "milestone", "milestone_clock"], t.column_names
assert t.schema.field("milestone").metadata[b"unit"] == b"milestone_clock"
rows = duckdb.connect().execute(
    f"SELECT count(*), count(DISTINCT job_id), min(milestone), max(milestone), "
    f"sum(len(peaks)) FROM read_parquet('{d}/evolution.parquet')").fetchone()
assert rows == (12, 2, 100.0, 600.0, 72), rows
j = duckdb.connect().execute(
    f"SELECT count(*) FROM read_parquet('{d}/evolution.parquet') e "
    f"JOIN read_parquet('{d}/jobs.parquet') USING (job_id)").fetchone()[0]
assert j == 12, j
print("ok")
"#;
    let out = Command::new("python3")
        .args(["-c", script, dirs.tables.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );

    // kill -9 again and again: the same milestones, bit for bit
    let killed = dir.join("killed");
    let args: Vec<String> = [
        "run",
        f,
        "--results",
        killed.to_str().unwrap(),
        "--threads",
        "1",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let kills = kill_until_done(&sweep, &killed, &args, Duration::from_secs(600));
    eprintln!("{kills} kills");
    let killed_dirs = sweep.results_dir(&killed);
    for job in &sweep.plan {
        let a = milestones_of(&dirs.job_dir(&job.id));
        let b = milestones_of(&killed_dirs.job_dir(&job.id));
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{}", job.id);
    }
}

/// A run until steady decides only after its last listed milestone, so the thesis' length is
/// always reached; without milestones the same run may stop earlier.
#[test]
fn a_run_until_steady_reaches_its_last_milestone() {
    let dir = scratch("milestones-steady");
    let sweep = |extra: &str| {
        format!(
            "(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 6.0, height_over_diameter: 4.0, volume_fraction: 0.15),
              run: (collisions_per_particle: 3000, snapshot_interval: 10, until_steady: (window: 100){extra}))"
        )
    };
    let run = |name: &str, text: &str| {
        let file = dir.join(format!("{name}.ron"));
        std::fs::write(&file, text).unwrap();
        let results = dir.join(name);
        granflow_ok(&[
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ]);
        let sweep = load_sweep(&file, &[]).unwrap();
        store::read_result(&sweep.results_dir(&results).job_dir(&sweep.plan[0].id)).unwrap()
    };
    let plain = run("plain", &sweep(""));
    let with = run("with", &sweep(", milestones: [1500]"));
    assert!(
        with.collisions_per_particle >= 1500.0,
        "stopped at {} before the milestone",
        with.collisions_per_particle
    );
    // the milestone run goes on past where the plain run stopped (when it stopped early)
    if plain.collisions_per_particle < 1500.0 {
        assert!(with.collisions_per_particle > plain.collisions_per_particle);
    }
}

#[test]
fn milestones_are_refused_where_they_cannot_be_kept() {
    let dir = scratch("milestones-bad");
    for (text, wanted) in [
        (
            "(engine: \"lga\", fixed: (length: 40, width: 5, density: 1.0), run: (steps: 100, snapshot_interval: 10, milestones: [50]))",
            "records no structure at milestones",
        ),
        (
            "(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15), run: (collisions_per_particle: 100, snapshot_interval: 10, milestones: [50, 20]))",
            "increasing order",
        ),
        (
            "(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15), run: (collisions_per_particle: 100, snapshot_interval: 10, milestone_window: 3))",
            "given without",
        ),
    ] {
        let file = dir.join("bad.ron");
        std::fs::write(&file, text).unwrap();
        let out = Command::new(BIN)
            .args(["plan", file.to_str().unwrap()])
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{said}");
        assert!(said.contains(wanted), "`{wanted}` not said: {said}");
    }
}

/// Every shipped sweep loads and validates (milestones included); the chapter 5 sweep holds
/// the thesis' 16 distinct points and the figure sweeps' jobs are among them.
#[test]
fn the_shipped_sweeps_load_and_chapter_5_holds_every_figure_point() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            load_sweep(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            names.push(path);
        }
    }
    assert!(names.len() >= 4);
    let chapter = load_sweep(&dir.join("thesis-chapter5.ron"), &[]).unwrap();
    assert_eq!(chapter.plan.len(), 16);
    let ids: std::collections::BTreeSet<_> = chapter.plan.iter().map(|j| j.id.clone()).collect();
    assert_eq!(ids.len(), 16, "two points of the chapter are the same job");
    for fig in ["thesis-fig5-25", "thesis-fig5-26", "thesis-fig5-27"] {
        let sweep = load_sweep(&dir.join(format!("{fig}.ron")), &[]).unwrap();
        for job in &sweep.plan {
            assert!(
                ids.contains(&job.id),
                "{fig}: job {} is not in the chapter sweep",
                job.id
            );
        }
    }
}
