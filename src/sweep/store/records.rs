//! `records.bin`: a job's analysis records, one frame per snapshot, appended as the job runs
//! and never rewritten.
//!
//! Layout: a header naming the job (the 16 bytes `GRANFLOW-RECLOG` zero-padded, then the
//! job id, 16 ASCII hex digits), then frames: payload length (u32 LE), CRC-32 of the payload
//! (u32 LE), payload (postcard of the [`Record`]). A checkpoint names the prefix of the log it
//! covers (records, bytes after the header, and the SHA-256 of header and covered frames);
//! frames after it (written after the last checkpoint by a job that was then killed) are cut
//! off when the job resumes, so a resumed job's log is the uninterrupted job's, byte for byte.
//! A log copied from another job is refused twice over: its header names the other job, and
//! its bytes do not match the digest this job's checkpoint holds.
//!
//! Older layouts still read: logs of checkpoint format 3 have no header and their checkpoint
//! no digest (their frames are checked by their CRCs alone); a job resumed from such a
//! checkpoint rewrites its log with the header first (atomically), and its next checkpoint
//! carries the digest.

use super::{JobCheckpoint, RECORDS_FILE, write_atomic};
use crate::analysis::Record;
use crate::sweep::fs_error::PathError;
use sha2::{Digest, Sha256};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const FRAME_HEADER: usize = 8;

/// The log's magic bytes (16, zero-padded).
const MAGIC: &[u8; 16] = b"GRANFLOW-RECLOG\0";
/// Bytes of the header: magic and the 16-digit job id.
pub const HEADER_LEN: usize = 32;

/// The header of job `job_id`'s log.
fn header(job_id: &str) -> anyhow::Result<[u8; HEADER_LEN]> {
    anyhow::ensure!(
        job_id.len() == 16 && job_id.bytes().all(|b| b.is_ascii_hexdigit()),
        "job id `{job_id}` is not 16 hex digits"
    );
    let mut out = [0u8; HEADER_LEN];
    out[..16].copy_from_slice(MAGIC);
    out[16..].copy_from_slice(job_id.as_bytes());
    Ok(out)
}

/// The job a log's first bytes name, when they are a header (None: an older log without one).
fn header_job(bytes: &[u8]) -> Option<String> {
    (bytes.len() >= HEADER_LEN && &bytes[..16] == MAGIC)
        .then(|| String::from_utf8_lossy(&bytes[16..HEADER_LEN]).into_owned())
}

/// SHA-256 of the header and covered frames, as a checkpoint holds it (hex).
fn digest_hex(hasher: &Sha256) -> String {
    crate::provenance::hex(&hasher.clone().finalize())
}

