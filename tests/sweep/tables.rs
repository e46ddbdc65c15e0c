//! Tables with a fixed schema: every table of every engine, read with
//! pyarrow and with DuckDB when no job, some jobs and every job of a tiny sweep is done, has
//! the schema the declarations give (`tables::schema`): the same columns and types in the
//! three states, signed 64-bit integers, plain UTF-8 strings, lists of structs for the mode
//! lists, null and never NaN, `job_id` the one key shared by the tables, zstd. The reading
//! is `tables_check.py`; python3 with pyarrow and duckdb is required (`.ci/run` installs them;
//! locally `python3 -m pip install pyarrow duckdb`). Also: gathers that run at the same time
//! (runners that end together) all succeed and leave one set.

use crate::common::{BIN, granflow_ok, scratch};
use granflow::registry;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Tiny sweeps of each engine: two jobs of well under a second each, every table non-empty
/// once they are done.
const SWEEPS: [(&str, &str); 3] = [
    (
        "edmd",
        "(engine: \"edmd\", fixed: (width_over_diameter: 5.0, height_over_diameter: 5.0, volume_fraction: 0.15),
          axes: (length_over_width: [1.0, 2.0]),
          run: (collisions_per_particle: 300, snapshot_interval: 50, checkpoint_every: 1000, milestones: [100, 250]))",
    ),
    (
        "lga",
        "(engine: \"lga\", fixed: (length: 44, width: 11, gravity_probability: 0.5, bounce_back: 0.5, dissipation: 0.5),
          axes: (density: [1.0, 3.0]),
          run: (steps: 100000, snapshot_interval: 10, checkpoint_every: 100000))",
    ),
    (
        "dsmc",
        "(engine: \"dsmc\", fixed: (forcing: 0.5, restitution: 0.7, particles_per_cell: 20.0, knudsen_number: 0.5),
          axes: (wall_model: [\"thermal\", \"maxwell\"]),
          run: (time: 4.0, snapshot_interval: 0.5, checkpoint_every: 1000))",
    ),
];

/// Copy the current table files (through their links) of a results directory into `to`.
fn keep_tables(results: &Path, names: &[String], to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for name in names {
        let file = format!("{name}.parquet");
        std::fs::copy(results.join(&file), to.join(&file))
            .unwrap_or_else(|e| panic!("{}: {e}", results.join(&file).display()));
    }
}

/// The tables of `engine`'s tiny sweep with no job, the first job, and both jobs done.
fn three_states(engine: &str, sweep: &str, names: &[String]) -> [PathBuf; 3] {
    let dir = scratch(&format!("tables-{engine}"));
    let file = dir.join(format!("{engine}.ron"));
    std::fs::write(&file, sweep).unwrap();
    let (f, r) = (file.to_str().unwrap(), dir.join("results"));
    let r = r.to_str().unwrap();
    let tables = Path::new(r).join(engine);
    let states = [dir.join("none"), dir.join("some"), dir.join("all")];
    granflow_ok(&["gather", f, "--results", r]);
    keep_tables(&tables, names, &states[0]);
    granflow_ok(&[
        "run",
        f,
        "--results",
        r,
        "--job-range",
        "0:1",
        "--threads",
        "1",
    ]);
    granflow_ok(&["gather", f, "--results", r]);
    keep_tables(&tables, names, &states[1]);
    granflow_ok(&["run", f, "--results", r, "--threads", "2"]);
    keep_tables(&tables, names, &states[2]);
    states
}

