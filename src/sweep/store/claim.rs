//! Claims on jobs: an exclusive OS lock (flock) on `jobs/<id>/lock`, held while a runner runs
//! the job, with the holder (host, pid, since) written into the file for `status`. A claim
//! whose lock file was deleted or replaced (so that another runner could lock a new file) is
//! detected: [`Claim::still_held`] compares the locked file with the one at the path, and a
//! runner checks it before every checkpoint and before the result. At start a runner checks
//! that locking works on the results file system at all ([`check_locking`]).

use super::{
    CHECKPOINT_FILE, FAILED_FILE, JobState, LOCK_FILE, PARAMS_FILE, RECORDS_FILE, RESULT_FILE, log,
    set_aside, state_unlocked,
};
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::os::unix::fs::MetadataExt;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Claims without OS locks (`run --unsafe-no-locks`, for file systems without flock): then
/// only one runner may work on a sweep at a time.
static WITHOUT_LOCKS: AtomicBool = AtomicBool::new(false);

/// Let claims succeed where the file system refuses locks (the documented override).
pub fn allow_claims_without_locks() {
    WITHOUT_LOCKS.store(true, Ordering::Relaxed);
}

/// An exclusive claim on a job; released when dropped (or when the process dies).
#[derive(Debug)]
pub struct Claim {
    /// the claimed job's directory
    pub dir: super::JobDir,
    /// the locked file: held, never read (dropping it releases the lock)
    _lock: File,
    /// (device, inode) of the locked file
    identity: (u64, u64),
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
    /// a file is damaged or misplaced (and retrying was not asked for)
    Damaged(String),
    /// the directory or its lock file could not be opened or written: the path and the error
    Unreadable(String),
}

fn identity(meta: &std::fs::Metadata) -> (u64, u64) {
    (meta.dev(), meta.ino())
}

impl Claim {
    /// Whether the lock file at the job's path is still the one this claim locked; the reason
    /// when not (deleted, or replaced by another file that another runner may hold).
    pub fn still_held(&self) -> Result<(), String> {
        let path = self.dir.path().join(LOCK_FILE);
        match std::fs::metadata(&path) {
            Ok(meta) if identity(&meta) == self.identity => Ok(()),
            Ok(_) => Err(format!(
                "{} was replaced while this runner held it: another runner may hold the job now",
                path.display()
            )),
            Err(_) => Err(format!(
                "{} was deleted while this runner held it: another runner may claim the job",
                path.display()
            )),
        }
    }
}

/// Who holds (or last held) a job: the `host=.. pid=.. since=..` line of its lock file.
pub fn holder(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(LOCK_FILE)).ok()?;
    let line = text.lines().next()?.trim().to_string();
    (!line.is_empty()).then_some(line)
}

