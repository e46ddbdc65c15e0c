//! `result.ron`: a finished job's result (its presence means done).

use super::{RESULT_FILE, write_atomic};
use crate::analysis::Analysis;
use crate::engine::Counters;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A finished job's result (`result.ron`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobResult {
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
/// carry the id of its directory, and (when it has one) match its checksum.
pub fn read_result(dir: &Path) -> anyhow::Result<JobResult> {
    let path = dir.join(RESULT_FILE);
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let result: JobResult =
        ron::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    super::check_owner(dir, &result.id, &path)?;
    if !result.checksum.is_empty() {
        let intact = blank_checksum(&text)
            .is_some_and(|(blank, sum)| sum == result.checksum && checksum_of(&blank) == sum);
        anyhow::ensure!(
            intact,
            "{}: checksum mismatch (the file was changed after it was written)",
            path.display()
        );
    }
    Ok(result)
}

/// Write a job's result atomically (this marks it done), with its checksum.
pub fn write_result(dir: &Path, result: &JobResult) -> anyhow::Result<()> {
    let blank = JobResult {
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
    let sealed = text.replacen(
        &empty,
        &format!("{CHECKSUM_FIELD}{}\"", checksum_of(&text)),
        1,
    );
    write_atomic(&dir.join(RESULT_FILE), sealed.as_bytes())?;
    Ok(())
}
