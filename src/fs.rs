//! Writing files safely, at the bottom of the house: atomic writes (temp file, fsync, rename),
//! I/O errors that carry their path, and lines on stdout that survive a closed pipe.

use std::io::Write;
use std::path::{Path, PathBuf};

/// An I/O error on a path (its message holds the error's, so it is not a separate cause).
#[derive(Debug, thiserror::Error)]
#[error("{}: {error}", path.display())]
pub struct PathError {
    pub path: PathBuf,
    pub error: std::io::Error,
}

impl PathError {
    pub fn new(path: &Path, error: std::io::Error) -> Self {
        PathError {
            path: path.to_path_buf(),
            error,
        }
    }
}

impl From<PathError> for std::io::Error {
    fn from(e: PathError) -> Self {
        std::io::Error::new(e.error.kind(), e)
    }
}

/// ENOSPC, EDQUOT, EFBIG, EIO, EROFS, EACCES (Linux numbers): the place the files go, not
/// the input, is at fault (a directory without write permission is a read-only directory).
const RESOURCE_ERRNOS: &[i32] = &[28, 122, 27, 5, 30, 13];

/// Whether an OS error number is a *resource* error (see `sweep::fs_error`).
pub fn is_resource_errno(n: i32) -> bool {
    RESOURCE_ERRNOS.contains(&n)
}

/// The first resource error (a full disk, ...) that stdout gave [`say`], if any.
static STDOUT_LOST: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// Print a line on stdout, ignoring a closed pipe (`granflow run ... | head` must not stop a
/// run: results are written whatever happens to the output). A full stdout does not stop the
/// run either (its results come first), but is remembered: [`stdout_lost`] says so, and the
/// command ends with the resource exit code.
pub fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = writeln!(out, "{line}").and_then(|()| out.flush())
        && e.raw_os_error().is_some_and(is_resource_errno)
    {
        let mut lost = STDOUT_LOST.lock().unwrap_or_else(|p| p.into_inner());
        lost.get_or_insert_with(|| e.to_string());
    }
}

/// The resource error that made [`say`] lose a line, if one did.
pub fn stdout_lost() -> Option<String> {
    STDOUT_LOST
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .clone()
}

/// Write a file atomically: temp file in the same directory (named by host, process and a
/// counter, so that writers on different nodes of a cluster never share one), fsync, rename,
/// fsync the directory. A failed write removes its temp file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_with(path, |f| f.write_all(bytes))
}

/// As [`write_atomic`], the contents written by `fill` into the (buffered) temp file: a big
/// file need not be assembled in memory first.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let dir = path.parent().unwrap_or(Path::new("."));
    let tmp = dir.join(format!(
        ".{}.tmp-{}-{}-{}",
        path.file_name()
            .map(|n| n.to_string_lossy())
            .unwrap_or_default(),
        crate::provenance::host(),
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let written = (|| {
        let mut f = std::io::BufWriter::with_capacity(1 << 16, std::fs::File::create(&tmp)?);
        fill(&mut f)?;
        f.into_inner().map_err(|e| e.into_error())?.sync_all()
    })();
    if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, path)) {
        let _ = std::fs::remove_file(&tmp);
        return Err(PathError::new(path, e).into());
    }
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}
