//! Running one job: build (or restore) the engine, advance snapshot by snapshot on the run's
//! clock, record each snapshot for the analysis, checkpoint at a fixed cadence of simulated
//! progress, analyse at the end. The job directory's files are the store's ([`super::store`]).
//!
//! Snapshot k (k = 0, 1, ..., K) is taken when the clock reads c_k = min(k * interval, run
//! length), K = ceil(run length / interval). A checkpoint (engine bytes + records so far) is
//! written after snapshot k when k is a multiple of `checkpoint_every` and after the last one:
//! the only point where `Engine::checkpoint` is valid, and never driven by wall-clock time, so
//! a resumed job ends bitwise identical to an uninterrupted one. Records are appended to the
//! job's record log at every snapshot and made durable before each checkpoint names them.
//!
//! An engine that prepares its initial state first (DEM: the packing settles onto a floor,
//! an hour or more at the paper's widths) does so before snapshot 0, in chunks of about
//! [`PREPARATION_CHUNK_WORK`] particle-steps, each followed by a preparation checkpoint
//! (`preparation.bin`) and a progress report; a killed job resumes its preparation from the
//! last one. Where a preparation is split does not change its bits (the engine's tests), so the
//! job ends identical to an uninterrupted one.

use super::grid::PlannedJob;
pub use super::job_error::JobError;
use super::store::{
    self, Claim, JobCheckpoint, JobDir, JobResult, PreparationCheckpoint, RecordLog,
};
use crate::analysis::{Analyser, Record, StopCheck};
use crate::engine::{Engine, PreparationProgress, StopAt};
use crate::provenance::Provenance;
use std::time::Instant;

/// How a call to [`run_job`] ended.
#[derive(Debug)]
pub enum JobEnd {
    Finished(Box<JobResult>),
    /// stopped after the snapshot asked for (tests of resumption)
    Stopped,
    /// the claim was lost (its lock file deleted or replaced): stopped without a result,
    /// leaving the job to whoever holds it now
    ClaimLost(String),
}

/// Where a call to [`run_job`] stops early (tests of resumption).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopAfter {
    /// after snapshot k (and its checkpoint, when one falls there)
    Snapshot(u32),
    /// once the preparation has done at least this many of its steps (its checkpoint written)
    PreparationSteps(u64),
}

/// Particle-steps of preparation between two preparation checkpoints: 20-60 s at the DEM
/// engine's 7-18 M particle-steps/s on one core (docs/performance.md). Any chunking gives the
/// same bits; this one bounds the work a kill can lose.
pub const PREPARATION_CHUNK_WORK: f64 = 4e8;

/// Progress of a running job, reported after each snapshot (and each chunk of a preparation).
#[derive(Clone, Debug)]
pub struct JobProgress {
    /// the run's clock now
    pub clock: f64,
    /// the run length on that clock
    pub target: f64,
    pub events_per_second: f64,
    /// the preparation's progress while the engine prepares its initial state (the clock
    /// then reads its start)
    pub preparing: Option<PreparationProgress>,
}

/// A job between snapshots: its engine, the records so far (also in the record log) and
/// the snapshot it is at.
struct Running {
    engine: Box<dyn Engine>,
    records: Vec<Record>,
    log: RecordLog,
    /// the snapshot taken last
    k: u32,
    /// wall-clock seconds spent on the job before this call (from its checkpoint)
    wall_before: f64,
}

/// Where the loop over snapshots ended.
enum Advanced {
    /// at the run length, or steady (`until_steady`): the stop reason ("" without a rule)
    Reached(String),
    /// after the snapshot `stop_after` asked for
    Stopped,
    /// the claim was lost
    ClaimLost(String),
}

/// Run (or resume) a claimed job up to its end, or up to snapshot `stop_after`. The result is
/// returned, not written: the caller's writer stores it. Errors come back by kind
/// ([`JobError`]): a resource error leaves the job resumable.
pub fn run_job(
    job: &PlannedJob,
    claim: &Claim,
    stop_after: Option<StopAfter>,
    on_progress: &mut dyn FnMut(JobProgress),
) -> Result<JobEnd, JobError> {
    let analyser = job.params.analyser()?;
    let started = Instant::now();
    let mut running = match claim.dir.checkpoint()? {
        Some(cp) => resume(job, &claim.dir, &analyser, cp)?,
        None => match prepare(job, claim, stop_after, started, on_progress)? {
            Prepared::Ready(engine, wall_before) => {
                start(job, &claim.dir, &analyser, engine, wall_before, started)?
            }
            Prepared::Stopped => return Ok(JobEnd::Stopped),
            Prepared::ClaimLost(why) => return Ok(JobEnd::ClaimLost(why)),
        },
    };
    let stop_after = match stop_after {
        Some(StopAfter::Snapshot(k)) => Some(k),
        _ => None,
    };
    if running.engine.def().name != job.params.engine {
        return Err(JobError::Engine(format!(
            "the checkpoint holds a {} engine, the job runs {}",
            running.engine.def().name,
            job.params.engine
        )));
    }
    let stop_reason = match advance(
        job,
        claim,
        &analyser,
        &mut running,
        stop_after,
        started,
        on_progress,
    )? {
        Advanced::Reached(reason) => reason,
        Advanced::Stopped => return Ok(JobEnd::Stopped),
        Advanced::ClaimLost(why) => return Ok(JobEnd::ClaimLost(why)),
    };
    finish(job, &claim.dir, &analyser, running, stop_reason, started)
        .map(|r| JobEnd::Finished(Box::new(r)))
}

