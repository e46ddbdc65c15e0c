//! `checkpoint.bin`: the engine's sealed state at a snapshot, the job it belongs to, and the
//! length and digest of the record log it covers (postcard, then a CRC-32). Older formats
//! still read: format 1 (before engines were plug-ins) held the structure records inline,
//! format 3 had no digest of the record log.

use super::{CHECKPOINT_FILE, write_postcard_with_crc};
use crate::analysis::{BinSums, Record, SnapshotRecord};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Format of `checkpoint.bin` written now (1: the structure records inline; 3: the records in
/// the record log, the checkpoint says how much of it is its own; 4: and the SHA-256 of that
/// part of the log, header included).
const CHECKPOINT_FORMAT: u32 = 4;

/// What a job's checkpoint file holds (postcard, followed by a CRC-32 of the bytes).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JobCheckpoint {
    /// format version
    pub format: u32,
    /// snapshots taken so far after the initial one (k of the last snapshot)
    pub snapshot: u32,
    /// [`crate::engine::Engine::checkpoint`] bytes taken right after snapshot k
    pub engine: Vec<u8>,
    /// records of snapshots 0..=k in the record log: how many, and their length in bytes
    /// (after the log's header)
    pub records: u64,
    pub records_bytes: u64,
    /// wall-clock seconds spent up to this checkpoint (informational)
    pub wall_seconds: f64,
    /// the engine's clocks at snapshot k
    pub progress: crate::engine::Progress,
    /// the job it belongs to (a checkpoint copied into another job's directory is refused)
    pub job_id: String,
    /// SHA-256 (hex) of the record log's header and covered frames (empty in format 3)
    pub records_digest: String,
    /// the records of a format-1 checkpoint, which held them itself
    #[serde(skip)]
    pub legacy_records: Option<Vec<Record>>,
}

/// Format 3: as now, without the digest of the record log (frozen: postcard needs the exact
/// layout).
#[derive(Deserialize)]
struct JobCheckpointV3 {
    format: u32,
    snapshot: u32,
    engine: Vec<u8>,
    records: u64,
    records_bytes: u64,
    wall_seconds: f64,
    progress: crate::engine::Progress,
    job_id: String,
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
    /// A checkpoint of job `job_id` in the current format, covering the record log up to
    /// `log`'s position.
    pub fn new(
        job_id: &str,
        snapshot: u32,
        engine: Vec<u8>,
        log: &super::RecordLog,
        wall_seconds: f64,
        progress: crate::engine::Progress,
    ) -> Self {
        let (records, records_bytes, records_digest) = log.position();
        JobCheckpoint {
            format: CHECKPOINT_FORMAT,
            snapshot,
            engine,
            records,
            records_bytes,
            wall_seconds,
            progress,
            job_id: job_id.to_string(),
            records_digest,
            legacy_records: None,
        }
    }
}

/// The engine's clocks at a job's last checkpoint, if it has one.
pub fn checkpoint_progress(dir: &Path) -> Option<crate::engine::Progress> {
    read_checkpoint(dir).ok().flatten().map(|c| c.progress)
}

/// A job's clocks at its checkpoint and the wall-clock seconds it had run to get there (None
/// without a readable checkpoint).
pub fn checkpoint_measure(dir: &Path) -> Option<(crate::engine::Progress, f64)> {
    read_checkpoint(dir)
        .ok()
        .flatten()
        .map(|c| (c.progress, c.wall_seconds))
}

/// Read a job's checkpoint (None when there is none).
pub fn read_checkpoint(dir: &Path) -> anyhow::Result<Option<JobCheckpoint>> {
    let path = dir.join(CHECKPOINT_FILE);
    let Some(body) = super::read_crc_checked(&path, "checkpoint")? else {
        return Ok(None);
    };
    let body = body.as_slice();
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
            let records: Vec<Record> = v1
                .records
                .into_iter()
                .map(|r| Record::Structure(r.into()))
                .collect();
            JobCheckpoint {
                format: v1.format,
                snapshot: v1.snapshot,
                engine: v1.engine,
                progress,
                records: records.len() as u64,
                records_bytes: 0,
                wall_seconds: v1.wall_seconds,
                job_id: String::new(),
                records_digest: String::new(),
                legacy_records: Some(records),
            }
        }
        3 => {
            let v3: JobCheckpointV3 = postcard::from_bytes(body)?;
            JobCheckpoint {
                format: v3.format,
                snapshot: v3.snapshot,
                engine: v3.engine,
                records: v3.records,
                records_bytes: v3.records_bytes,
                wall_seconds: v3.wall_seconds,
                progress: v3.progress,
                job_id: v3.job_id,
                records_digest: String::new(),
                legacy_records: None,
            }
        }
        CHECKPOINT_FORMAT => {
            let cp: JobCheckpoint = postcard::from_bytes(body)?;
            anyhow::ensure!(
                cp.records_digest.len() == 64 && cp.job_id.len() == 16,
                "{}: a format-{CHECKPOINT_FORMAT} checkpoint without its job id or record digest \
                 (damaged)",
                path.display()
            );
            cp
        }
        other => anyhow::bail!(
            "{}: checkpoint format {other} (this granflow reads formats 1, 3 and {CHECKPOINT_FORMAT})",
            path.display()
        ),
    };
    if !cp.job_id.is_empty() {
        super::check_owner(dir, &cp.job_id, &path)?;
    }
    Ok(Some(cp))
}

