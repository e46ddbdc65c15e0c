//! The researcher's side of the command line: selection by parameter (`--where`)
//! for run, plan, status and gather; `status --json`; a phase diagram refuses an axis that
//! does not vary; ranges (`linspace`, `logspace`, `range`) in sweep files and `--set`;
//! examples in every subcommand's help; shell completions.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use crate::common::BIN;

use crate::common::scratch;

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// The rows of `granflow bench --json <args>` (which must succeed).
fn bench_rows(args: &[&str]) -> Vec<serde_json::Value> {
    let out = common::granflow_ok(&[&["bench", "--json"], args].concat());
    serde_json::from_str(&out).unwrap()
}

#[test]
fn where_selects_jobs_and_status_speaks_json() {
    let dir = scratch("where");
    let file = dir.join("w.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0], restitution: [0.7, 0.9]),\n run: (collisions_per_particle: 40, snapshot_interval: 20))",
    )
    .unwrap();
    let results = dir.join("results");
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    let out = granflow(&["run", f, "--results", r, "--where", "restitution=0.9"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // the tables written at the end are the whole sweep's (2 done, 2 pending), not the
    // selection's
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("tables of the whole sweep: 4 jobs, 2 done in"),
        "{stdout}"
    );
    let jobs_table = std::fs::File::open(results.join("w").join("jobs.parquet")).unwrap();
    let jobs_table = {
        use polars::prelude::SerReader;
        // (one plain column: polars here is built without the struct type of the mode lists)
        polars::prelude::ParquetReader::new(jobs_table)
            .with_columns(Some(vec!["job_id".into()]))
            .finish()
            .unwrap()
    };
    assert_eq!(jobs_table.height(), 4);
    let out = granflow(&["status", f, "--results", r, "--json"]);
    assert!(out.status.success());
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(status["counts"]["done"], 2);
    assert_eq!(status["counts"]["pending"], 2);
    for job in status["jobs"].as_array().unwrap() {
        let e = job["params"]["restitution"].as_f64().unwrap();
        assert_eq!(job["state"] == "done", e == 0.9, "{job}");
        if e == 0.9 {
            assert_eq!(job["progress"].as_f64(), Some(40.0));
            assert!(job["label"].is_string());
        }
    }
    // several conditions must all hold; comparisons
    let out = granflow(&[
        "status",
        f,
        "--results",
        r,
        "--json",
        "--where",
        "length_over_width>=2",
        "--where",
        "restitution!=0.7",
    ]);
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let jobs = status["jobs"].as_array().unwrap();
    assert_eq!(jobs.len(), 1);
    assert_eq!(jobs[0]["params"]["length_over_width"], 2.0);
    // plan shows the selection; a bad condition is bad input
    let out = granflow(&["plan", f, "--results", r, "--where", "restitution<0.8"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("2 jobs"));
    for bad in ["no_such=1", "restitution", "restitution>=high"] {
        let out = granflow(&["status", f, "--results", r, "--where", bad]);
        assert_eq!(out.status.code(), Some(2), "--where {bad}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--where"),
            "--where {bad}"
        );
    }
    let out = granflow(&["run", f, "--results", r, "--where", "restitution=0.5"]);
    assert_eq!(out.status.code(), Some(2));
    // the text status names each job by its swept parameters
    let out = granflow(&["status", f, "--results", r]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("L/W=2 e=0.9"), "{text}");
    // a phase diagram over a parameter that does not vary is refused
    let out = granflow(&["phase-diagram", f, "--results", r, "--x", "roughness"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not vary"));
    // `gather --where` writes the selection's tables apart and leaves the sweep's
    // own jobs.parquet whole (it used to overwrite it with the selected rows alone)
    let out = granflow(&["gather", f, "--results", r, "--where", "restitution=0.9"]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{said}");
    let rows = |path: &Path| {
        use polars::prelude::SerReader;
        polars::prelude::ParquetReader::new(std::fs::File::open(path).unwrap())
            .with_columns(Some(vec!["job_id".into()]))
            .finish()
            .unwrap()
            .height()
    };
    let selection = results
        .join("w")
        .join("where")
        .join("restitution=0.9")
        .join("jobs.parquet");
    assert!(said.contains("where/restitution=0.9"), "{said}");
    assert_eq!(rows(&results.join("w").join("jobs.parquet")), 4);
    assert_eq!(rows(&selection), 2);
    // a plot of a column without errors: no error column of NaN, no Knudsen-minimum wording
    let out = granflow(&[
        "plot",
        f,
        "--results",
        r,
        "--x",
        "length_over_width",
        "--y",
        "slip_velocity",
        "--where",
        "restitution=0.9",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("slip_velocity  jobs"), "{text}");
    for unwanted in ["NaN", "error", "interior minimum"] {
        assert!(!text.contains(unwanted), "`{unwanted}` in {text}");
    }
}

/// A run without a terminal (piped, as in a Slurm log) prints a plain progress line per
/// running job at a fixed wall-clock interval, naming the job by its parameters.
#[test]
fn a_piped_run_prints_progress_lines() {
    let dir = scratch("progress");
    let file = dir.join("p.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 6.0, height_over_diameter: 6.0, volume_fraction: 0.15),\n axes: (length_over_width: [2.0]), run: (collisions_per_particle: 3000, snapshot_interval: 50))",
    )
    .unwrap();
    let results = dir.join("results");
    let out = Command::new(BIN)
        .args([
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ])
        .env("GRANFLOW_PROGRESS_SECONDS", "0")
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("running ")).collect();
    assert!(lines.len() >= 10, "{text}");
    assert!(
        lines[0].contains("/3000 cpp") && lines[0].contains("ETA"),
        "{}",
        lines[0]
    );
}

/// `granflow bench --json` keeps its keys (users' scripts read them), for every kind of
/// workload; numbers are measured (positive), not checked for speed.
#[test]
fn bench_json_keeps_its_keys() {
    let rows = bench_rows(&["--workload", "dsmc-kn1-6000-sampled", "--moves", "2e6"]);
    assert_eq!(rows.len(), 1);
    let row = rows[0].as_object().unwrap();
    for key in [
        "workload",
        "n",
        "phi",
        "collisions_per_s",
        "events_per_s",
        "bytes_per_particle",
        "moves_per_s",
    ] {
        assert!(row.contains_key(key), "bench --json lacks `{key}`: {row:?}");
    }
    assert_eq!(row["n"], 6000);
    assert!(row["moves_per_s"].as_f64().unwrap() > 0.0);
    let rows = bench_rows(&["--workload", "lga-fig2", "--site-updates", "1e6"]);
    assert!(rows[0]["site_updates_per_s"].as_f64().unwrap() > 0.0);
    assert!(rows[0]["phi"].as_f64().is_some());
}

/// A workload whose name is part of another's (`channel-ch4-dense-N19600`, and the same from
/// the thermalised start, `...-steady`): the text selects both, each measured once in a
/// process of its own, and the whole name selects that one alone (the processes of their own
/// are started with it: a selection by part of the name there would start them again and
/// again).
#[test]
fn bench_selects_a_workload_whose_name_is_part_of_another() {
    let rows = |workload: &str| -> Vec<String> {
        bench_rows(&[
            "--workload",
            workload,
            "--collisions-per-particle",
            "0.5",
            "--channel-warmup",
            "0.5",
        ])
        .iter()
        .map(|r| r["workload"].as_str().unwrap().to_string())
        .collect()
    };
    assert_eq!(
        rows("channel-ch4-dense"),
        [
            "channel-ch4-dense-N19600",
            "channel-ch4-dense-N19600-steady"
        ]
    );
    assert_eq!(
        rows("channel-ch4-dense-N19600"),
        ["channel-ch4-dense-N19600"]
    );
}

/// `bench --from-job` times a job's saved state with the same JSON keys, for each search;
/// a job without a checkpoint is refused with the directory named.
#[test]
fn bench_from_job_times_a_saved_state() {
    let dir = scratch("bench-from-job");
    let file = dir.join("b.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (length_over_width: 2.0, width_over_diameter: 6.0, height_over_diameter: 6.0, volume_fraction: 0.3),\n run: (collisions_per_particle: 40, snapshot_interval: 20))",
    )
    .unwrap();
    let results = dir.join("results");
    common::granflow_ok(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ]);
    let jobs = results.join("b").join("jobs");
    let job = std::fs::read_dir(&jobs)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let n = serde_json::from_str::<serde_json::Value>(
        &std::fs::read_to_string(job.join("params.json")).unwrap(),
    )
    .unwrap()["params"]["values"]["particles"]
        .as_f64()
        .unwrap();
    for search in ["auto", "cells", "lists"] {
        let rows = bench_rows(&[
            "--from-job",
            job.to_str().unwrap(),
            "--search",
            search,
            "--collisions-per-particle",
            "5",
        ]);
        let row = rows[0].as_object().unwrap();
        for key in [
            "workload",
            "n",
            "phi",
            "collisions_per_s",
            "events_per_s",
            "bytes_per_particle",
        ] {
            assert!(row.contains_key(key), "{key}: {row:?}");
        }
        assert_eq!(row["n"].as_f64(), Some(n));
        assert!(row["collisions_per_s"].as_f64().unwrap() > 0.0);
    }
    let empty = dir.join("no-job");
    std::fs::create_dir_all(&empty).unwrap();
    let out = granflow(&["bench", "--from-job", empty.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no-job"));
}

/// Ranges: an axis written as `linspace`/`logspace`/`range`, in the file or
/// with `--set`, gives the same jobs (same ids, same order) as its values written as a list;
/// the resolved sweep keeps the values as a list.
#[test]
fn ranges_give_the_same_jobs_as_the_values_written_out() {
    use granflow::sweep::{load_sweep, spec};
    let dir = scratch("ranges");
    let sweep = |name: &str, engine_and_fixed: &str, run: &str, axes: &str| {
        let file = dir.join(format!("{name}.ron"));
        std::fs::write(
            &file,
            format!(
                "({engine_and_fixed},\n axes: ({axes}),\n run: ({run}, snapshot_interval: 20))"
            ),
        )
        .unwrap();
        file
    };
    let edmd = "engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15)";
    let edmd_n = "engine: \"edmd\", fixed: (length_over_width: 2.0, width_over_diameter: 4.0, height_over_diameter: 4.0)";
    let dsmc = "engine: \"dsmc\", fixed: (forcing: 0.5)";
    let ids = |file: &Path, overrides: &[&str]| -> Vec<String> {
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let sweep = load_sweep(file, &overrides).unwrap_or_else(|e| panic!("{e}"));
        sweep.plan.iter().map(|j| j.id.to_string()).collect()
    };
    let cpp = "collisions_per_particle: 40";
    let pairs = [
        (
            edmd,
            cpp,
            "restitution: linspace(0.5, 0.9, 5), length_over_width: range(1, 2, 0.5)",
            "restitution: [0.5, 0.6, 0.7, 0.8, 0.9], length_over_width: [1.0, 1.5, 2.0]",
        ),
        (
            edmd_n,
            cpp,
            "roughness: range(-0.2, 0.2, 0.1), particles: range(10, 16, 3)",
            "roughness: [-0.2, -0.1, 0.0, 0.1, 0.2], particles: [10, 13, 16]",
        ),
        (
            dsmc,
            "time: 40",
            "knudsen_number: logspace(0.01, 10, 4), restitution: linspace(1, 0.7, 4)",
            "knudsen_number: [0.01, 0.1, 1.0, 10.0], restitution: [1.0, 0.9, 0.8, 0.7]",
        ),
    ];
    for (i, (head, run, ranges, lists)) in pairs.into_iter().enumerate() {
        let (a, b) = (
            sweep(&format!("ranges{i}"), head, run, ranges),
            sweep(&format!("lists{i}"), head, run, lists),
        );
        let expected = ids(&b, &[]);
        assert!(expected.len() >= 12);
        assert_eq!(ids(&a, &[]), expected, "{ranges}");
        // the resolved sweep writes the values as a list, which reads back the same
        let resolved = load_sweep(&a, &[]).unwrap().spec;
        let text = ron::ser::to_string(&resolved).unwrap();
        assert!(
            !text.contains("space(") && !text.contains("range("),
            "{text}"
        );
        let reread = spec::parse(Path::new("resolved.ron"), &text).unwrap();
        assert_eq!(reread.axes, resolved.axes);
    }
    // --set takes the same ranges
    let file = sweep("set", edmd, cpp, "length_over_width: [1.0]");
    assert_eq!(
        ids(
            &file,
            &[
                "restitution=linspace(0.5,0.9,5)",
                "length_over_width=range(1, 2, 0.5)"
            ]
        ),
        ids(&dir.join("lists0.ron"), &[])
    );
}

/// A bad range is bad input (exit 2) that names the key and says what a range may be.
#[test]
fn bad_ranges_are_refused_naming_the_key() {
    let dir = scratch("bad-ranges");
    let file = dir.join("r.ron");
    let write = |axis: &str| {
        std::fs::write(
            &file,
            format!(
                "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: ({axis}),\n run: (collisions_per_particle: 40, snapshot_interval: 20))"
            ),
        )
        .unwrap();
    };
    let f = file.to_str().unwrap();
    for (axis, expect) in [
        (
            "restitution: linspace(0.5, 0.9, 1)",
            "count must be a whole number >= 2",
        ),
        (
            "restitution: lnspace(0.5, 0.9, 5)",
            "did you mean `linspace`?",
        ),
        ("restitution: logspace(0, 0.9, 5)", "must be > 0"),
        ("restitution: range(0.9, 0.5, 0.1)", "does not lead from"),
        (
            "restitution: linspace(0.5, 1.5, 3)",
            "out of range: allowed [0, 1]",
        ),
        (
            "restitution: 0.5",
            "an axis is a list [v1, v2, ...] or a range",
        ),
    ] {
        write(axis);
        let out = granflow(&["plan", f, "--results", dir.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{axis}: {err}");
        assert!(
            err.contains("restitution") && err.contains(expect),
            "{axis}: {err}"
        );
        assert!(
            err.contains("r.ron:2:"),
            "{axis}: the error is placed: {err}"
        );
    }
    write("restitution: [0.7]");
    for (set, expect) in [
        (
            "restitution=linspace(0.5,0.9)",
            "expected linspace(start, stop, count)",
        ),
        ("restitution=range(1,2,0)", "step must not be 0"),
        ("restitution=linspace(0.5,0.9,x)", "`x` is not a number"),
        ("seeds=linspace(1,2,3)", "is not a seed"),
        (
            "collisions_per_particle=range(10,20,5)",
            "takes exactly one value",
        ),
    ] {
        let out = granflow(&["plan", f, "--results", dir.to_str().unwrap(), "--set", set]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{set}: {err}");
        let key = set.split('=').next().unwrap();
        assert!(
            err.contains(&format!("key `{key}`")) && err.contains(expect),
            "{set}: {err}"
        );
    }
    // sim runs one simulation: a range there is refused before anything runs
    let out = granflow(&["sim", "--set", "restitution=linspace(0.5,0.9,5)"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("granflow run"));
}

/// Every subcommand's --help (`granflow slurm submit` and `slurm status` too) ends with
/// examples that run that very subcommand. The list of subcommands comes
/// from the command definitions, so a new subcommand without examples fails here.
#[test]
fn every_subcommand_help_shows_examples() {
    use clap::CommandFactory;
    fn paths(command: &clap::Command, prefix: &[String], out: &mut Vec<Vec<String>>) {
        for sub in command.get_subcommands() {
            let mut path = prefix.to_vec();
            path.push(sub.get_name().to_string());
            out.push(path.clone());
            paths(sub, &path, out);
        }
    }
    let mut all = Vec::new();
    paths(&granflow::cli::Cli::command(), &[], &mut all);
    assert!(all.len() >= 13, "{all:?}");
    for path in &all {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let out = granflow(&args);
        assert!(out.status.success(), "{args:?}");
        let help = String::from_utf8_lossy(&out.stdout);
        let (_, examples) = help
            .split_once("\nExamples:\n")
            .unwrap_or_else(|| panic!("`granflow {}` has no examples:\n{help}", path.join(" ")));
        let invocation = format!("granflow {}", path.join(" "));
        assert!(
            examples
                .lines()
                .any(|l| l.trim_start().starts_with(&invocation)),
            "the examples of `{invocation}` do not run it:\n{examples}"
        );
    }
}

/// `granflow completions SHELL` prints a completion script that knows the subcommands.
#[test]
fn completions_print_a_script_for_the_shell() {
    let out = granflow(&["completions", "bash"]);
    assert!(out.status.success());
    let script = String::from_utf8_lossy(&out.stdout);
    assert!(script.contains("_granflow()") && script.contains("complete -F _granflow"));
    for sub in [
        "sim",
        "engines",
        "bench",
        "run",
        "plan",
        "status",
        "gather",
        "phase-diagram",
        "plot",
        "slurm",
        "submit",
        "completions",
    ] {
        assert!(script.contains(sub), "bash completion lacks `{sub}`");
    }
    assert!(script.contains("--where") && script.contains("--xyz"));
    for (shell, marker) in [
        ("zsh", "#compdef granflow"),
        ("fish", "complete -c granflow"),
    ] {
        let out = granflow(&["completions", shell]);
        assert!(out.status.success());
        let script = String::from_utf8_lossy(&out.stdout);
        assert!(script.contains(marker), "{shell}: {script:.200}");
        assert!(script.contains("phase-diagram"), "{shell}");
    }
    let out = granflow(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("bash"));
}

/// An overnight log (stdout and stderr in a file, no terminal): a line per running job at the
/// progress interval naming its parameters, the sweep's done/total with an ETA, and "done"
/// lines that name the parameters, not only the id.
#[test]
fn overnight_logs_name_parameters_and_the_sweeps_progress() {
    let dir = scratch("overnight");
    let file = dir.join("o.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0]), run: (collisions_per_particle: 2000, snapshot_interval: 20))",
    )
    .unwrap();
    let out = Command::new(BIN)
        .args([
            "run",
            file.to_str().unwrap(),
            "--results",
            dir.join("r").to_str().unwrap(),
            "--threads",
            "1",
        ])
        .env("GRANFLOW_PROGRESS_SECONDS", "0")
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{log}");
    let running = log.lines().find(|l| l.starts_with("running")).expect(&log);
    assert!(
        running.contains("L/W=") && running.contains("ETA"),
        "{running}"
    );
    for l in log.lines().filter(|l| l.starts_with("done")) {
        assert!(l.contains("L/W="), "a done line without parameters: {l}");
    }
    assert!(
        log.lines()
            .any(|l| l.starts_with("sweep   o: 1/2 jobs done") && l.contains("ETA")),
        "{log}"
    );
}

/// `plan` calibrates its estimate on the sweep's own finished jobs: before any job has run it
/// says it uses the engine's typical rate, after one has finished the measured one; a run
/// until steady shows its work as a range (its last milestone to its cap).
#[test]
fn plan_estimates_from_what_the_sweep_measured() {
    let dir = scratch("plan-estimate");
    let file = dir.join("p.ron");
    std::fs::write(
        &file,
        "(engine: \"edmd\", fixed: (width_over_diameter: 4.0, height_over_diameter: 4.0, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0]), run: (collisions_per_particle: 400, snapshot_interval: 20, milestones: [100], until_steady: (window: 100)))",
    )
    .unwrap();
    let (f, r) = (file.to_str().unwrap(), dir.join("r"));
    let r = r.to_str().unwrap();
    let plan = |threads: &str| {
        let out = granflow(&["plan", f, "--results", r, "--threads", threads]);
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let before = plan("2");
    assert!(before.contains("typical"), "{before}");
    assert!(
        before.contains(" to "),
        "no range for a run until steady: {before}"
    );
    let out = granflow(&[
        "run",
        f,
        "--results",
        r,
        "--job-range",
        "0:1",
        "--threads",
        "1",
    ]);
    assert!(out.status.success());
    let after = plan("2");
    assert!(after.contains("measured on 1 finished jobs"), "{after}");
}

/// `granflow --version` names the commit the binary was built from (the stamp every result
/// carries): in a git checkout, HEAD's short hash (with `-dirty` for uncommitted edits).
/// A stale stamp, from a build script that did not rerun, names another commit.
#[test]
fn version_names_the_commit_built() {
    let head = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    let Ok(head) = head else {
        eprintln!("git is not available: nothing to compare with");
        return;
    };
    if !head.status.success() {
        eprintln!("not a git checkout: nothing to compare with");
        return;
    }
    let head = String::from_utf8_lossy(&head.stdout).trim().to_string();
    let out = Command::new(BIN).arg("--version").output().unwrap();
    assert!(out.status.success());
    let version = String::from_utf8_lossy(&out.stdout);
    assert!(
        version.starts_with(&format!("granflow {} ({head}", env!("CARGO_PKG_VERSION"))),
        "{version} does not name HEAD {head}"
    );
}

/// `granflow engines` (without --markdown) lists every parameter with its symbol,
/// unit, default and allowed values, as README says.
#[test]
fn engines_lists_unit_default_and_range() {
    use granflow::engine::declare::ParamDefault;
    let out = granflow(&["engines"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("key") && text.contains("unit") && text.contains("default"));
    for engine in granflow::registry::engines() {
        for d in engine.params {
            let default = match d.default {
                ParamDefault::Required => "required".to_string(),
                ParamDefault::Derived => "derived".to_string(),
                ParamDefault::Number(v) => format!("{v}"),
                ParamDefault::Text(s) => format!("\"{s}\""),
            };
            let section = text
                .split(&format!("\n{}: ", engine.name))
                .nth(1)
                .or_else(|| text.strip_prefix(&format!("{}: ", engine.name)))
                .unwrap_or_else(|| panic!("{} not listed", engine.name));
            let line = section
                .lines()
                .take_while(|l| l.starts_with(' ') || !l.contains(": "))
                .find(|l| l.split_whitespace().next() == Some(d.name))
                .unwrap_or_else(|| panic!("{}: {} not listed", engine.name, d.name));
            // name, symbol, unit, default in this order, then the allowed values
            let mut at = line.find(d.name).unwrap() + d.name.len();
            for part in [d.symbol, d.unit, default.as_str()] {
                let found = line[at..].find(&format!(" {part} ")).unwrap_or_else(|| {
                    panic!("{}: `{part}` not in its place: {line}", engine.name)
                });
                at += found + part.len() + 1;
            }
            assert!(line.ends_with(d.allowed), "{line}");
        }
    }
}
