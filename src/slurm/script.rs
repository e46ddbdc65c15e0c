//! The sbatch script of one job array: readable, self-contained, with the exact granflow
//! command each task runs.
//!
//! Array index a of an array whose first task is t0 is global task t = t0 + a; it runs
//! `granflow run <resolved sweep> --results <root> --threads $SLURM_CPUS_PER_TASK
//! --job-range tJ:min((t+1)J, n)`, which claims its jobs through the local runner's locks, skips
//! jobs already done and resumes a job from its checkpoint. Requeue (`--requeue`, preemption,
//! node failure) reruns the same task in the same results directory and appends to the same log.

use super::split::ArrayChunk;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Options of `sbatch` that granflow sets or passes through.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SbatchOptions {
    /// `--partition`
    pub partition: Option<String>,
    /// `--time` (any Slurm time format, e.g. `2-00:00:00` or `90`)
    pub time: Option<String>,
    /// `--cpus-per-task`: the thread count of each task's runner
    pub cpus_per_task: usize,
    /// `%K` of `--array=0-N%K`: at most K tasks of this array run at once
    pub max_parallel: Option<usize>,
    /// Further sbatch options, written verbatim as `#SBATCH` lines (e.g. `--account=abc`).
    pub extra: Vec<String>,
}

/// Everything that goes into one array's script.
#[derive(Debug, Clone)]
pub struct ArrayScript {
    /// The sweep's name (for the job name).
    pub sweep_name: String,
    /// The sweep's results directory (absolute): `results/<sweep>/`.
    pub sweep_dir: PathBuf,
    /// What the runner's `--results` gets (absolute).
    pub results_arg: PathBuf,
    /// The resolved sweep file inside the results directory (absolute).
    pub sweep_file: PathBuf,
    /// The submission's job-id list (absolute): task t runs the ids on its lines
    /// [t J, (t+1) J), whatever is written into the sweep directory later.
    pub ids_file: PathBuf,
    /// The granflow executable the tasks run (absolute; on a shared file system).
    pub granflow: PathBuf,
    /// `--set key=value` overrides of the submission: already applied in `sweep_file` (the
    /// resolved sweep records them), so the command does not repeat them; shown as a comment.
    pub sets: Vec<String>,
    /// n, number of jobs in the plan.
    pub total_jobs: usize,
    /// J, jobs per task.
    pub jobs_per_task: usize,
    /// This array's tasks.
    pub chunk: ArrayChunk,
    /// Position of this array among the submission's arrays (0-based) and their count.
    pub array_number: usize,
    pub array_count: usize,
    pub options: SbatchOptions,
}

/// Directory of the per-task logs inside a sweep's results directory.
pub fn log_dir(sweep_dir: &Path) -> PathBuf {
    sweep_dir.join("slurm").join("logs")
}

/// Directory where each task records its exit code (read by status after squeue forgets it).
pub fn exit_dir(sweep_dir: &Path) -> PathBuf {
    sweep_dir.join("slurm").join("tasks")
}

/// Log file of array task `array_job_id`_`index` (stdout and stderr, appended across requeues).
pub fn task_log(sweep_dir: &Path, array_job_id: &str, index: usize) -> PathBuf {
    log_dir(sweep_dir).join(format!("{array_job_id}_{index}.log"))
}

/// Exit record of array task `array_job_id`_`index`.
pub fn task_exit_file(sweep_dir: &Path, array_job_id: &str, index: usize) -> PathBuf {
    exit_dir(sweep_dir).join(format!("{array_job_id}_{index}.exit"))
}

