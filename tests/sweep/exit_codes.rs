//! Exit codes and messages a script can rely on: 2 for bad input (naming the key or option and
//! what is allowed), 75 for a resource error anywhere (naming the path), never a panic on a
//! closed or full stdout, and one line on stderr when a run is stopped by SIGTERM or SIGINT.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::common::BIN;

use crate::common::scratch;

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn said(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// `granflow <args>` in a shell with the file-size limit `blocks` (a write past it fails with
/// EFBIG, a resource error, as a full disk would).
fn limited(blocks: u32, args: &[&str]) -> Output {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    Command::new("sh")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f {blocks}; exec {BIN} {}",
            quoted.join(" ")
        ))
        .output()
        .unwrap()
}

const SMALL: &str = "engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15), axes: (length_over_width: [1.0, 2.0]), run: (collisions_per_particle: 60, snapshot_interval: 20)";

fn sweep_file(dir: &Path, name: &str, body: &str) -> PathBuf {
    let file = dir.join(name);
    std::fs::write(&file, format!("({body})")).unwrap();
    file
}

#[test]
fn bad_input_exits_2_naming_the_key() {
    let dir = scratch("bad-input");
    let long = "a".repeat(5000);
    let cases: Vec<(String, &str)> = vec![
        (format!("name: \"two\\nlines\", {SMALL}"), "name"),
        (format!("name: \"a b\", {SMALL}"), "does not belong in a directory name"),
        (format!("name: \"{long}\", {SMALL}"), "allowed 1 to 100"),
        (format!("seeds: [-1], {SMALL}"), "seed -1 is out of range"),
        (
            SMALL.replace("volume_fraction: 0.15", "volume_fraction: [0.15]"),
            "a list where one value belongs",
        ),
        (
            "engine: \"lga\", fixed: (length: 40, width: 5, density: 1.0), run: (steps: 100, snapshot_interval: 2.5)".into(),
            "not a whole number of steps",
        ),
    ];
    for (i, (body, wanted)) in cases.iter().enumerate() {
        let file = sweep_file(&dir, &format!("c{i}.ron"), body);
        let out = granflow(&["plan", file.to_str().unwrap()]);
        let text = said(&out);
        assert_eq!(out.status.code(), Some(2), "case {i}: {text}");
        assert!(
            text.contains(wanted),
            "case {i}: `{wanted}` not said: {text}"
        );
        assert!(!text.contains("untagged enum"), "case {i}: {text}");
        assert!(
            !text.contains("Integer is out of bounds"),
            "case {i}: {text}"
        );
    }

    // a --set value is blamed on the option, not on a line of the file
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let f = file.to_str().unwrap();
    let out = granflow(&["plan", f, "--set", "snapshot_interval=1000"]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(
        text.contains("--set snapshot_interval=1000"),
        "not blamed on the option: {text}"
    );
    assert!(!text.contains("ok.ron:"), "blamed on the file: {text}");

    // an empty job range selects nothing: an error, not a silent success
    let results = dir.join("results");
    let out = granflow(&[
        "run",
        f,
        "--results",
        results.to_str().unwrap(),
        "--job-range",
        "1:1",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", said(&out));
    assert!(said(&out).contains("--job-range 1:1"), "{}", said(&out));
}

/// `granflow <args>` with stdout on /dev/full (every write fails with ENOSPC).
fn to_full_stdout(args: &[&str]) -> Output {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    Command::new(BIN)
        .args(args)
        .stdout(Stdio::from(full))
        .output()
        .unwrap()
}

/// Every subcommand, `--help`, `--version` and `completions` included, exits 75 when
/// its stdout is full, saying so, and never panics (completions panicked with exit 101,
/// `--help` exited 0 with its text lost). `run` first finishes its jobs: its results are on
/// disk whatever happens to its output.
#[test]
fn a_full_stdout_is_an_error_not_a_panic() {
    let dir = scratch("stdout");
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let (f, results) = (file.to_str().unwrap(), dir.join("results"));
    let r = results.to_str().unwrap();
    let out = to_full_stdout(&["run", f, "--results", r, "--threads", "1"]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(75), "run: {text}");
    assert!(text.contains("standard output"), "run: {text}");
    let tables = results.join("ok");
    let t = tables.to_str().unwrap();
    assert!(tables.join("jobs.parquet").exists(), "run: {text}");
    // every subcommand clap knows, so that a new one is covered too
    let command = <granflow::cli::Cli as clap::CommandFactory>::command();
    let subcommands: Vec<String> = command
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .filter(|name| name != "help")
        .collect();
    assert!(subcommands.len() >= 14, "{subcommands:?}");
    let mut cases: Vec<Vec<&str>> = vec![vec!["--help"], vec!["--version"]];
    cases.extend(subcommands.iter().map(|c| vec![c.as_str(), "--help"]));
    cases.extend([
        vec!["completions", "bash"],
        vec!["engines"],
        vec!["engines", "--markdown"],
        vec!["plan", f, "--results", r],
        vec!["status", t],
        vec!["gather", t],
        vec!["phase-diagram", t, "--x", "length_over_width"],
        vec!["plot", t, "--x", "length_over_width", "--y", "humps"],
        vec!["report", t],
        vec!["slurm", "submit", f, "--results", r, "--dry-run"],
        vec![
            "sim",
            "--length-over-width",
            "1",
            "--width-over-diameter",
            "4",
            "--height-over-diameter",
            "4",
            "--volume-fraction",
            "0.15",
            "--collisions-per-particle",
            "20",
        ],
        vec!["bench", "--workload", "lga-fig2"],
    ]);
    for args in &cases {
        let out = to_full_stdout(args);
        let text = said(&out);
        assert_eq!(out.status.code(), Some(75), "{args:?}: {text}");
        assert!(!text.contains("panicked"), "{args:?}: {text}");
        assert!(text.contains("standard output"), "{args:?}: {text}");
    }
    // the closed pipe of `granflow ... | head` is no error
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "{BIN} completions bash | head -c 10 >/dev/null; {BIN} --help | head -c 10"
        ))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", said(&out));
    assert!(!said(&out).contains("panicked"), "{}", said(&out));
}

/// A resource error while writing the resolved sweep, the tables or the phase diagram exits
/// 75 and names the file.
#[test]
fn resource_errors_anywhere_exit_75_with_the_path() {
    let dir = scratch("resource");
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let (f, results) = (file.to_str().unwrap(), dir.join("results"));
    let r = results.to_str().unwrap();

    // nothing may be written: the first write (the resolved sweep) fails
    let out = limited(0, &["run", f, "--results", r, "--threads", "1"]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(75), "{text}");
    assert!(text.contains("sweep.ron"), "{text}");
    assert!(text.contains("file size limit"), "{text}");

    // the jobs run; then the tables and the diagram do not fit
    let out = granflow(&["run", f, "--results", r, "--threads", "1"]);
    assert!(out.status.success(), "{}", said(&out));
    let tables = results.join("ok");
    let out = limited(1, &["gather", tables.to_str().unwrap()]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(75), "{text}");
    assert!(text.contains(".parquet"), "{text}");
    assert!(!text.contains("transport error"), "{text}");
    let out = limited(
        1,
        &[
            "phase-diagram",
            tables.to_str().unwrap(),
            "--x",
            "length_over_width",
        ],
    );
    let text = said(&out);
    assert_eq!(out.status.code(), Some(75), "{text}");
    assert!(text.contains(".png") || text.contains(".svg"), "{text}");
}

/// Mount a tmpfs of `size` at `mount` (created); false where this machine does not let a test
/// mount one (it needs root in a container that allows it).
fn mount_tmpfs(mount: &Path, size: &str) -> bool {
    std::fs::create_dir_all(mount).unwrap();
    Command::new("mount")
        .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
        .arg(mount)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Where this machine lets a test mount a tiny tmpfs (root in a container that allows it), a
/// really full disk: "no space left" and the path, exit 75.
#[test]
fn a_really_full_disk_says_no_space_left() {
    let dir = scratch("tmpfs");
    let mount = dir.join("tiny");
    if !mount_tmpfs(&mount, "48k") {
        eprintln!("no tmpfs could be mounted here: the file-size limit tests cover exit 75");
        return;
    }
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let out = granflow(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        mount.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    let _ = Command::new("umount").arg(&mount).status();
    let text = said(&out);
    assert_eq!(out.status.code(), Some(75), "{text}");
    assert!(text.to_lowercase().contains("no space left"), "{text}");
    assert!(text.contains(mount.to_str().unwrap()), "no path: {text}");
}

/// SIGTERM and SIGINT end a run with one line that says how to resume, and leave the job
/// resumable from its checkpoint (resuming itself is what the kill -9 tests check).
#[test]
fn a_stopped_run_says_how_to_resume() {
    let dir = scratch("signal");
    let file = sweep_file(
        &dir,
        "long.ron",
        "engine: \"lga\", fixed: (length: 220, width: 11, density: 1.0, dissipation: 0.5), run: (steps: 40000000, snapshot_interval: 1000)",
    );
    let results = dir.join("results");
    let args = [
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--threads",
        "1",
    ];
    for (signal, name) in [(libc_sigterm(), "SIGTERM"), (libc_sigint(), "SIGINT")] {
        let _ = std::fs::remove_dir_all(&results);
        let child = Command::new(BIN)
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(700));
        Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        let out = child.wait_with_output().unwrap();
        let text = said(&out);
        assert!(!out.status.success(), "{name}: not stopped: {text}");
        assert!(
            text.contains(&format!("stopped by signal {name}")),
            "{name}: {text}"
        );
        assert!(text.contains("resume with:"), "{name}: {text}");
        // What it says is true (a job was running, none was done), and the
        // running job's own log says it was stopped
        assert!(text.contains("the running job resumes"), "{name}: {text}");
        assert!(!text.contains("kept"), "{name}: {text}");
        let status = granflow(&["status", results.join("long").to_str().unwrap()]);
        let text = said(&status);
        assert!(status.status.success(), "{name}: {text}");
        assert!(text.contains("partial 1"), "{name}: {text}");
        let jobs = results.join("long").join("jobs");
        let job = std::fs::read_dir(&jobs)
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
            .path();
        let log = std::fs::read_to_string(job.join("log.txt")).unwrap();
        let last = log.lines().last().unwrap_or_default();
        assert!(
            last.ends_with(&format!(
                "stopped by signal {name}; resumes from its last checkpoint"
            )),
            "{name}: {log}"
        );
    }
}

fn libc_sigterm() -> i32 {
    15
}

fn libc_sigint() -> i32 {
    2
}

/// `granflow <args>` with its address space capped at `kb` kB (`ulimit -v`: an allocation
/// past it fails), with the CPU seconds it used (wait4 on this child alone: other tests'
/// children run at the same time). The child's peak RSS is not used: a forked child counts the
/// test process's own pages until it execs.
fn measured(kb: u32, args: &[&str]) -> (Output, f64) {
    use std::io::Read;
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kb}; exec {BIN} {}", quoted.join(" ")))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (mut stdout, mut stderr) = (Vec::new(), Vec::new());
    let mut err_pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut buf = Vec::new();
        err_pipe.read_to_end(&mut buf).unwrap();
        buf
    });
    child
        .stdout
        .take()
        .unwrap()
        .read_to_end(&mut stdout)
        .unwrap();
    stderr.extend(reader.join().unwrap());
    let mut status = 0;
    // SAFETY: an all-zero rusage is valid; wait4 fills it for this child
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32);
    let cpu = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    let output = Output {
        status: std::os::unix::process::ExitStatusExt::from_raw(status),
        stdout,
        stderr,
    };
    (output, cpu(usage.ru_utime) + cpu(usage.ru_stime))
}

