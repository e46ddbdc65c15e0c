//! The engine registry: job ids of the sweeps shipped before it exist are
//! unchanged, files written before it still read (and resume to the same result), EDMD tables
//! keep their columns (under their documented names and types), the parameter tables of docs/parameters.md are
//! the declarations', results/README.md documents every column, and keys are checked against
//! the engine a sweep names.

use granflow::analysis::Analysis;
use granflow::engine::ParamValue;
use granflow::registry;
use granflow::sweep::execute::{self, JobEnd};
use granflow::sweep::{load_sweep, store};
use polars::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::BIN;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

use crate::common::scratch;

fn granflow(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// The DEM sweeps shipped before `wall_damping` existed (they do not set it) keep their job
/// ids: the canonical form with today's DEM table is the one without that parameter, since
/// its default is the convention those jobs ran with. A job that asks for the paper's walls
/// has another id.
#[test]
fn dem_ids_without_wall_damping_are_unchanged() {
    let dem = registry::find("dem").unwrap();
    let before: Vec<_> = dem
        .params
        .iter()
        .filter(|d| d.name != "wall_damping")
        .copied()
        .collect();
    assert_eq!(before.len() + 1, dem.params.len());
    let sweeps = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
    for file in ["dem-small.ron", "dem-wide.ron", "dem-small-stiffness.ron"] {
        let sweep = load_sweep(&sweeps.join(file), &[]).unwrap();
        for job in &sweep.plan {
            assert_eq!(
                job.params.values.get("wall_damping"),
                Some(&ParamValue::Text("pair_rate".into())),
                "{file}"
            );
            let old = granflow::sweep::job::canonical_with(&before, &job.params);
            assert_eq!(
                granflow::sweep::job::id_of_canonical(&old),
                job.id,
                "{file}"
            );
            let mut paper = job.params.clone();
            paper.values.insert(
                "wall_damping".into(),
                ParamValue::Text("pair_restitution".into()),
            );
            assert_ne!(paper.id(), job.id, "{file}");
        }
    }
}

/// Copies of the sweep files shipped at 7062f8f give the ids that binary printed.
#[test]
fn shipped_sweep_ids_are_pinned() {
    let dir = fixtures().join("sweeps-7062f8f");
    let pinned = std::fs::read_to_string(dir.join("ids.txt")).unwrap();
    let mut files: Vec<&str> = pinned
        .lines()
        .map(|l| l.split(' ').next().unwrap())
        .collect();
    files.dedup();
    assert_eq!(files.len(), 4, "four shipped sweeps");
    let mut checked = 0;
    for file in files {
        let sweep = load_sweep(&dir.join(file), &[]).unwrap();
        let expect: Vec<(usize, &str)> = pinned
            .lines()
            .filter(|l| l.starts_with(&format!("{file} ")))
            .map(|l| {
                let parts: Vec<&str> = l.split(' ').collect();
                (parts[1].parse().unwrap(), parts[2])
            })
            .collect();
        assert_eq!(sweep.plan.len(), expect.len(), "{file}: number of jobs");
        for (index, id) in expect {
            assert_eq!(sweep.plan[index].id.0, id, "{file}: job {index}");
            checked += 1;
        }
    }
    assert_eq!(checked, 22);
}

/// A job directory of the pre-registry binary: its result and checkpoint (format 1) read; a
/// job resumed from that checkpoint and the same job run afresh follow the old binary's
/// trajectory bit for bit; the tables of an EDMD sweep keep the columns (names and types)
/// that binary wrote (new columns may follow).
#[test]
fn pre_registry_files_still_read() {
    let fixture = fixtures().join("pre-registry-job");
    let old = fixture.join("3b8f366cc0133d90");
    let old_result = store::read_result(&old).expect("an old result.ron reads");
    assert_eq!(old_result.engine, "edmd");
    assert!(old_result.counters.get("pair_collisions") > 0);
    let cp = store::read_checkpoint(&old)
        .unwrap()
        .expect("old checkpoint");
    assert_eq!(cp.format, 1);
    assert_eq!(cp.snapshot, 4);
    assert_eq!(store::load_records(&old, &cp).unwrap().len(), 5);
    let engine = granflow::registry::restore(&cp.engine).expect("old engine bytes restore");
    assert_eq!(engine.def().name, "edmd");

    let sweep = load_sweep(&fixture.join("tiny.ron"), &[]).unwrap();
    let job = &sweep.plan[0];
    assert_eq!(job.id.0, "3b8f366cc0133d90");
    let dir = scratch("pre-registry");
    let finish = |jd: &Path| {
        let claim = store::try_claim(jd, false).unwrap().unwrap();
        match execute::run_job(job, &claim, None, &mut |_| {}).unwrap() {
            JobEnd::Finished(r) => *r,
            other => panic!("not finished: {other:?}"),
        }
    };
    let resumed = dir.join("resumed").join(&job.id.0);
    std::fs::create_dir_all(&resumed).unwrap();
    for f in ["params.json", "checkpoint.bin"] {
        std::fs::copy(old.join(f), resumed.join(f)).unwrap();
    }
    let fresh = dir.join("fresh").join(&job.id.0);
    store::init_job_dir(&fresh, job).unwrap();
    let (resumed, fresh) = (finish(&resumed), finish(&fresh));
    // the engine's trajectory is the old binary's, bit for bit, resumed or afresh (the
    // analysis has grown since: label statistics and balances)
    for (name, r) in [("resumed", &resumed), ("fresh", &fresh)] {
        assert_eq!(r.counters, old_result.counters, "{name}");
        assert_eq!(r.time.to_bits(), old_result.time.to_bits(), "{name}");
        assert_eq!(r.snapshots, old_result.snapshots, "{name}");
        let (Analysis::Structure(now), Analysis::Structure(was)) =
            (&r.analysis, &old_result.analysis)
        else {
            panic!("structure analyses")
        };
        assert_eq!(now.energy, was.energy, "{name}: energy trace");
        assert_eq!(now.spectra, was.spectra, "{name}: window spectra");
        assert_eq!(now.summary.label, was.summary.label, "{name}: label");
    }
    // the old records do not know what the collapse guard suppressed: the resumed job says so
    let (Analysis::Structure(r), Analysis::Structure(f)) = (&resumed.analysis, &fresh.analysis)
    else {
        panic!("structure analyses")
    };
    assert!(r.summary.window_suppressed_dissipation.is_nan());
    assert!(!r.summary.collapse_guard_valid);
    assert!(
        r.summary.note.contains("not recorded"),
        "{}",
        r.summary.note
    );
    assert!(f.summary.window_suppressed_dissipation >= 0.0);

    // the tables: every column of the old binary's, under its issue-14 name and type (the key
    // `id` is `job_id`, the final clocks `final_*`; integers signed 64-bit, strings plain
    // UTF-8, the mode lists lists of structs)
    let results = dir.join("results");
    crate::common::granflow_ok(&[
        "run",
        fixture.join("tiny.ron").to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    for table in ["jobs", "spectra", "profiles", "energy"] {
        let schema = |path: PathBuf| {
            let mut file = std::fs::File::open(&path).unwrap();
            ParquetReader::new(&mut file).schema().unwrap()
        };
        let was = schema(fixture.join(format!("{table}.parquet")));
        let now = schema(results.join(format!("tiny/{table}.parquet")));
        for (name, field) in was.iter() {
            let renamed = match (table, name.as_str()) {
                (_, "id") => "job_id".to_string(),
                // one profile layout for every engine: the bin centre as y / W
                ("profiles", "y") => "coordinate".to_string(),
                ("jobs", "collisions_per_particle" | "time") => format!("final_{name}"),
                _ => name.to_string(),
            };
            let now = now
                .get(renamed.as_str())
                .unwrap_or_else(|| panic!("{table}.{name} is missing (as {renamed})"));
            // (polars reads every string column as a view: pyarrow's view of the types is
            // checked in tests/sweep/tables.rs)
            use ArrowDataType as T;
            let renamed_type = match (&field.dtype, &now.dtype) {
                (T::UInt32 | T::UInt64, now) => now == &T::Int64,
                (T::Utf8View, T::List(item) | T::LargeList(item))
                    if name.ends_with("_modes") || name.ends_with("_peaks") =>
                {
                    matches!(item.dtype, T::Struct(_))
                }
                (T::Utf8View, now) => matches!(now, T::Utf8View | T::LargeUtf8 | T::Utf8),
                (was, now) => was == now,
            };
            assert!(
                renamed_type,
                "{table}.{name}: {:?} became {:?}",
                field.dtype, now.dtype
            );
        }
    }
}

/// The parameter tables of the documentation (docs/parameters.md, which README links) are
/// exactly what the declarations generate.
#[test]
fn readme_parameter_tables_match_the_declarations() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/parameters.md"))
            .unwrap();
    let out = granflow(&["engines", "--markdown"]);
    assert!(out.status.success());
    let generated = String::from_utf8(out.stdout).unwrap();
    assert!(!generated.trim().is_empty());
    for engine in registry::engines() {
        let table = engine.markdown_table();
        assert!(generated.contains(&table));
        assert!(
            readme.contains(&table),
            "docs/parameters.md lacks the current parameter table of `{}`; paste `granflow engines --markdown` there:\n{table}",
            engine.name
        );
    }
}

fn write_sweep(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("s.ron");
    std::fs::write(&path, text).unwrap();
    path
}

const FIXED: &str = "width_over_diameter: 4.0, height_over_diameter: 4.0";

fn rejected(name: &str, text: &str, expect: &[&str]) {
    let dir = scratch(name);
    let file = write_sweep(&dir, text);
    let results = dir.join("results");
    let out = granflow(&[
        "plan",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
    for e in expect {
        assert!(stderr.contains(e), "{name}: expected `{e}` in {stderr}");
    }
}

#[test]
fn keys_are_checked_against_the_engine() {
    // a misspelt parameter: its own position and a suggestion
    rejected(
        "typo",
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15, roughnes: 0.2),\n axes: (length_over_width: [1.0]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
        &["s.ron:1:", "fixed.roughnes", "did you mean `roughness`"],
    );
    // phi and N both given in one place
    rejected(
        "phi-and-n",
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15, particles: 30),\n axes: (length_over_width: [1.0]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
        &["particles", "both given"],
    );
    // a run length on a clock the engine does not have
    rejected(
        "clock",
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15),\n axes: (length_over_width: [1.0]),\n run: (steps: 10, snapshot_interval: 5))"
        ),
        &["run.steps", "collisions_per_particle, time"],
    );
    // non-finite values
    rejected(
        "nan",
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15),\n axes: (length_over_width: [1.0], restitution: [NaN, 0.9]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
        &["axes.restitution", "not a finite number"],
    );
    // a missing section is named at the start of the file, not at its end
    rejected(
        "missing-engine",
        &format!(
            "(fixed: ({FIXED}, volume_fraction: 0.15),\n axes: (length_over_width: [1.0]),\n run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
        &["s.ron:1:1", "engine"],
    );
}

/// A point's N replaces the fixed phi (alternatives), and `--set` does the same.
#[test]
fn alternatives_replace_each_other() {
    let dir = scratch("alternatives");
    let file = write_sweep(
        &dir,
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15), axes: (length_over_width: [1.0]),\n points: [(length_over_width: 2.0, particles: 20)],\n run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
    );
    let sweep = load_sweep(&file, &[]).unwrap();
    assert_eq!(sweep.plan[1].params.get("particles"), 20.0);
    let set = load_sweep(&file, &["particles=25".into()]).unwrap();
    assert_eq!(set.plan[0].params.get("particles"), 25.0);
    assert!(!set.spec.fixed.0.contains_key("volume_fraction"));
    assert_eq!(
        set.plan[0].params.values.get("volume_fraction"),
        Some(&ParamValue::Number(
            25.0 * std::f64::consts::PI / 6.0 / 64.0
        ))
    );
}

/// `sim` rejects bad input with exit code 2 before printing anything.
#[test]
fn sim_rejects_bad_input_before_running() {
    for args in [
        vec!["sim", "--restitution", "1.5"],
        vec!["sim", "--set", "no_such=1"],
        vec!["sim", "--engine", "nope"],
        vec!["sim", "--steps", "10"],
        vec!["sim", "--volume-fraction", "0.7"],
    ] {
        let out = granflow(&args);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            out.stdout.is_empty(),
            "{args:?} printed {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    let out = granflow(&[
        "sim",
        "--collisions-per-particle",
        "20",
        "--report-every",
        "10",
        "--set",
        "restitution=0.9",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("e = 0.9"), "{text}");
}

/// A key of another engine is named as such, in sweep files and in `--set`.
#[test]
fn a_key_of_another_engine_says_so() {
    rejected(
        "other-engine",
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15, bounce_back: 0.5),\n axes: (length_over_width: [1.0]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
        &[
            "fixed.bounce_back",
            "parameter of the \"lga\" engine, not of the edmd engine",
        ],
    );
    rejected(
        "other-engine-lga",
        "(engine: \"lga\", fixed: (restitution: 0.7), run: (steps: 100, snapshot_interval: 10))",
        &[
            "fixed.restitution",
            "parameter of the \"edmd\", \"dsmc\" and \"dem\" engines, not of the lga engine",
        ],
    );
    let dir = scratch("other-engine-set");
    let file = write_sweep(
        &dir,
        "(engine: \"lga\", fixed: (density: 1.0), run: (steps: 100, snapshot_interval: 10))",
    );
    let out = granflow(&[
        "plan",
        file.to_str().unwrap(),
        "--set",
        "width_over_diameter=30",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("of the \"edmd\" and \"dem\" engines"),
        "{stderr}"
    );
    // and a clock the lattice gas does not have
    rejected(
        "lga-clock",
        "(engine: \"lga\", run: (collisions_per_particle: 100, snapshot_interval: 10))",
        &["run.collisions_per_particle", "steps"],
    );
}

/// Input that cannot run is refused before anything is written (exit 2, naming what is wrong):
/// a job too large for the machine's memory, an empty job range, a results path that is a file.
#[test]
fn impossible_runs_are_refused_up_front() {
    let dir = scratch("impossible");
    let file = write_sweep(
        &dir,
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15),\n axes: (length_over_width: [1.0]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
    );
    let results = dir.join("results");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        granflow(&args)
    };
    // N = 2.9e8 spheres: within the engine's size bound, beyond any CI machine's memory.
    let out = run(&[
        "--set",
        "width_over_diameter=1000",
        "--set",
        "height_over_diameter=1000",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("GB of memory"), "{stderr}");
    assert!(!results.exists(), "something was written");
    // N = 2.9e14 spheres: refused by the size bound, naming the volume fraction and the bound.
    let out = run(&[
        "--set",
        "width_over_diameter=100000",
        "--set",
        "height_over_diameter=100000",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("allowed N <= 1e9"), "{stderr}");
    assert!(!results.exists(), "something was written");
    let out = run(&["--job-range", "5:9"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("selects no job"));
    assert!(!results.exists(), "something was written");
    let a_file = dir.join("a-file");
    std::fs::write(&a_file, b"").unwrap();
    let out = granflow(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        a_file.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is not a directory"));
}

/// A closed stdout (`granflow run ... | head -1`) does not stop a run: it ends normally and
/// its results are written.
#[test]
fn a_closed_stdout_does_not_stop_a_run() {
    let dir = scratch("closed-stdout");
    let file = write_sweep(
        &dir,
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15),\n axes: (length_over_width: [1.0, 2.0, 3.0]), run: (collisions_per_particle: 200, snapshot_interval: 20))"
        ),
    );
    let results = dir.join("results");
    let mut child = Command::new(BIN)
        .args([
            "run",
            file.to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
            "--threads",
            "1",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away at once
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}");
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&results);
    for job in &sweep.plan {
        assert!(dirs.job_dir(&job.id).join(store::RESULT_FILE).exists());
    }
    assert!(dirs.tables.join("jobs.parquet").exists());
}

/// results/README.md documents every column of every table of every engine with its type, and
/// names no column (or type) that no table has.
#[test]
fn results_readme_documents_every_column() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("results/README.md"))
            .unwrap();
    // table rows `| name | type | unit | meaning |`, several names of one type separated by
    // ", ": each with a unit (the tables' field metadata carries it)
    let docs = granflow::sweep::tables::column_docs::parse(&doc);
    assert!(!docs.is_empty());
    for d in &docs {
        assert!(
            !d.unit.is_empty() && !d.meaning.is_empty(),
            "results/README.md: `{}` ({}.parquet) lacks a unit or a meaning",
            d.name,
            d.table
        );
    }
    let documented: Vec<(String, String)> = docs
        .iter()
        .map(|d| (d.name.clone(), d.kind.clone()))
        .collect();
    let mut all: Vec<(String, String)> = Vec::new();
    for engine in registry::engines() {
        for (table, columns) in granflow::sweep::tables::schema_with_statistics(engine) {
            for (c, kind) in columns {
                let kind = kind.doc_name();
                assert!(
                    documented.iter().any(|d| d.0 == c),
                    "results/README.md does not document {table}.parquet column `{c}` ({} engine)",
                    engine.name
                );
                assert!(
                    documented.contains(&(c.clone(), kind.clone())),
                    "results/README.md gives {table}.parquet column `{c}` ({} engine) another type than {kind}",
                    engine.name
                );
                all.push((c, kind));
            }
        }
    }
    for (d, kind) in &documented {
        assert!(
            all.iter().any(|(c, _)| c == d),
            "results/README.md documents `{d}`, which no table has"
        );
        assert!(
            all.contains(&(d.clone(), kind.clone())),
            "results/README.md documents `{d}` as {kind}, which no table has"
        );
    }
}

