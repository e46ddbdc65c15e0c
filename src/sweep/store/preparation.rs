//! `preparation.bin`: the engine's sealed state in the middle of its preparation (DEM: the
//! packing settling onto its floor), before the job's first snapshot and its checkpoint 0
//! exist. Postcard, then a CRC-32 of the bytes; it names its job, so a file copied from
//! another job is refused. Removed once checkpoint 0 is written: from then on
//! `checkpoint.bin` holds the job.

use super::{PREPARATION_FILE, write_postcard_with_crc};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Format of `preparation.bin` written now.
const PREPARATION_FORMAT: u32 = 1;

/// What a job's preparation checkpoint holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PreparationCheckpoint {
    /// format version
    pub format: u32,
    /// the job it belongs to
    pub job_id: String,
    /// the preparation's steps done (informational: the engine's state holds them)
    pub steps: u64,
    /// wall-clock seconds spent on the preparation so far (informational)
    pub wall_seconds: f64,
    /// [`crate::engine::Engine::checkpoint`] bytes taken after a call to `prepare`
    pub engine: Vec<u8>,
}

impl PreparationCheckpoint {
    /// A preparation checkpoint of job `job_id` in the current format.
    pub fn new(job_id: &str, steps: u64, wall_seconds: f64, engine: Vec<u8>) -> Self {
        PreparationCheckpoint {
            format: PREPARATION_FORMAT,
            job_id: job_id.to_string(),
            steps,
            wall_seconds,
            engine,
        }
    }
}

/// Replace the job's preparation checkpoint (atomically, durable when this returns).
pub fn write_preparation(dir: &Path, cp: &PreparationCheckpoint) -> anyhow::Result<()> {
    write_postcard_with_crc(&dir.join(PREPARATION_FILE), cp)
}

/// Read a job's preparation checkpoint (None when there is none), checked: its CRC, its
/// format and the job it names.
pub fn read_preparation(dir: &Path) -> anyhow::Result<Option<PreparationCheckpoint>> {
    let path = dir.join(PREPARATION_FILE);
    let Some(body) = super::read_crc_checked(&path, "preparation checkpoint")? else {
        return Ok(None);
    };
    let body = body.as_slice();
    let (format, _) = postcard::take_from_bytes::<u32>(body)?;
    anyhow::ensure!(
        format == PREPARATION_FORMAT,
        "{}: preparation checkpoint format {format} (this granflow reads format \
         {PREPARATION_FORMAT})",
        path.display()
    );
    let cp: PreparationCheckpoint =
        postcard::from_bytes(body).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    super::check_owner(dir, &cp.job_id, &path)?;
    Ok(Some(cp))
}

/// Remove the preparation checkpoint (once checkpoint 0 holds the job); none is fine.
pub fn remove_preparation(dir: &Path) -> anyhow::Result<()> {
    let path = dir.join(PREPARATION_FILE);
    match std::fs::remove_file(&path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(anyhow::anyhow!("removing {}: {e}", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir()
            .join(format!(
                "granflow-preparation-{name}-{}",
                std::process::id()
            ))
            .join("0123456789abcdef");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn round_trip_and_removal() {
        let dir = scratch("round-trip");
        assert_eq!(read_preparation(&dir).unwrap(), None);
        let cp = PreparationCheckpoint::new("0123456789abcdef", 4200, 1.5, vec![1, 2, 3, 250]);
        write_preparation(&dir, &cp).unwrap();
        assert_eq!(read_preparation(&dir).unwrap(), Some(cp));
        remove_preparation(&dir).unwrap();
        assert_eq!(read_preparation(&dir).unwrap(), None);
        remove_preparation(&dir).unwrap();
    }

    #[test]
    fn a_flipped_bit_or_another_jobs_file_is_refused() {
        let dir = scratch("tamper");
        let cp = PreparationCheckpoint::new("0123456789abcdef", 7, 0.0, vec![9; 64]);
        write_preparation(&dir, &cp).unwrap();
        let path = dir.join(PREPARATION_FILE);
        let mut bytes = std::fs::read(&path).unwrap();
        bytes[30] ^= 1;
        std::fs::write(&path, &bytes).unwrap();
        let e = read_preparation(&dir).unwrap_err().to_string();
        assert!(e.contains("checksum mismatch"), "{e}");
        let other = PreparationCheckpoint::new("fedcba9876543210", 7, 0.0, vec![9; 64]);
        write_preparation(&dir, &other).unwrap();
        let e = read_preparation(&dir).unwrap_err().to_string();
        assert!(e.contains("belongs to job fedcba9876543210"), "{e}");
    }
}
