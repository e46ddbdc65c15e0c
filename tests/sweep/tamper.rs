//! Every file of a job names its job and is checked, for every engine: a record log copied
//! from another job of the same length, a result whose checksum is blanked or deleted, and an
//! emptied or foreign `params.json` are all damage. `status` then fails (exit 1) after listing
//! them, `run` refuses them, and `run --retry-failed` sets them aside and recomputes (or, for
//! the parameters file, rewrites) them, ending with each job's own result again.

use granflow::sweep::{load_sweep, store};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::BIN;

use crate::common::scratch;

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Small sweeps of three jobs of the same length, one per engine.
const SWEEPS: &[(&str, &str)] = &[
    (
        "edmd",
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0, 3.0]), run: (collisions_per_particle: 100, snapshot_interval: 20))",
    ),
    (
        "lga",
        "(engine: \"lga\", fixed: (length: 40, width: 5, density: 1.0, dissipation: 0.5),\n axes: (bounce_back: [0.0, 0.5, 1.0]),\n run: (steps: 400, snapshot_interval: 10))",
    ),
    (
        "dsmc",
        "(engine: \"dsmc\", fixed: (knudsen_number: 0.1, particles_per_cell: 20),\n axes: (forcing: [0.2, 0.4, 0.6]),\n run: (steps: 200, snapshot_interval: 20))",
    ),
];

/// A sweep run to the end: its file, results root, tables directory, job directories and
/// each job's result without wall-clock figures.
struct Ran {
    file: PathBuf,
    results: PathBuf,
    tables: PathBuf,
    jobs: Vec<PathBuf>,
    good: Vec<String>,
}

fn deterministic(dir: &Path) -> String {
    ron::to_string(&store::read_result(dir).unwrap().without_wall_clock()).unwrap()
}

impl Ran {
    fn new(name: &str, sweep: &str) -> Ran {
        let dir = scratch(name);
        let file = dir.join("s.ron");
        std::fs::write(&file, sweep).unwrap();
        let results = dir.join("results");
        let mut ran = Ran {
            file,
            results,
            tables: PathBuf::new(),
            jobs: Vec::new(),
            good: Vec::new(),
        };
        let out = ran.run(&[]);
        assert!(out.status.success(), "{name}: {}", text(&out));
        let sweep = load_sweep(&ran.file, &[]).unwrap();
        let dirs = sweep.results_dir(&ran.results);
        ran.tables = dirs.tables.clone();
        ran.jobs = sweep.plan.iter().map(|j| dirs.job_dir(&j.id)).collect();
        ran.good = ran.jobs.iter().map(|d| deterministic(d)).collect();
        ran
    }

    fn run(&self, extra: &[&str]) -> Output {
        let mut args = vec![
            "run",
            self.file.to_str().unwrap(),
            "--results",
            self.results.to_str().unwrap(),
            "--threads",
            "1",
        ];
        args.extend_from_slice(extra);
        granflow(&args)
    }

    fn status(&self) -> Output {
        granflow(&["status", self.tables.to_str().unwrap()])
    }

    /// `status` fails and names every damaged job with `why`; `run` refuses them; `run
    /// --retry-failed` recomputes each to its own result.
    fn detected_and_recomputed(&self, engine: &str, damaged: &[usize], why: &[&str]) {
        let status = self.status();
        let out = text(&status);
        assert_eq!(status.status.code(), Some(1), "{engine}: status: {out}");
        assert!(
            out.contains(&format!("damaged {}", damaged.len())),
            "{engine}: {out}"
        );
        for w in why {
            assert!(out.contains(w), "{engine}: `{w}` not said: {out}");
        }
        let refused = self.run(&[]);
        assert_eq!(
            refused.status.code(),
            Some(1),
            "{engine}: {}",
            text(&refused)
        );
        let retried = self.run(&["--retry-failed"]);
        assert!(retried.status.success(), "{engine}: {}", text(&retried));
        for (i, d) in self.jobs.iter().enumerate() {
            assert_eq!(deterministic(d), self.good[i], "{engine}: job {i}");
        }
        let status = self.status();
        assert!(status.status.success(), "{engine}: {}", text(&status));
    }
}