/// Sweep files written with RON's explicit `Some(..)` around values (and `None` for "not
/// given"), as the typed sweep files before the registry allowed, read as before.
#[test]
fn explicit_some_in_sweep_files_still_reads() {
    let dir = scratch("some");
    let plain = write_sweep(
        &dir,
        &format!(
            "(engine: \"edmd\", fixed: ({FIXED}, volume_fraction: 0.15), axes: (length_over_width: [1.0, 2.0]), run: (collisions_per_particle: 10, snapshot_interval: 5))"
        ),
    );
    let a = load_sweep(&plain, &[]).unwrap();
    let some = dir.join("some.ron");
    std::fs::write(
        &some,
        "(name: Some(\"s\"), engine: \"edmd\", fixed: (width_over_diameter: Some(4.0), height_over_diameter: 4.0, volume_fraction: Some(0.15), roughness: None),\n axes: (length_over_width: Some([1.0, 2.0])), run: (collisions_per_particle: 10, snapshot_interval: 5))",
    )
    .unwrap();
    let b = load_sweep(&some, &[]).unwrap();
    let ids = |s: &granflow::sweep::Sweep| s.plan.iter().map(|j| j.id.clone()).collect::<Vec<_>>();
    assert_eq!(ids(&a), ids(&b));
}
