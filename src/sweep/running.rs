//! The jobs this process is running now and how many jobs of its sweep are done: what a run
//! stopped by a signal reports, and where it writes its stop line (each running job's
//! `log.txt`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

struct State {
    /// job directories claimed by this process and not yet handed back
    running: BTreeSet<PathBuf>,
    /// jobs of the sweep with a result (before this run and by it)
    done: usize,
    /// whether this process has started a job
    started_any: bool,
}

static STATE: Mutex<State> = Mutex::new(State {
    running: BTreeSet::new(),
    done: 0,
    started_any: false,
});

fn state() -> std::sync::MutexGuard<'static, State> {
    STATE.lock().unwrap_or_else(|p| p.into_inner())
}

/// The sweep has `n` done jobs as the run starts.
pub fn set_done(n: usize) {
    state().done = n;
}

/// One more job has its result.
pub fn add_done() {
    state().done += 1;
}

/// This process claimed the job in `dir` and runs it.
pub fn started(dir: &Path) {
    let mut state = state();
    state.running.insert(dir.to_path_buf());
    state.started_any = true;
}

/// The job in `dir` is no longer this process's (its outcome is written, or it was given up).
pub fn ended(dir: &Path) {
    state().running.remove(dir);
}

/// What a stop finds: the jobs running and the jobs done.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtStop {
    pub running: usize,
    pub done: usize,
    /// whether this process had started a job
    pub started_any: bool,
}

/// Write `event` into the log of every running job (a job whose log cannot be written is
/// skipped: the process is stopping) and say what was running and done. The jobs stay
/// registered, so that a job handed back meanwhile waits for its line.
pub fn log_stop(event: &str) -> AtStop {
    let state = state();
    for dir in &state.running {
        let _ = super::store::log(dir, event);
    }
    AtStop {
        running: state.running.len(),
        done: state.done,
        started_any: state.started_any,
    }
}
