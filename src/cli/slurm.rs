//! `granflow slurm submit|status`: run a sweep on a Slurm cluster as job arrays, and show
//! where its jobs are in Slurm.

use super::out::{out, outln};
use crate::slurm::{self, RunnerLink, SbatchOptions, SubmitOptions};
use anyhow::Context;
use clap::{Args, Subcommand};
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow slurm submit sweeps/thesis-fig5-25.ron --results /scratch/$USER/granflow \\
      --partition compute --time 2-00:00:00 --max-parallel 12 -- --account=myproject
  granflow slurm status /scratch/$USER/granflow/thesis-fig5-25")]
pub struct SlurmArgs {
    #[command(subcommand)]
    pub command: SlurmCommand,
}

#[derive(Debug, Subcommand)]
pub enum SlurmCommand {
    /// Write the sbatch script(s) into the results directory, submit the sweep as job
    /// array(s), print the array id(s) and exit. Options after `--` go to sbatch verbatim.
    Submit(SubmitArgs),
    /// Show the sweep's jobs as Slurm sees them (one squeue call; no sacct needed).
    Status(StatusArgs),
}

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  # write the script only, to read it
  granflow slurm submit sweeps/quick.ron --results /scratch/$USER/granflow --dry-run
  granflow slurm submit sweeps/thesis-fig5-25.ron --results /scratch/$USER/granflow \\
      --partition compute --time 2-00:00:00 --max-parallel 12 -- --account=myproject --mem=8G")]
pub struct SubmitArgs {
    /// The sweep file (sweeps/X.ron)
    pub sweep: PathBuf,
    /// Results root, as for `granflow run` (must be on a file system the nodes share)
    #[arg(long)]
    pub results: Option<PathBuf>,
    /// Slurm partition (sbatch --partition)
    #[arg(long)]
    pub partition: Option<String>,
    /// Time limit per array task, in a Slurm time format (e.g. 12:00:00 or 2-00:00:00)
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per array task; each task's runner uses this many threads
    #[arg(long, default_value_t = 1)]
    pub cpus_per_task: usize,
    /// At most this many array tasks run at once (--array=0-N%K)
    #[arg(long)]
    pub max_parallel: Option<usize>,
    /// Jobs each array task runs (J); use J > 1 for sweeps with very many short jobs
    #[arg(long, default_value_t = 1)]
    pub jobs_per_task: usize,
    /// Override a sweep key for this submission, as for `granflow run` (repeatable)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Write the script(s) only; submit nothing
    #[arg(long)]
    pub dry_run: bool,
    /// The granflow executable the tasks run (default: this one; must be visible on the nodes)
    #[arg(long)]
    pub granflow: Option<PathBuf>,
    /// Extra sbatch options, after `--` (e.g. -- --account=abc --mem=4G --qos normal)
    #[arg(last = true, value_name = "SBATCH_OPTION")]
    pub sbatch: Vec<String>,
}

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow slurm status /scratch/$USER/granflow/thesis-fig5-25")]
pub struct StatusArgs {
    /// The sweep's results directory (results/<sweep>)
    pub results_dir: PathBuf,
}

/// Join pass-through tokens into one option per `#SBATCH` line: `--qos normal` stays together.
pub fn group_sbatch_options(tokens: &[String]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for t in tokens {
        match out.last_mut() {
            Some(prev) if !t.starts_with('-') && !prev.contains('=') && !prev.contains(' ') => {
                prev.push(' ');
                prev.push_str(t);
            }
            _ => out.push(t.clone()),
        }
    }
    out
}

pub fn run(args: SlurmArgs) -> anyhow::Result<()> {
    match args.command {
        SlurmCommand::Submit(a) => submit(a),
        SlurmCommand::Status(a) => status(a),
    }
}

fn submit(a: SubmitArgs) -> anyhow::Result<()> {
    let extra = group_sbatch_options(&a.sbatch);
    if let Some(bad) = extra.iter().find(|o| !o.starts_with('-')) {
        anyhow::bail!("sbatch option '{bad}' after `--` must start with '-'");
    }
    let opts = SubmitOptions {
        sweep_file: a.sweep.clone(),
        results: a.results,
        sets: a.sets,
        sbatch: SbatchOptions {
            partition: a.partition,
            time: a.time,
            cpus_per_task: a.cpus_per_task,
            max_parallel: a.max_parallel,
            extra,
        },
        jobs_per_task: a.jobs_per_task,
        granflow: a.granflow,
        max_array_size: None,
        dry_run: a.dry_run,
    };
    let out = slurm::submit(&RunnerLink, &opts)
        .with_context(|| format!("granflow slurm submit {}", a.sweep.display()))?;
    if out.sweep.refining && out.sweep.job_ids.is_empty() {
        outln!(
            "sweep '{}': its refinement is complete, nothing to submit (tables: granflow gather {})",
            out.sweep.name,
            out.sweep.sweep_dir.display()
        );
        return Ok(());
    }
    let jobs = out.sweep.job_ids.len();
    outln!(
        "sweep '{}': {jobs} jobs, {} jobs per task, {} array(s) (MaxArraySize {} from {})",
        out.sweep.name,
        opts.jobs_per_task,
        out.scripts.len(),
        out.max_array_size,
        out.max_array_size_source
    );
    for s in &out.scripts {
        outln!("script: {}", s.display());
    }
    if opts.dry_run {
        outln!("dry run: nothing submitted (submit a script by hand with `sbatch <script>`)");
        return Ok(());
    }
    for id in &out.array_job_ids {
        outln!("submitted array job {id}");
    }
    if let Some(id) = &out.next_round_job {
        outln!(
            "submitted job {id}: after the arrays it computes the refinement's next round and \
             submits it (`granflow slurm status` follows every round)"
        );
    }
    outln!(
        "logs: {}\nfollow with: granflow status {}   (or: granflow slurm status {})",
        slurm::script::log_dir(&out.sweep.sweep_dir).display(),
        out.sweep.sweep_dir.display(),
        out.sweep.sweep_dir.display()
    );
    Ok(())
}

fn status(a: StatusArgs) -> anyhow::Result<()> {
    match slurm::slurm_status(&a.results_dir)? {
        Some(st) => out!("{st}"),
        None => outln!(
            "{}: not submitted to Slurm (no slurm/submissions.json)",
            a.results_dir.display()
        ),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pass_through_options_keep_their_values() {
        let t = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            group_sbatch_options(&t(&[
                "--account=abc",
                "--qos",
                "normal",
                "-N",
                "1",
                "--exclusive"
            ])),
            t(&["--account=abc", "--qos normal", "-N 1", "--exclusive"])
        );
    }
}