/// What [`checkpoint_tail`] reads of a checkpoint: the job it names and how much of the
/// record log it covers.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointTail {
    pub job_id: String,
    /// bytes of frames after the log's header
    pub records_bytes: u64,
    /// whether the log it covers starts with a header (format 4 on)
    pub log_has_header: bool,
}

/// The fields after the engine's bytes, formats 3 and 4 (frozen: postcard needs the layout).
#[derive(Deserialize)]
struct TailV4 {
    _records: u64,
    records_bytes: u64,
    _wall_seconds: f64,
    _progress: crate::engine::Progress,
    job_id: String,
    records_digest: String,
}

#[derive(Deserialize)]
struct TailV3 {
    _records: u64,
    records_bytes: u64,
    _wall_seconds: f64,
    _progress: crate::engine::Progress,
    job_id: String,
}

/// Most bytes a checkpoint's fields after the engine's bytes take (they are a few hundred).
const TAIL_MAX: u64 = 4096;

/// A cheap look at a job's checkpoint (None when there is none, or it is of format 1, which
/// held its records itself): its first bytes and its last ones, skipping the engine's state,
/// so that a checkpoint of another job, or one cut short or grown, is found without reading
/// it whole. Its CRC is not checked ([`read_checkpoint`] does that).
pub fn checkpoint_tail(dir: &Path) -> anyhow::Result<Option<CheckpointTail>> {
    use std::io::{Read, Seek, SeekFrom};
    let path = dir.join(CHECKPOINT_FILE);
    let mut file = match std::fs::File::open(&path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(anyhow::anyhow!("{}: {e}", path.display())),
    };
    let len = file.metadata()?.len();
    let mut head = [0u8; 32];
    let got = file.read(&mut head)?;
    let damaged = |why: &str| anyhow::anyhow!("{}: {why} (damaged)", path.display());
    let head = &head[..got];
    let (format, rest) =
        postcard::take_from_bytes::<u32>(head).map_err(|_| damaged("truncated checkpoint"))?;
    if format == 1 {
        return Ok(None);
    }
    let (_snapshot, rest) =
        postcard::take_from_bytes::<u32>(rest).map_err(|_| damaged("truncated checkpoint"))?;
    let (engine_len, rest) =
        postcard::take_from_bytes::<u64>(rest).map_err(|_| damaged("truncated checkpoint"))?;
    let engine_at = (head.len() - rest.len()) as u64;
    let tail_at = engine_at.saturating_add(engine_len);
    anyhow::ensure!(
        tail_at + 4 <= len && len - tail_at <= TAIL_MAX,
        "{}: {len} bytes where its engine state alone takes {engine_len} (cut short or grown: \
         damaged)",
        path.display()
    );
    file.seek(SeekFrom::Start(tail_at))?;
    let mut tail = Vec::new();
    file.read_to_end(&mut tail)?;
    let fields = &tail[..tail.len() - 4];
    let tail = match format {
        3 => postcard::take_from_bytes::<TailV3>(fields).map(|(t, rest)| {
            (
                CheckpointTail {
                    job_id: t.job_id,
                    records_bytes: t.records_bytes,
                    log_has_header: false,
                },
                rest.len(),
            )
        }),
        CHECKPOINT_FORMAT => postcard::take_from_bytes::<TailV4>(fields).map(|(t, rest)| {
            (
                CheckpointTail {
                    job_id: t.job_id,
                    records_bytes: t.records_bytes,
                    log_has_header: t.records_digest.len() == 64,
                },
                rest.len(),
            )
        }),
        other => anyhow::bail!(
            "{}: checkpoint format {other} (this granflow reads formats 1, 3 and {CHECKPOINT_FORMAT})",
            path.display()
        ),
    };
    let (tail, left) = tail.map_err(|_| damaged("its last fields do not read"))?;
    anyhow::ensure!(
        left == 0,
        "{}: {left} bytes too many after its last field (damaged)",
        path.display()
    );
    if !tail.job_id.is_empty() {
        super::check_owner(dir, &tail.job_id, &path)?;
    }
    Ok(Some(tail))
}

/// Write a job's checkpoint atomically.
pub fn write_checkpoint(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<()> {
    write_postcard_with_crc(&dir.join(CHECKPOINT_FILE), cp)
}