/// The build and host, as log lines name them.
fn build_tag() -> String {
    format!(
        "[{} on {}]",
        crate::provenance::Provenance::build(),
        crate::provenance::host()
    )
}

/// The job's state from its last checkpoint.
fn resume(
    job: &PlannedJob,
    dir: &JobDir,
    analyser: &Analyser,
    cp: JobCheckpoint,
) -> Result<Running, JobError> {
    let (log, records) = RecordLog::resume(dir.path(), &job.id.0, &cp)?;
    dir.log(&format!(
        "resume at snapshot {} {}",
        cp.snapshot,
        build_tag()
    ))?;
    let mut engine: Box<dyn Engine> = crate::registry::restore(&cp.engine)?;
    // free paths are not part of the engine's state: switched on again (the checkpoint
    // was taken right after a snapshot had emptied the tally)
    if let Some(slabs) = analyser.free_path_slabs() {
        engine.record_free_paths(slabs);
    }
    Ok(Running {
        engine,
        records,
        log,
        k: cp.snapshot,
        wall_before: cp.wall_seconds,
    })
}

/// How the preparation ended.
enum Prepared {
    /// the engine in its initial state, and the wall-clock seconds its preparation took in
    /// earlier calls
    Ready(Box<dyn Engine>, f64),
    /// at the step [`StopAfter::PreparationSteps`] asked for
    Stopped,
    /// the claim was lost
    ClaimLost(String),
}

/// A job without a checkpoint: its engine built (or restored from its preparation
/// checkpoint) and, when it has a preparation, prepared chunk by chunk, each chunk followed by
/// a preparation checkpoint and a progress report.
fn prepare(
    job: &PlannedJob,
    claim: &Claim,
    stop_after: Option<StopAfter>,
    started: Instant,
    on_progress: &mut dyn FnMut(JobProgress),
) -> Result<Prepared, JobError> {
    let dir = &claim.dir;
    let (mut engine, wall_before, mut logged) = match dir.preparation()? {
        Some(cp) => {
            let engine = crate::registry::restore(&cp.engine)?;
            dir.log(&format!(
                "resume the preparation at step {} {}",
                cp.steps,
                build_tag()
            ))?;
            (engine, cp.wall_seconds, true)
        }
        None => (job.params.build_engine()?, 0.0, false),
    };
    let n = engine.particle_count().max(1) as f64;
    let chunk = ((PREPARATION_CHUNK_WORK / n) as u64).max(100);
    let events_at_start = engine.progress().events;
    while let Some(at) = engine.preparation() {
        let steps = match stop_after {
            Some(StopAfter::PreparationSteps(s)) if at.steps >= s => return Ok(Prepared::Stopped),
            Some(StopAfter::PreparationSteps(s)) => chunk.min(s - at.steps),
            _ => chunk,
        };
        engine.prepare(steps)?;
        if let Err(why) = claim.still_held() {
            return Ok(Prepared::ClaimLost(why));
        }
        let preparing = engine.preparation();
        // a finished preparation is held by checkpoint 0, written next
        if let Some(p) = &preparing {
            dir.write_preparation(&PreparationCheckpoint::new(
                &job.id.0,
                p.steps,
                wall_before + started.elapsed().as_secs_f64(),
                engine.checkpoint(),
            ))?;
            // the log line after the state is on disk, as for `start`
            if !logged {
                dir.log(&format!("prepare {}", build_tag()))?;
                logged = true;
            }
        }
        // reported while it lasts (once over, the run's first snapshot reports next)
        if preparing.is_some() {
            let secs = started.elapsed().as_secs_f64().max(1e-9);
            on_progress(JobProgress {
                clock: 0.0,
                target: job.params.run.length(),
                events_per_second: (engine.progress().events - events_at_start) as f64 / secs,
                preparing,
            });
        }
    }
    Ok(Prepared::Ready(engine, wall_before))
}

/// A new job from its prepared engine: its first snapshot recorded and checkpoint 0 written
/// (the preparation checkpoint, if any, removed after it).
fn start(
    job: &PlannedJob,
    dir: &JobDir,
    analyser: &Analyser,
    mut engine: Box<dyn Engine>,
    wall_before: f64,
    started: Instant,
) -> Result<Running, JobError> {
    if let Some(slabs) = analyser.free_path_slabs() {
        engine.record_free_paths(slabs);
    }
    let snap = engine.snapshot();
    let paths = engine.take_free_paths();
    let records = vec![analyser.record_with(&snap, 0, paths)?];
    let mut log = RecordLog::start(dir.path(), &job.id.0)?;
    log.append(&records[0])?;
    log.sync()?;
    // checkpoint 0 first, then the log line: a job is "started" once its initial state is on
    // disk; a kill before that leaves nothing to resume and no trace
    dir.write_checkpoint(&JobCheckpoint::new(
        &job.id.0,
        0,
        engine.checkpoint(),
        &log,
        wall_before + started.elapsed().as_secs_f64(),
        snap.progress,
    ))?;
    dir.remove_preparation()?;
    dir.log(&format!("start {}", build_tag()))?;
    Ok(Running {
        engine,
        records,
        log,
        k: 0,
        wall_before,
    })
}

