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

#[test]
fn a_full_stdout_is_an_error_not_a_panic() {
    let dir = scratch("stdout");
    let file = sweep_file(&dir, "ok.ron", SMALL);
    for args in [
        vec!["plan", file.to_str().unwrap()],
        vec!["engines"],
        vec![
            "status",
            file.to_str().unwrap(),
            "--results",
            dir.to_str().unwrap(),
        ],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = Command::new(BIN)
            .args(&args)
            .stdout(Stdio::from(full))
            .output()
            .unwrap();
        let text = said(&out);
        assert_eq!(out.status.code(), Some(75), "{args:?}: {text}");
        assert!(!text.contains("panicked"), "{args:?}: {text}");
        assert!(text.contains("standard output"), "{args:?}: {text}");
    }
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

/// Where this machine lets a test mount a tiny tmpfs (root in a container that allows it), a
/// really full disk: "no space left" and the path, exit 75.
#[test]
fn a_really_full_disk_says_no_space_left() {
    let dir = scratch("tmpfs");
    let mount = dir.join("tiny");
    std::fs::create_dir_all(&mount).unwrap();
    let mounted = Command::new("mount")
        .args([
            "-t",
            "tmpfs",
            "-o",
            "size=48k",
            "tmpfs",
            mount.to_str().unwrap(),
        ])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
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
        let status = granflow(&["status", results.join("long").to_str().unwrap()]);
        let text = said(&status);
        assert!(status.status.success(), "{name}: {text}");
        assert!(text.contains("partial 1"), "{name}: {text}");
    }
}

fn libc_sigterm() -> i32 {
    15
}

fn libc_sigint() -> i32 {
    2
}
