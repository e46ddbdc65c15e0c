//! `granflow slurm submit`: write one sbatch script per job array into the results directory,
//! submit the arrays with `sbatch --parsable`, record them in `slurm/submissions.json`, exit.
//!
//! No driver process stays alive: the arrays, the scripts and the results directory are all
//! there is. A sweep with more tasks than `MaxArraySize` becomes several arrays; with
//! `--max-parallel K` each array after the first waits for the one before
//! (`--dependency=afterany:<previous>`), so at most K tasks of the sweep run at once.

use super::config::{DEFAULT_MAX_ARRAY_SIZE, query_max_array_size};
use super::link::{PreparedSweep, SweepLink};
use super::record::{self, Submission, SubmissionLog, SubmittedArray};
use super::script::{ArrayScript, NextRoundScript, SbatchOptions, exit_dir, log_dir};
use super::split::{split_into_arrays, task_count};
use anyhow::{Context, Result, bail, ensure};
use std::path::{Path, PathBuf};
use std::process::Command;

/// What to submit and how.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    pub sweep_file: PathBuf,
    /// `--results` as given to `granflow run` (None: the runner's default).
    pub results: Option<PathBuf>,
    /// `--set key=value` overrides.
    pub sets: Vec<String>,
    pub sbatch: SbatchOptions,
    /// J, jobs per array task (>= 1).
    pub jobs_per_task: usize,
    /// The granflow executable the tasks run (None: this executable).
    pub granflow: Option<PathBuf>,
    /// Cap on tasks per array (None: `MaxArraySize` from `scontrol show config`).
    pub max_array_size: Option<usize>,
    /// Write the scripts only.
    pub dry_run: bool,
}

/// What a submission did.
#[derive(Debug, Clone)]
pub struct SubmitOutcome {
    pub sweep: PreparedSweep,
    /// The scripts written, one per array.
    pub scripts: Vec<PathBuf>,
    /// Array job ids (empty for a dry run).
    pub array_job_ids: Vec<String>,
    /// Tasks per array limit used, and where it came from.
    pub max_array_size: usize,
    pub max_array_size_source: &'static str,
    /// The job that submits a refined sweep's next round after these arrays.
    pub next_round_job: Option<String>,
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).with_context(|| format!("making {} absolute", p.display()))
}

/// Write the scripts and (unless a dry run) submit the arrays.
pub fn submit(link: &dyn SweepLink, opts: &SubmitOptions) -> Result<SubmitOutcome> {
    ensure!(
        opts.jobs_per_task >= 1,
        "--jobs-per-task must be at least 1"
    );
    ensure!(
        opts.sbatch.cpus_per_task >= 1,
        "--cpus-per-task must be at least 1"
    );
    if let Some(k) = opts.sbatch.max_parallel {
        ensure!(k >= 1, "--max-parallel must be at least 1");
    }
    let mut sweep = link.prepare(&opts.sweep_file, opts.results.as_deref(), &opts.sets)?;
    sweep.sweep_dir = absolute(&sweep.sweep_dir)?;
    sweep.results_arg = absolute(&sweep.results_arg)?;
    sweep.sweep_file = absolute(&sweep.sweep_file)?;
    if let Some(bad) = [&sweep.sweep_dir, &sweep.results_arg, &sweep.sweep_file]
        .iter()
        .find(|p| p.to_string_lossy().contains(['"', '\n']))
    {
        bail!(
            "{}: a results path with a double quote or newline cannot go into an sbatch script",
            bad.display()
        );
    }
    if sweep.job_ids.is_empty() {
        if sweep.refining {
            // the next-round job of a refinement that is complete: nothing left to submit
            return Ok(SubmitOutcome {
                sweep,
                scripts: Vec::new(),
                array_job_ids: Vec::new(),
                max_array_size: 0,
                max_array_size_source: "nothing submitted: the refinement is complete",
                next_round_job: None,
            });
        }
        bail!(
            "{}: the sweep has no jobs, nothing to submit",
            opts.sweep_file.display()
        );
    }
    let granflow = match &opts.granflow {
        Some(p) => absolute(p)?,
        None => std::env::current_exe().context("finding the granflow executable")?,
    };
    let (max_array_size, source) = match opts.max_array_size {
        Some(m) => (m, "given"),
        None if opts.dry_run => match query_max_array_size() {
            Ok(m) => (m, "scontrol show config"),
            Err(_) => (
                DEFAULT_MAX_ARRAY_SIZE,
                "Slurm's default (scontrol not reachable)",
            ),
        },
        None => (query_max_array_size()?, "scontrol show config"),
    };
    ensure!(max_array_size >= 1, "MaxArraySize must be at least 1");

    let (chunks, scripts) = write_scripts(&sweep, opts, &granflow, max_array_size)?;
    let mut outcome = SubmitOutcome {
        sweep,
        scripts,
        array_job_ids: Vec::new(),
        max_array_size,
        max_array_size_source: source,
        next_round_job: None,
    };
    if opts.dry_run {
        return Ok(outcome);
    }

    let arrays = submit_arrays(&outcome, &chunks, opts);
    let (arrays, failure) = arrays?;
    outcome.array_job_ids = arrays.into_iter().map(|a| a.array_job_id).collect();
    if failure.is_none() && outcome.sweep.next_round {
        outcome.next_round_job = Some(submit_next_round(&outcome, opts, &granflow)?);
    }
    if let Some(e) = failure {
        let done = if outcome.array_job_ids.is_empty() {
            "nothing was submitted".to_string()
        } else {
            format!(
                "arrays {} were submitted and recorded",
                outcome.array_job_ids.join(", ")
            )
        };
        return Err(e.context(format!("submitting to Slurm ({done})")));
    }
    Ok(outcome)
}

