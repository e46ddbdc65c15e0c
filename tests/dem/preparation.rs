//! A DEM job's preparation (the packing settling onto its floor) runs in checkpointed chunks:
//! a job stopped in the middle of it is partial, says so in its log, reports the preparation's
//! progress, resumes from `preparation.bin` and ends bitwise identical to an uninterrupted job.

use crate::common::scratch;
use granflow::sweep::execute::{self, JobEnd, JobProgress, StopAfter};
use granflow::sweep::{load_sweep, store as queue};
use std::path::{Path, PathBuf};

/// One small channel (W = 10, B = 5, L = 10 d_p, about 430 particles) run for two time units
/// after its preparation (some 7e4 steps).
const SWEEP: &str = r#"(
    name: "prep",
    engine: "dem",
    fixed: (
        width_over_diameter: 10.0,
        span_over_diameter: 5.0,
        length_over_diameter: 10.0,
        normal_stiffness: 1e5,
        time_step: 3.7e-4,
        volume_fraction: 0.45,
    ),
    seeds: [3],
    run: (time: 2.0, snapshot_interval: 1.0),
)"#;

/// The comparable part of a result: everything except wall-clock figures and times.
fn deterministic_part(dir: &Path) -> String {
    ron::to_string(&queue::read_result(dir).unwrap().without_wall_clock()).unwrap()
}

fn log_of(dir: &Path) -> String {
    std::fs::read_to_string(dir.join(queue::LOG_FILE)).unwrap_or_default()
}

#[test]
fn a_preparation_stopped_midway_resumes_to_the_same_bits() {
    let dir = scratch("prep");
    let file = dir.join("prep.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    let run_in = |sub: &str, stops: &[u64], reports: &mut Vec<JobProgress>| -> PathBuf {
        let jd = dir.join(sub).join(&job.id.0);
        queue::init_job_dir(&jd, job).unwrap();
        for &stop in stops {
            let claim = queue::try_claim(&jd, false).unwrap().unwrap();
            let end = execute::run_job(
                job,
                &claim,
                Some(StopAfter::PreparationSteps(stop)),
                &mut |p| reports.push(p),
            )
            .unwrap();
            assert!(matches!(end, JobEnd::Stopped), "{end:?}");
            drop(claim);
            // in the middle of the preparation: partial at the clocks' start, with its file
            assert_eq!(
                queue::job_state(&jd),
                queue::JobState::Partial(Default::default())
            );
            let cp = queue::read_preparation(&jd).unwrap().unwrap();
            assert_eq!(cp.steps, stop);
            assert_eq!(cp.job_id, job.id.0);
            assert!(queue::read_checkpoint(&jd).unwrap().is_none());
        }
        let claim = queue::try_claim(&jd, false).unwrap().unwrap();
        match execute::run_job(job, &claim, None, &mut |p| reports.push(p)).unwrap() {
            JobEnd::Finished(r) => {
                queue::write_result(&jd, &r).unwrap();
            }
            other => panic!("not finished: {other:?}"),
        }
        jd
    };
    let mut straight_reports = Vec::new();
    let straight = run_in("straight", &[], &mut straight_reports);
    let mut reports = Vec::new();
    let resumed = run_in("resumed", &[3000, 20_000], &mut reports);

    // the same bits: result, final engine state, records
    assert_eq!(deterministic_part(&straight), deterministic_part(&resumed));
    let a = queue::read_checkpoint(&straight).unwrap().unwrap();
    let b = queue::read_checkpoint(&resumed).unwrap().unwrap();
    assert_eq!(a.engine, b.engine, "final engine checkpoints differ");
    assert_eq!(
        std::fs::read(straight.join(queue::RECORDS_FILE)).unwrap(),
        std::fs::read(resumed.join(queue::RECORDS_FILE)).unwrap()
    );
    let prep_steps = queue::read_result(&resumed)
        .unwrap()
        .counters
        .get("prep_steps");
    assert!(
        prep_steps > 20_000,
        "the preparation took {prep_steps} steps"
    );

    // once checkpoint 0 holds the job, its preparation file is gone
    for jd in [&straight, &resumed] {
        assert!(queue::read_preparation(jd).unwrap().is_none());
    }
    // the log: one preparation, resumed once from each stop, then one start
    let log = log_of(&resumed);
    let events: Vec<_> = queue::log_events(&log);
    let named = |word: &str| events.iter().filter(|e| e.starts_with(word)).count();
    assert_eq!(named("prepare "), 1, "{log}");
    assert_eq!(named("resume the preparation at step 3000 "), 1, "{log}");
    assert_eq!(named("resume the preparation at step 20000 "), 1, "{log}");
    assert_eq!(named("start "), 1, "{log}");
    assert_eq!(
        queue::first_start(&resumed).as_deref(),
        log.split(' ').next(),
        "the job started when its preparation did"
    );
    // the straight run had no stop inside its preparation: no `prepare` line, no file left
    assert_eq!(
        queue::log_events(&log_of(&straight))
            .iter()
            .filter(|e| e.starts_with("prepare "))
            .count(),
        0
    );

    // progress: the preparation's stage and steps while it lasts, then the run's clock
    let preparing: Vec<_> = reports.iter().filter_map(|p| p.preparing.clone()).collect();
    assert_eq!(
        preparing.iter().map(|p| p.steps).collect::<Vec<_>>(),
        [3000, 20_000],
        "one report per chunk (each ends at a stop here)"
    );
    assert!(preparing.iter().all(|p| p.max_steps > 20_000
        && ["compaction", "freezing"].contains(&p.stage)
        && p.measure.contains("kinetic energy per particle")));
    assert!(reports.last().unwrap().preparing.is_none());
    let last = reports.last().unwrap();
    assert!((last.clock - last.target).abs() < 1e-3, "{last:?}");
}

/// A damaged preparation checkpoint makes the job damaged, naming the file, and is not run.
#[test]
fn a_damaged_preparation_file_is_named() {
    let dir = scratch("prep-damaged");
    let file = dir.join("prep.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let sweep = load_sweep(&file, &[]).unwrap();
    let job = &sweep.plan[0];
    let jd = dir.join("r").join(&job.id.0);
    queue::init_job_dir(&jd, job).unwrap();
    let claim = queue::try_claim(&jd, false).unwrap().unwrap();
    let end = execute::run_job(
        job,
        &claim,
        Some(StopAfter::PreparationSteps(500)),
        &mut |_| {},
    )
    .unwrap();
    assert!(matches!(end, JobEnd::Stopped));
    drop(claim);
    let path = jd.join(queue::PREPARATION_FILE);
    let mut bytes = std::fs::read(&path).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    std::fs::write(&path, &bytes).unwrap();
    match queue::job_state_checked(&jd, true) {
        queue::JobState::Damaged { file, reason } => {
            assert_eq!(file, queue::PREPARATION_FILE);
            assert!(reason.contains("checksum mismatch"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
}
