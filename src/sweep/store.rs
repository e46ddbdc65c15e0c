//! The job store: the one owner of a job directory's files. One directory per job, its state
//! read from the files in it alone, claims through an OS file lock that dies with its process,
//! and the formats of the checkpoint and the result.
//!
//! `jobs/<id>/` holds:
//! - `params.json`: the resolved parameters and canonical form, written once;
//! - `lock`: the claim; a runner holds an exclusive `flock` on it while the job runs;
//! - `checkpoint.bin`: engine checkpoint + analysis records, replaced atomically;
//! - `result.ron`: the job's analysis and counters; its presence means done;
//! - `failed.txt`: the error of a failed job (removed by `--retry-failed`);
//! - `log.txt`: one line per start ("start" or "resume"), end ("done") or failure, appended.

use super::grid::PlannedJob;
use super::job::{JobId, JobParams};
use super::write_atomic;
use crate::analysis::{Analysis, BinSums, Record, SnapshotRecord};
use crate::engine::Counters;
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

pub const PARAMS_FILE: &str = "params.json";
pub const LOCK_FILE: &str = "lock";
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";
pub const RESULT_FILE: &str = "result.ron";
pub const FAILED_FILE: &str = "failed.txt";
pub const LOG_FILE: &str = "log.txt";

/// The state of a job as its directory tells it.
#[derive(Clone, Debug, PartialEq)]
pub enum JobState {
    /// nothing run yet
    Pending,
    /// checkpointed at this point of progress, not running
    Partial(crate::engine::Progress),
    /// claimed by a live runner (its lock is held)
    Running,
    /// finished: result.ron exists
    Done,
    /// failed with this error
    Failed(String),
}

impl JobState {
    /// Short name: pending, partial, running, done, failed.
    pub fn name(&self) -> &'static str {
        match self {
            JobState::Pending => "pending",
            JobState::Partial(_) => "partial",
            JobState::Running => "running",
            JobState::Done => "done",
            JobState::Failed(_) => "failed",
        }
    }
}

/// What `params.json` holds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ParamsFile {
    pub id: JobId,
    pub canonical: String,
    pub params: JobParams,
}

/// Create the job directory and write `params.json` once (an existing one is kept).
pub fn init_job_dir(dir: &Path, job: &PlannedJob) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let path = dir.join(PARAMS_FILE);
    if !path.exists() {
        let file = ParamsFile {
            id: job.id.clone(),
            canonical: job.params.canonical(),
            params: job.params.clone(),
        };
        let text = serde_json::to_string_pretty(&file).map_err(std::io::Error::other)?;
        write_atomic(&path, text.as_bytes())?;
    }
    Ok(())
}

/// The state of the job in `dir`, from its files and lock alone (a missing dir is pending).
/// Probing the lock takes it for an instant when it is free.
pub fn job_state(dir: &Path) -> JobState {
    if dir.join(RESULT_FILE).exists() {
        return JobState::Done;
    }
    if let Ok(f) = OpenOptions::new().write(true).open(dir.join(LOCK_FILE))
        && f.try_lock().is_err()
    {
        return JobState::Running;
    }
    state_unlocked(dir)
}

/// The state ignoring the lock (what a runner that holds the lock sees).
fn state_unlocked(dir: &Path) -> JobState {
    if dir.join(RESULT_FILE).exists() {
        return JobState::Done;
    }
    if let Ok(err) = std::fs::read_to_string(dir.join(FAILED_FILE)) {
        return JobState::Failed(err.trim().to_string());
    }
    match checkpoint_progress(dir) {
        Some(progress) => JobState::Partial(progress),
        None => JobState::Pending,
    }
}

/// An exclusive claim on a job; released when dropped (or when the process dies).
#[derive(Debug)]
pub struct Claim {
    pub dir: PathBuf,
    _lock: File,
}

/// Why a job was not claimed.
#[derive(Clone, Debug, PartialEq)]
pub enum NotClaimed {
    /// another runner holds it
    Busy,
    /// already done
    Done,
    /// failed earlier (and retrying was not asked for)
    Failed(String),
}