/// Quote a string for a POSIX shell (single quotes; embedded quotes as `'\''`).
pub fn shell_quote(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if plain {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

fn path_str(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// A path as the value of an `#SBATCH` option: double-quoted when it has white space (sbatch
/// splits `#SBATCH` lines at white space but honours double quotes).
fn sbatch_path(p: &Path) -> String {
    let s = path_str(p);
    if s.chars().any(char::is_whitespace) {
        format!("\"{s}\"")
    } else {
        s
    }
}

impl ArrayScript {
    /// The `--array` value: `0-N` or `0-N%K`.
    pub fn array_spec(&self) -> String {
        let last = self.chunk.tasks - 1;
        match self.options.max_parallel {
            Some(k) => format!("0-{last}%{k}"),
            None => format!("0-{last}"),
        }
    }

    /// The script text.
    pub fn render(&self) -> String {
        let o = &self.options;
        let log = log_dir(&self.sweep_dir).join("%A_%a.log");
        let first_task = self.chunk.first_task;
        let last_task = first_task + self.chunk.tasks - 1;
        let mut s = String::new();
        let _ = writeln!(s, "#!/bin/bash");
        let _ = writeln!(
            s,
            "# granflow sweep '{}' on Slurm: array {} of {}, tasks {first_task}..={last_task} \
             of {} in all;",
            self.sweep_name,
            self.array_number + 1,
            self.array_count,
            super::split::task_count(self.total_jobs, self.jobs_per_task),
        );
        let _ = writeln!(
            s,
            "# task t runs jobs [t*{j}, min(t*{j}+{j}, {n})) of `granflow plan` order.",
            j = self.jobs_per_task,
            n = self.total_jobs
        );
        let _ = writeln!(
            s,
            "# Written by `granflow slurm submit`; it can be resubmitted by hand with sbatch."
        );
        let _ = writeln!(s, "#SBATCH --job-name=granflow-{}", self.sweep_name);
        let _ = writeln!(s, "#SBATCH --array={}", self.array_spec());
        let _ = writeln!(s, "#SBATCH --requeue");
        let _ = writeln!(s, "#SBATCH --open-mode=append");
        let _ = writeln!(s, "#SBATCH --output={}", sbatch_path(&log));
        let _ = writeln!(s, "#SBATCH --error={}", sbatch_path(&log));
        let _ = writeln!(s, "#SBATCH --chdir={}", sbatch_path(&self.sweep_dir));
        let _ = writeln!(s, "#SBATCH --cpus-per-task={}", o.cpus_per_task);
        if let Some(t) = &o.time {
            let _ = writeln!(s, "#SBATCH --time={t}");
        }
        if let Some(p) = &o.partition {
            let _ = writeln!(s, "#SBATCH --partition={p}");
        }
        for extra in &o.extra {
            let _ = writeln!(s, "#SBATCH {extra}");
        }
        let _ = writeln!(s);
        let _ = writeln!(s, "set -uo pipefail");
        let _ = writeln!(s, "TASK=$(( {first_task} + SLURM_ARRAY_TASK_ID ))");
        let _ = writeln!(s, "FIRST=$(( TASK * {} ))", self.jobs_per_task);
        let _ = writeln!(s, "END=$(( FIRST + {} ))", self.jobs_per_task);
        let _ = writeln!(
            s,
            "if [ \"$END\" -gt {n} ]; then END={n}; fi",
            n = self.total_jobs
        );
        let exit_file = format!(
            "{}/${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}.exit",
            path_str(&exit_dir(&self.sweep_dir))
        );
        let _ = writeln!(s, "EXIT_FILE={}", shell_quote_keep_vars(&exit_file));
        let _ = writeln!(s, "rm -f \"$EXIT_FILE\"");
        let _ = writeln!(
            s,
            "echo \"granflow: task $TASK (${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}) \
             attempt $(( ${{SLURM_RESTART_COUNT:-0}} + 1 )) on $(hostname) at $(date -Is): \
             jobs [$FIRST, $END)\""
        );
        let cmd = vec![
            shell_quote(&path_str(&self.granflow)),
            "run".to_string(),
            shell_quote(&path_str(&self.sweep_file)),
            "--results".to_string(),
            shell_quote(&path_str(&self.results_arg)),
            "--threads".to_string(),
            "\"${SLURM_CPUS_PER_TASK:-1}\"".to_string(),
            "--job-ids".to_string(),
            shell_quote(&path_str(&self.ids_file)),
            "--job-range".to_string(),
            "\"$FIRST:$END\"".to_string(),
        ];
        if !self.sets.is_empty() {
            let _ = writeln!(
                s,
                "# The overrides {} are applied in the resolved sweep file; not repeated here.",
                self.sets
                    .iter()
                    .map(|x| shell_quote(x))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
        }
        let _ = writeln!(s, "{}", cmd.join(" "));
        let _ = writeln!(s, "STATUS=$?");
        let _ = writeln!(
            s,
            "# The exit record lets `granflow status` report the exit code without sacct."
        );
        let _ = writeln!(
            s,
            "printf '%s %s %s\\n' \"$STATUS\" \"${{SLURM_RESTART_COUNT:-0}}\" \"$(date -Is)\" \
             > \"$EXIT_FILE.tmp\" && mv -f \"$EXIT_FILE.tmp\" \"$EXIT_FILE\""
        );
        let _ = writeln!(
            s,
            "echo \"granflow: task $TASK exit $STATUS at $(date -Is)\""
        );
        let _ = writeln!(s, "exit $STATUS");
        s
    }
}

/// The one-task job that follows a refined sweep's arrays (`--dependency=afterany` on all of
/// them): it runs `granflow slurm submit` on the resolved sweep again, which computes the next
/// round of the refinement from the results and submits it as further arrays (with its own
/// next-round job), or, when the refinement is complete, submits nothing and gathers the
/// tables. No process waits on the login node.
#[derive(Debug, Clone)]
pub struct NextRoundScript {
    pub sweep_name: String,
    pub sweep_dir: PathBuf,
    pub results_arg: PathBuf,
    pub sweep_file: PathBuf,
    pub granflow: PathBuf,
    /// the array job ids it waits for
    pub after: Vec<String>,
    pub jobs_per_task: usize,
    pub options: SbatchOptions,
}

impl NextRoundScript {
    pub fn render(&self) -> String {
        let o = &self.options;
        let log = log_dir(&self.sweep_dir).join("next-round-%j.log");
        let mut s = String::new();
        let _ = writeln!(s, "#!/bin/bash");
        let _ = writeln!(
            s,
            "# granflow sweep '{}' on Slurm: the next round of its refinement, after arrays {}.",
            self.sweep_name,
            self.after.join(", ")
        );
        let _ = writeln!(s, "#SBATCH --job-name=granflow-{}-next", self.sweep_name);
        let _ = writeln!(s, "#SBATCH --dependency=afterany:{}", self.after.join(":"));
        let _ = writeln!(s, "#SBATCH --output={}", sbatch_path(&log));
        let _ = writeln!(s, "#SBATCH --error={}", sbatch_path(&log));
        let _ = writeln!(s, "#SBATCH --chdir={}", sbatch_path(&self.sweep_dir));
        let _ = writeln!(s, "#SBATCH --cpus-per-task=1");
        if let Some(p) = &o.partition {
            let _ = writeln!(s, "#SBATCH --partition={p}");
        }
        for extra in &o.extra {
            let _ = writeln!(s, "#SBATCH {extra}");
        }
        let _ = writeln!(s);
        let mut cmd = vec![
            shell_quote(&path_str(&self.granflow)),
            "slurm".to_string(),
            "submit".to_string(),
            shell_quote(&path_str(&self.sweep_file)),
            "--results".to_string(),
            shell_quote(&path_str(&self.results_arg)),
            "--jobs-per-task".to_string(),
            self.jobs_per_task.to_string(),
            "--cpus-per-task".to_string(),
            o.cpus_per_task.to_string(),
            "--granflow".to_string(),
            shell_quote(&path_str(&self.granflow)),
        ];
        if let Some(p) = &o.partition {
            cmd.extend(["--partition".to_string(), shell_quote(p)]);
        }
        if let Some(t) = &o.time {
            cmd.extend(["--time".to_string(), shell_quote(t)]);
        }
        if let Some(k) = o.max_parallel {
            cmd.extend(["--max-parallel".to_string(), k.to_string()]);
        }
        if !o.extra.is_empty() {
            cmd.push("--".to_string());
            cmd.extend(o.extra.iter().map(|e| shell_quote(e)));
        }
        let _ = writeln!(
            s,
            "# the tables of the rounds so far, then the next round (nothing when complete)"
        );
        let _ = writeln!(
            s,
            "{} gather {} || echo \"granflow: gather failed\"",
            shell_quote(&path_str(&self.granflow)),
            shell_quote(&path_str(&self.sweep_dir))
        );
        let _ = writeln!(s, "exec {}", cmd.join(" "));
        s
    }
}

/// Double-quote a string that contains `${...}` expansions to keep, escaping the rest.
fn shell_quote_keep_vars(s: &str) -> String {
    let escaped: String = s
        .chars()
        .flat_map(|c| match c {
            '"' | '\\' | '`' => vec!['\\', c],
            _ => vec![c],
        })
        .collect();
    format!("\"{escaped}\"")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    fn example(chunk: ArrayChunk, max_parallel: Option<usize>) -> ArrayScript {
        ArrayScript {
            sweep_name: "quick".into(),
            sweep_dir: "/scratch/my results/quick".into(),
            results_arg: "/scratch/my results".into(),
            sweep_file: "/scratch/my results/quick/sweep.ron".into(),
            ids_file: "/scratch/my results/quick/slurm/scripts/submit0.ids".into(),
            granflow: "/home/u/bin/granflow".into(),
            sets: vec!["restitution=0.9".into(), "note=it's".into()],
            total_jobs: 7,
            jobs_per_task: 3,
            chunk,
            array_number: 1,
            array_count: 2,
            options: SbatchOptions {
                partition: Some("short".into()),
                time: Some("01:30:00".into()),
                cpus_per_task: 4,
                max_parallel,
                extra: vec!["--account=granular".into(), "--mem=8G".into()],
            },
        }
    }

    fn sbatch_lines(script: &str) -> Vec<&str> {
        script
            .lines()
            .filter_map(|l| l.strip_prefix("#SBATCH "))
            .collect()
    }

    #[test]
    fn header_has_array_throttle_requeue_logs_and_pass_through_options() {
        let s = example(
            ArrayChunk {
                first_task: 0,
                tasks: 3,
            },
            Some(2),
        )
        .render();
        assert!(s.starts_with("#!/bin/bash\n"));
        let lines = sbatch_lines(&s);
        for want in [
            "--array=0-2%2",
            "--requeue",
            "--open-mode=append",
            "--output=\"/scratch/my results/quick/slurm/logs/%A_%a.log\"",
            "--error=\"/scratch/my results/quick/slurm/logs/%A_%a.log\"",
            "--chdir=\"/scratch/my results/quick\"",
            "--cpus-per-task=4",
            "--time=01:30:00",
            "--partition=short",
            "--account=granular",
            "--mem=8G",
        ] {
            assert!(lines.contains(&want), "missing #SBATCH {want} in\n{s}");
        }
        // sbatch stops reading #SBATCH lines at the first command: all must come first.
        let first_cmd = s
            .lines()
            .position(|l| !l.starts_with('#') && !l.trim().is_empty())
            .unwrap();
        let lines: Vec<&str> = s.lines().collect();
        let last_sbatch = lines
            .iter()
            .rposition(|l| l.starts_with("#SBATCH"))
            .unwrap();
        assert!(last_sbatch < first_cmd);
        let unthrottled = example(
            ArrayChunk {
                first_task: 0,
                tasks: 3,
            },
            None,
        )
        .render();
        assert!(sbatch_lines(&unthrottled).contains(&"--array=0-2"));
    }

    #[test]
    fn command_is_the_runner_with_quoted_paths_and_overrides() {
        let s = example(
            ArrayChunk {
                first_task: 2,
                tasks: 1,
            },
            None,
        )
        .render();
        let cmd = s.lines().find(|l| l.contains(" run ")).unwrap();
        assert_eq!(
            cmd,
            "/home/u/bin/granflow run '/scratch/my results/quick/sweep.ron' \
             --results '/scratch/my results' --threads \"${SLURM_CPUS_PER_TASK:-1}\" \
             --job-ids '/scratch/my results/quick/slurm/scripts/submit0.ids' \
             --job-range \"$FIRST:$END\""
        );
        assert!(s.contains("# The overrides restitution=0.9 'note=it'\\''s' are applied"));
    }

    /// Run the script's arithmetic in bash with a stand-in granflow and compare the job ranges
    /// with `split::task_jobs` (an independent check of the shell code).
    #[test]
    fn bash_computes_the_same_job_ranges_as_the_planner() {
        let dir = std::env::temp_dir().join(format!("granflow-script-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("slurm/tasks")).unwrap();
        let fake = dir.join("fake-granflow");
        std::fs::write(&fake, "#!/bin/bash\necho \"ARGS $*\"\n").unwrap();
        Command::new("chmod").arg("+x").arg(&fake).status().unwrap();
        let (jobs, jpt) = (7usize, 3usize);
        let chunk = ArrayChunk {
            first_task: 1,
            tasks: 2,
        };
        let mut script = example(chunk, None);
        script.sweep_dir = dir.clone();
        script.granflow = fake;
        script.sets.clear();
        let text = script.render();
        for index in 0..chunk.tasks {
            let out = Command::new("bash")
                .arg("-c")
                .arg(&text)
                .env("SLURM_ARRAY_TASK_ID", index.to_string())
                .env("SLURM_ARRAY_JOB_ID", "77")
                .env("SLURM_CPUS_PER_TASK", "4")
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let stdout = String::from_utf8_lossy(&out.stdout);
            let r = super::super::split::task_jobs(chunk.first_task + index, jpt, jobs);
            let want = format!("--job-range {}:{}", r.start, r.end);
            assert!(stdout.contains("--job-ids "), "{stdout} lacks --job-ids");
            assert!(stdout.contains(&want), "{stdout} lacks {want}");
            let exit =
                std::fs::read_to_string(dir.join(format!("slurm/tasks/77_{index}.exit"))).unwrap();
            assert!(exit.starts_with("0 0 "), "exit record '{exit}'");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn quoting_survives_the_shell() {
        for s in ["plain", "with space", "it's", "$HOME", "a\"b", ""] {
            let out = Command::new("bash")
                .arg("-c")
                .arg(format!("printf %s {}", shell_quote(s)))
                .output()
                .unwrap();
            assert_eq!(String::from_utf8_lossy(&out.stdout), s);
        }
    }
}
