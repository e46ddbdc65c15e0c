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
use super::store::{self, Claim, JobCheckpoint, JobResult, RecordLog};
use crate::analysis::StopCheck;
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

/// Run (or resume) a claimed job up to its end, or up to snapshot `stop_after`. The result is
/// returned, not written: the caller's writer stores it. Engine errors come back as `Err`.
pub fn run_job(
    job: &PlannedJob,
    claim: &Claim,
    stop_after: Option<u32>,
    on_progress: &mut dyn FnMut(JobProgress),
) -> anyhow::Result<JobEnd> {
    let dir = &claim.dir;
    let run = &job.params.run;
    let clock = run.clock();
    let analyser = job.params.analyser().map_err(anyhow::Error::msg)?;
    let total = run.snapshot_count();
    let started = Instant::now();
    let build = format!(
        "[{} on {}]",
        crate::provenance::Provenance::build(),
        crate::provenance::host()
    );
    let (mut engine, mut records, mut log, mut k, wall_before) = match store::read_checkpoint(dir)?
    {
        Some(cp) => {
            let (log, records) = RecordLog::resume(dir, &job.id.0, &cp)?;
            store::log(dir, &format!("resume at snapshot {} {build}", cp.snapshot))?;
            let mut engine: Box<dyn Engine> = crate::registry::restore(&cp.engine)?;
            // free paths are not part of the engine's state: switched on again (the
            // checkpoint was taken right after a snapshot had emptied the tally)
            if let Some(slabs) = analyser.free_path_slabs() {
                engine.record_free_paths(slabs);
            }
            (engine, records, log, cp.snapshot, cp.wall_seconds)
        }
        None => {
            let mut engine = job.params.build_engine()?;
            if let Some(slabs) = analyser.free_path_slabs() {
                engine.record_free_paths(slabs);
            }
            let snap = engine.snapshot();
            let paths = engine.take_free_paths();
            let records = vec![
                analyser
                    .record_with(&snap, 0, paths)
                    .map_err(anyhow::Error::msg)?,
            ];
            let mut log = RecordLog::start(dir, &job.id.0)?;
            log.append(&records[0])?;
            log.sync()?;
            // checkpoint 0 first, then the log line: a job is "started" once its initial
            // state is on disk; a kill before that leaves nothing to resume and no trace
            store::write_checkpoint(
                dir,
                &JobCheckpoint::new(
                    &job.id.0,
                    0,
                    engine.checkpoint(),
                    &log,
                    started.elapsed().as_secs_f64(),
                    snap.progress,
                ),
            )?;
            store::log(dir, &format!("start {build}"))?;
            (engine, records, log, 0, 0.0)
        }
    };
    anyhow::ensure!(
        engine.def().name == job.params.engine,
        "the checkpoint holds a {} engine, the job runs {}",
        engine.def().name,
        job.params.engine
    );
    let events_at_start = engine.progress().events;
    let mut check = StopCheck::default();
    let mut stop_reason = String::new();
    while k < total {
        // run until steady: asked after every snapshot (also right after a resume, so that a
        // job killed after its deciding snapshot stops where the uninterrupted one did)
        if let Some(rule) = &run.until_steady
            && run.past_milestones(engine.def(), &engine.progress())
            && let Some(reason) = analyser.steady_over(&records, clock, rule.window, &mut check)
        {
            stop_reason = format!("stopped at snapshot {k}: {reason}");
            break;
        }
        if stop_after.is_some_and(|s| k >= s) {
            return Ok(JobEnd::Stopped);
        }
        k += 1;
        engine.advance(StopAt::on(clock, run.snapshot_target(k)))?;
        let snap = engine.snapshot();
        let paths = engine.take_free_paths();
        let record = analyser
            .record_with(&snap, k, paths)
            .map_err(anyhow::Error::msg)?;
        log.append(&record)?;
        records.push(record);
        if k % run.checkpoint_every == 0 || k == total {
            if let Err(why) = claim.still_held() {
                return Ok(JobEnd::ClaimLost(why));
            }
            log.sync()?;
            store::write_checkpoint(
                dir,
                &JobCheckpoint::new(
                    &job.id.0,
                    k,
                    engine.checkpoint(),
                    &log,
                    wall_before + started.elapsed().as_secs_f64(),
                    snap.progress,
                ),
            )?;
        }
        let secs = started.elapsed().as_secs_f64().max(1e-9);
        on_progress(JobProgress {
            clock: snap.progress.on(clock),
            target: run.length(),
            events_per_second: (snap.progress.events - events_at_start) as f64 / secs,
        });
    }
    if run.until_steady.is_some() && stop_reason.is_empty() {
        stop_reason = format!(
            "reached the cap of {} {} before a steady window of {} with a stable label",
            run.length(),
            clock.key(),
            run.until_steady.as_ref().map_or(0.0, |u| u.window)
        );
    }
    let snap = engine.snapshot();
    let analysis = analyser
        .analyse(&records)
        .map_err(|e| anyhow::anyhow!("analysing the job's {} records: {e}", records.len()))?;
    // the figures are a view of the result: one that cannot be drawn is logged, not a failed
    // job (a full disk still stops the run, as any other write does)
    let figures = crate::job_figures::figures(&job.heading(), &analysis, &records);
    if let Err(e) = crate::job_figures::write(dir, &figures) {
        if super::fs_error::is_resource_error(&e) {
            return Err(e);
        }
        store::log(dir, &format!("figures not written: {e:#}"))?;
    }
    let wall_seconds = wall_before + started.elapsed().as_secs_f64();
    let def = job.params.def();
    let mut provenance = Provenance::here(def.version, crate::registry::analysis_of(def).version());
    provenance.started = store::first_start(dir).unwrap_or_default();
    provenance.finished = crate::provenance::now();
    Ok(JobEnd::Finished(Box::new(JobResult {
        format: store::RESULT_FORMAT,
        id: job.id.0.clone(),
        engine: job.params.engine.clone(),
        particles: engine.particle_count(),
        snapshots: k,
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
    })))
}