fn frame(record: &Record) -> anyhow::Result<Vec<u8>> {
    let payload = postcard::to_stdvec(record)?;
    let mut out = Vec::with_capacity(FRAME_HEADER + payload.len());
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

/// The records a checkpoint covers: the first `cp.records` frames after the log's header,
/// which must fill exactly `cp.records_bytes` bytes, each with a good checksum; the header must
/// name the job `cp` belongs to and, where the checkpoint holds one, header and frames must
/// match its digest (format-1 checkpoints carry their records themselves).
pub fn load_records(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<Vec<Record>> {
    Ok(read_covered(dir, cp)?.0)
}

/// The covered records and the bytes of the log they were read from (header included when the
/// log has one).
fn read_covered(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<(Vec<Record>, Vec<u8>)> {
    if let Some(records) = &cp.legacy_records {
        return Ok((records.clone(), Vec::new()));
    }
    let path = dir.join(RECORDS_FILE);
    let mut file = File::open(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot open the record log: {e}", path.display()))?;
    let mut head = vec![0u8; HEADER_LEN];
    let got =
        read_up_to(&mut file, &mut head).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    head.truncate(got);
    let owner = header_job(&head);
    let header_len = match (&owner, cp.records_digest.is_empty()) {
        (Some(owner), _) => {
            anyhow::ensure!(
                cp.job_id.is_empty() || *owner == cp.job_id,
                "{}: the record log belongs to job {owner}, not to {} (copied from another job?)",
                path.display(),
                cp.job_id
            );
            HEADER_LEN
        }
        (None, true) => 0,
        (None, false) => anyhow::bail!(
            "{}: the record log has no header naming its job, and its checkpoint expects one \
             (replaced or damaged)",
            path.display()
        ),
    };
    let mut bytes = head[..header_len].to_vec();
    let mut rest = head[header_len..].to_vec();
    let wanted = cp.records_bytes as usize;
    if rest.len() < wanted {
        let mut more = vec![0u8; wanted - rest.len()];
        file.read_exact(&mut more).map_err(|e| {
            anyhow::anyhow!(
                "{}: the record log is shorter than the {} bytes its checkpoint covers: {e}",
                path.display(),
                cp.records_bytes
            )
        })?;
        rest.extend_from_slice(&more);
    }
    rest.truncate(wanted);
    bytes.extend_from_slice(&rest);
    if !cp.records_digest.is_empty() {
        let mut hasher = Sha256::new();
        hasher.update(&bytes);
        anyhow::ensure!(
            digest_hex(&hasher) == cp.records_digest,
            "{}: the record log does not match its checkpoint's digest (replaced or changed \
             after it was written)",
            path.display()
        );
    }
    let (records, end) = parse_frames(&bytes[header_len..]);
    if let Some(why) = end {
        anyhow::bail!("{}: {why}", path.display());
    }
    anyhow::ensure!(
        records.len() as u64 == cp.records,
        "{}: {} records where the checkpoint covers {}",
        path.display(),
        records.len(),
        cp.records
    );
    Ok((records, bytes))
}

/// Read into `buf` until it is full or the file ends; the bytes read.
fn read_up_to(file: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match file.read(&mut buf[got..])? {
            0 => break,
            n => got += n,
        }
    }
    Ok(got)
}

/// The frames of `bytes` in order, up to the first that is incomplete or damaged (and why it
/// stopped there, None when every byte was read).
fn parse_frames(bytes: &[u8]) -> (Vec<Record>, Option<String>) {
    let mut records = Vec::new();
    let mut at = 0usize;
    while at < bytes.len() {
        if at + FRAME_HEADER > bytes.len() {
            return (records, Some(format!("truncated frame at byte {at}")));
        }
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as usize;
        let crc = u32::from_le_bytes(bytes[at + 4..at + 8].try_into().expect("4 bytes"));
        let start = at + FRAME_HEADER;
        if start + len > bytes.len() {
            return (
                records,
                Some(format!(
                    "frame at byte {at} runs past the checkpointed length"
                )),
            );
        }
        let payload = &bytes[start..start + len];
        if crc32fast::hash(payload) != crc {
            return (
                records,
                Some(format!("checksum mismatch in the frame at byte {at}")),
            );
        }
        match postcard::from_bytes(payload) {
            Ok(r) => records.push(r),
            Err(e) => return (records, Some(format!("frame at byte {at}: {e}"))),
        }
        at = start + len;
    }
    (records, None)
}

/// The records a job has written so far, for a look at a running, partial or done job: every
/// complete frame of its record log (a frame being written, or one a killed run left half
/// written, ends the list), or the records of a format-1 checkpoint. Nothing is changed;
/// a job without records gives an empty list.
pub fn records_so_far(dir: &Path) -> anyhow::Result<Vec<Record>> {
    let path = dir.join(RECORDS_FILE);
    match std::fs::read(&path) {
        Ok(bytes) => {
            let skip = if header_job(&bytes).is_some() {
                HEADER_LEN
            } else {
                0
            };
            Ok(parse_frames(&bytes[skip..]).0)
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(super::read_checkpoint(dir)?
            .and_then(|cp| cp.legacy_records)
            .unwrap_or_default()),
        Err(e) => Err(anyhow::anyhow!("{}: {e}", path.display())),
    }
}

/// A cheap look at a job's record log against what its checkpoint says (`tail`): the header
/// names job `job_id` (where the checkpoint expects one) and the log holds at least the bytes
/// the checkpoint covers. Frames are not read ([`load_records`] does that).
pub fn check_log_cheaply(
    dir: &Path,
    job_id: &str,
    tail: &super::CheckpointTail,
) -> anyhow::Result<()> {
    let path = dir.join(RECORDS_FILE);
    let mut file = File::open(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot open the record log: {e}", path.display()))?;
    let len = file.metadata()?.len();
    let mut head = vec![0u8; HEADER_LEN];
    let got = read_up_to(&mut file, &mut head)?;
    head.truncate(got);
    let header = if tail.log_has_header {
        let owner = header_job(&head).ok_or_else(|| {
            anyhow::anyhow!(
                "{}: the record log has no header naming its job, and its checkpoint expects \
                 one (replaced or damaged)",
                path.display()
            )
        })?;
        anyhow::ensure!(
            owner == job_id,
            "{}: the record log belongs to job {owner}, not to {job_id} (copied from another job?)",
            path.display()
        );
        HEADER_LEN as u64
    } else {
        0
    };
    anyhow::ensure!(
        len >= header + tail.records_bytes,
        "{}: the record log is {len} bytes, shorter than the {} its checkpoint covers (cut \
         short: damaged)",
        path.display(),
        header + tail.records_bytes
    );
    Ok(())
}

/// The record log of a running job, open for appending.
pub struct RecordLog {
    path: PathBuf,
    file: BufWriter<File>,
    records: u64,
    /// bytes of frames after the header
    bytes: u64,
    /// SHA-256 of the header and every frame appended so far
    hasher: Sha256,
}

impl RecordLog {
    /// Start job `job_id`'s log afresh: the header alone (replacing a log a run killed before
    /// its first checkpoint left).
    pub fn start(dir: &Path, job_id: &str) -> anyhow::Result<Self> {
        Ok(Self::open(dir, job_id, None)?.0)
    }

    /// Open job `job_id`'s log to continue after `cp`, cut back to what it covers and checked
    /// as [`load_records`] checks it (a log of an older layout, and a format-1 checkpoint's
    /// records, are first written out anew with the header); with the covered records.
    pub fn resume(
        dir: &Path,
        job_id: &str,
        cp: &JobCheckpoint,
    ) -> anyhow::Result<(Self, Vec<Record>)> {
        Self::open(dir, job_id, Some(cp))
    }

    fn open(
        dir: &Path,
        job_id: &str,
        cp: Option<&JobCheckpoint>,
    ) -> anyhow::Result<(Self, Vec<Record>)> {
        let path = dir.join(RECORDS_FILE);
        let head = header(job_id)?;
        let (covered, bytes) = match cp {
            Some(cp) => read_covered(dir, cp)?,
            None => (Vec::new(), Vec::new()),
        };
        let legacy = cp.is_some_and(|c| c.legacy_records.is_some());
        let has_header = header_job(&bytes).is_some();
        if cp.is_none() || legacy || !has_header {
            // a fresh log, or the covered frames of an older one behind a header: written
            // whole and renamed into place, so that a kill leaves either log, never half of one
            let mut fresh = head.to_vec();
            if !legacy {
                fresh.extend_from_slice(&bytes);
            }
            write_atomic(&path, &fresh).map_err(|e| PathError::new(&path, e))?;
        }
        let file = OpenOptions::new()
            .write(true)
            .open(&path)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let mut hasher = Sha256::new();
        hasher.update(head);
        let frames = if legacy || bytes.is_empty() {
            &[][..]
        } else if has_header {
            &bytes[HEADER_LEN..]
        } else {
            &bytes[..]
        };
        hasher.update(frames);
        let end = (HEADER_LEN + frames.len()) as u64;
        file.set_len(end).map_err(|e| PathError::new(&path, e))?;
        let mut file = BufWriter::new(file);
        file.seek(SeekFrom::Start(end))?;
        let mut log = RecordLog {
            path,
            file,
            records: if legacy { 0 } else { covered.len() as u64 },
            bytes: frames.len() as u64,
            hasher,
        };
        if legacy {
            for r in &covered {
                log.append(r)?;
            }
        }
        Ok((log, covered))
    }

    /// Append one record (buffered; [`RecordLog::sync`] makes it durable).
    pub fn append(&mut self, record: &Record) -> anyhow::Result<()> {
        let bytes = frame(record)?;
        self.file
            .write_all(&bytes)
            .map_err(|e| PathError::new(&self.path, e))?;
        self.hasher.update(&bytes);
        self.records += 1;
        self.bytes += bytes.len() as u64;
        Ok(())
    }

    /// Write out and fsync what was appended (before a checkpoint names it).
    pub fn sync(&mut self) -> anyhow::Result<()> {
        let path = &self.path;
        self.file.flush().map_err(|e| PathError::new(path, e))?;
        self.file
            .get_ref()
            .sync_data()
            .map_err(|e| PathError::new(path, e))?;
        Ok(())
    }

    /// Records and frame bytes written so far, and the digest of the log up to here.
    pub fn position(&self) -> (u64, u64, String) {
        (self.records, self.bytes, digest_hex(&self.hasher))
    }
}
