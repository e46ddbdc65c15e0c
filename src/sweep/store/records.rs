//! `records.bin`: a job's analysis records, one frame per snapshot, appended as the job runs
//! and never rewritten. Frame: payload length (u32 LE), CRC-32 of the payload (u32 LE),
//! payload (postcard of the [`Record`]). A checkpoint names the prefix of the log it covers
//! (records and bytes); frames after it (written after the last checkpoint by a job that was
//! then killed) are cut off when the job resumes, so a resumed job's log is the uninterrupted
//! job's, byte for byte.

use super::{JobCheckpoint, RECORDS_FILE};
use crate::analysis::Record;
use crate::sweep::fs_error::PathError;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const FRAME_HEADER: usize = 8;

fn frame(record: &Record) -> anyhow::Result<Vec<u8>> {
    let payload = postcard::to_stdvec(record)?;
    let mut out = Vec::with_capacity(FRAME_HEADER + payload.len());
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

/// The records a checkpoint covers: the first `cp.records` frames of the log, which must fill
/// exactly `cp.records_bytes` bytes, each with a good checksum (format-1 checkpoints carry their
/// records themselves).
pub fn load_records(dir: &Path, cp: &JobCheckpoint) -> anyhow::Result<Vec<Record>> {
    if let Some(records) = &cp.legacy_records {
        return Ok(records.clone());
    }
    let path = dir.join(RECORDS_FILE);
    let mut bytes = vec![0u8; cp.records_bytes as usize];
    let mut file = File::open(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot open the record log: {e}", path.display()))?;
    file.read_exact(&mut bytes).map_err(|e| {
        anyhow::anyhow!(
            "{}: the record log is shorter than the {} bytes its checkpoint covers: {e}",
            path.display(),
            cp.records_bytes
        )
    })?;
    let (records, end) = parse_frames(&bytes);
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
    Ok(records)
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
        Ok(bytes) => Ok(parse_frames(&bytes).0),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(super::read_checkpoint(dir)?
            .and_then(|cp| cp.legacy_records)
            .unwrap_or_default()),
        Err(e) => Err(anyhow::anyhow!("{}: {e}", path.display())),
    }
}

/// The record log of a running job, open for appending.
pub struct RecordLog {
    path: PathBuf,
    file: BufWriter<File>,
    records: u64,
    bytes: u64,
}

impl RecordLog {
    /// Open the log to continue after `cp` (cut back to what it covers; a format-1
    /// checkpoint's records are written out first), or start an empty one.
    pub fn open(dir: &Path, cp: Option<&JobCheckpoint>) -> anyhow::Result<Self> {
        let path = dir.join(RECORDS_FILE);
        let file = OpenOptions::new()
            .create(true)
            .write(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let (records, bytes) = match cp {
            Some(cp) if cp.legacy_records.is_none() => (cp.records, cp.records_bytes),
            _ => (0, 0),
        };
        file.set_len(bytes).map_err(|e| PathError::new(&path, e))?;
        let mut file = BufWriter::new(file);
        file.seek(SeekFrom::Start(bytes))?;
        let mut log = RecordLog {
            path,
            file,
            records,
            bytes,
        };
        if let Some(legacy) = cp.and_then(|c| c.legacy_records.as_ref()) {
            for r in legacy {
                log.append(r)?;
            }
        }
        Ok(log)
    }

    /// Append one record (buffered; [`RecordLog::sync`] makes it durable).
    pub fn append(&mut self, record: &Record) -> anyhow::Result<()> {
        let bytes = frame(record)?;
        self.file
            .write_all(&bytes)
            .map_err(|e| PathError::new(&self.path, e))?;
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

    /// Records and bytes written so far.
    pub fn position(&self) -> (u64, u64) {
        (self.records, self.bytes)
    }
}