/// A record log copied from another job of the same length: without a result the job would
/// resume from it into a wrong result.
#[test]
fn a_record_log_copied_from_another_job_is_refused() {
    for (engine, sweep) in SWEEPS {
        let ran = Ran::new(&format!("records-{engine}"), sweep);
        let (a, b) = (&ran.jobs[0], &ran.jobs[1]);
        let len_a = std::fs::metadata(a.join(store::RECORDS_FILE))
            .unwrap()
            .len();
        let len_b = std::fs::metadata(b.join(store::RECORDS_FILE))
            .unwrap()
            .len();
        for d in &ran.jobs {
            std::fs::remove_file(d.join(store::RESULT_FILE)).unwrap();
        }
        std::fs::copy(a.join(store::RECORDS_FILE), b.join(store::RECORDS_FILE)).unwrap();
        if len_a == len_b {
            // the same length: only the header and the digest tell them apart
            ran.detected_and_recomputed(engine, &[1], &["belongs to job"]);
        } else {
            ran.detected_and_recomputed(engine, &[1], &["records.bin"]);
        }
        // the copy was set aside, never deleted
        let kept = std::fs::read_dir(b)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with("records.bin.damaged-")
            })
            .count();
        assert_eq!(kept, 1, "{engine}");
    }
}

/// The same log with its header rewritten to name the job it now sits in: the checkpoint's
/// digest still tells.
#[test]
fn a_record_log_renamed_to_its_new_job_fails_the_digest() {
    let (engine, sweep) = SWEEPS[0];
    let ran = Ran::new("records-renamed", sweep);
    let (a, b) = (&ran.jobs[0], &ran.jobs[1]);
    for d in &ran.jobs {
        std::fs::remove_file(d.join(store::RESULT_FILE)).unwrap();
    }
    let mut copied = std::fs::read(a.join(store::RECORDS_FILE)).unwrap();
    let own = std::fs::read(b.join(store::RECORDS_FILE)).unwrap();
    copied[..32].copy_from_slice(&own[..32]);
    std::fs::write(b.join(store::RECORDS_FILE), &copied).unwrap();
    ran.detected_and_recomputed(engine, &[1], &["digest"]);
}

/// A result whose checksum is blanked, or whose checksum line is deleted, after an edit.
#[test]
fn a_result_without_its_checksum_is_damaged() {
    for (engine, sweep) in SWEEPS {
        let ran = Ran::new(&format!("checksum-{engine}"), sweep);
        let edit = |d: &Path, blank: bool| {
            let path = d.join(store::RESULT_FILE);
            let text = std::fs::read_to_string(&path).unwrap();
            let lines: Vec<String> = text
                .lines()
                .filter_map(|l| {
                    if l.starts_with("    checksum: ") {
                        blank.then(|| "    checksum: \"\",".to_string())
                    } else if l.starts_with("    time: ") {
                        Some("    time: 12345.0,".to_string())
                    } else {
                        Some(l.to_string())
                    }
                })
                .collect();
            let edited = lines.join("\n");
            assert_ne!(edited, text, "{engine}: nothing edited");
            std::fs::write(&path, edited).unwrap();
        };
        edit(&ran.jobs[0], true);
        edit(&ran.jobs[2], false);
        ran.detected_and_recomputed(engine, &[0, 2], &["no checksum"]);
    }
}

/// A result whose `format` and checksum lines are both deleted (what an older layout looks
/// like) is still damage: the job's log names the checksum its result had.
#[test]
fn a_result_made_to_look_older_is_damaged() {
    let (engine, sweep) = SWEEPS[0];
    let ran = Ran::new("older-looking", sweep);
    let path = ran.jobs[1].join(store::RESULT_FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    let edited: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with("    checksum: ") && !l.starts_with("    format: "))
        .collect();
    std::fs::write(&path, edited.join("\n")).unwrap();
    ran.detected_and_recomputed(engine, &[1], &["no checksum"]);
}