/// Lock `file` without blocking: Ok(true) locked, Ok(false) held elsewhere.
fn lock_now(file: &File) -> std::io::Result<bool> {
    match file.try_lock() {
        Ok(()) => Ok(true),
        Err(std::fs::TryLockError::WouldBlock) => Ok(false),
        Err(std::fs::TryLockError::Error(_)) if WITHOUT_LOCKS.load(Ordering::Relaxed) => Ok(true),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}

/// Open and lock the job's lock file, retrying briefly while a state probe holds it, and
/// again when the file was replaced between opening and locking. None: another runner holds
/// it.
pub(super) fn lock_job(dir: &Path) -> std::io::Result<Option<(File, (u64, u64))>> {
    let path = dir.join(LOCK_FILE);
    for _ in 0..3 {
        let lock = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)?;
        // a state probe ([`super::job_state`]) holds the lock for an instant: try a few
        // times before concluding that another runner holds it
        let mut locked = false;
        for attempt in 0..6 {
            if lock_now(&lock)? {
                locked = true;
                break;
            }
            if attempt < 5 {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
        }
        if !locked {
            return Ok(None);
        }
        let mine = identity(&lock.metadata()?);
        match std::fs::metadata(&path) {
            Ok(meta) if identity(&meta) == mine => return Ok(Some((lock, mine))),
            // replaced or deleted between open and lock: lock what is there now
            _ => continue,
        }
    }
    Ok(None)
}

/// Try to claim the job in `dir` (non-blocking). The state is re-read under the lock, so a job
/// finished by another runner in the meantime is never run again. With `retry_failed` a failed
/// job's `failed.txt` is removed and it resumes from its last checkpoint.
pub fn try_claim(dir: &Path, retry_failed: bool) -> std::io::Result<Result<Claim, NotClaimed>> {
    std::fs::create_dir_all(dir)?;
    let Some((mut lock, identity)) = lock_job(dir)? else {
        return Ok(Err(NotClaimed::Busy));
    };
    // The state is read with its files checked (a result's checksum and owner, the records a
    // checkpoint covers): a damaged file is refused here, or with --retry-failed set aside and
    // the state read again. A checkpoint and its record log are one resumable state: when
    // either is damaged both are set aside and the job restarts from scratch.
    let mut state = state_unlocked(dir, true);
    loop {
        match &state {
            // a damaged parameters file is repaired from the plan before the claim
            // ([`super::repair_params`]); here it is only refused
            JobState::Damaged { reason, file } if !retry_failed || *file == PARAMS_FILE => {
                return Ok(Err(NotClaimed::Damaged(reason.clone())));
            }
            JobState::Damaged { file, reason } => {
                // a done job's result goes with them: it is recomputed from scratch, so that
                // result, checkpoint and records are one run's again
                let files: &[&str] = match *file {
                    CHECKPOINT_FILE | RECORDS_FILE => &[CHECKPOINT_FILE, RECORDS_FILE, RESULT_FILE],
                    _ => std::slice::from_ref(file),
                };
                for f in files {
                    if dir.join(f).exists() {
                        let to = set_aside(dir, f)?;
                        let why = if f == file {
                            reason.clone()
                        } else {
                            format!("its partner {file} is damaged")
                        };
                        log(dir, &format!("set aside {f} as {}: {why}", to.display()))?;
                    }
                }
            }
            JobState::Done => return Ok(Err(NotClaimed::Done)),
            JobState::Failed(e) if !retry_failed => return Ok(Err(NotClaimed::Failed(e.clone()))),
            JobState::Failed(_) => std::fs::remove_file(dir.join(FAILED_FILE))?,
            _ => break,
        }
        state = state_unlocked(dir, true);
    }
    remove_stale_temps(dir);
    // the holder, for `status` (the lock file's content is information only)
    lock.set_len(0)?;
    writeln!(
        lock,
        "host={} pid={} since={}",
        crate::provenance::host(),
        std::process::id(),
        crate::provenance::now()
    )?;
    Ok(Ok(Claim {
        dir: super::JobDir::new(dir),
        _lock: lock,
        identity,
    }))
}

/// Remove the temp files of atomic writes (`.<name>.tmp-<host>-<pid>-<n>`) that a killed or
/// failed writer left in a job directory. Called under the job's lock: no live writer of this
/// job can own them.
fn remove_stale_temps(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') && name.contains(".tmp-") {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Check that exclusive locks work in `root` (where the job directories go): a probe file is
/// locked through one descriptor and must then refuse a second. Err names the directory and
/// what to do. Locks that are only node-local (NFS `local_lock=flock|all`, Lustre
/// `localflock`) pass this probe; they are reported as a warning (Ok(Some)).
pub fn check_locking(root: &Path) -> Result<Option<String>, String> {
    let probe = root.join(format!(
        ".granflow-lock-probe-{}-{}",
        crate::provenance::host(),
        std::process::id()
    ));
    let refuse = |why: String| {
        format!(
            "file locking does not work in {}: {why}. granflow needs exclusive flock locks to \
             keep two runners off the same job; use a file system with locks (local disk, \
             NFS with lockd, Lustre mounted with `flock`), or, if only one runner will ever \
             work on this sweep at a time, pass --unsafe-no-locks",
            root.display()
        )
    };
    let result = (|| {
        let first =
            File::create(&probe).map_err(|e| format!("creating {}: {e}", probe.display()))?;
        match first.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(refuse("a fresh probe file was reported as locked".into()));
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(refuse(format!("flock: {e}"))),
        }
        let second = File::open(&probe).map_err(|e| format!("opening {}: {e}", probe.display()))?;
        match second.try_lock() {
            Err(std::fs::TryLockError::WouldBlock) => Ok(()),
            Ok(()) => Err(refuse("a second lock of a locked file succeeded".into())),
            Err(std::fs::TryLockError::Error(e)) => Err(refuse(format!("flock: {e}"))),
        }
    })();
    let _ = std::fs::remove_file(&probe);
    result?;
    Ok(node_local_locks(root))
}

/// A warning when `root` lies on a mount whose locks are node-local (read from /proc/mounts).
fn node_local_locks(root: &Path) -> Option<String> {
    let root = std::fs::canonicalize(root).ok()?;
    let mounts = std::fs::read_to_string("/proc/mounts").ok()?;
    node_local_in(&root, &mounts)
}

/// The warning for `root` (absolute) given the text of /proc/mounts.
fn node_local_in(root: &Path, mounts: &str) -> Option<String> {
    let (mount, fstype, options) = mounts
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() >= 4).then(|| (f[1].to_string(), f[2].to_string(), f[3].to_string()))
        })
        .filter(|(m, _, _)| root.starts_with(m))
        .max_by_key(|(m, _, _)| m.len())?;
    let local = (fstype.starts_with("nfs")
        && options
            .split(',')
            .any(|o| o == "local_lock=flock" || o == "local_lock=all"))
        || (fstype == "lustre" && options.split(',').any(|o| o == "localflock"));
    local.then(|| {
        format!(
            "warning: {} is on {mount} ({fstype}, {options}), whose locks are node-local: runners \
             on different nodes do not see each other's claims. Run one runner per sweep, or \
             Slurm tasks by id (`granflow slurm submit`), whose job sets are disjoint",
            root.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOUNTS: &str = "\
/dev/sda1 / ext4 rw,relatime 0 0
srv:/home /home nfs4 rw,vers=4.2,local_lock=none 0 0
srv:/scratch /scratch nfs rw,vers=3,local_lock=flock 0 0
mds@tcp:/lus /lus lustre rw,localflock 0 0
mds@tcp:/lus2 /lus2 lustre rw,flock 0 0
";

    #[test]
    fn node_local_locks_are_recognised_from_the_mount_table() {
        let warn = |p: &str| node_local_in(Path::new(p), MOUNTS);
        assert!(warn("/scratch/me/results").is_some());
        assert!(warn("/lus/proj/results").is_some());
        // global locks, local disks: no warning
        assert!(warn("/home/me/results").is_none());
        assert!(warn("/lus2/proj").is_none());
        assert!(warn("/tmp/results").is_none());
        // the longest mount point wins (/lus2 is not under /lus)
        assert!(warn("/lus2").is_none());
    }

    #[test]
    fn locking_works_here() {
        let dir = std::env::temp_dir().join(format!("granflow-lock-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_locking(&dir).is_ok());
        // the probe is removed
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
