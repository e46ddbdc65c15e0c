//! The job store: the one owner of a job directory's files. One directory per job, its state
//! read from the files in it alone, claims through an OS file lock that dies with its process;
//! the formats of the checkpoint ([`checkpoint`]), the record log ([`records`]) and the result
//! ([`result`]) live in submodules.
//!
//! `jobs/<id>/` holds:
//! - `params.json`: the resolved parameters and canonical form, written once;
//! - `lock`: the claim; a runner holds an exclusive `flock` on it while the job runs;
//! - `preparation.bin`: the engine in the middle of preparing its initial state (DEM's
//!   settling), replaced atomically, removed once `checkpoint.bin` exists;
//! - `checkpoint.bin`: engine checkpoint and how many records it covers, replaced atomically;
//! - `records.bin`: the analysis records, one frame per snapshot, appended (never rewritten:
//!   checkpoint I/O stays linear in the run length);
//! - `result.ron`: the job's analysis and counters; its presence means done;
//! - `failed.txt`: the error of a failed job (removed by `--retry-failed`);
//! - `log.txt`: one line per start ("prepare", "start" or "resume"), end ("done") or failure,
//!   appended;
//! - `figures/`: the job's figures (`<name>.png` and `.svg`, see `crate::job_figures`),
//!   written when it finishes (and by `granflow report` where they are missing).

use super::grid::PlannedJob;
use super::job::{JobId, JobParams};
use super::write_atomic;
use anyhow::Context;
use serde::{Deserialize, Serialize};

mod checkpoint;
mod claim;
mod job_dir;
mod preparation;
mod records;
mod result;

pub use checkpoint::{
    CheckpointTail, JobCheckpoint, checkpoint_measure, checkpoint_progress, checkpoint_tail,
    read_checkpoint, write_checkpoint,
};
pub use claim::{Claim, NotClaimed, allow_claims_without_locks, check_locking, holder, try_claim};
pub use job_dir::JobDir;
pub use preparation::{
    PreparationCheckpoint, read_preparation, remove_preparation, write_preparation,
};
pub use records::{RecordLog, check_log_cheaply, load_records, records_so_far};
pub use result::{JobResult, RESULT_FORMAT, done_line, read_result, write_result};
use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};

pub const PARAMS_FILE: &str = "params.json";
pub const LOCK_FILE: &str = "lock";
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";
pub const PREPARATION_FILE: &str = "preparation.bin";
pub const RESULT_FILE: &str = "result.ron";
pub const FAILED_FILE: &str = "failed.txt";
pub const LOG_FILE: &str = "log.txt";
pub const RECORDS_FILE: &str = "records.bin";
pub use crate::job_figures::FIGURES_DIR;

/// Write `value`'s postcard bytes followed by their CRC-32 (little endian) to `path`
/// atomically, streamed into the file: a checkpoint's engine bytes are not copied again.
pub(crate) fn write_postcard_with_crc<T: Serialize>(path: &Path, value: &T) -> anyhow::Result<()> {
    crate::fs::write_atomic_with(path, |file| {
        let mut out = Crc32Writer {
            inner: file,
            crc: crc32fast::Hasher::new(),
        };
        postcard::to_io(value, &mut out).map_err(std::io::Error::other)?;
        let crc = out.crc.finalize();
        out.inner.write_all(&crc.to_le_bytes())
    })?;
    Ok(())
}

/// The bytes [`write_postcard_with_crc`] wrote to `path`, its CRC-32 checked and cut off (None
/// when there is no file); `what` names the file in the errors ("checkpoint").
pub(crate) fn read_crc_checked(path: &Path, what: &str) -> anyhow::Result<Option<Vec<u8>>> {
    let mut bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e.into()),
    };
    anyhow::ensure!(bytes.len() >= 4, "{}: truncated {what}", path.display());
    let body_len = bytes.len() - 4;
    anyhow::ensure!(
        crc32fast::hash(&bytes[..body_len]).to_le_bytes() == bytes[body_len..],
        "{}: {what} checksum mismatch",
        path.display()
    );
    bytes.truncate(body_len);
    Ok(Some(bytes))
}

/// A writer that keeps the CRC-32 of what passes through it.
struct Crc32Writer<'a> {
    inner: &'a mut dyn Write,
    crc: crc32fast::Hasher,
}