/// Read the tables of `engine`'s sweep in the three states with pyarrow and DuckDB and check
/// them against `schema` (and the field units in `units`: table -> column -> unit).
fn check_tables(
    name: &str,
    label: &str,
    sweep: &str,
    schema: &[(
        String,
        Vec<(String, granflow::analysis::columns::ColumnKind)>,
    )],
    units: serde_json::Value,
) {
    let names: Vec<String> = schema.iter().map(|(t, _)| t.clone()).collect();
    let [none, some, all] = three_states(label, sweep, &names);
    let tables: Vec<serde_json::Value> = schema
        .iter()
        .map(|(table, columns)| {
            let columns: Vec<[String; 2]> = columns
                .iter()
                .map(|(c, kind)| [c.clone(), kind.doc_name()])
                .collect();
            serde_json::json!([table, columns])
        })
        .collect();
    let spec = serde_json::json!({
        "engine": name,
        "jobs": 2,
        "some_done": 1,
        "tables": tables,
        "units": units,
        "states": {"none": none, "some": some, "all": all},
    });
    let out = Command::new("python3")
        .args(["-c", include_str!("tables_check.py"), &spec.to_string()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{label}: the tables do not read as declared:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprint!("{}", String::from_utf8_lossy(&out.stdout));
}

fn python_readers_present() {
    let probe = Command::new("python3")
        .args(["-c", "import pyarrow, duckdb"])
        .output();
    assert!(
        probe.as_ref().is_ok_and(|o| o.status.success()),
        "python3 with pyarrow and duckdb is needed (.ci/run installs them; locally: python3 -m pip install pyarrow duckdb): {probe:?}"
    );
}

#[test]
fn every_table_has_one_schema_whether_no_some_or_all_jobs_are_done() {
    python_readers_present();
    for (name, sweep) in SWEEPS {
        let engine = registry::find(name).unwrap();
        let schema = granflow::sweep::tables::schema(engine);
        check_tables(name, name, sweep, &schema, serde_json::json!({}));
    }
}

/// The statistics' tables of an EDMD sweep with `run.statistics`: the same checks
/// (one schema in three states, pyarrow and DuckDB, no NaN, `job_id` the only shared column),
/// every statistics table non-empty once the jobs are done, and the units in the fields'
/// metadata.
#[test]
fn the_statistics_tables_read_back_with_pyarrow_and_duckdb() {
    python_readers_present();
    let engine = registry::find("edmd").unwrap();
    let schema = granflow::sweep::tables::schema_with_statistics(engine);
    // the units results/README.md gives, which every field must carry
    let mut units = serde_json::Map::new();
    for (table, columns) in &schema {
        let m: serde_json::Map<String, serde_json::Value> = columns
            .iter()
            .map(|(c, _)| {
                let doc = granflow::sweep::tables::column_docs::lookup(table, "edmd", c)
                    .unwrap_or_else(|| panic!("{table}.{c} is not documented"));
                (c.clone(), serde_json::json!(doc.unit))
            })
            .collect();
        units.insert(table.clone(), serde_json::Value::Object(m));
    }
    let sweep = SWEEPS[0].1.replace(
        "milestones: [100, 250])",
        "milestones: [100, 250], statistics: (bins: 4, r_max: 2.0))",
    );
    assert!(sweep.contains("statistics"));
    check_tables(
        "edmd",
        "edmd-statistics",
        &sweep,
        &schema,
        serde_json::Value::Object(units),
    );
}

/// The tables hold seeds as signed 64-bit integers: a larger seed is refused as bad input.
#[test]
fn a_seed_beyond_the_signed_range_is_bad_input() {
    let dir = scratch("tables-seed");
    let file = dir.join("s.ron");
    let edmd = SWEEPS[0].1;
    let results = dir.join("results");
    let plan = |file: &Path| {
        Command::new(BIN)
            .args(["plan", file.to_str().unwrap(), "--results"])
            .arg(&results)
            .output()
            .unwrap()
    };
    std::fs::write(
        &file,
        edmd.replace("axes:", "seeds: [1, 9223372036854775808],\n          axes:"),
    )
    .unwrap();
    let out = plan(&file);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("seed 9223372036854775808 is out of range")
            && stderr.contains("9223372036854775807"),
        "{stderr}"
    );
    // the largest signed one is fine
    std::fs::write(
        &file,
        edmd.replace("axes:", "seeds: [9223372036854775807],\n          axes:"),
    )
    .unwrap();
    let out = plan(&file);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Gathers started together on one results directory (as runners that end together do) all
/// succeed, one after the other, and leave one current set and no other generation.
#[test]
fn gathers_at_the_same_time_all_succeed() {
    let dir = scratch("tables-concurrent");
    let file = dir.join("edmd.ron");
    std::fs::write(&file, SWEEPS[0].1).unwrap();
    let results = dir.join("results");
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    granflow_ok(&["run", f, "--results", r, "--threads", "2"]);
    let gathers: Vec<_> = (0..6)
        .map(|_| {
            Command::new(BIN)
                .args(["gather", f, "--results", r])
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for g in gathers {
        let out = g.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let tables = results.join("edmd");
    let generations: Vec<String> = std::fs::read_dir(&tables)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".tables-"))
        .collect();
    assert_eq!(generations.len(), 1, "{generations:?}");
    let current = std::fs::read_link(tables.join("tables")).unwrap();
    assert_eq!(current, Path::new(&generations[0]));
    for name in ["jobs", "spectra", "profiles", "energy"] {
        assert!(tables.join(format!("{name}.parquet")).is_file(), "{name}");
    }
}
