//! Running one job: build (or restore) the engine, advance snapshot by snapshot in collisions
//! per particle, record each snapshot for the analysis, checkpoint at a fixed cadence of
//! simulated progress, analyse at the end.
//!
//! Snapshot k (k = 0, 1, ..., K) is taken at collisions per particle
//! c_k = min(k * interval, run length), K = ceil(run length / interval). A checkpoint (engine
//! bytes + records so far) is written after snapshot k when k is a multiple of
//! `checkpoint_every` and after the last one: the only point where `Engine::checkpoint` is
//! valid, and never driven by wall-clock time, so a resumed job ends bitwise identical to an
//! uninterrupted one.

use super::grid::PlannedJob;
use super::queue::{self, CHECKPOINT_FILE, Claim, RESULT_FILE};
use super::write_atomic;
use crate::analysis::{self, JobAnalysis, SnapshotRecord};
use crate::engine::{self, Counters, Engine, StopAt};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

const CHECKPOINT_FORMAT: u32 = 1;

/// What a job's checkpoint file holds (postcard, followed by a CRC-32 of the bytes).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JobCheckpoint {
    /// format version
    pub format: u32,
    /// snapshots taken so far after the initial one (k of the last snapshot)
    pub snapshot: u32,
    /// [`Engine::checkpoint`] bytes taken right after snapshot k
    pub engine: Vec<u8>,
    /// analysis records of snapshots 0..=k
    pub records: Vec<SnapshotRecord>,
    /// wall-clock seconds spent up to this checkpoint (informational)
    pub wall_seconds: f64,
}

/// A finished job's result (`result.ron`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobResult {
    /// the job id
    pub id: String,
    /// N
    pub particles: usize,
    /// snapshots taken after the initial one
    pub snapshots: u32,
    /// final collisions per particle
    pub collisions_per_particle: f64,
    /// final simulated time
    pub time: f64,
    /// final event counters
    pub counters: Counters,
    /// wall-clock seconds of simulation (summed over resumes, up to their last checkpoint)
    pub wall_seconds: f64,
    /// events per wall-clock second
    pub events_per_second: f64,
    /// the analysis
    pub analysis: JobAnalysis,
}

/// How a call to [`run_job`] ended.
#[derive(Debug)]
pub enum JobEnd {
    Finished(Box<JobResult>),
    /// stopped after the snapshot asked for (tests of resumption)
    Stopped,
}

/// Progress of a running job, reported after each snapshot.
#[derive(Clone, Copy, Debug)]
pub struct JobProgress {
    pub collisions_per_particle: f64,
    pub target: f64,
    pub events_per_second: f64,
}

/// Collisions per particle of a job's last checkpoint, if it has one.
pub fn checkpoint_progress(dir: &Path) -> Option<f64> {
    read_checkpoint(dir)
        .ok()
        .flatten()
        .and_then(|c| c.records.last().map(|r| r.collisions_per_particle))
}

/// Read a job's checkpoint (None when there is none).
pub fn read_checkpoint(dir: &Path) -> anyhow::Result<Option<JobCheckpoint>> {
    let path = dir.join(CHECKPOINT_FILE);
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e.into()),
    };
    anyhow::ensure!(bytes.len() >= 4, "{}: truncated checkpoint", path.display());
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    anyhow::ensure!(
        crc32fast::hash(body).to_le_bytes() == crc,
        "{}: checkpoint checksum mismatch",
        path.display()
    );
    let cp: JobCheckpoint = postcard::from_bytes(body)?;
    anyhow::ensure!(
        cp.format == CHECKPOINT_FORMAT,
        "{}: checkpoint format {} (expected {CHECKPOINT_FORMAT})",
        path.display(),
        cp.format
    );
    Ok(Some(cp))
}

fn write_checkpoint(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<()> {
    let mut bytes = postcard::to_stdvec(cp)?;
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    write_atomic(&dir.join(CHECKPOINT_FILE), &bytes)?;
    Ok(())
}

/// Read a finished job's result.
pub fn read_result(dir: &Path) -> anyhow::Result<JobResult> {
    let path = dir.join(RESULT_FILE);
    let text = std::fs::read_to_string(&path)?;
    ron::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// Write a job's result atomically (this marks it done).
pub fn write_result(dir: &Path, result: &JobResult) -> anyhow::Result<()> {
    let text = ron::ser::to_string_pretty(result, ron::ser::PrettyConfig::default())?;
    write_atomic(&dir.join(RESULT_FILE), text.as_bytes())?;
    Ok(())
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
    let settings = &job.params.analysis;
    let total = run.snapshot_count();
    let started = Instant::now();
    let (mut engine, mut records, mut k, wall_before): (Box<dyn Engine>, _, u32, f64) =
        match read_checkpoint(dir)? {
            Some(cp) => {
                queue::log(dir, &format!("resume at snapshot {}", cp.snapshot))?;
                (
                    engine::restore(&cp.engine)?,
                    cp.records,
                    cp.snapshot,
                    cp.wall_seconds,
                )
            }
            None => {
                let mut engine = engine::build(&job.params.engine_spec())?;
                let snap = engine.snapshot();
                let records = vec![analysis::record_snapshot(&snap, settings)];
                // checkpoint 0 first, then the log line: a job is "started" once its initial
                // state is on disk; a kill before that leaves nothing to resume and no trace
                write_checkpoint(
                    dir,
                    &JobCheckpoint {
                        format: CHECKPOINT_FORMAT,
                        snapshot: 0,
                        engine: engine.checkpoint(),
                        records: records.clone(),
                        wall_seconds: started.elapsed().as_secs_f64(),
                    },
                )?;
                queue::log(dir, "start")?;
                (engine, records, 0, 0.0)
            }
        };
    let events_at_start = engine.progress().events;
    while k < total {
        if stop_after.is_some_and(|s| k >= s) {
            return Ok(JobEnd::Stopped);
        }
        k += 1;
        let target = run.snapshot_target(k);
        engine.advance(StopAt::CollisionsPerParticle(target))?;
        let snap = engine.snapshot();
        records.push(analysis::record_snapshot(&snap, settings));
        if k % run.checkpoint_every == 0 || k == total {
            write_checkpoint(
                dir,
                &JobCheckpoint {
                    format: CHECKPOINT_FORMAT,
                    snapshot: k,
                    engine: engine.checkpoint(),
                    records: records.clone(),
                    wall_seconds: wall_before + started.elapsed().as_secs_f64(),
                },
            )?;
        }
        let secs = started.elapsed().as_secs_f64().max(1e-9);
        on_progress(JobProgress {
            collisions_per_particle: snap.collisions_per_particle,
            target: run.collisions_per_particle,
            events_per_second: (snap.counters.events - events_at_start) as f64 / secs,
        });
    }
    let snap = engine.snapshot();
    let analysis = analysis::analyse_job(&records, settings);
    let wall_seconds = wall_before + started.elapsed().as_secs_f64();
    Ok(JobEnd::Finished(Box::new(JobResult {
        id: job.id.0.clone(),
        particles: engine.particle_count(),
        snapshots: k,
        collisions_per_particle: snap.collisions_per_particle,
        time: snap.time,
        counters: snap.counters,
        wall_seconds,
        events_per_second: snap.counters.events as f64 / wall_seconds.max(1e-9),
        analysis,
    })))
}
