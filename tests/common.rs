//! Helpers shared by every test: the binary under test, scratch directories, and the kill -9 loop.

use granflow::sweep::{Sweep, store};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub const BIN: &str = env!("CARGO_BIN_EXE_granflow");

/// An empty directory `<CARGO_TARGET_TMPDIR>/<test>/<name>` for the running test. libtest runs
/// each test on a thread named after its path (`sweep::store::a_copied_log_is_found`), so two
/// tests running side by side in this one program never share a directory, whatever `name`.
pub fn scratch(name: &str) -> PathBuf {
    let test = std::thread::current()
        .name()
        .unwrap_or("main")
        .replace("::", "-");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(test).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Run `granflow <args>` and fail with its stderr unless it succeeds; its stdout.
pub fn granflow_ok(args: &[&str]) -> String {
    let out = Command::new(BIN).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "granflow {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Start `granflow <args>` (a run into `results`) again and again, killing it with SIGKILL
/// after a growing delay, until every job of `sweep` has its result; the number of kills.
pub fn kill_until_done(sweep: &Sweep, results: &Path, args: &[String], limit: Duration) -> u64 {
    let dirs = sweep.results_dir(results);
    let mut kills = 0u64;
    let started = Instant::now();
    while !sweep
        .plan
        .iter()
        .all(|j| dirs.job_dir(&j.id).join(store::RESULT_FILE).exists())
    {
        let mut child = Command::new(BIN)
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(150 + 97 * kills));
        if child.try_wait().unwrap().is_none() {
            child.kill().unwrap();
            kills += 1;
        }
        child.wait().unwrap();
        assert!(started.elapsed() < limit, "no progress after {kills} kills");
    }
    kills
}
