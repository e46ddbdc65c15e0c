//! Standard output of the commands that report (status, plan, engines, ...): written without
//! a panic when stdout is closed or full. A full stdout (`status > /dev/full`, a full disk
//! under a redirected report) ends the command with the resource exit code and says so; a
//! closed pipe ends it quietly, as the Unix default would (`granflow status | head`). `run`
//! and `slurm` keep running whatever happens to their output (`crate::sweep::say`).

use std::fmt;
use std::io::Write;

/// Write `args` to stdout; on failure end the process (see the module doc).
pub fn write(args: fmt::Arguments) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        end_on(e);
    }
}

/// The end of a command whose stdout failed: exit 0 after a closed pipe (the reader has what
/// it wanted), exit 75 with the reason on a resource error, exit 1 otherwise.
fn end_on(e: std::io::Error) -> ! {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    let resource = e
        .raw_os_error()
        .is_some_and(crate::sweep::fs_error::is_resource_errno);
    let _ = writeln!(
        std::io::stderr(),
        "error: writing to standard output: {e}{}",
        if e.raw_os_error() == Some(libc::ENOSPC) {
            " (no space left where stdout goes)"
        } else {
            ""
        }
    );
    std::process::exit(if resource {
        i32::from(crate::sweep::fs_error::EXIT_RESOURCE)
    } else {
        1
    });
}

/// `println!` to stdout through [`write`].
macro_rules! outln {
    () => { $crate::cli::out::write(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::cli::out::write(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `print!` to stdout through [`write`].
macro_rules! out {
    ($($arg:tt)*) => { $crate::cli::out::write(format_args!($($arg)*)) };
}

pub(crate) use {out, outln};