/// Three 1000-value ranges make 10^9 jobs; such a grid is refused before it is
/// expanded (it used to grow to gigabytes without a word), by `plan` and by `run`, naming each
/// axis, the product and the limit. The bounds (1 CPU second, 100 MB of address space) are the
/// issue's: a refusal costs milliseconds and the binary's own pages, expanding ~4 kB per job.
#[test]
fn a_grid_of_a_billion_jobs_is_refused_at_once() {
    let dir = scratch("billion");
    let file = sweep_file(
        &dir,
        "huge.ron",
        "engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0), \
         axes: (length_over_width: linspace(1, 2, 1000), restitution: linspace(0.1, 0.9, 1000), \
         volume_fraction: linspace(0.01, 0.2, 1000)), run: (collisions_per_particle: 60, snapshot_interval: 20)",
    );
    let results = dir.join("results");
    for command in ["plan", "run"] {
        let (out, cpu) = measured(
            100_000,
            &[
                command,
                file.to_str().unwrap(),
                "--results",
                results.to_str().unwrap(),
            ],
        );
        let text = said(&out);
        assert_eq!(out.status.code(), Some(2), "{command}: {text}");
        for wanted in [
            "1 000 x 1 000 x 1 000",
            "length_over_width x volume_fraction x restitution",
            "1 000 000 000 jobs",
            "at most 100 000 jobs",
        ] {
            assert!(
                text.contains(wanted),
                "{command}: `{wanted}` not said: {text}"
            );
        }
        assert!(cpu < 1.0, "{command}: {cpu} CPU s");
        assert!(!results.exists(), "{command} wrote something");
    }
}