/// Try to claim the job in `dir` (non-blocking). The state is re-read under the lock, so a job
/// finished by another runner in the meantime is never run again. With `retry_failed` a failed
/// job's `failed.txt` is removed and it resumes from its last checkpoint.
pub fn try_claim(dir: &Path, retry_failed: bool) -> std::io::Result<Result<Claim, NotClaimed>> {
    std::fs::create_dir_all(dir)?;
    let lock = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(dir.join(LOCK_FILE))?;
    // a state probe ([`job_state`]) holds the lock for an instant: try a few times before
    // concluding that another runner holds it
    let mut attempt = 0;
    loop {
        match lock.try_lock() {
            Ok(()) => break,
            Err(std::fs::TryLockError::WouldBlock) if attempt < 5 => {
                attempt += 1;
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            Err(std::fs::TryLockError::WouldBlock) => return Ok(Err(NotClaimed::Busy)),
            Err(std::fs::TryLockError::Error(e)) => return Err(e),
        }
    }
    match state_unlocked(dir) {
        JobState::Done => Ok(Err(NotClaimed::Done)),
        JobState::Failed(e) if !retry_failed => Ok(Err(NotClaimed::Failed(e))),
        JobState::Failed(_) => {
            std::fs::remove_file(dir.join(FAILED_FILE))?;
            Ok(Ok(Claim {
                dir: dir.to_path_buf(),
                _lock: lock,
            }))
        }
        _ => Ok(Ok(Claim {
            dir: dir.to_path_buf(),
            _lock: lock,
        })),
    }
}

/// Append one line to the job's log, `<UTC time> <event>`, and flush it to disk.
pub fn log(dir: &Path, event: &str) -> std::io::Result<()> {
    let mut f = OpenOptions::new()
        .create(true)
        .append(true)
        .open(dir.join(LOG_FILE))?;
    writeln!(f, "{} {event}", crate::provenance::now())?;
    f.sync_data()
}

/// The events of a log's text, without their times (lines written before logs had times are
/// taken whole).
pub fn log_events(text: &str) -> Vec<&str> {
    text.lines()
        .map(|l| match l.split_once(' ') {
            Some((time, event)) if time.len() == 20 && time.ends_with('Z') => event,
            _ => l,
        })
        .collect()
}

/// When the job first started (the time of its log's first `start`), if the log says.
pub fn first_start(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(LOG_FILE)).ok()?;
    text.lines()
        .find(|l| l.split(' ').nth(1) == Some("start"))
        .and_then(|l| l.split(' ').next())
        .map(str::to_string)
}

/// Record a failure (atomically).
pub fn mark_failed(dir: &Path, error: &str) -> std::io::Result<()> {
    write_atomic(&dir.join(FAILED_FILE), format!("{error}\n").as_bytes())?;
    log(dir, &format!("failed: {error}"))
}

/// Format of `checkpoint.bin` written now (1: records were structure records only).
const CHECKPOINT_FORMAT: u32 = 2;

/// What a job's checkpoint file holds (postcard, followed by a CRC-32 of the bytes).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JobCheckpoint {
    /// format version
    pub format: u32,
    /// snapshots taken so far after the initial one (k of the last snapshot)
    pub snapshot: u32,
    /// [`crate::engine::Engine::checkpoint`] bytes taken right after snapshot k
    pub engine: Vec<u8>,
    /// analysis records of snapshots 0..=k
    pub records: Vec<Record>,
    /// wall-clock seconds spent up to this checkpoint (informational)
    pub wall_seconds: f64,
    /// the engine's clocks at snapshot k
    pub progress: crate::engine::Progress,
}

/// Format 1 (before engines were plug-ins): the records were the structure analysis's, in
/// the layout of [`SnapshotRecordV1`].
#[derive(Deserialize)]
struct JobCheckpointV1 {
    format: u32,
    snapshot: u32,
    engine: Vec<u8>,
    records: Vec<SnapshotRecordV1>,
    wall_seconds: f64,
}

/// A structure record as format 1 stored it (frozen: postcard needs the exact layout). The
/// balance totals it lacks read as NaN (unknown).
#[derive(Deserialize)]
struct SnapshotRecordV1 {
    collisions_per_particle: f64,
    time: f64,
    translational_energy: f64,
    rotational_energy: f64,
    particles: u64,
    box_extent: [f64; 3],
    gravity: f64,
    inertia_factor: f64,
    grid: [u32; 3],
    grid_volume: f64,
    counts_xy: Vec<u32>,
    counts_xz: Vec<u32>,
    counts_yz: Vec<u32>,
    profile: Vec<BinSums>,
}