/// An emptied `params.json`, and one copied from another job, in done jobs.
#[test]
fn an_emptied_or_foreign_params_file_is_damaged() {
    for (engine, sweep) in SWEEPS {
        let ran = Ran::new(&format!("params-{engine}"), sweep);
        std::fs::write(ran.jobs[0].join(store::PARAMS_FILE), "").unwrap();
        std::fs::copy(
            ran.jobs[2].join(store::PARAMS_FILE),
            ran.jobs[1].join(store::PARAMS_FILE),
        )
        .unwrap();
        ran.detected_and_recomputed(engine, &[0, 1], &["params.json", "belongs to job"]);
        // rewritten from the plan, the damaged ones kept beside; the job stays done with the
        // result it had, and its log gets no second (false) `done` line
        for d in &ran.jobs[..2] {
            assert!(store::read_params(d).is_ok(), "{engine}");
            let log = std::fs::read_to_string(d.join(store::LOG_FILE)).unwrap();
            assert!(!log.contains("logged late"), "{engine}: {log}");
            assert_eq!(
                store::log_events(&log)
                    .iter()
                    .filter(|e| e.starts_with("done"))
                    .count(),
                1,
                "{engine}: {log}"
            );
        }
    }
    // a params.json whose parameters were edited (its id and canonical form left alone)
    let ran = Ran::new("params-edited", SWEEPS[0].1);
    let path = ran.jobs[0].join(store::PARAMS_FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    let edited = text.replacen("\"restitution\": 0.7,", "\"restitution\": 0.75,", 1);
    assert_ne!(edited, text, "nothing edited");
    std::fs::write(&path, edited).unwrap();
    ran.detected_and_recomputed("edmd", &[0], &["do not give its canonical form"]);
}

/// The checkpoint and record log of *done* jobs are checked too. Cheaply by every
/// `status` (which job they name, their lengths): a record log copied from another job and a
/// checkpoint cut short are found at once; a byte flipped inside a record log only by `status
/// --verify`, which reads the files whole. `run --retry-failed` finds all three, sets the
/// files aside with the result and recomputes each job to the result it had.
#[test]
fn damaged_files_of_done_jobs_are_found_by_status() {
    for (engine, sweep) in SWEEPS {
        let ran = Ran::new(&format!("done-files-{engine}"), sweep);
        let (a, b, c) = (&ran.jobs[0], &ran.jobs[1], &ran.jobs[2]);
        std::fs::copy(b.join(store::RECORDS_FILE), a.join(store::RECORDS_FILE)).unwrap();
        let cp = std::fs::read(b.join(store::CHECKPOINT_FILE)).unwrap();
        std::fs::write(b.join(store::CHECKPOINT_FILE), &cp[..cp.len() - 9]).unwrap();
        let mut log = std::fs::read(c.join(store::RECORDS_FILE)).unwrap();
        let mid = log.len() / 2;
        log[mid] ^= 0x40;
        std::fs::write(c.join(store::RECORDS_FILE), &log).unwrap();

        let status = ran.status();
        let out = text(&status);
        assert_eq!(status.status.code(), Some(1), "{engine}: {out}");
        assert!(out.contains("damaged 2"), "{engine}: {out}");
        assert!(out.contains("belongs to job"), "{engine}: {out}");
        assert!(out.contains("checkpoint.bin"), "{engine}: {out}");
        let verified = granflow(&["status", ran.tables.to_str().unwrap(), "--verify"]);
        let out = text(&verified);
        assert_eq!(verified.status.code(), Some(1), "{engine}: {out}");
        assert!(out.contains("damaged 3"), "{engine}: {out}");
        assert!(out.contains("digest"), "{engine}: {out}");

        let retried = ran.run(&["--retry-failed"]);
        assert!(retried.status.success(), "{engine}: {}", text(&retried));
        for (i, d) in ran.jobs.iter().enumerate() {
            assert_eq!(deterministic(d), ran.good[i], "{engine}: job {i}");
        }
        let verified = granflow(&["status", ran.tables.to_str().unwrap(), "--verify"]);
        assert!(verified.status.success(), "{engine}: {}", text(&verified));
        // the damaged files were set aside (never deleted), the result with them
        for d in &ran.jobs {
            let names: Vec<String> = std::fs::read_dir(d)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            assert!(
                names.iter().any(|n| n.starts_with("result.ron.damaged-")),
                "{engine}: {names:?}"
            );
        }
    }
}
