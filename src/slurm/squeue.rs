//! One batched `squeue` call for all arrays of a sweep, and parsing of its lines.
//!
//! `squeue --noheader --array --states=all --format=%F|%K|%T|%r|%N --jobs=A,B,...` lists every
//! task of the given arrays that the controller still knows (pending, running, and finished
//! ones for `MinJobAge`, 300 s by default), one line per task thanks to `--array`. No `sacct`.

use anyhow::{Context, Result, bail};
use std::collections::BTreeMap;
use std::process::Command;

/// The `--format` granflow asks for: array job id, array task id, state, reason, nodes.
pub const SQUEUE_FORMAT: &str = "%F|%K|%T|%r|%N";

/// What squeue says about one array task.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QueuedTask {
    /// `PENDING`, `RUNNING`, `COMPLETING`, `COMPLETED`, `FAILED`, `CANCELLED`, `TIMEOUT`, ...
    pub state: String,
    /// Why it is pending or how it ended (`JobArrayTaskLimit`, `BeginTime`, `NonZeroExitCode`, ...).
    pub reason: String,
    /// Node list (empty while pending).
    pub nodes: String,
}

/// squeue's view, keyed by (array job id, array index).
pub type QueueView = BTreeMap<(String, usize), QueuedTask>;

/// The arguments of the one squeue call for these array job ids.
pub fn squeue_args(array_job_ids: &[String]) -> Vec<String> {
    vec![
        "--noheader".into(),
        "--array".into(),
        "--states=all".into(),
        format!("--format={SQUEUE_FORMAT}"),
        format!("--jobs={}", array_job_ids.join(",")),
    ]
}

/// Parse squeue's output in [`SQUEUE_FORMAT`]. Lines of tasks that are not single array
/// tasks (e.g. an unexpanded range `2-5%2`) are an error: `--array` should prevent them.
pub fn parse_squeue(text: &str) -> Result<QueueView> {
    let mut view = QueueView::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.splitn(5, '|').collect();
        if fields.len() != 5 {
            bail!(
                "squeue line {}: expected 5 '|'-separated fields, got '{line}'",
                n + 1
            );
        }
        let index: usize = fields[1].trim().parse().with_context(|| {
            format!(
                "squeue line {}: array task id '{}' is not a single index",
                n + 1,
                fields[1]
            )
        })?;
        view.insert(
            (fields[0].trim().to_string(), index),
            QueuedTask {
                state: fields[2].trim().to_string(),
                reason: fields[3].trim().to_string(),
                nodes: fields[4].trim().to_string(),
            },
        );
    }
    Ok(view)
}

/// Run the one squeue call. Arrays the controller has forgotten are simply absent; if it has
/// forgotten all of them squeue exits 1 with "Invalid job id specified", which is an empty view.
pub fn query(array_job_ids: &[String]) -> Result<QueueView> {
    if array_job_ids.is_empty() {
        return Ok(QueueView::new());
    }
    let out = Command::new("squeue")
        .args(squeue_args(array_job_ids))
        .output()
        .context("running squeue (is Slurm's client installed and on PATH?)")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        if stderr.contains("Invalid job id") {
            return Ok(QueueView::new());
        }
        bail!("squeue failed ({}): {}", out.status, stderr.trim());
    }
    parse_squeue(&String::from_utf8_lossy(&out.stdout))
}

/// Whether a task in this squeue state may still run (or is running) its jobs.
pub fn is_active(state: &str) -> bool {
    matches!(
        state,
        "PENDING"
            | "RUNNING"
            | "CONFIGURING"
            | "COMPLETING"
            | "REQUEUED"
            | "REQUEUE_FED"
            | "REQUEUE_HOLD"
            | "RESIZING"
            | "SUSPENDED"
            | "STOPPED"
            | "SIGNALING"
            | "STAGE_OUT"
            | "RESV_DEL_HOLD"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lines as printed by Slurm 22.05 for a throttled array (`--array=0-5%2`).
    const SAMPLE: &str = "5|2|PENDING|JobArrayTaskLimit|\n\
                          5|3|PENDING|JobArrayTaskLimit|\n\
                          5|1|RUNNING|None|localhost\n\
                          5|0|COMPLETED|None|localhost\n\
                          9|0|FAILED|NonZeroExitCode|node[01-02]\n";

    #[test]
    fn parses_one_entry_per_task() {
        let v = parse_squeue(SAMPLE).unwrap();
        assert_eq!(v.len(), 5);
        let t = &v[&("5".to_string(), 1)];
        assert_eq!(
            (t.state.as_str(), t.nodes.as_str()),
            ("RUNNING", "localhost")
        );
        assert_eq!(v[&("5".to_string(), 2)].reason, "JobArrayTaskLimit");
        assert_eq!(v[&("9".to_string(), 0)].nodes, "node[01-02]");
    }

    #[test]
    fn rejects_unexpanded_ranges_and_short_lines() {
        assert!(parse_squeue("5|2-5%2|PENDING|JobArrayTaskLimit|\n").is_err());
        assert!(parse_squeue("5|2|PENDING\n").is_err());
    }

    #[test]
    fn one_call_for_all_arrays() {
        let args = squeue_args(&["12".into(), "13".into()]);
        assert!(args.contains(&"--jobs=12,13".to_string()));
        assert!(args.contains(&"--array".to_string()));
        assert!(is_active("PENDING") && !is_active("FAILED") && !is_active("COMPLETED"));
    }
}
