//! Sweeps: RON sweep files, grid expansion, job ids, the resumable job queue, the rayon runner,
//! Parquet tables and phase diagrams.
//!
//! Library entry points (also used by the Slurm front end):
//! - [`load_sweep`]: parse + override + validate + expand a sweep file into a [`Sweep`] (its
//!   resolved spec and its [`Sweep::plan`], the ordered jobs with id and parameters);
//! - [`Sweep::results_dir`] / [`open_results`]: where a sweep's results live, and reading a
//!   sweep back from its results directory alone ([`SweepDirs`]: tables dir + jobs dir);
//! - [`store`]: the job directories and their files: states ([`store::job_state`]), claims (OS
//!   file locks), checkpoints, results;
//! - [`execute::run_job`]: run one claimed job (checkpointed, resumable);
//! - [`runner::run_sweep`]: the rayon pool with progress bars and a single writer;
//! - [`tables::gather`]: write the Parquet tables of a results directory.

pub mod curves;
pub mod estimate;
pub mod eta;
pub mod execute;
pub mod fs_error;
pub mod grid;
pub mod job;
mod job_error;
pub mod phase;
pub mod ranges;
mod readable;
pub mod refine;
pub mod rounds;
pub mod runner;
pub mod running;
pub mod select;
pub mod spec;
pub mod store;
mod suggest;
pub mod tables;
pub mod vertex_fit;

pub use grid::PlannedJob;
pub use job::{JobId, JobParams, RunSettings};
pub use spec::{Origin, SpecError, SweepSpec};

use std::path::{Path, PathBuf};

/// Bad command-line input other than the sweep file (exit code 2).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

/// File name of the resolved sweep inside a results directory.
pub const RESOLVED_SWEEP_FILE: &str = "sweep.ron";

/// A validated, expanded sweep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// the sweep's name (the results directory name)
    pub name: String,
    /// the spec after overrides (what `sweep.ron` in the results directory holds)
    pub spec: SweepSpec,
    /// the jobs in plan order
    pub plan: Vec<PlannedJob>,
}

/// The two directories of a sweep's results.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepDirs {
    /// tables, resolved sweep and phase diagrams: `results/<name>/` or, for a run with
    /// overrides, `results/<name>/runs/<overrides>/`
    pub tables: PathBuf,
    /// job directories `jobs/<id>/`, shared by all runs of the sweep: `results/<name>/jobs/`
    pub jobs: PathBuf,
}

impl SweepDirs {
    /// The job directory of a job id.
    pub fn job_dir(&self, id: &JobId) -> PathBuf {
        self.jobs.join(&id.0)
    }

    /// The job directory of a job id, with the methods that own its files.
    pub fn job(&self, id: &JobId) -> store::JobDir {
        store::JobDir::new(self.job_dir(id))
    }
}

/// Load a sweep file, apply `--set` overrides, validate and expand it. Errors name the file,
/// line/column, key and the allowed values; nothing is written.
pub fn load_sweep(path: &Path, overrides: &[String]) -> Result<Sweep, SpecError> {
    let text = std::fs::read_to_string(path).map_err(|e| SpecError {
        origin: Origin::File {
            path: path.to_path_buf(),
            line: 0,
            col: 0,
        },
        key: None,
        message: format!("cannot read the sweep file: {e}"),
    })?;
    let src = spec::Source { path, text: &text };
    let mut spec = spec::parse(path, &text)?;
    spec::apply_overrides(&mut spec, overrides)?;
    spec::unsign_zeros(&mut spec);
    spec::validate(&spec, &src)?;
    let plan = grid::expand(&spec, &src)?;
    let name = match &spec.name {
        Some(n) => n.clone(),
        None => path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep".into()),
    };
    spec.name = Some(name.clone());
    let mut sweep = Sweep { name, spec, plan };
    let swept = phase::swept_in(&sweep);
    for job in &mut sweep.plan {
        job.swept = swept.clone();
    }
    Ok(sweep)
}

impl Sweep {
    /// The sweep's engine (a loaded sweep names one of the registry).
    pub fn engine(&self) -> &'static crate::engine::EngineDef {
        spec::engine_of(&self.spec).expect("a loaded sweep names a registered engine")
    }

    /// Where this sweep's results go under a results root (default `results`): tables in
    /// `<root>/<name>/` (or `<root>/<name>/runs/<overrides>/` when `--set` was used, so that
    /// runs with different overrides never share tables), jobs in `<root>/<name>/jobs/` (shared:
    /// a point already computed is found by its id and reused).
    pub fn results_dir(&self, root: &Path) -> SweepDirs {
        let base = root.join(&self.name);
        let tables = if self.spec.overrides.is_empty() {
            base.clone()
        } else {
            base.join("runs").join(override_tag(&self.spec.overrides))
        };
        SweepDirs {
            tables,
            jobs: base.join("jobs"),
        }
    }

    /// Write the resolved sweep (after overrides) into the tables directory.
    pub fn write_resolved(&self, dirs: &SweepDirs) -> anyhow::Result<()> {
        std::fs::create_dir_all(&dirs.tables)?;
        std::fs::create_dir_all(&dirs.jobs)?;
        // a run with overrides keeps its tables under runs/: the sweep's directory says so
        if !self.spec.overrides.is_empty()
            && let Some(base) = dirs.jobs.parent()
            && !base.join("README.txt").exists()
        {
            write_atomic(&base.join("README.txt"), RESULTS_README.as_bytes())?;
        }
        let config = ron::ser::PrettyConfig::default()
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
        let text = ron::ser::to_string_pretty(&self.spec, config)?;
        write_atomic(
            &dirs.tables.join(RESOLVED_SWEEP_FILE),
            format!(
                "// resolved sweep written by granflow (overrides applied); do not edit\n{text}\n"
            )
            .as_bytes(),
        )?;
        Ok(())
    }
}