/// Write this submission's job ids and one sbatch script per array: the arrays' chunks of
/// tasks and the scripts' paths.
fn write_scripts(
    sweep: &PreparedSweep,
    opts: &SubmitOptions,
    granflow: &Path,
    max_array_size: usize,
) -> Result<(Vec<super::split::ArrayChunk>, Vec<PathBuf>)> {
    let tasks = task_count(sweep.job_ids.len(), opts.jobs_per_task);
    let chunks = split_into_arrays(tasks, max_array_size);
    let slurm_dir = record::slurm_dir(&sweep.sweep_dir);
    let number = SubmissionLog::read(&sweep.sweep_dir)?.map_or(0, |l| l.submissions.len());
    for dir in [
        slurm_dir.join("scripts"),
        log_dir(&sweep.sweep_dir),
        exit_dir(&sweep.sweep_dir),
    ] {
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    // the job ids of this submission: tasks run these, by line, even if a later `run` or
    // `submit` rewrites the sweep directory's resolved sweep
    let ids_file = slurm_dir
        .join("scripts")
        .join(format!("submit{number}.ids"));
    record::write_atomically(
        &ids_file,
        format!("{}\n", sweep.job_ids.join("\n")).as_bytes(),
    )?;
    let mut scripts = Vec::new();
    for (k, chunk) in chunks.iter().enumerate() {
        let script = ArrayScript {
            sweep_name: sweep.name.clone(),
            sweep_dir: sweep.sweep_dir.clone(),
            results_arg: sweep.results_arg.clone(),
            sweep_file: sweep.sweep_file.clone(),
            ids_file: ids_file.clone(),
            granflow: granflow.to_path_buf(),
            sets: opts.sets.clone(),
            total_jobs: sweep.job_ids.len(),
            jobs_per_task: opts.jobs_per_task,
            chunk: *chunk,
            array_number: k,
            array_count: chunks.len(),
            options: opts.sbatch.clone(),
        };
        let path = slurm_dir
            .join("scripts")
            .join(format!("submit{number}-array{k}.sbatch"));
        record::write_atomically(&path, script.render().as_bytes())?;
        scripts.push(path);
    }
    Ok((chunks, scripts))
}

/// Submit the scripts in order (each after the one before with `--max-parallel`) and record
/// the arrays that were submitted even when a later sbatch failed, so that `status` can follow
/// them: the arrays, and the sbatch error that stopped the rest.
fn submit_arrays(
    outcome: &SubmitOutcome,
    chunks: &[super::split::ArrayChunk],
    opts: &SubmitOptions,
) -> Result<(Vec<SubmittedArray>, Option<anyhow::Error>)> {
    let mut arrays = Vec::new();
    let mut failure = None;
    for (k, (chunk, path)) in chunks.iter().zip(&outcome.scripts).enumerate() {
        let mut cmd = Command::new("sbatch");
        cmd.arg("--parsable");
        if k > 0 && opts.sbatch.max_parallel.is_some() {
            let previous: &SubmittedArray = &arrays[k - 1];
            cmd.arg(format!("--dependency=afterany:{}", previous.array_job_id));
        }
        cmd.arg(path);
        match run_sbatch(cmd, path) {
            Ok(id) => arrays.push(SubmittedArray {
                array_job_id: id,
                script: path
                    .strip_prefix(&outcome.sweep.sweep_dir)
                    .unwrap_or(path)
                    .to_path_buf(),
                chunk: *chunk,
            }),
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }
    // Record what was submitted even if a later sbatch failed, so status can follow it.
    if !arrays.is_empty() {
        let submitted_at = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        record::append(
            &outcome.sweep.sweep_dir,
            Submission {
                submitted_at,
                jobs_per_task: opts.jobs_per_task,
                job_ids: outcome.sweep.job_ids.clone(),
                sets: opts.sets.clone(),
                arrays: arrays.clone(),
            },
        )?;
    }
    Ok((arrays, failure))
}

/// Submit the one-task job that computes and submits a refined sweep's next round once the
/// arrays of this submission have ended ([`NextRoundScript`]); its Slurm job id.
fn submit_next_round(
    outcome: &SubmitOutcome,
    opts: &SubmitOptions,
    granflow: &Path,
) -> Result<String> {
    let sweep = &outcome.sweep;
    let script = NextRoundScript {
        sweep_name: sweep.name.clone(),
        sweep_dir: sweep.sweep_dir.clone(),
        results_arg: sweep.results_arg.clone(),
        sweep_file: sweep.sweep_file.clone(),
        granflow: granflow.to_path_buf(),
        after: outcome.array_job_ids.clone(),
        jobs_per_task: opts.jobs_per_task,
        options: opts.sbatch.clone(),
    };
    let path = record::slurm_dir(&sweep.sweep_dir)
        .join("scripts")
        .join(format!(
            "next-round-after-{}.sbatch",
            outcome.array_job_ids[0]
        ));
    record::write_atomically(&path, script.render().as_bytes())?;
    let mut cmd = Command::new("sbatch");
    cmd.arg("--parsable").arg(&path);
    run_sbatch(cmd, &path)
}

/// Run `sbatch --parsable ...` and return the job id (`<id>` or `<id>;<cluster>`).
fn run_sbatch(mut cmd: Command, script: &Path) -> Result<String> {
    let out = cmd
        .output()
        .context("running sbatch (is Slurm's client installed and on PATH?)")?;
    if !out.status.success() {
        bail!(
            "sbatch {} failed ({}): {}",
            script.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    parse_parsable(&String::from_utf8_lossy(&out.stdout))
        .with_context(|| format!("sbatch {}", script.display()))
}

/// The job id from `sbatch --parsable` output.
pub fn parse_parsable(stdout: &str) -> Result<String> {
    let line = stdout
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty())
        .unwrap_or("");
    let id = line.split(';').next().unwrap_or("").trim();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        bail!(
            "could not read a job id from sbatch --parsable output '{}'",
            stdout.trim()
        );
    }
    Ok(id.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_parsable_job_ids() {
        assert_eq!(parse_parsable("1234\n").unwrap(), "1234");
        assert_eq!(parse_parsable("1234;cluster2\n").unwrap(), "1234");
        assert!(parse_parsable("Submitted batch job 12\n").is_err());
        assert!(parse_parsable("").is_err());
    }
}
