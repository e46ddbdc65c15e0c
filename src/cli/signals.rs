//! A run stopped by SIGTERM or SIGINT says so: one line on stderr (the overnight log), "stopped
//! by signal ...; resume with: <the same command>", then the process ends by that signal as it
//! would have without the handler (exit status 128 + the signal number in a shell). Nothing else
//! needs doing: every job file is written atomically and the claims are locks that die with
//! the process, so the queue is resumable exactly as after a kill -9.

use std::sync::OnceLock;

/// The line the handler writes, formatted before any signal can arrive (the handler itself may
/// only call async-signal-safe functions: write, signal, raise).
static MESSAGE: OnceLock<Vec<u8>> = OnceLock::new();

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
    if let Some(message) = MESSAGE.get() {
        let name: &[u8] = if signal == libc::SIGINT {
            b"granflow: stopped by signal SIGINT"
        } else {
            b"granflow: stopped by signal SIGTERM"
        };
        // SAFETY: write(2), signal(2) and raise(3) are async-signal-safe; the buffers are
        // static and never change after installation
        unsafe {
            libc::write(2, name.as_ptr().cast(), name.len());
            libc::write(2, message.as_ptr().cast(), message.len());
            libc::signal(signal, libc::SIG_DFL);
            libc::raise(signal);
        }
    }
}

/// Install the handlers for SIGTERM and SIGINT for a run started with `args` (the whole
/// command line).
pub fn announce_stops(args: &[String]) {
    let text = format!(
        "; every finished job is kept and the running ones resume from their last checkpoint: \
         resume with: {}\n",
        shell_line(args)
    );
    if MESSAGE.set(text.into_bytes()).is_err() {
        return;
    }
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
}