/// A directory name for a set of overrides: `key=value+key=v1,v2` (characters other than
/// letters, digits and `._-=,+` replaced by `_`; long sets shortened with a hash).
pub fn override_tag(overrides: &[String]) -> String {
    let tag: String = overrides
        .join("+")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._-=,+".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if tag.len() <= 100 {
        tag
    } else {
        let id = job::id_of_canonical(&overrides.join("\n"));
        format!("{}-{}", &tag[..60], id)
    }
}

/// Read a sweep back from its results directory (`results/<name>` or
/// `results/<name>/runs/<overrides>`) using the resolved `sweep.ron` written by `run`.
pub fn open_results(dir: &Path) -> Result<(Sweep, SweepDirs), SpecError> {
    let file = dir.join(RESOLVED_SWEEP_FILE);
    if !file.exists() {
        return Err(SpecError {
            origin: Origin::File {
                path: dir.to_path_buf(),
                line: 0,
                col: 0,
            },
            key: None,
            message: not_a_results_dir(dir),
        });
    }
    let sweep = load_sweep(&file, &[])?;
    // the layout is `Sweep::results_dir`'s (DIR = <root>/<name>/, or <root>/<name>/runs/
    // <overrides>/ whose jobs are <root>/<name>/jobs/): take the jobs of the root the sweep
    // was run under; a directory moved out of that layout keeps its jobs beside its tables
    let levels = if sweep.spec.overrides.is_empty() {
        1
    } else {
        3
    };
    let full = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
    let jobs = full
        .ancestors()
        .nth(levels)
        .map(|root| sweep.results_dir(root))
        .filter(|laid_out| laid_out.tables == full)
        .map_or_else(|| dir.join("jobs"), |laid_out| laid_out.jobs);
    let dirs = SweepDirs {
        tables: dir.to_path_buf(),
        jobs,
    };
    // the points its refinement added so far (none without a `refine` section)
    let sweep = rounds::replay(&sweep, &dirs)?.sweep;
    Ok((sweep, dirs))
}

/// Why a directory without `sweep.ron` cannot be read as a sweep's results, and where to
/// look: the runs with overrides under its `runs/`, when it has them.
fn not_a_results_dir(dir: &Path) -> String {
    let mut runs: Vec<String> = std::fs::read_dir(dir.join("runs"))
        .map(|entries| {
            entries
                .flatten()
                .filter(|e| e.path().join(RESOLVED_SWEEP_FILE).exists())
                .map(|e| e.path().display().to_string())
                .collect()
        })
        .unwrap_or_default();
    runs.sort();
    if runs.is_empty() {
        format!(
            "no {RESOLVED_SWEEP_FILE} here: not the results directory of a sweep (give \
             results/<sweep> after `granflow run`, or the sweep file)"
        )
    } else {
        format!(
            "no {RESOLVED_SWEEP_FILE} here: this sweep was run only with --set overrides, whose \
             tables are in runs/<overrides>/: give one of {} (or the sweep file with the same \
             --set)",
            runs.join(", ")
        )
    }
}

/// What `results/<sweep>/README.txt` says: where the tables of the sweep's runs are.
const RESULTS_README: &str = "Results of a granflow sweep (layout: results/README.md of granflow).
jobs/            every job of the sweep (one directory per job id), shared by all its runs
runs/<set>/      the tables, phase diagrams and report of a run with --set overrides
                 (one directory per set of overrides, named after it)
sweep.ron, *.parquet, report.html here: those of the run without overrides, once there was one
";

/// Open a sweep from either a sweep file (with overrides, results under `root`) or a results
/// directory.
pub fn open_any(
    path: &Path,
    overrides: &[String],
    root: &Path,
) -> Result<(Sweep, SweepDirs), SpecError> {
    if path.is_dir() {
        open_results(path)
    } else {
        let sweep = load_sweep(path, overrides)?;
        let dirs = sweep.results_dir(root);
        // the points its refinement added so far (none without a `refine` section)
        let sweep = rounds::replay(&sweep, &dirs)?.sweep;
        Ok((sweep, dirs))
    }
}

/// Check that results can be written under `root` (created if missing): a path that is a file
/// is bad input naming the path; a directory that cannot be created or written is a resource
/// error naming the path and why (read-only, full, no permission: exit 75 as everywhere), or
/// bad input for any other reason.
pub fn check_results_root(root: &Path) -> anyhow::Result<()> {
    if root.exists() && !root.is_dir() {
        return Err(BadInput(format!(
            "results path {} is not a directory",
            root.display()
        ))
        .into());
    }
    let refused = |what: &str, e: std::io::Error| -> anyhow::Error {
        if e.raw_os_error().is_some_and(fs_error::is_resource_errno) {
            anyhow::Error::new(fs_error::PathError::new(root, e))
                .context(format!("results path {}: {what}", root.display()))
        } else {
            BadInput(format!("results path {}: {what}: {e}", root.display())).into()
        }
    };
    std::fs::create_dir_all(root).map_err(|e| refused("cannot create it", e))?;
    let probe = root.join(format!(".granflow-write-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| refused("cannot be written", e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

pub use crate::fs::{say, write_atomic};

/// Err (exit code 75) when a line [`say`] wrote was lost to a resource error of stdout.
pub fn stdout_failure() -> anyhow::Result<()> {
    match crate::fs::stdout_lost() {
        None => Ok(()),
        Some(e) => Err(fs_error::ResourceStop(format!(
            "writing to standard output: {e}: the command's own files are written, its \
             output lines were lost (exit code {})",
            fs_error::EXIT_RESOURCE
        ))
        .into()),
    }
}
