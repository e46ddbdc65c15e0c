//! File-system errors of the job store with the path they happened on, and which of them are
//! *resource* errors (full disk, quota, file-size limit, a failing device, a read-only file
//! system): those stop a runner from starting new jobs and leave the job resumable instead of
//! failing it, since they say nothing about the job.

#[cfg(test)]
use std::path::Path;

pub use crate::fs::PathError;

/// A run stopped by a resource error (exit code [`EXIT_RESOURCE`]): what happened, where.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct ResourceStop(pub String);

/// Exit code of a run stopped by a resource error (EX_TEMPFAIL of sysexits.h: try again
/// once the disk has room).
pub const EXIT_RESOURCE: u8 = 75;

pub use crate::fs::is_resource_errno;

fn is_resource_io(e: &std::io::Error) -> bool {
    if e.raw_os_error().is_some_and(is_resource_errno) {
        return true;
    }
    e.get_ref()
        .and_then(|inner| inner.downcast_ref::<PathError>())
        .is_some_and(|p| is_resource_io(&p.error))
}

/// What a resource error is, in words ("no space left on the device", ...), from the first
/// OS error number in the chain.
pub fn resource_kind(err: &anyhow::Error) -> &'static str {
    let errno = err.chain().find_map(|e| {
        e.downcast_ref::<PathError>()
            .and_then(|p| p.error.raw_os_error())
            .or_else(|| {
                e.downcast_ref::<std::io::Error>().and_then(|io| {
                    io.raw_os_error().or_else(|| {
                        io.get_ref()
                            .and_then(|i| i.downcast_ref::<PathError>())
                            .and_then(|p| p.error.raw_os_error())
                    })
                })
            })
    });
    match errno {
        Some(28) => "no space left on the device",
        Some(122) => "disk quota exceeded",
        Some(27) => "file size limit exceeded",
        Some(5) => "input/output error of the device",
        Some(30) => "read-only file system",
        Some(13) => "permission denied (a directory without write permission)",
        _ => "resource error",
    }
}

/// Whether an error (anywhere in its chain) is a resource error: the disk, not the job.
pub fn is_resource_error(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(is_resource_io)
            || e.downcast_ref::<PathError>()
                .is_some_and(|p| is_resource_io(&p.error))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_errors_are_recognised_through_wrappers() {
        let full = std::io::Error::from_raw_os_error(28);
        let wrapped: std::io::Error = PathError::new(Path::new("/r/x"), full).into();
        assert!(wrapped.to_string().contains("/r/x"));
        let err = anyhow::Error::new(wrapped).context("writing the checkpoint");
        assert!(is_resource_error(&err));
        let other = anyhow::Error::new(std::io::Error::from_raw_os_error(2)).context("x");
        assert!(!is_resource_error(&other));
        assert!(!is_resource_error(&anyhow::anyhow!("the engine stalled")));
    }
}