/// The longest run of digits in a text (a number a person cannot read is one of hundreds).
fn longest_digit_run(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0)
}

/// Values near the largest double are refused with the key and the source that set
/// them (the file's line, or the --set option) in numbers a person can read; a key given twice
/// by --set is refused naming both; -0 is the same point as 0.
#[test]
fn huge_values_repeated_overrides_and_negative_zero() {
    let dir = scratch("huge");
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let f = file.to_str().unwrap();

    // W/d = 1e308 in the file: blamed on the width (not on the volume fraction that follows
    // from it) with its allowed range; no 309-digit numbers
    let huge = sweep_file(
        &dir,
        "huge.ron",
        &SMALL.replace("width_over_diameter: 4.0", "width_over_diameter: 1e308"),
    );
    let out = granflow(&["plan", huge.to_str().unwrap()]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("huge.ron:"), "{text}");
    assert!(text.contains("1e308"), "{text}");
    assert!(text.contains("key `fixed.width_over_diameter`"), "{text}");
    assert!(text.contains("3 <= W/d <= 1e5"), "{text}");
    assert!(longest_digit_run(&text) <= 20, "{text}");

    // a box that is fine on each side but too large for phi: blamed on phi, with N readable
    let out = granflow(&[
        "plan",
        f,
        "--set",
        "width_over_diameter=1e5",
        "--set",
        "height_over_diameter=1e5",
    ]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(text.contains("allowed N <= 1e9"), "{text}");
    assert!(longest_digit_run(&text) <= 20, "{text}");

    // a run length of 1e308 from --set with the file's interval: too many snapshots, blamed on
    // the option that gave it, not on the file's line of the interval
    let out = granflow(&["plan", f, "--set", "collisions_per_particle=1e308"]);
    let text = said(&out);
    assert_eq!(out.status.code(), Some(2), "{text}");
    assert!(
        text.contains("--set collisions_per_particle=1e308"),
        "{text}"
    );
    assert!(!text.contains("ok.ron:"), "blamed on the file: {text}");
    assert!(text.contains("at most 1e6"), "{text}");
    assert!(longest_digit_run(&text) <= 20, "{text}");

    // the same key twice (or its alternative): refused, naming both
    for (first, second) in [
        ("restitution=0.5", "restitution=0.6"),
        ("volume_fraction=0.1", "particles=20"),
        ("collisions_per_particle=40", "time=3"),
        ("seeds=1,2", "seed=3"),
    ] {
        let out = granflow(&["plan", f, "--set", first, "--set", second]);
        let text = said(&out);
        assert_eq!(out.status.code(), Some(2), "{first} {second}: {text}");
        assert!(text.contains(&format!("--set {second}")), "{text}");
        assert!(
            text.contains(&format!("already set by --set {first}")),
            "{text}"
        );
    }

    // -0 is 0: the same job ids, shown as 0, with --set and in the file
    let ids = |args: &[&str]| -> Vec<String> {
        let out = granflow(args);
        assert!(out.status.success(), "{args:?}: {}", said(&out));
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                (w.len() > 2 && w[0].parse::<usize>().is_ok()).then(|| w[1].to_string())
            })
            .collect()
    };
    let zero = ids(&["plan", f, "--set", "restitution=0"]);
    assert_eq!(zero.len(), 2);
    assert_eq!(ids(&["plan", f, "--set", "restitution=-0"]), zero);
    let negative = sweep_file(
        &dir,
        "negative.ron",
        &SMALL.replace(
            "volume_fraction: 0.15",
            "volume_fraction: 0.15, restitution: -0.0",
        ),
    );
    assert_eq!(ids(&["plan", negative.to_str().unwrap()]), zero);
    let both = sweep_file(
        &dir,
        "both.ron",
        &SMALL.replace("axes: (", "axes: (restitution: [0.0, -0.0], "),
    );
    let out = granflow(&["plan", both.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", said(&out));
    assert!(said(&out).contains("duplicate value"), "{}", said(&out));
}

/// A read-only results directory is a resource error (exit 75, naming the path and
/// "read-only") for every command that must write there (run, gather, report); `status` only
/// reads and reports it as it is. Where this machine lets a test mount a tmpfs read-only.
#[test]
fn a_read_only_results_directory_exits_75_everywhere() {
    let dir = scratch("read-only");
    let mount = dir.join("ro");
    if !mount_tmpfs(&mount, "16m") {
        eprintln!("no tmpfs could be mounted here: the read-only case is not tested");
        return;
    }
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let (f, m) = (file.to_str().unwrap(), mount.to_str().unwrap());
    let ran = granflow(&["run", f, "--results", m, "--threads", "1"]);
    let read_only = Command::new("mount")
        .args(["-o", "remount,ro", m])
        .status()
        .is_ok_and(|s| s.success());
    let tables = mount.join("ok");
    let t = tables.to_str().unwrap();
    let outs: Vec<(&str, Output)> = if ran.status.success() && read_only {
        vec![
            (
                "run",
                granflow(&["run", f, "--results", m, "--threads", "1"]),
            ),
            ("gather", granflow(&["gather", t])),
            ("report", granflow(&["report", t])),
            ("status", granflow(&["status", t])),
        ]
    } else {
        Vec::new()
    };
    let _ = Command::new("umount").arg(m).status();
    assert!(ran.status.success(), "{}", said(&ran));
    assert!(read_only, "remount read-only failed");
    for (command, out) in &outs {
        let text = said(out);
        if *command == "status" {
            assert!(out.status.success(), "status: {text}");
            assert!(text.contains("done 2"), "status: {text}");
        } else {
            assert_eq!(out.status.code(), Some(75), "{command}: {text}");
            assert!(text.contains("read-only"), "{command}: {text}");
            assert!(text.contains(m), "{command}: no path: {text}");
        }
    }
}

/// The sweep line counts jobs with a result, never a job a resource error stopped
/// (it said "1/2 jobs done" right after the only running job was stopped). Every `sweep`
/// line's count equals the `done` lines before it.
#[test]
fn the_sweep_line_after_a_stop_counts_only_done_jobs() {
    let dir = scratch("sweep-line");
    let file = sweep_file(&dir, "ok.ron", SMALL);
    let f = file.to_str().unwrap();
    let mut stopped = None;
    // a file-size limit that lets the resolved sweep and the parameters through but stops the
    // first job's checkpoint or record log
    for blocks in 1..=64 {
        let results = dir.join(format!("results-{blocks}"));
        let out = limited(
            blocks,
            &[
                "run",
                f,
                "--results",
                results.to_str().unwrap(),
                "--threads",
                "1",
            ],
        );
        let text = said(&out);
        if text.contains("STOPPED") {
            assert_eq!(out.status.code(), Some(75), "{text}");
            stopped = Some(text);
            break;
        }
    }
    let text = stopped.expect("no file-size limit stopped a job");
    let mut done = 0;
    let mut lines = 0;
    for line in text.lines() {
        if line.starts_with("done    ") {
            done += 1;
        }
        if let Some(rest) = line.strip_prefix("sweep   ok: ") {
            let counted: usize = rest.split('/').next().unwrap().parse().unwrap();
            assert_eq!(counted, done, "{line}\n{text}");
            lines += 1;
        }
    }
    assert!(lines > 0, "no sweep line: {text}");
}