impl Write for Crc32Writer<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.crc.update(&buf[..n]);
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

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
    /// a file of the job is damaged or belongs to another job: which file and why
    Damaged { file: &'static str, reason: String },
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
            JobState::Damaged { .. } => "damaged",
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

/// A job's resolved parameters from its `params.json`, checked: the file names the job of its
/// directory, its canonical form hashes to that id, and its parameters give that canonical
/// form (an emptied, edited or foreign file is refused, saying which).
pub fn read_params(dir: &Path) -> anyhow::Result<JobParams> {
    let path = dir.join(PARAMS_FILE);
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let file: ParamsFile =
        serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    check_owner(dir, &file.id.0, &path)?;
    anyhow::ensure!(
        super::job::id_of_canonical(&file.canonical) == file.id,
        "{}: its canonical form does not hash to the id {} (edited?)",
        path.display(),
        file.id
    );
    anyhow::ensure!(
        file.params.canonical() == file.canonical,
        "{}: its parameters do not give its canonical form (edited?)",
        path.display()
    );
    Ok(file.params)
}

/// Set aside a damaged `params.json` of `job` and write it anew from the plan, under the job's
/// lock (`run --retry-failed`); false when another runner holds the job.
pub fn repair_params(dir: &Path, job: &PlannedJob, reason: &str) -> anyhow::Result<bool> {
    let Some((_lock, _)) = claim::lock_job(dir)? else {
        return Ok(false);
    };
    if dir.join(PARAMS_FILE).exists() {
        let to = set_aside(dir, PARAMS_FILE)?;
        log(
            dir,
            &format!("set aside {PARAMS_FILE} as {}: {reason}", to.display()),
        )?;
    }
    init_job_dir(dir, job)?;
    Ok(true)
}

/// The state of the job in `dir`, from its files and lock alone (a missing dir is pending).
/// Probing the lock takes it for an instant when it is free.
pub fn job_state(dir: &Path) -> JobState {
    job_state_checked(dir, false)
}

/// As [`job_state`], reading and checking a result (`verify`) instead of trusting its presence:
/// a damaged or misplaced result makes the job damaged.
pub fn job_state_checked(dir: &Path, verify: bool) -> JobState {
    if !verify && dir.join(RESULT_FILE).exists() {
        return JobState::Done;
    }
    if held_by_a_runner(dir) {
        return JobState::Running;
    }
    state_unlocked(dir, verify)
}

/// Whether a live runner holds the job's lock. The lock file is opened for writing, or for
/// reading where the directory is read-only (`status` of an archived sweep), and locked for
/// an instant when free.
fn held_by_a_runner(dir: &Path) -> bool {
    let path = dir.join(LOCK_FILE);
    let file = OpenOptions::new()
        .write(true)
        .open(&path)
        .or_else(|_| std::fs::File::open(&path));
    matches!(
        file.map(|f| f.try_lock()),
        Ok(Err(std::fs::TryLockError::WouldBlock))
    )
}

/// The state ignoring the lock (what a runner that holds the lock sees). A result counts as
/// done by its presence unless `verify` asks to read and check it (and the job's parameters
/// file with it); a checkpoint that cannot be read makes the job damaged.
fn state_unlocked(dir: &Path, verify: bool) -> JobState {
    if verify
        && dir.join(PARAMS_FILE).exists()
        && let Err(e) = read_params(dir)
    {
        return JobState::Damaged {
            file: PARAMS_FILE,
            reason: format!("{e:#}"),
        };
    }
    if dir.join(RESULT_FILE).exists() {
        if verify {
            if let Err(e) = read_result(dir) {
                return JobState::Damaged {
                    file: RESULT_FILE,
                    reason: format!("{e:#}"),
                };
            }
            if let Err((file, reason)) = check_done_files(dir, true) {
                return JobState::Damaged { file, reason };
            }
        }
        return JobState::Done;
    }
    if let Ok(err) = std::fs::read_to_string(dir.join(FAILED_FILE)) {
        return JobState::Failed(err.trim().to_string());
    }
    match read_checkpoint(dir) {
        // with `verify`, the records the checkpoint covers are read too: a resume needs them
        Ok(Some(cp)) => match verify.then(|| load_records(dir, &cp)) {
            Some(Err(e)) => JobState::Damaged {
                file: RECORDS_FILE,
                reason: format!("{e:#}"),
            },
            _ => JobState::Partial(cp.progress),
        },
        // in the middle of its preparation: partial at the clocks' start
        Ok(None) => match read_preparation(dir) {
            Ok(None) => JobState::Pending,
            Ok(Some(_)) => JobState::Partial(crate::engine::Progress::default()),
            Err(e) => JobState::Damaged {
                file: PREPARATION_FILE,
                reason: format!("{e:#}"),
            },
        },
        Err(e) => JobState::Damaged {
            file: CHECKPOINT_FILE,
            reason: format!("{e:#}"),
        },
    }
}

/// Check a done job's checkpoint and record log (its result and parameters are checked when
/// read): cheaply (the checkpoint's first and last bytes name this job and fit its length, the
/// log's header names it and the log holds what the checkpoint covers), or in `full` (the
/// checkpoint's CRC, the log's frames and its digest). A done job without a checkpoint (one
/// imported from another code) has nothing to check. The damaged file and why.
pub fn check_done_files(dir: &Path, full: bool) -> Result<(), (&'static str, String)> {
    let damaged = |file: &'static str| move |e: anyhow::Error| (file, format!("{e:#}"));
    if full {
        let Some(cp) = read_checkpoint(dir).map_err(damaged(CHECKPOINT_FILE))? else {
            return Ok(());
        };
        load_records(dir, &cp).map_err(damaged(RECORDS_FILE))?;
        return Ok(());
    }
    let Some(tail) = checkpoint_tail(dir).map_err(damaged(CHECKPOINT_FILE))? else {
        return Ok(());
    };
    let id = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    check_log_cheaply(dir, &id, &tail).map_err(damaged(RECORDS_FILE))
}

/// A file that names another job than its directory's is misplaced.
fn check_owner(dir: &Path, owner: &str, path: &Path) -> anyhow::Result<()> {
    let here = dir.file_name().map(|n| n.to_string_lossy().into_owned());
    anyhow::ensure!(
        here.as_deref() == Some(owner),
        "{}: belongs to job {owner}, not to {} (copied from another job?)",
        path.display(),
        here.unwrap_or_default()
    );
    Ok(())
}

/// Move a damaged file aside, never deleting it: `<name>.damaged-<UTC time>`. Returns its new
/// path.
pub fn set_aside(dir: &Path, file: &str) -> std::io::Result<PathBuf> {
    let to = dir.join(format!("{file}.damaged-{}", crate::provenance::now()));
    std::fs::rename(dir.join(file), &to)?;
    Ok(to)
}

/// Retire an outdated result so that the job runs again (`run --rerun-outdated`): under the
/// job's lock, `result.ron` (and, when the engine changed, the checkpoint and the records, so
/// that the run restarts from scratch) are renamed `<name>.outdated-<UTC time>`, never
/// deleted, and the log says why. Returns the reason, or None when the job is not done, not
/// outdated, or held by a runner.
pub fn retire_if_outdated(
    dir: &Path,
    engine_version: u32,
    analysis_version: u32,
) -> anyhow::Result<Option<String>> {
    let Ok(lock) = OpenOptions::new().write(true).open(dir.join(LOCK_FILE)) else {
        return Ok(None);
    };
    if lock.try_lock().is_err() || !dir.join(RESULT_FILE).exists() {
        return Ok(None);
    }
    let Ok(result) = read_result(dir) else {
        // a damaged result is --retry-failed's business
        return Ok(None);
    };
    let Some(outdated) = result.provenance.outdated(engine_version, analysis_version) else {
        return Ok(None);
    };
    let stamp = crate::provenance::now();
    let mut files = vec![RESULT_FILE];
    if outdated.engine_changed {
        files.extend([CHECKPOINT_FILE, RECORDS_FILE]);
    }
    for file in files {
        let from = dir.join(file);
        if from.exists() {
            std::fs::rename(&from, dir.join(format!("{file}.outdated-{stamp}")))
                .with_context(|| format!("setting aside {}", from.display()))?;
        }
    }
    log(
        dir,
        &format!(
            "outdated: {}; rerun {}",
            outdated.reason,
            if outdated.engine_changed {
                "from the start"
            } else {
                "of the analysis from the last checkpoint"
            }
        ),
    )?;
    Ok(Some(outdated.reason))
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

/// A result is written before its log's `done` line; a runner stopped between the two leaves
/// a done job whose log does not say so. Add the line for such a job (the result is the
/// authority), so that the log and the result agree again.
pub fn complete_done_log(dir: &Path) -> std::io::Result<()> {
    if !dir.join(RESULT_FILE).exists() {
        return Ok(());
    }
    let text = std::fs::read_to_string(dir.join(LOG_FILE)).unwrap_or_default();
    // the last line of the job's course (start, resume, done, outdated): lines about its
    // files (a parameters file set aside and rewritten), claims or stops do not undo a done
    match result::last_course_event(&text) {
        Some(last) if last.starts_with("done") => Ok(()),
        _ => match read_result(dir) {
            Ok(result) => log(
                dir,
                &format!(
                    "{} (logged late: the runner stopped between writing the result and this line)",
                    done_line(&result.checksum)
                ),
            ),
            // a damaged result is reported by the checks that read it, not sealed by the log
            Err(_) => Ok(()),
        },
    }
}

/// When the job first started (the time of its log's first `prepare` or `start`), if the log
/// says.
pub fn first_start(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(LOG_FILE)).ok()?;
    text.lines()
        .find(|l| matches!(l.split(' ').nth(1), Some("start" | "prepare")))
        .and_then(|l| l.split(' ').next())
        .map(str::to_string)
}

/// Record a failure (atomically).
pub fn mark_failed(dir: &Path, error: &str) -> std::io::Result<()> {
    write_atomic(&dir.join(FAILED_FILE), format!("{error}\n").as_bytes())?;
    log(dir, &format!("failed: {error}"))
}