impl From<SnapshotRecordV1> for SnapshotRecord {
    fn from(r: SnapshotRecordV1) -> Self {
        SnapshotRecord {
            collisions_per_particle: r.collisions_per_particle,
            time: r.time,
            translational_energy: r.translational_energy,
            rotational_energy: r.rotational_energy,
            particles: r.particles,
            box_extent: r.box_extent,
            gravity: r.gravity,
            inertia_factor: r.inertia_factor,
            grid: r.grid,
            grid_volume: r.grid_volume,
            counts_xy: r.counts_xy,
            counts_xz: r.counts_xz,
            counts_yz: r.counts_yz,
            profile: r.profile,
            wall_impulse_x: f64::NAN,
            momentum_x: f64::NAN,
            energy_dissipated: f64::NAN,
            gravity_work: f64::NAN,
            suppressed_dissipation: f64::NAN,
            pair_collisions: 0,
            tc_elastic_collisions: 0,
        }
    }
}

impl JobCheckpoint {
    /// A checkpoint in the current format.
    pub fn new(
        snapshot: u32,
        engine: Vec<u8>,
        records: Vec<Record>,
        wall_seconds: f64,
        progress: crate::engine::Progress,
    ) -> Self {
        JobCheckpoint {
            format: CHECKPOINT_FORMAT,
            snapshot,
            engine,
            records,
            wall_seconds,
            progress,
        }
    }
}

/// A finished job's result (`result.ron`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobResult {
    /// the job id
    pub id: String,
    /// the engine that ran it (results written before the registry are EDMD's)
    #[serde(default = "edmd")]
    pub engine: String,
    /// N
    pub particles: usize,
    /// snapshots taken after the initial one
    pub snapshots: u32,
    /// final collisions per particle (0 for engines without collisions)
    pub collisions_per_particle: f64,
    /// final simulated time
    pub time: f64,
    /// final time steps (0 for event-driven engines)
    #[serde(default)]
    pub steps: u64,
    /// final counters, named as the engine declares them
    pub counters: Counters,
    /// wall-clock seconds of simulation (summed over resumes, up to their last checkpoint)
    pub wall_seconds: f64,
    /// events per wall-clock second
    pub events_per_second: f64,
    /// for runs until steady: where and why the job stopped, or that it reached its cap
    #[serde(default)]
    pub stop_reason: String,
    /// which code made it, where and when (results of older builds: empty, versions 0)
    #[serde(default)]
    pub provenance: crate::provenance::Provenance,
    /// the analysis
    pub analysis: Analysis,
}

impl JobResult {
    /// The final reading of a clock.
    pub fn clock(&self, clock: crate::engine::Clock) -> f64 {
        match clock {
            crate::engine::Clock::CollisionsPerParticle => self.collisions_per_particle,
            crate::engine::Clock::Steps => self.steps as f64,
            crate::engine::Clock::Time => self.time,
        }
    }
}

fn edmd() -> String {
    "edmd".into()
}

/// The engine's clocks at a job's last checkpoint, if it has one.
pub fn checkpoint_progress(dir: &Path) -> Option<crate::engine::Progress> {
    read_checkpoint(dir).ok().flatten().map(|c| c.progress)
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
    let (format, _) = postcard::take_from_bytes::<u32>(body)?;
    let cp = match format {
        1 => {
            let v1: JobCheckpointV1 = postcard::from_bytes(body)?;
            let progress =
                v1.records
                    .last()
                    .map_or_else(Default::default, |r| crate::engine::Progress {
                        time: r.time,
                        collisions_per_particle: r.collisions_per_particle,
                        steps: 0,
                        events: 0,
                    });
            JobCheckpoint {
                format: v1.format,
                snapshot: v1.snapshot,
                engine: v1.engine,
                progress,
                records: v1
                    .records
                    .into_iter()
                    .map(|r| Record::Structure(r.into()))
                    .collect(),
                wall_seconds: v1.wall_seconds,
            }
        }
        CHECKPOINT_FORMAT => postcard::from_bytes(body)?,
        other => anyhow::bail!(
            "{}: checkpoint format {other} (this granflow reads 1 and {CHECKPOINT_FORMAT})",
            path.display()
        ),
    };
    Ok(Some(cp))
}

/// Write a job's checkpoint atomically.
pub fn write_checkpoint(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<()> {
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
