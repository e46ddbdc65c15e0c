//! Helpers shared by every test: the binary under test, scratch directories, and the kill -9 loop.

use granflow::sweep::{Sweep, store};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
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
/// after a growing delay, until a run ends by itself, and check that every job of `sweep` then
/// has its result; the number of kills (see [`kill_until_exit`]: first delay 150 ms, growing
/// by 97 ms). `hang` is a hang guard, not a speed limit.
pub fn kill_until_done(sweep: &Sweep, results: &Path, args: &[String], hang: Duration) -> u64 {
    let (kills, status) = kill_until_exit(
        args,
        Duration::from_millis(150),
        Duration::from_millis(97),
        hang,
    );
    assert!(status.success(), "the last run failed: {status}");
    let dirs = sweep.results_dir(results);
    let missing: Vec<&str> = sweep
        .plan
        .iter()
        .filter(|j| !dirs.job_dir(&j.id).join(store::RESULT_FILE).exists())
        .map(|j| j.id.0.as_str())
        .collect();
    assert!(
        missing.is_empty(),
        "a run ended by itself ({status}) before every job was done: {missing:?}"
    );
    kills
}

/// Start `granflow <args>` again and again, killing it with SIGKILL after a delay that starts
/// at `first` and grows by `step` a kill for the first 20 kills (kills at many different
/// moments), then doubles, so the loop ends once one run outlasts it however loaded the
/// machine is; the number of kills and the status of the run that ended by itself. `hang` is a
/// hang guard, not a speed limit: the test fails only when a run given `hang` uninterrupted
/// has still not finished.
pub fn kill_until_exit(
    args: &[impl AsRef<std::ffi::OsStr>],
    first: Duration,
    step: Duration,
    hang: Duration,
) -> (u64, ExitStatus) {
    let mut kills = 0u64;
    let mut delay = first;
    loop {
        assert!(
            delay <= 2 * hang,
            "a run given {:?} uninterrupted did not finish (after {kills} kills): a hang?",
            delay / 2
        );
        let mut child = Command::new(BIN)
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let started = Instant::now();
        while started.elapsed() < delay && child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_millis(20));
        }
        if let Some(status) = child.try_wait().unwrap() {
            return (kills, status);
        }
        child.kill().unwrap();
        child.wait().unwrap();
        kills += 1;
        delay = if kills < 20 { delay + step } else { delay * 2 };
    }
}