/// Snapshot after snapshot up to the run length (or until steady, or `stop_after`): record
/// each, checkpoint at the fixed cadence, report progress.
fn advance(
    job: &PlannedJob,
    claim: &Claim,
    analyser: &Analyser,
    at: &mut Running,
    stop_after: Option<u32>,
    started: Instant,
    on_progress: &mut dyn FnMut(JobProgress),
) -> Result<Advanced, JobError> {
    let run = &job.params.run;
    let clock = run.clock();
    let total = run.snapshot_count();
    let events_at_start = at.engine.progress().events;
    let mut check = StopCheck::default();
    while at.k < total {
        // run until steady: asked after every snapshot (also right after a resume, so that a
        // job killed after its deciding snapshot stops where the uninterrupted one did)
        if let Some(rule) = &run.until_steady
            && run.past_milestones(at.engine.def(), &at.engine.progress())
            && let Some(reason) = analyser.steady_over(&at.records, clock, rule.window, &mut check)
        {
            return Ok(Advanced::Reached(format!(
                "stopped at snapshot {}: {reason}",
                at.k
            )));
        }
        if stop_after.is_some_and(|s| at.k >= s) {
            return Ok(Advanced::Stopped);
        }
        at.k += 1;
        let k = at.k;
        at.engine
            .advance(StopAt::on(clock, run.snapshot_target(k)))?;
        let snap = at.engine.snapshot();
        let paths = at.engine.take_free_paths();
        let record = analyser.record_with(&snap, k, paths)?;
        // the snapshot's particles are not needed past its record: freed before the
        // checkpoint, which is the peak of a big job's memory
        let progress = snap.progress;
        drop(snap);
        at.log.append(&record)?;
        at.records.push(record);
        if k % run.checkpoint_every == 0 || k == total {
            if let Err(why) = claim.still_held() {
                return Ok(Advanced::ClaimLost(why));
            }
            at.log.sync()?;
            claim.dir.write_checkpoint(&JobCheckpoint::new(
                &job.id.0,
                k,
                at.engine.checkpoint(),
                &at.log,
                at.wall_before + started.elapsed().as_secs_f64(),
                progress,
            ))?;
        }
        let secs = started.elapsed().as_secs_f64().max(1e-9);
        on_progress(JobProgress {
            clock: progress.on(clock),
            target: run.length(),
            events_per_second: (progress.events - events_at_start) as f64 / secs,
            preparing: None,
        });
    }
    let reason = match &run.until_steady {
        Some(rule) => format!(
            "reached the cap of {} {} before a steady window of {} with a stable label",
            run.length(),
            clock.key(),
            rule.window
        ),
        None => String::new(),
    };
    Ok(Advanced::Reached(reason))
}

/// Analyse the records, draw the job's figures and assemble its result.
fn finish(
    job: &PlannedJob,
    dir: &JobDir,
    analyser: &Analyser,
    mut at: Running,
    stop_reason: String,
    started: Instant,
) -> Result<JobResult, JobError> {
    let snap = at.engine.snapshot();
    let analysis = analyser.analyse(&at.records).map_err(|e| {
        JobError::Analysis(format!(
            "analysing the job's {} records: {e}",
            at.records.len()
        ))
    })?;
    // the figures are a view of the result: one that cannot be drawn is logged, not a failed
    // job (a full disk still stops the run, as any other write does)
    let figures = crate::job_figures::figures(&job.heading(), &analysis, &at.records);
    if let Err(e) = crate::job_figures::write(dir.path(), &figures) {
        let e = JobError::from(e);
        if e.is_resource() {
            return Err(e);
        }
        dir.log(&format!("figures not written: {e}"))?;
    }
    let wall_seconds = at.wall_before + started.elapsed().as_secs_f64();
    let def = job.params.def();
    let mut provenance = Provenance::here(def.version, crate::registry::analysis_of(def).version());
    provenance.started = dir.first_start().unwrap_or_default();
    provenance.finished = crate::provenance::now();
    Ok(JobResult {
        format: store::RESULT_FORMAT,
        id: job.id.0.clone(),
        engine: job.params.engine.clone(),
        particles: at.engine.particle_count(),
        snapshots: at.k,
        collisions_per_particle: snap.progress.collisions_per_particle,
        time: snap.progress.time,
        steps: snap.progress.steps,
        counters: snap.counters,
        wall_seconds,
        events_per_second: snap.progress.events as f64 / wall_seconds.max(1e-9),
        stop_reason,
        provenance,
        checksum: String::new(),
        analysis,
    })
}
