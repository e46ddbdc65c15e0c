//! Sweep orchestrator tests: malformed sweep files (exit code 2, nothing written), job-id
//! stability, bitwise resume, kill -9 of a real `granflow run` and rerun, two concurrent
//! runners, and the Parquet tables read back by an independent reader (Python pyarrow).

use granflow::engine::declare::{InId, ParamDefault, ParamKind};
use granflow::engine::{ParamDef, ParamValue, edmd};
use granflow::sweep::execute::{self, JobEnd};
use granflow::sweep::job::{JobParams, canonical_with, id_of_canonical};
use granflow::sweep::{load_sweep, store as queue};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common::BIN;

/// A fresh scratch directory for one test.
use crate::common::scratch;

/// A small valid sweep; `fixed_extra`, `axes` and `rest` are spliced in.
fn sweep_text(fixed_extra: &str, axes: &str, rest: &str, cpp: f64, interval: f64) -> String {
    format!(
        "(\n    engine: \"edmd\",\n    fixed: (\n        width_over_diameter: 4.0,\n        height_over_diameter: 4.0,\n        volume_fraction: 0.15,\n{fixed_extra}    ),\n    axes: (\n{axes}    ),\n{rest}    run: (collisions_per_particle: {cpp:?}, snapshot_interval: {interval:?}),\n)\n"
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// 1-based line and column of the first occurrence of `needle` in `text`.
/// Run the granflow binary with `args`.
fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// Run the granflow binary with `args`; it must succeed (its stderr is shown if not).
fn granflow_ok(args: &[&str]) -> Output {
    let out = granflow(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Arguments of `granflow run FILE --results RESULTS` followed by `extra`.
fn run_args<'a>(file: &'a Path, results: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    args
}

fn position_of(text: &str, needle: &str) -> (usize, usize) {
    let at = text.find(needle).expect("needle in text");
    let before = &text[..at];
    (
        before.matches('\n').count() + 1,
        before.rsplit('\n').next().unwrap().chars().count() + 1,
    )
}

/// Run `granflow run` on a malformed sweep: exit code 2, an error naming the file, the line of
/// `needle` and every word of `expect`, and nothing written.
fn assert_rejected(case: &str, text: &str, needle: &str, expect: &[&str]) {
    let dir = scratch(&format!("bad-{case}"));
    let file = write(&dir, "bad.ron", text);
    let results = dir.join("results");
    let out = granflow(&run_args(&file, &results, &[]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{case}: exit code; stderr:\n{stderr}"
    );
    let (line, _) = position_of(text, needle);
    let at = format!("{}:{line}:", file.display());
    assert!(
        stderr.contains(&at),
        "{case}: expected position {at} in:\n{stderr}"
    );
    for word in expect {
        assert!(
            stderr.contains(word),
            "{case}: expected `{word}` in:\n{stderr}"
        );
    }
    assert!(!results.exists(), "{case}: something was written");
}

#[test]
fn malformed_unknown_key() {
    let text = sweep_text(
        "        restitutoin: 0.7,\n",
        "        length_over_width: [1.0],\n",
        "",
        10.0,
        5.0,
    );
    assert_rejected(
        "unknown-key",
        &text,
        "restitutoin",
        &["restitutoin", "restitution"],
    );
}

#[test]
fn malformed_wrong_type() {
    let text = sweep_text(
        "        restitution: \"high\",\n",
        "        length_over_width: [1.0],\n",
        "",
        10.0,
        5.0,
    );
    assert_rejected("wrong-type", &text, "\"high\"", &["restitution"]);
}

#[test]
fn malformed_restitution_out_of_range() {
    let text = sweep_text(
        "        restitution: 1.5,\n",
        "        length_over_width: [1.0],\n",
        "",
        10.0,
        5.0,
    );
    assert_rejected(
        "e-range",
        &text,
        "restitution: 1.5",
        &["fixed.restitution", "1.5", "[0, 1]"],
    );
}

#[test]
fn malformed_roughness_out_of_range() {
    let text = sweep_text(
        "",
        "        length_over_width: [1.0],\n        roughness: [0.1, -1.2],\n",
        "",
        10.0,
        5.0,
    );
    assert_rejected(
        "beta-range",
        &text,
        "roughness:",
        &["axes.roughness", "-1.2", "[-1, 1]"],
    );
}

#[test]
fn malformed_unplaceable_volume_fraction() {
    // the densest lattice placement puts 108 spheres in a 4.5^3 channel with walls without
    // contact (phi <= 0.62: a checkerboard of 6 x 6 x 6 points with spacings 0.75, 0.7, 0.75,
    // nearest distance 1.026); phi = 0.70 asks for 125
    let text = sweep_text("", "        length_over_width: [1.0],\n", "", 10.0, 5.0)
        .replace("volume_fraction: 0.15", "volume_fraction: 0.70")
        .replace("diameter: 4.0", "diameter: 4.5");
    assert_rejected(
        "phi",
        &text,
        "volume_fraction: 0.70",
        &[
            "fixed.volume_fraction",
            "cannot be placed",
            "allowed 1 <= N <= 108",
        ],
    );
}

#[test]
fn malformed_non_positive_size() {
    let text = sweep_text("", "        length_over_width: [1.0],\n", "", 10.0, 5.0)
        .replace("width_over_diameter: 4.0", "width_over_diameter: -4.0");
    assert_rejected(
        "size",
        &text,
        "width_over_diameter: -4.0",
        &["width_over_diameter", "-4", "3 <= W/d <= 1e5"],
    );
}

#[test]
fn malformed_empty_axis() {
    let text = sweep_text("", "        length_over_width: [],\n", "", 10.0, 5.0);
    assert_rejected(
        "empty-axis",
        &text,
        "length_over_width: []",
        &["axes.length_over_width", "empty"],
    );
}

#[test]
fn malformed_duplicate_points() {
    let point = "        (length_over_width: 2.0),\n";
    let text = sweep_text(
        "",
        "        length_over_width: [1.0],\n",
        &format!("    points: [\n{point}{point}    ],\n"),
        10.0,
        5.0,
    );
    assert_rejected("dup-points", &text, "points:", &["duplicate point"]);
    let text = sweep_text(
        "",
        "        length_over_width: [1.0, 2.0, 1.0],\n",
        "",
        10.0,
        5.0,
    );
    assert_rejected(
        "dup-axis",
        &text,
        "length_over_width: [",
        &["duplicate value 1"],
    );
}

#[test]
fn malformed_unknown_engine() {
    let text = sweep_text("", "        length_over_width: [1.0],\n", "", 10.0, 5.0)
        .replace("engine: \"edmd\"", "engine: \"lbm\"");
    assert_rejected(
        "engine",
        &text,
        "engine:",
        &["\"lbm\" does not exist", "\"edmd\"", "\"dem\""],
    );
}

#[test]
fn malformed_override_is_rejected() {
    let dir = scratch("bad-override");
    let file = write(
        &dir,
        "ok.ron",
        &sweep_text("", "        length_over_width: [1.0],\n", "", 10.0, 5.0),
    );
    let results = dir.join("results");
    for set in ["restitution=2", "no_such_key=1", "restitution"] {
        let out = granflow(&run_args(&file, &results, &["--set", set]));
        assert_eq!(out.status.code(), Some(2), "--set {set}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--set"),
            "--set {set}"
        );
        assert!(!results.exists(), "--set {set}: something was written");
    }
}

/// The id is SHA-256 of the documented canonical text, written here by hand.
#[test]
fn job_id_is_hash_of_documented_canonical_form() {
    let dir = scratch("id-canonical");
    let file = write(
        &dir,
        "s.ron",
        &sweep_text("", "        length_over_width: [2.0],\n", "", 10.0, 5.0),
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    // N = round(0.15 * 8*4*4 / (pi/6)) = round(36.67) = 37
    let canonical = concat!(
        r#"{"analysis":{},"engine":"edmd","params":{"gravity":1.0,"height_over_diameter":4.0,"#,
        r#""inertia_factor":0.4,"initial_temperature":0.01,"length_over_width":2.0,"particles":37.0,"#,
        r#""restitution":0.7,"roughness":0.1,"tc":0.0001,"wall_restitution":0.99,"wall_roughness":0.99,"#,
        r#""width_over_diameter":4.0},"run":{"collisions_per_particle":10.0,"snapshot_interval":5.0},"seed":1}"#
    );
    assert_eq!(job.params.canonical(), canonical);
    let digest = Sha256::digest(canonical.as_bytes());
    let hex: String = digest[..8].iter().map(|b| format!("{b:02x}")).collect();
    assert_eq!(job.id.0, hex);
}

/// Adding an optional parameter at its default leaves ids alone; away from it, ids change.
/// Stating a default explicitly, or reaching a point through an override, gives the same id.
#[test]
fn job_id_stability() {
    let dir = scratch("id-stability");
    let base = write(
        &dir,
        "a.ron",
        &sweep_text(
            "",
            "        length_over_width: [1.0, 2.0],\n        restitution: [0.7, 0.9],\n",
            "",
            10.0,
            5.0,
        ),
    );
    let explicit = write(
        &dir,
        "b.ron",
        &sweep_text(
            "        tc: 0.0001,\n        roughness: 0.1,\n",
            "        length_over_width: [1.0, 2.0],\n        restitution: [0.7, 0.9],\n",
            "",
            10.0,
            5.0,
        ),
    );
    let a = load_sweep(&base, &[]).unwrap();
    let b = load_sweep(&explicit, &[]).unwrap();
    let ids = |s: &granflow::sweep::Sweep| s.plan.iter().map(|j| j.id.clone()).collect::<Vec<_>>();
    assert_eq!(ids(&a), ids(&b));
    let mut all = ids(&a);
    all.sort();
    all.dedup();
    assert_eq!(all.len(), 4, "distinct points have distinct ids");

    // an override reaching an existing point reuses its id
    let o = load_sweep(&base, &["restitution=0.9".into()]).unwrap();
    assert_eq!(o.plan.len(), 2);
    for job in &o.plan {
        assert!(
            a.plan
                .iter()
                .any(|j| j.id == job.id && j.params == job.params)
        );
    }

    // a parameter added later (in_id_at_default = false)
    let mut table: Vec<ParamDef> = edmd::DECLARATION.params.to_vec();
    table.push(ParamDef {
        name: "wall_friction_new",
        symbol: "mu_w",
        unit: "1",
        kind: ParamKind::Real,
        default: ParamDefault::Number(0.25),
        allowed: "[0, 1]",
        check: |v| (0.0..=1.0).contains(&v),
        doc: "a parameter added later",
        in_id: InId::AwayFromDefault,
    });
    let job: &JobParams = &a.plan[0].params;
    let mut at_default = job.clone();
    at_default
        .values
        .insert("wall_friction_new".into(), ParamValue::Number(0.25));
    assert_eq!(
        id_of_canonical(&canonical_with(&table, &at_default)),
        a.plan[0].id,
        "a new parameter at its default must not change the id"
    );
    let mut changed = job.clone();
    changed
        .values
        .insert("wall_friction_new".into(), ParamValue::Number(0.5));
    assert_ne!(
        id_of_canonical(&canonical_with(&table, &changed)),
        a.plan[0].id
    );
    // the seed and run length are part of the id, the checkpoint cadence is not
    let mut other_seed = job.clone();
    other_seed.seed = 2;
    assert_ne!(other_seed.id(), job.id());
    let mut cadence = job.clone();
    cadence.run.checkpoint_every = 7;
    assert_eq!(cadence.id(), job.id());
}

/// How many lines of a job log record `event` (its first word after the time).
fn event_count(log: &str, event: &str) -> usize {
    queue::log_events(log)
        .iter()
        .filter(|e| e.split(' ').next() == Some(event))
        .count()
}

/// The comparable part of a result: everything except wall-clock figures and times.
fn deterministic_part(dir: &Path) -> String {
    ron::to_string(&queue::read_result(dir).unwrap().without_wall_clock()).unwrap()
}

/// A job stopped after a few snapshots and resumed from its checkpoint ends bitwise identical
/// to an uninterrupted one (engine state, records and analysis).
#[test]
fn resumed_job_is_bitwise_identical() {
    let dir = scratch("resume-bitwise");
    let file = write(
        &dir,
        "s.ron",
        &sweep_text(
            "",
            "        length_over_width: [2.0],\n",
            "    seeds: [7],\n",
            120.0,
            10.0,
        ),
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    let run_in = |sub: &str, stops: &[u32]| -> PathBuf {
        let jd = dir.join(sub).join(&job.id.0);
        queue::init_job_dir(&jd, job).unwrap();
        for &stop in stops {
            let claim = queue::try_claim(&jd, false).unwrap().unwrap();
            let end = execute::run_job(
                job,
                &claim,
                Some(execute::StopAfter::Snapshot(stop)),
                &mut |_| {},
            )
            .unwrap();
            assert!(matches!(end, JobEnd::Stopped));
        }
        let claim = queue::try_claim(&jd, false).unwrap().unwrap();
        match execute::run_job(job, &claim, None, &mut |_| {}).unwrap() {
            JobEnd::Finished(r) => {
                queue::write_result(&jd, &r).unwrap();
            }
            other => panic!("not finished: {other:?}"),
        }
        jd
    };
    let straight = run_in("straight", &[]);
    let resumed = run_in("resumed", &[3, 7]);
    assert_eq!(deterministic_part(&straight), deterministic_part(&resumed));
    let a = queue::read_checkpoint(&straight).unwrap().unwrap();
    let b = queue::read_checkpoint(&resumed).unwrap().unwrap();
    assert_eq!(a.engine, b.engine, "final engine checkpoints differ");
    let (ra, rb) = (
        queue::load_records(&straight, &a).unwrap(),
        queue::load_records(&resumed, &b).unwrap(),
    );
    assert_eq!(
        postcard::to_stdvec(&ra).unwrap(),
        postcard::to_stdvec(&rb).unwrap()
    );
    // the record logs themselves are byte for byte the same (the resumed one was cut back to
    // its checkpoint and continued)
    assert_eq!(
        std::fs::read(straight.join(queue::RECORDS_FILE)).unwrap(),
        std::fs::read(resumed.join(queue::RECORDS_FILE)).unwrap()
    );
    let log = std::fs::read_to_string(resumed.join(queue::LOG_FILE)).unwrap();
    assert_eq!(event_count(&log, "start"), 1, "{log}");
    assert_eq!(event_count(&log, "resume"), 2, "{log}");
    assert_eq!(ra.len(), 13, "snapshots 0, 10, ..., 120");
}

/// The sweep used by the subprocess tests: 6 small jobs of a few seconds each.
fn subprocess_sweep(dir: &Path) -> PathBuf {
    write(
        dir,
        "proc.ron",
        &sweep_text(
            "",
            "        length_over_width: [1.0, 2.0, 3.0],\n        restitution: [0.7, 0.9],\n",
            "",
            1500.0,
            50.0,
        )
        .replace("width_over_diameter: 4.0", "width_over_diameter: 6.0")
        .replace("height_over_diameter: 4.0", "height_over_diameter: 6.0"),
    )
}

fn job_dirs(results: &Path) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(results.join("proc").join("jobs"))
        .map(|rd| rd.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    dirs.sort();
    dirs
}

fn run_to_end(file: &Path, results: &Path, threads: &str) {
    granflow_ok(&run_args(file, results, &["--threads", threads]));
}

/// kill -9 a real `granflow run` midway, rerun it: complete tables, no job started twice,
/// results identical to an uninterrupted run; then read the tables with pyarrow.
#[test]
fn kill_and_rerun_completes_without_rerunning_jobs() {
    let dir = scratch("kill");
    let file = subprocess_sweep(&dir);
    let results = dir.join("results");
    let mut child = Command::new(BIN)
        .args(run_args(&file, &results, &["--threads", "2"]))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // wait until one job is done and another has a checkpoint but no result
    let started = Instant::now();
    loop {
        let dirs = job_dirs(&results);
        let done = dirs
            .iter()
            .filter(|d| d.join(queue::RESULT_FILE).exists())
            .count();
        let partial = dirs
            .iter()
            .filter(|d| {
                d.join(queue::CHECKPOINT_FILE).exists() && !d.join(queue::RESULT_FILE).exists()
            })
            .count();
        if done >= 1 && partial >= 1 {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it could be killed"
        );
        assert!(started.elapsed() < Duration::from_secs(120), "no progress");
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let done_before = job_dirs(&results)
        .iter()
        .filter(|d| d.join(queue::RESULT_FILE).exists())
        .count();
    assert!(done_before < 6, "killed after the end");

    run_to_end(&file, &results, "2");
    let dirs = job_dirs(&results);
    assert_eq!(dirs.len(), 6);
    let mut resumed = 0;
    for d in &dirs {
        let log = std::fs::read_to_string(d.join(queue::LOG_FILE)).unwrap();
        // a fresh start is logged once its initial checkpoint is on disk: a second "start"
        // would mean that a run ignored an existing checkpoint
        assert!(event_count(&log, "start") <= 1, "{}: {log}", d.display());
        // "done" is appended after result.ron is in place: a kill in between may drop it
        assert!(event_count(&log, "done") <= 1, "{}: {log}", d.display());
        assert!(d.join(queue::RESULT_FILE).exists(), "{}", d.display());
        resumed += event_count(&log, "resume");
    }
    assert!(resumed >= 1, "no job was resumed from a checkpoint");

    // the same sweep without interruption gives the same results
    let reference = dir.join("reference");
    run_to_end(&file, &reference, "1");
    for d in &dirs {
        let id = d.file_name().unwrap();
        let r = reference.join("proc").join("jobs").join(id);
        assert_eq!(deterministic_part(d), deterministic_part(&r), "job {id:?}");
    }
    check_tables_with_pyarrow(&results.join("proc"), 6);
}

/// Read the four tables with Python pyarrow (an independent Parquet reader).
fn check_tables_with_pyarrow(tables: &Path, jobs: usize) {
    let probe = Command::new("python3")
        .args(["-c", "import pyarrow"])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!(
            "\n!!!!! SKIPPED: the pyarrow read-back check (python3 with pyarrow not found; .ci/run installs it) !!!!!\n"
        );
        return;
    }
    let script = r#"
import sys, pyarrow.parquet as pq
d, n = sys.argv[1], int(sys.argv[2])
jobs = pq.read_table(d + "/jobs.parquet").to_pydict()
assert len(jobs["job_id"]) == n, jobs["job_id"]
assert all(s == "done" for s in jobs["state"]), jobs["state"]
for col in ["length_over_width", "width_over_diameter", "height_over_diameter", "volume_fraction",
            "particles", "restitution", "roughness", "seed", "label", "humps", "pair_collisions",
            "tc_elastic_fraction", "wall_seconds", "events_per_second", "final_collisions_per_particle"]:
    assert col in jobs, col
assert all(c >= 1500 for c in jobs["final_collisions_per_particle"])
assert sorted(set(jobs["length_over_width"])) == [1.0, 2.0, 3.0]
energy = pq.read_table(d + "/energy.parquet").to_pydict()
assert set(energy["job_id"]) == set(jobs["job_id"])
assert all(0.0 <= c <= 1500.0 for c in energy["collisions_per_particle"])
for name, cols in [("spectra", ["job_id", "plane", "k1", "k2", "power"]),
                   ("profiles", ["job_id", "quantity", "bin", "coordinate", "value", "standard_error"])]:
    t = pq.read_table(d + "/" + name + ".parquet")
    assert t.column_names == cols, t.column_names
    assert set(t.column("job_id").to_pylist()) <= set(jobs["job_id"])
print("pyarrow ok")
"#;
    let out = Command::new("python3")
        .args(["-c", script, tables.to_str().unwrap(), &jobs.to_string()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "pyarrow check failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Two runners started together on one results directory: every job runs exactly once.
#[test]
fn two_runners_never_run_the_same_job() {
    let dir = scratch("two-runners");
    let file = subprocess_sweep(&dir);
    let results = dir.join("results");
    let spawn = || {
        Command::new(BIN)
            .args(run_args(&file, &results, &["--threads", "1"]))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn(), spawn());
    for child in [a, b] {
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // The final tables are never stale. Each runner gathers at its end under the
    // gather lock from what is on disk, so the runner that ends last writes every result;
    // the tables are read back before anything else gathers
    let states = {
        use polars::prelude::SerReader;
        let table = std::fs::File::open(results.join("proc").join("jobs.parquet")).unwrap();
        let frame = polars::prelude::ParquetReader::new(table)
            .with_columns(Some(vec!["state".into()]))
            .finish()
            .unwrap();
        frame
            .column("state")
            .unwrap()
            .str()
            .unwrap()
            .iter()
            .map(|s| s.unwrap_or_default().to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(states, vec!["done"; 6], "stale final tables");
    let dirs = job_dirs(&results);
    assert_eq!(dirs.len(), 6);
    for d in &dirs {
        let log = std::fs::read_to_string(d.join(queue::LOG_FILE)).unwrap();
        assert_eq!(event_count(&log, "start"), 1, "{}: {log}", d.display());
        assert_eq!(event_count(&log, "resume"), 0, "{}: {log}", d.display());
        assert_eq!(event_count(&log, "done"), 1, "{}: {log}", d.display());
    }
    // status and gather work from the results directory alone
    granflow_ok(&["gather", results.join("proc").to_str().unwrap()]);
    let out = granflow(&["status", results.join("proc").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("done 6"), "{text}");
    // a sweep run only with overrides: its directory has no tables of its own, and says
    // where they are (README.txt); `status` on it points to runs/
    let only = dir.join("only-overrides");
    granflow_ok(&run_args(&file, &only, &["--set", "restitution=0.9"]));
    let readme = std::fs::read_to_string(only.join("proc").join("README.txt")).unwrap();
    assert!(readme.contains("runs/<set>/"), "{readme}");
    let out = granflow(&["status", only.join("proc").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("runs/restitution=0.9"), "{text}");
    // an override reaching computed points: its own tables, the jobs reused (not rerun)
    granflow_ok(&run_args(&file, &results, &["--set", "restitution=0.9"]));
    let run_dir = results.join("proc/runs/restitution=0.9");
    let overridden = granflow::sweep::open_results(&run_dir).unwrap().0;
    assert_eq!(overridden.plan.len(), 3);
    assert!(run_dir.join("jobs.parquet").exists());
    assert_eq!(job_dirs(&results).len(), 6, "no new job directories");
    for d in &dirs {
        let log = std::fs::read_to_string(d.join(queue::LOG_FILE)).unwrap();
        assert_eq!(event_count(&log, "start"), 1, "{}: {log}", d.display());
    }
    // a results root that happens to be called `runs` is not taken for an override's
    // runs/<overrides>/ directory: status and gather find its jobs beside its tables
    let runs_root = dir.join("runs");
    granflow_ok(&run_args(&file, &runs_root, &["--job-range", "0:2"]));
    let out = granflow(&["status", runs_root.join("proc").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("done 2"), "{text}");
    // --job-range runs only its slice of the plan order
    let ranged = dir.join("ranged");
    granflow_ok(&run_args(&file, &ranged, &["--job-range", "1:3"]));
    let sweep = load_sweep(&file, &[]).unwrap();
    for job in &sweep.plan {
        let done = ranged
            .join("proc/jobs")
            .join(&job.id.0)
            .join(queue::RESULT_FILE)
            .exists();
        assert_eq!(done, (1..3).contains(&job.index), "job {}", job.index);
    }
}

/// A failing job is recorded with its error and the sweep goes on; `--retry-failed` reruns it.
#[test]
fn failed_job_is_recorded_and_retried() {
    let dir = scratch("failed");
    // the point stalls (perfectly inelastic smooth spheres without the TC model collapse)
    let file = write(
        &dir,
        "proc.ron",
        &sweep_text(
            "",
            "        length_over_width: [1.0, 3.0],\n",
            "    points: [(length_over_width: 2.0, restitution: 0.0, tc: 0.0, wall_restitution: 0.0,\n        roughness: -1.0, wall_roughness: -1.0)],\n",
            1000.0,
            50.0,
        ),
    );
    let results = dir.join("results");
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = |i: usize| results.join("proc/jobs").join(&sweep.plan[i].id.0);
    let (good, damaged, stalling) = (job(0), job(1), job(2));
    std::fs::create_dir_all(&damaged).unwrap();
    std::fs::write(damaged.join(queue::CHECKPOINT_FILE), b"not a checkpoint").unwrap();
    let run = |extra: &[&str]| granflow(&run_args(&file, &results, extra));
    let out = run(&[]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "a run with failed jobs exits with 1"
    );
    assert!(
        good.join(queue::RESULT_FILE).exists(),
        "the other job went on"
    );
    let failure = std::fs::read_to_string(stalling.join(queue::FAILED_FILE)).unwrap();
    assert!(failure.contains("stalled"), "{failure}");
    let status = granflow(&["status", results.join("proc").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(
        text.contains("failed 1") && text.contains("damaged 1") && text.contains("checksum"),
        "{text}"
    );
    // without --retry-failed neither is run again, and the damaged file stays where it is
    assert_eq!(run(&[]).status.code(), Some(1));
    assert!(!damaged.join(queue::RESULT_FILE).exists());
    assert_eq!(
        std::fs::read(damaged.join(queue::CHECKPOINT_FILE)).unwrap(),
        b"not a checkpoint"
    );
    // with it the damaged checkpoint is set aside (renamed, not deleted) and the job runs
    // afresh; the failed job runs again (and stalls again: exit code 1)
    assert_eq!(run(&["--retry-failed"]).status.code(), Some(1));
    assert!(damaged.join(queue::RESULT_FILE).exists());
    let aside: Vec<_> = std::fs::read_dir(&damaged)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("checkpoint.bin.damaged-"))
        .collect();
    assert_eq!(aside.len(), 1, "{aside:?}");
    assert_eq!(
        std::fs::read(damaged.join(&aside[0])).unwrap(),
        b"not a checkpoint"
    );
    assert!(stalling.join(queue::FAILED_FILE).exists());
    let log = std::fs::read_to_string(stalling.join(queue::LOG_FILE)).unwrap();
    assert_eq!(event_count(&log, "failed:"), 2, "{log}");

    // the phase diagram of the finished sweep: a strip over L/W, PNG and SVG, and bad axes
    let out = granflow(&[
        "phase-diagram",
        results.join("proc").to_str().unwrap(),
        "--x",
        "length_over_width",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let png = std::fs::read(results.join("proc/phase-length_over_width.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = std::fs::read_to_string(results.join("proc/phase-length_over_width.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("length_over_width"));
    let row = text
        .lines()
        .find(|l| l.trim_start().starts_with("structure"))
        .unwrap();
    assert_eq!(row.split_whitespace().count(), 4, "{text}");
    let out = granflow(&[
        "phase-diagram",
        results.join("proc").to_str().unwrap(),
        "--x",
        "no_such",
    ]);
    assert_eq!(out.status.code(), Some(2));
}

/// `plan` calibrates its rate on unfinished jobs too (the work to their checkpoint over the
/// wall seconds they ran to reach it), so a long sweep's first night-time estimate does not
/// rest on the engine's typical rate once a job has checkpointed.
#[test]
fn plan_calibrates_on_checkpointed_jobs() {
    let dir = scratch("plan-checkpointed");
    let file = write(
        &dir,
        "s.ron",
        &sweep_text(
            "",
            "        length_over_width: [1.0, 2.0],\n",
            "",
            400.0,
            20.0,
        ),
    );
    let results = dir.join("results");
    let plan = || {
        let out = granflow_ok(&[
            "plan",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ]);
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    assert!(plan().contains("typical"), "{}", plan());
    // job 0 runs 5 snapshots (100 of 400 collisions per particle) and stops, checkpointed
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&results);
    let job = &sweep.plan[0];
    let jd = dirs.job_dir(&job.id);
    queue::init_job_dir(&jd, job).unwrap();
    let claim = queue::try_claim(&jd, false).unwrap().unwrap();
    assert!(matches!(
        execute::run_job(
            job,
            &claim,
            Some(execute::StopAfter::Snapshot(5)),
            &mut |_| {}
        )
        .unwrap(),
        JobEnd::Stopped
    ));
    drop(claim);
    let cp = queue::read_checkpoint(&jd).unwrap().unwrap();
    assert!(cp.wall_seconds > 0.0 && cp.progress.collisions_per_particle > 0.0);
    let after = plan();
    assert!(
        after.contains("measured on 0 finished and 1 unfinished jobs"),
        "{after}"
    );
    // the rate it states is the checkpoint's: the work to it over its wall seconds
    let stated: f64 = after
        .split("of this sweep (")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .expect("a stated rate");
    let def = job.params.def();
    let work = (def.work)(
        &job.params.values,
        granflow::engine::Clock::CollisionsPerParticle,
        cp.progress.collisions_per_particle,
    );
    let measured = work / cp.wall_seconds;
    // the plan prints four significant digits
    assert!(
        (stated / measured - 1.0).abs() < 1e-3,
        "stated {stated}, checkpoint {measured}"
    );
}
