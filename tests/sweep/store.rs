//! The job store cannot be fooled: files copied from another job or edited after
//! they were written are detected, shown as damaged, set aside (renamed, never deleted) and
//! recomputed by `--retry-failed`, from the job's own checkpoint where it has one.

use granflow::sweep::{load_sweep, store};
use polars::prelude::SerReader;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::BIN;

use crate::common::scratch;

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// The comparable part of a result: everything except wall-clock figures and times.
fn deterministic(r: store::JobResult) -> String {
    ron::to_string(&r.without_wall_clock()).unwrap()
}

fn files_named(dir: &Path, prefix: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(prefix))
        .collect()
}

/// Write the sweep `text` as `dir/name` and run it to the end (into `dir/results`); the sweep
/// file and the results root.
fn run_to_the_end(dir: &Path, name: &str, text: &str) -> (PathBuf, PathBuf) {
    let file = dir.join(name);
    std::fs::write(&file, text).unwrap();
    let results = dir.join("results");
    let out = granflow(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    (file, results)
}

/// A sweep of three small EDMD jobs run once to the end: its job directories and each job's
/// result in deterministic form (what a recomputation must reproduce).
struct ThreeJobs {
    file: PathBuf,
    results: PathBuf,
    /// the sweep's tables directory (what `status` reads)
    tables: PathBuf,
    job_dirs: Vec<PathBuf>,
    good: Vec<String>,
}

impl ThreeJobs {
    fn run(name: &str) -> ThreeJobs {
        let (file, results) = run_to_the_end(
            &scratch(name),
            "s.ron",
            "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0, 3.0]), run: (collisions_per_particle: 200, snapshot_interval: 20))",
        );
        let mut three = ThreeJobs {
            file,
            results,
            tables: PathBuf::new(),
            job_dirs: Vec::new(),
            good: Vec::new(),
        };
        let sweep = load_sweep(&three.file, &[]).unwrap();
        let dirs = sweep.results_dir(&three.results);
        three.tables = dirs.tables.clone();
        three.job_dirs = sweep.plan.iter().map(|j| dirs.job_dir(&j.id)).collect();
        three.good = three
            .job_dirs
            .iter()
            .map(|d| deterministic(store::read_result(d).unwrap()))
            .collect();
        three
    }

    /// `granflow run` of the sweep with `extra` arguments.
    fn run_again(&self, extra: &[&str]) -> std::process::Output {
        let mut args = vec![
            "run",
            self.file.to_str().unwrap(),
            "--results",
            self.results.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        granflow(&args)
    }
}

#[test]
fn misplaced_and_edited_files_are_detected_set_aside_and_recomputed() {
    let sweep = ThreeJobs::run("misplaced");
    let (jd, good) = (sweep.job_dirs.clone(), sweep.good.clone());
    let run = |extra: &[&str]| sweep.run_again(extra);

    // job 1 gets job 0's result; job 2's result is edited; job 0 gets job 2's checkpoint
    std::fs::copy(
        jd[0].join(store::RESULT_FILE),
        jd[1].join(store::RESULT_FILE),
    )
    .unwrap();
    let text = std::fs::read_to_string(jd[2].join(store::RESULT_FILE)).unwrap();
    let edited = text.replacen("label: \"", "label: \"plug-", 1);
    assert!(edited != text, "nothing edited");
    std::fs::write(jd[2].join(store::RESULT_FILE), edited).unwrap();
    std::fs::remove_file(jd[0].join(store::RESULT_FILE)).unwrap();
    std::fs::copy(
        jd[2].join(store::CHECKPOINT_FILE),
        jd[0].join(store::CHECKPOINT_FILE),
    )
    .unwrap();

    let status = granflow(&["status", sweep.tables.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(text.contains("damaged 3"), "{text}");
    assert!(text.contains("belongs to job"), "{text}");
    assert!(text.contains("checksum mismatch"), "{text}");

    // without --retry-failed nothing is touched and the run says so (exit 1)
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("damaged"));
    // with it: set aside, recomputed; each job ends with its own result again
    let out = run(&["--retry-failed"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    for (i, d) in jd.iter().enumerate() {
        assert_eq!(
            deterministic(store::read_result(d).unwrap()),
            good[i],
            "job {i}"
        );
    }
    assert_eq!(files_named(&jd[0], "checkpoint.bin.damaged-").len(), 1);
    assert_eq!(files_named(&jd[1], "result.ron.damaged-").len(), 1);
    assert_eq!(files_named(&jd[2], "result.ron.damaged-").len(), 1);
    // jobs 1 and 2 were recomputed from their own (good) checkpoints: resumed, not restarted
    for d in &jd[1..] {
        let log = std::fs::read_to_string(d.join(store::LOG_FILE)).unwrap();
        let events = store::log_events(&log);
        assert!(
            events.iter().any(|e| e.starts_with("set aside result.ron")),
            "{log}"
        );
        assert!(events.iter().any(|e| e.starts_with("resume")), "{log}");
        assert_eq!(
            events.iter().filter(|e| e.starts_with("start")).count(),
            1,
            "{log}"
        );
    }
}

/// The table set (key-value metadata `granflow.table_set` of every table) of a tables
/// directory, one entry per table file.
fn table_sets(dir: &Path, names: &[&str]) -> Vec<String> {
    names
        .iter()
        .map(|n| {
            let mut f = std::fs::File::open(dir.join(format!("{n}.parquet"))).unwrap();
            let mut reader = polars::prelude::ParquetReader::new(&mut f);
            let meta = reader.get_metadata().unwrap();
            meta.key_value_metadata()
                .as_ref()
                .and_then(|kv| {
                    kv.iter()
                        .find(|k| k.key == "granflow.table_set")
                        .and_then(|k| k.value.clone())
                })
                .unwrap_or_default()
        })
        .collect()
}

/// kill -9 during table writing: the four tables always form one set (the same generation
/// in every file), and they carry their provenance.
#[test]
fn tables_are_always_one_consistent_set() {
    let dir = scratch("tables");
    let (_file, results) = run_to_the_end(
        &dir,
        "t.ron",
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), run: (collisions_per_particle: 400, snapshot_interval: 5))",
    );
    let tables = results.join("t");
    let names = ["jobs", "spectra", "profiles", "energy"];
    let first = table_sets(&tables, &names);
    assert!(!first[0].is_empty() && first.iter().all(|s| *s == first[0]));
    let mut seen = vec![first[0].clone()];
    // kill moments spread over 2.5 times the length of one whole gather, timed here (so that
    // many are cut and, even when a loaded machine slows some gathers to twice the time
    // measured, several complete)
    let timed = std::time::Instant::now();
    let out = granflow(&["gather", tables.to_str().unwrap()]);
    assert!(out.status.success());
    let whole = timed.elapsed();
    seen.push(table_sets(&tables, &names)[0].clone());
    for k in 0..40u32 {
        let mut child = Command::new(BIN)
            .args(["gather", tables.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(whole.mul_f64(2.5 * f64::from(k) / 40.0));
        let _ = child.kill();
        child.wait().unwrap();
        let sets = table_sets(&tables, &names);
        assert!(
            sets.iter().all(|s| *s == sets[0]),
            "kill {k}: a mixed set {sets:?}"
        );
        if !seen.contains(&sets[0]) {
            seen.push(sets[0].clone());
        }
    }
    assert!(
        seen.len() > 3,
        "no gather completed between the kills: {seen:?}"
    );
    // provenance in the file metadata
    let mut f = std::fs::File::open(tables.join("jobs.parquet")).unwrap();
    let mut reader = polars::prelude::ParquetReader::new(&mut f);
    let kv = reader
        .get_metadata()
        .unwrap()
        .key_value_metadata()
        .clone()
        .unwrap();
    for key in [
        "granflow.version",
        "granflow.commit",
        "granflow.sweep_ron",
        "granflow.host",
    ] {
        assert!(kv.iter().any(|k| k.key == key), "no {key}");
    }
    // killed gathers leave their staging directories until the next whole gather removes
    // them: after one, no generation directory is left but the current one
    let out = granflow(&["gather", tables.to_str().unwrap()]);
    assert!(out.status.success());
    let generations: Vec<_> = std::fs::read_dir(&tables)
        .unwrap()
        .filter_map(|e| {
            let n = e.unwrap().file_name().to_string_lossy().into_owned();
            n.starts_with(".tables-").then_some(n)
        })
        .collect();
    assert_eq!(generations.len(), 1, "{generations:?}");
}

/// Results made by another engine or analysis version are flagged by `status` (text and
/// JSON) and rerun by `run --rerun-outdated`: an analysis change reruns only the analysis from
/// the job's last checkpoint (same records, same analysis), an engine change reruns the job
/// from the start (bitwise the same result, as the engine did not really change); the old
/// files are kept as `.outdated-<time>`; current results are left alone.
#[test]
fn outdated_results_are_flagged_and_rerun_on_request() {
    let dir = scratch("outdated");
    let file = dir.join("o.ron");
    std::fs::write(
        &file,
        "(engine: \"lga\", fixed: (length: 40, width: 5, density: 1.0, dissipation: 0.5),\n axes: (bounce_back: [0.0, 0.5, 1.0]),\n run: (steps: 3000, snapshot_interval: 10, checkpoint_every: 50))",
    )
    .unwrap();
    let results = dir.join("results");
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    let out = granflow(&["run", f, "--results", r]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&results);
    let job_dir = |i: usize| dirs.job_dir(&sweep.plan[i].id);
    let original: Vec<store::JobResult> = (0..3)
        .map(|i| store::read_result(&job_dir(i)).unwrap())
        .collect();
    // job 0 as if made by analysis version 0, job 1 by engine version 0 (resealed and logged
    // as that build would have: valid files)
    let mut old = original[0].clone();
    old.provenance.analysis_version = 0;
    let sum = store::write_result(&job_dir(0), &old).unwrap();
    store::log(&job_dir(0), &store::done_line(&sum)).unwrap();
    let mut old = original[1].clone();
    old.provenance.engine_version = 0;
    let sum = store::write_result(&job_dir(1), &old).unwrap();
    store::log(&job_dir(1), &store::done_line(&sum)).unwrap();

    let out = granflow(&["status", f, "--results", r]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.matches("OUTDATED").count(), 2, "{text}");
    assert!(
        text.contains("made by analysis version 0") && text.contains("made by engine version 0")
    );
    let out = granflow(&["status", f, "--results", r, "--json"]);
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let flags: Vec<bool> = status["jobs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| !j["outdated"].is_null())
        .collect();
    assert_eq!(flags, [true, true, false]);

    // a plain run keeps them; --rerun-outdated reruns exactly those two
    let out = granflow(&["run", f, "--results", r]);
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("3 done, 0 to run")
            || String::from_utf8_lossy(&out.stdout).contains("3 done, 0 to run")
    );
    let out = granflow(&["run", f, "--results", r, "--rerun-outdated"]);
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{all}");
    assert!(
        all.contains("2 to run (2 of them outdated results)"),
        "{all}"
    );
    for (i, rerun_from) in [(0, "of the analysis"), (1, "from the start")] {
        let log = std::fs::read_to_string(job_dir(i).join(store::LOG_FILE)).unwrap();
        assert!(
            log.contains(&format!("rerun {rerun_from}")),
            "job {i}: {log}"
        );
        let kept = files_named(&job_dir(i), "result.ron.outdated-");
        assert_eq!(kept.len(), 1, "job {i}");
        let new = store::read_result(&job_dir(i)).unwrap();
        assert_eq!(
            deterministic(new),
            deterministic(original[i].clone()),
            "job {i}"
        );
    }
    // the engine rerun restarted: its checkpoint and records were set aside too
    assert_eq!(
        files_named(&job_dir(1), "checkpoint.bin.outdated-").len(),
        1
    );
    assert_eq!(
        files_named(&job_dir(0), "checkpoint.bin.outdated-").len(),
        0
    );
    let log = std::fs::read_to_string(job_dir(1).join(store::LOG_FILE)).unwrap();
    assert_eq!(log.matches(" start ").count(), 2, "{log}");
    // the current job was not touched
    assert!(files_named(&job_dir(2), "result.ron.outdated-").is_empty());
    let out = granflow(&["status", f, "--results", r]);
    assert!(!String::from_utf8_lossy(&out.stdout).contains("OUTDATED"));
}

/// A claim whose lock file is deleted while its job runs is detected: a second runner may
/// then claim the job (a new lock file), and the first stops at its next checkpoint without a
/// result, so the job is finished once (one `done`), by one runner, with the result of an
/// uninterrupted run. `status` names the holder of a running job.
#[test]
fn a_stolen_lock_stops_the_runner_that_lost_it() {
    use std::process::Stdio;
    let dir = scratch("stolen-lock");
    let file = dir.join("s.ron");
    std::fs::write(
        &file,
        "(engine: \"lga\", fixed: (length: 220, width: 11, density: 1.0, dissipation: 0.5),\n run: (steps: 300000, snapshot_interval: 100, checkpoint_every: 5))",
    )
    .unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    let reference = dir.join("reference");
    let out = granflow(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        reference.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let results = dir.join("results");
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    let job_dir = sweep.results_dir(&results).job_dir(&sweep.plan[0].id);
    let first = Command::new(BIN)
        .args(["run", f, "--results", r])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // wait for its first checkpoints
    let started = std::time::Instant::now();
    while store::checkpoint_progress(&job_dir).is_none_or(|p| p.steps < 2000) {
        assert!(started.elapsed().as_secs() < 60, "the job does not start");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let out = granflow(&["status", f, "--results", r]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!("pid={}", first.id())),
        "status does not name the holder: {text}"
    );
    // the theft: the lock file deleted, a second runner claims the job
    std::fs::remove_file(job_dir.join(store::LOCK_FILE)).unwrap();
    let second = granflow(&["run", f, "--results", r]);
    assert!(
        second.status.success(),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );
    let first = first.wait_with_output().unwrap();
    let first_out = String::from_utf8_lossy(&first.stdout);
    assert!(
        first_out.contains("lost "),
        "the first runner did not notice: {first_out}"
    );
    let log = std::fs::read_to_string(job_dir.join(store::LOG_FILE)).unwrap();
    assert_eq!(log.matches(" done").count(), 1, "{log}");
    assert!(log.contains("claim lost"), "{log}");
    let a = store::read_result(&sweep.results_dir(&reference).job_dir(&sweep.plan[0].id)).unwrap();
    let b = store::read_result(&job_dir).unwrap();
    assert_eq!(deterministic(a), deterministic(b));
}

/// A full disk (here: the file-size limit of `ulimit -f`, EFBIG, with SIGXFSZ ignored, as a
/// full disk's ENOSPC would) stops the runner from starting new jobs, names the file, leaves
/// the job resumable (partial, not failed) with no temp files behind, and exits with code 75;
/// the same command without the limit then finishes every job with the results of an
/// uninterrupted run.
#[test]
fn a_full_disk_stops_the_run_and_leaves_jobs_resumable() {
    let dir = scratch("full-disk");
    let file = dir.join("f.ron");
    std::fs::write(
        &file,
        "(engine: \"lga\", fixed: (length: 220, width: 11, dissipation: 0.5),\n axes: (density: [1.0, 1.2]),\n run: (steps: 30000, snapshot_interval: 10, checkpoint_every: 20))",
    )
    .unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    let (f, reference) = (file.to_str().unwrap(), dir.join("reference"));
    let out = granflow(&["run", f, "--results", reference.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let results = dir.join("results");
    let r = results.to_str().unwrap();
    let limited = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f 200; exec {BIN} run {f} --results {r} --threads 1"
        ))
        .output()
        .unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&limited.stdout),
        String::from_utf8_lossy(&limited.stderr)
    );
    assert_eq!(limited.status.code(), Some(75), "{said}");
    assert!(
        said.contains("records.bin"),
        "the message names no file: {said}"
    );
    let dirs = sweep.results_dir(&results);
    let states: Vec<String> = sweep
        .plan
        .iter()
        .map(|j| store::job_state(&dirs.job_dir(&j.id)).name().to_string())
        .collect();
    // the job that hit the limit is partial; the other never started
    let mut sorted = states.clone();
    sorted.sort();
    assert_eq!(sorted, ["partial", "pending"], "{said}");
    for job in &sweep.plan {
        let d = dirs.job_dir(&job.id);
        assert!(
            files_named(&d, ".").iter().all(|n| !n.contains(".tmp-")),
            "temp files left"
        );
        assert!(!d.join(store::FAILED_FILE).exists());
    }
    let out = granflow(&["run", f, "--results", r]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for job in &sweep.plan {
        let a = store::read_result(&sweep.results_dir(&reference).job_dir(&job.id)).unwrap();
        let b = store::read_result(&dirs.job_dir(&job.id)).unwrap();
        assert_eq!(deterministic(a), deterministic(b), "job {}", job.id);
    }
}

/// A truncated or corrupted checkpoint and a corrupted record log are no dead
/// end. The runner refuses them (exit 1, "damaged") until `--retry-failed`, which sets the
/// checkpoint and its record log aside (renamed, never deleted) and recomputes the job from
/// scratch, to the result it had before.
#[test]
fn damaged_checkpoints_and_record_logs_are_set_aside_and_recomputed() {
    let sweep = ThreeJobs::run("damaged");
    let (jd, good) = (sweep.job_dirs.clone(), sweep.good.clone());
    let run = |extra: &[&str]| sweep.run_again(extra);
    for d in &jd {
        std::fs::remove_file(d.join(store::RESULT_FILE)).unwrap();
    }
    // job 0: checkpoint cut in half; job 1: one checkpoint byte flipped; job 2: one byte of
    // the record log flipped inside the part its checkpoint covers
    let cp0 = std::fs::read(jd[0].join(store::CHECKPOINT_FILE)).unwrap();
    std::fs::write(jd[0].join(store::CHECKPOINT_FILE), &cp0[..cp0.len() / 2]).unwrap();
    let mut cp1 = std::fs::read(jd[1].join(store::CHECKPOINT_FILE)).unwrap();
    let mid = cp1.len() / 2;
    cp1[mid] ^= 0x40;
    std::fs::write(jd[1].join(store::CHECKPOINT_FILE), &cp1).unwrap();
    let mut log2 = std::fs::read(jd[2].join(store::RECORDS_FILE)).unwrap();
    let mid = log2.len() / 2;
    log2[mid] ^= 0x40;
    std::fs::write(jd[2].join(store::RECORDS_FILE), &log2).unwrap();

    // all three, the record log too: `status` reads what a resume would (and fails)
    let status = granflow(&["status", sweep.tables.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&status.stdout);
    assert!(text.contains("damaged 3"), "{text}");
    assert_eq!(status.status.code(), Some(1), "{text}");

    // refused, not failed, without --retry-failed; nothing is touched
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("damaged"), "{stdout}");
    assert!(
        std::fs::read_to_string(jd[2].join(store::LOG_FILE))
            .unwrap()
            .lines()
            .all(|l| !l.contains("set aside")),
        "touched without --retry-failed"
    );
    for d in &jd {
        assert!(!d.join(store::FAILED_FILE).exists(), "marked failed");
    }

    let out = run(&["--retry-failed"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    for (i, d) in jd.iter().enumerate() {
        assert_eq!(
            deterministic(store::read_result(d).unwrap()),
            good[i],
            "job {i}"
        );
        assert_eq!(
            files_named(d, "checkpoint.bin.damaged-").len(),
            1,
            "job {i}"
        );
        assert_eq!(files_named(d, "records.bin.damaged-").len(), 1, "job {i}");
        let log = std::fs::read_to_string(d.join(store::LOG_FILE)).unwrap();
        let events = store::log_events(&log);
        // recomputed from scratch: a second start, no resume
        assert_eq!(
            events.iter().filter(|e| e.starts_with("start")).count(),
            2,
            "{log}"
        );
    }
    // the damaged files are kept as they were
    let kept = files_named(&jd[2], "records.bin.damaged-");
    assert_eq!(std::fs::read(jd[2].join(&kept[0])).unwrap(), log2);
}

/// Checkpoint I/O is linear in the run length. The checkpoint holds the
/// engine state and names a prefix of the append-only record log, so its size does not grow
/// with the number of snapshots, while the log grows by one frame per snapshot.
#[test]
fn checkpoint_size_does_not_grow_with_the_run() {
    let dir = scratch("linear");
    let mut sizes = Vec::new();
    for cpp in [200, 800] {
        let file = dir.join(format!("s{cpp}.ron"));
        std::fs::write(
            &file,
            format!("(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n run: (collisions_per_particle: {cpp}, snapshot_interval: 10))"),
        )
        .unwrap();
        let results = dir.join(format!("results{cpp}"));
        let out = granflow(&[
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        let sweep = load_sweep(&file, &[]).unwrap();
        let jd = sweep.results_dir(&results).job_dir(&sweep.plan[0].id);
        let size = |f: &str| std::fs::metadata(jd.join(f)).unwrap().len();
        sizes.push((size(store::CHECKPOINT_FILE), size(store::RECORDS_FILE)));
    }
    let ((cp_short, log_short), (cp_long, log_long)) = (sizes[0], sizes[1]);
    // 21 and 81 snapshots: the log grows with them (frames differ a little in size) ...
    let growth = log_long as f64 / log_short as f64;
    assert!(
        (3.0..4.6).contains(&growth),
        "record log {log_short} -> {log_long}"
    );
    // ... the checkpoint does not (the engine state is the same size; counters may need a
    // few more bytes as varints)
    assert!(
        cp_long.abs_diff(cp_short) < 64,
        "checkpoint {cp_short} -> {cp_long} bytes"
    );
}

/// Every result says which code made it, where and when; log lines carry UTC
/// times; the tables carry the build in their metadata (checked in
/// `tables_are_always_one_consistent_set`).
#[test]
fn results_and_logs_carry_their_provenance() {
    let dir = scratch("provenance");
    let (file, results) = run_to_the_end(
        &dir,
        "s.ron",
        "(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n run: (collisions_per_particle: 100, snapshot_interval: 20))",
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let jd = sweep.results_dir(&results).job_dir(&sweep.plan[0].id);
    let p = store::read_result(&jd).unwrap().provenance;
    assert_eq!(p.granflow, env!("CARGO_PKG_VERSION"));
    assert_eq!(p.commit, granflow::provenance::COMMIT);
    assert!(!p.commit.is_empty());
    assert_eq!(p.host, granflow::provenance::host());
    assert_eq!(
        p.engine_version,
        granflow::registry::find("edmd").unwrap().version
    );
    // RFC 3339 UTC times, start before finish
    for t in [&p.started, &p.finished] {
        assert!(
            t.len() >= 20 && t.ends_with('Z') && t.as_bytes()[10] == b'T',
            "{t}"
        );
    }
    assert!(p.started <= p.finished, "{} > {}", p.started, p.finished);
    let log = std::fs::read_to_string(jd.join(store::LOG_FILE)).unwrap();
    for line in log.lines() {
        assert!(
            line.len() > 21 && line.as_bytes()[10] == b'T',
            "untimed log line: {line}"
        );
    }
    assert!(
        log.contains(&granflow::provenance::Provenance::build()),
        "{log}"
    );

    // a runner stopped between writing the result and its `done` line (item 9): the next run
    // completes the log
    let cut: String = log
        .lines()
        .filter(|l| !l.contains(" done checksum="))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_ne!(cut, log, "no done line");
    std::fs::write(jd.join(store::LOG_FILE), &cut).unwrap();
    let out = granflow(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let log = std::fs::read_to_string(jd.join(store::LOG_FILE)).unwrap();
    let events = store::log_events(&log);
    let last = events.last().unwrap();
    assert!(
        last.starts_with("done checksum=") && last.contains("(logged late"),
        "{log}"
    );
    assert_eq!(
        events.iter().filter(|e| e.starts_with("start")).count(),
        1,
        "{log}"
    );
}

/// A result stays valid when a later granflow reads it into changed types: its checksum is
/// that of the file's own text (with the checksum value blanked), never of a re-serialisation.
/// Here a result written as an older build would have written it (a field that later builds
/// write, `stop_reason`, is missing from its text; its checksum is of that text) is done, not
/// damaged; the same file with a changed value is damaged.
#[test]
fn results_of_older_layouts_keep_their_checksums() {
    let dir = scratch("layouts");
    let (file, results) = run_to_the_end(
        &dir,
        "s.ron",
        "(engine: \"edmd\", fixed: (length_over_width: 1.0, width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n run: (collisions_per_particle: 100, snapshot_interval: 20))",
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    let jd = sweep.results_dir(&results).job_dir(&sweep.plan[0].id);
    let path = jd.join(store::RESULT_FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    let written = store::read_result(&jd).unwrap();
    // the older layout: no stop_reason line, checksum of that text with the value blanked
    let older: String = text
        .lines()
        .filter(|l| !l.starts_with("    stop_reason:"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_ne!(older, text, "no stop_reason line to leave out");
    let field = format!("\n    checksum: \"{}\"", written.checksum);
    let blank = older.replacen(&field, "\n    checksum: \"\"", 1);
    let sum = granflow::sweep::job::id_of_canonical(blank.trim_end_matches('\n')).0;
    let older = blank.replacen(
        "\n    checksum: \"\"",
        &format!("\n    checksum: \"{sum}\""),
        1,
    );
    std::fs::write(&path, older.trim_end_matches('\n')).unwrap();
    // older builds logged a bare `done` (the log names no checksum)
    let log = std::fs::read_to_string(jd.join(store::LOG_FILE)).unwrap();
    let bare = format!("done checksum={}", written.checksum);
    assert!(log.contains(&bare), "{log}");
    std::fs::write(jd.join(store::LOG_FILE), log.replace(&bare, "done")).unwrap();
    let read = store::read_result(&jd).expect("an older layout is not damage");
    assert_eq!(read.stop_reason, "");
    // (compared as text: the analysis holds NaN where a balance is not known, and NaN != NaN)
    assert_eq!(
        format!("{:?}", read.analysis),
        format!("{:?}", written.analysis)
    );
    // an edit of a value is damage
    let edited = older.replacen("particles: ", "particles: 1", 1);
    std::fs::write(&path, edited.trim_end_matches('\n')).unwrap();
    let err = store::read_result(&jd).unwrap_err();
    assert!(format!("{err:#}").contains("checksum mismatch"), "{err:#}");
}

/// Parameters read back from JSON to the same bits, 17 significant digits included (a DEM
/// default time step 1.2e-4 sqrt(1e6 / 1e5) is such a value; without exact parsing its job
/// was reported damaged).
#[test]
fn seventeen_digit_values_read_back_bit_for_bit() {
    let mut x = 1.2e-4 * (1e6f64 / 1e5).sqrt();
    for _ in 0..2000 {
        let text = serde_json::to_string(&x).unwrap();
        let back: f64 = serde_json::from_str(&text).unwrap();
        assert_eq!(back.to_bits(), x.to_bits(), "{text}");
        x = x * 1.000_000_7 + 3.1e-19;
    }
}
