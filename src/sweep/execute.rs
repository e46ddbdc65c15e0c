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

use super::grid::PlannedJob;
pub use super::job_error::JobError;
use super::store::{self, Claim, JobCheckpoint, JobDir, JobResult, RecordLog};
use crate::analysis::{Analyser, Record, StopCheck};
use crate::engine::{Engine, StopAt};
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

/// Progress of a running job, reported after each snapshot.
#[derive(Clone, Copy, Debug)]
pub struct JobProgress {
    /// the run's clock now
    pub clock: f64,
    /// the run length on that clock
    pub target: f64,
    pub events_per_second: f64,
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
    stop_after: Option<u32>,
    on_progress: &mut dyn FnMut(JobProgress),
) -> Result<JobEnd, JobError> {
    let analyser = job.params.analyser()?;
    let started = Instant::now();
    let mut running = start_or_resume(job, &claim.dir, &analyser, started)?;
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

/// The job's state from its last checkpoint, or (without one) a new engine with its first
/// snapshot recorded and checkpoint 0 written.
fn start_or_resume(
    job: &PlannedJob,
    dir: &JobDir,
    analyser: &Analyser,
    started: Instant,
) -> Result<Running, JobError> {
    let build = format!(
        "[{} on {}]",
        crate::provenance::Provenance::build(),
        crate::provenance::host()
    );
    if let Some(cp) = dir.checkpoint()? {
        let (log, records) = RecordLog::resume(dir.path(), &job.id.0, &cp)?;
        dir.log(&format!("resume at snapshot {} {build}", cp.snapshot))?;
        let mut engine: Box<dyn Engine> = crate::registry::restore(&cp.engine)?;
        // free paths are not part of the engine's state: switched on again (the checkpoint
        // was taken right after a snapshot had emptied the tally)
        if let Some(slabs) = analyser.free_path_slabs() {
            engine.record_free_paths(slabs);
        }
        return Ok(Running {
            engine,
            records,
            log,
            k: cp.snapshot,
            wall_before: cp.wall_seconds,
        });
    }
    let mut engine = job.params.build_engine()?;
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
        started.elapsed().as_secs_f64(),
        snap.progress,
    ))?;
    dir.log(&format!("start {build}"))?;
    Ok(Running {
        engine,
        records,
        log,
        k: 0,
        wall_before: 0.0,
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
                snap.progress,
            ))?;
        }
        let secs = started.elapsed().as_secs_f64().max(1e-9);
        on_progress(JobProgress {
            clock: snap.progress.on(clock),
            target: run.length(),
            events_per_second: (snap.progress.events - events_at_start) as f64 / secs,
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
