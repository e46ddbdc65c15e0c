//! A run stopped by SIGTERM or SIGINT says so: a line in the log of every job it was running
//! ("stopped by signal SIGTERM; resumes from its last checkpoint"), one line on stderr (the
//! overnight log) saying what was running and what is kept, and the command that resumes it;
//! then the process ends by that signal as it would have without the handler (exit status
//! 128 + the signal number in a shell). Nothing else needs doing: every job file is written
//! atomically and the claims are locks that die with the process, so the queue is resumable
//! exactly as after a kill -9.
//!
//! The handler itself only writes the signal's number into a pipe (async-signal-safe); a
//! thread waiting on the pipe writes the lines and ends the process. A second signal while it
//! does so ends the process at once.

use crate::sweep::running;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// The write end of the pipe the handler signals through (-1 before installation).
static PIPE: AtomicI32 = AtomicI32::new(-1);
/// Set by the first signal: a second one ends the process at once.
static STOPPING: AtomicBool = AtomicBool::new(false);

/// The command line as a shell would take it back: arguments with anything but safe characters
/// in single quotes.
fn shell_line(args: &[String]) -> String {
    args.iter()
        .map(|a| {
            if !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
            {
                a.clone()
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

extern "C" fn on_signal(signal: libc::c_int) {
    // SAFETY: write(2), signal(2) and raise(3) are async-signal-safe; the byte is on the stack
    unsafe {
        if STOPPING.swap(true, Ordering::SeqCst) {
            libc::signal(signal, libc::SIG_DFL);
            libc::raise(signal);
            return;
        }
        let byte = signal as u8;
        libc::write(PIPE.load(Ordering::SeqCst), (&byte as *const u8).cast(), 1);
    }
}

fn signal_name(signal: libc::c_int) -> &'static str {
    if signal == libc::SIGINT {
        "SIGINT"
    } else {
        "SIGTERM"
    }
}

/// The stderr line of a stop: what was running, what is kept, how to go on.
fn stop_message(name: &str, at: running::AtStop, resume: &str) -> String {
    let kept = match at.done {
        0 => String::new(),
        1 => "the 1 done job is kept".to_string(),
        n => format!("the {n} done jobs are kept"),
    };
    let resumed = match at.running {
        0 => String::new(),
        1 => "the running job resumes from its last checkpoint (its log.txt says so)".to_string(),
        n => format!(
            "the {n} running jobs resume from their last checkpoint (each job's log.txt says so)"
        ),
    };
    match (resumed.is_empty(), kept.is_empty()) {
        (true, true) if !at.started_any => format!(
            "granflow: stopped by signal {name} before this run started a job (what earlier \
             runs did is untouched): run again with: {resume}"
        ),
        (true, true) => format!(
            "granflow: stopped by signal {name} while no job was running and none was done: \
             run again with: {resume}"
        ),
        (true, false) => format!(
            "granflow: stopped by signal {name} while no job was running; {kept}: resume with: \
             {resume}"
        ),
        (false, true) => {
            format!("granflow: stopped by signal {name}; {resumed}: resume with: {resume}")
        }
        (false, false) => {
            format!("granflow: stopped by signal {name}; {resumed}, {kept}: resume with: {resume}")
        }
    }
}

/// Wait for a signal on the pipe, write the stop lines, end the process by that signal.
fn wait_and_stop(read: libc::c_int, resume: String) {
    let mut byte = 0u8;
    loop {
        // SAFETY: reading one byte into a byte on the stack
        let n = unsafe { libc::read(read, (&mut byte as *mut u8).cast(), 1) };
        if n == 1 {
            break;
        }
        if n < 0 && std::io::Error::last_os_error().kind() == std::io::ErrorKind::Interrupted {
            continue;
        }
        return;
    }
    let signal = libc::c_int::from(byte);
    let name = signal_name(signal);
    let at = running::log_stop(&format!(
        "stopped by signal {name}; resumes from its last checkpoint"
    ));
    eprintln!("{}", stop_message(name, at, &resume));
    // SAFETY: ending the process by the signal with its default action
    unsafe {
        libc::signal(signal, libc::SIG_DFL);
        libc::raise(signal);
    }
    std::process::exit(128 + signal);
}

/// Install the handlers for SIGTERM and SIGINT for a run started with `args` (the whole
/// command line).
pub fn announce_stops(args: &[String]) {
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: pipe2 fills the two descriptors
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return;
    }
    if PIPE
        .compare_exchange(-1, fds[1], Ordering::SeqCst, Ordering::SeqCst)
        .is_err()
    {
        return;
    }
    let resume = shell_line(args);
    std::thread::spawn(move || wait_and_stop(fds[0], resume));
    // SAFETY: installing a handler that only calls async-signal-safe functions
    unsafe {
        libc::signal(libc::SIGTERM, on_signal as *const () as libc::sighandler_t);
        libc::signal(libc::SIGINT, on_signal as *const () as libc::sighandler_t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_resume_line_quotes_what_a_shell_would_split() {
        let args: Vec<String> = [
            "granflow",
            "run",
            "sweeps/q.ron",
            "--set",
            "e=linspace(0.5, 0.9, 3)",
            "it's",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        assert_eq!(
            shell_line(&args),
            r"granflow run sweeps/q.ron --set 'e=linspace(0.5, 0.9, 3)' 'it'\''s'"
        );
    }

    #[test]
    fn the_stop_line_says_only_what_is_true() {
        let at = |running, done| running::AtStop {
            running,
            done,
            started_any: running > 0 || done > 0,
        };
        let none = stop_message("SIGTERM", at(0, 0), "granflow run x.ron");
        assert!(none.contains("before this run started a job"), "{none}");
        assert!(!none.contains("kept:"), "{none}");
        let idle = stop_message("SIGINT", at(0, 3), "granflow run x.ron");
        assert!(idle.contains("the 3 done jobs are kept"), "{idle}");
        let busy = stop_message("SIGTERM", at(2, 1), "granflow run x.ron");
        assert!(busy.contains("the 2 running jobs resume"), "{busy}");
        assert!(busy.contains("the 1 done job is kept"), "{busy}");
        let fresh = stop_message("SIGTERM", at(1, 0), "granflow run x.ron");
        assert!(!fresh.contains("done"), "{fresh}");
    }
}
