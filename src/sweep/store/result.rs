//! `result.ron`: a finished job's result (its presence means done), sealed by a checksum.
//!
//! The checksum is SHA-256 (first 16 hex digits) of the file's text with the checksum's value
//! left empty; the job's log repeats it in its `done` line. A result of layout 2 (every result
//! written since the `format` field exists) without a checksum, with an empty one, or with one
//! that does not match its text is damaged; so is a result whose job log names another
//! checksum. Results of older layouts (no `format` field) carry no checksum where they were
//! written before checksums existed: they read as they are, as long as their log names none.

use super::{RESULT_FILE, write_atomic};
use crate::analysis::Analysis;
use crate::engine::Counters;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Layout of `result.ron` written now (1: every older layout, which had no `format` field;
/// 2: the checksum is required).
pub const RESULT_FORMAT: u32 = 2;

/// A finished job's result (`result.ron`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobResult {
    /// layout of the file ([`RESULT_FORMAT`]; 1 for files without the field)
    #[serde(default = "older_layout")]
    pub format: u32,
    /// the job id
    pub id: String,
    /// the engine that ran it (results written before the registry are EDMD's)
    #[serde(default = "edmd")]
    pub engine: String,
    /// N
    pub particles: usize,
    /// snapshots taken after the initial one
    pub snapshots: u32,
    /// final collisions per particle (0 for engines without collisions)
    pub collisions_per_particle: f64,
    /// final simulated time
    pub time: f64,
    /// final time steps (0 for event-driven engines)
    #[serde(default)]
    pub steps: u64,
    /// final counters, named as the engine declares them
    pub counters: Counters,
    /// wall-clock seconds of simulation (summed over resumes, up to their last checkpoint)
    pub wall_seconds: f64,
    /// events per wall-clock second
    pub events_per_second: f64,
    /// for runs until steady: where and why the job stopped, or that it reached its cap
    #[serde(default)]
    pub stop_reason: String,
    /// which code made it, where and when (results of older builds: empty, versions 0)
    #[serde(default)]
    pub provenance: crate::provenance::Provenance,
    /// SHA-256 (first 16 hex digits) of the file's text written with this field empty; a
    /// result whose text does not match is damaged (results of older builds: empty, not
    /// checked)
    #[serde(default)]
    pub checksum: String,
    /// the analysis
    pub analysis: Analysis,
}

impl JobResult {
    /// The result without what depends on the wall clock (seconds, rates, start and finish
    /// times, and so the checksum): what determinism promises to be bitwise the same for the
    /// same parameters and seed, whatever the threads and interruptions.
    pub fn without_wall_clock(&self) -> JobResult {
        let mut r = self.clone();
        r.wall_seconds = 0.0;
        r.events_per_second = 0.0;
        r.provenance.started.clear();
        r.provenance.finished.clear();
        r.checksum.clear();
        r
    }

    /// The final reading of a clock.
    pub fn clock(&self, clock: crate::engine::Clock) -> f64 {
        match clock {
            crate::engine::Clock::CollisionsPerParticle => self.collisions_per_particle,
            crate::engine::Clock::Steps => self.steps as f64,
            crate::engine::Clock::Time => self.time,
        }
    }
}

fn older_layout() -> u32 {
    1
}

fn edmd() -> String {
    "edmd".into()
}

/// The top-level `checksum` field as the pretty RON writer puts it (fields of nested values
/// are indented further).
const CHECKSUM_FIELD: &str = "\n    checksum: \"";

/// The checksum of a result's text: SHA-256 (first 16 hex digits) of the text with the value
/// of its top-level `checksum` field empty. Computed on the file's own text, never on a
/// re-serialisation, so that a result stays valid when a later granflow reads it into
/// changed types.
fn checksum_of(text_with_blank_field: &str) -> String {
    crate::sweep::job::id_of_canonical(text_with_blank_field).0
}

/// A result's text with its top-level checksum value cut out, and that value (None without
/// the field).
fn blank_checksum(text: &str) -> Option<(String, &str)> {
    let start = text.find(CHECKSUM_FIELD)? + CHECKSUM_FIELD.len();
    let len = text[start..].find('"')?;
    let blank = format!("{}{}", &text[..start], &text[start + len..]);
    Some((blank, &text[start..start + len]))
}

/// Read a finished job's result and check that it is this job's and undamaged: it must parse,
/// carry the id of its directory, match its checksum (required from layout 2 on, and whenever
/// the job's log names one), and carry the checksum its log's `done` line names.
pub fn read_result(dir: &Path) -> anyhow::Result<JobResult> {
    let path = dir.join(RESULT_FILE);
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let result: JobResult =
        ron::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    super::check_owner(dir, &result.id, &path)?;
    let logged = logged_checksum(dir);
    if result.checksum.is_empty() {
        anyhow::ensure!(
            result.format < 2 && logged.is_none(),
            "{}: no checksum (removed or blanked after the file was written)",
            path.display()
        );
        return Ok(result);
    }
    let intact = blank_checksum(&text)
        .is_some_and(|(blank, sum)| sum == result.checksum && checksum_of(&blank) == sum);
    anyhow::ensure!(
        intact,
        "{}: checksum mismatch (the file was changed after it was written)",
        path.display()
    );
    if let Some(logged) = logged {
        anyhow::ensure!(
            logged == result.checksum,
            "{}: checksum {} where the job's log says {logged} (replaced after it was written)",
            path.display(),
            result.checksum
        );
    }
    Ok(result)
}

/// The checksum the job's log names for its current result: that of the last `done` line
/// (`done checksum=<hex>`), unless a later start, resume or retirement of the result makes a
/// new result due.
fn logged_checksum(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(super::LOG_FILE)).ok()?;
    last_course_event(&text)?
        .strip_prefix("done")?
        .split_whitespace()
        .find_map(|w| w.strip_prefix("checksum="))
        .filter(|s| !s.is_empty())
        .map(str::to_string)
}

/// The last event of a log's text that marks the job's course (start, resume, done, a result
/// retired as outdated), without its time.
pub(super) fn last_course_event(text: &str) -> Option<&str> {
    super::log_events(text).into_iter().rev().find(|e| {
        ["done", "start", "resume", "outdated"]
            .iter()
            .any(|w| e.starts_with(w))
    })
}

/// The log line that marks a job done, with the checksum of its result (results of older
/// layouts may have none).
pub fn done_line(checksum: &str) -> String {
    if checksum.is_empty() {
        "done".into()
    } else {
        format!("done checksum={checksum}")
    }
}

/// Write a job's result atomically (this marks it done), with its checksum; the checksum.
pub fn write_result(dir: &Path, result: &JobResult) -> anyhow::Result<String> {
    let blank = JobResult {
        format: RESULT_FORMAT,
        checksum: String::new(),
        ..result.clone()
    };
    let text = ron::ser::to_string_pretty(&blank, ron::ser::PrettyConfig::default())?;
    let empty = format!("{CHECKSUM_FIELD}\"");
    anyhow::ensure!(
        text.matches(&empty).count() == 1,
        "result of job {}: no single top-level checksum field in its text",
        result.id
    );
    let checksum = checksum_of(&text);
    let sealed = text.replacen(&empty, &format!("{CHECKSUM_FIELD}{checksum}\""), 1);
    let path = dir.join(RESULT_FILE);
    write_atomic(&path, sealed.as_bytes())
        .map_err(|e| crate::sweep::fs_error::PathError::new(&path, e))?;
    Ok(checksum)
}
