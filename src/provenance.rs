//! Provenance: which code made a result (granflow version, the commit it was built from, the
//! physics version of the engine and the version of the analysis), where and when.
//!
//! Job ids hold the physical input only (docs/sweeps.md, "Job ids"): a result made by another engine or
//! analysis version keeps its id and is *flagged* as outdated by `status` and the tables;
//! `granflow run --rerun-outdated` recomputes it (from scratch when the engine changed, from the
//! job's last checkpoint, whose records are complete, when only the analysis did).

use serde::{Deserialize, Serialize};

/// The granflow release (Cargo's version).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The commit granflow was built from (`-dirty` with uncommitted changes; "unknown" outside
/// git), embedded by build.rs.
pub const COMMIT: &str = env!("GRANFLOW_COMMIT");

/// Who made a result, with what, where and when.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Provenance {
    /// granflow version
    pub granflow: String,
    /// commit of the build
    pub commit: String,
    /// the engine's physics version (its declaration's `version`)
    pub engine_version: u32,
    /// the analysis' version (its kind's `version`)
    pub analysis_version: u32,
    /// the machine
    pub host: String,
    /// when the job first started and when it finished (UTC, RFC 3339)
    pub started: String,
    pub finished: String,
}

impl Provenance {
    /// This build on this machine, with the given versions; times left to the caller.
    pub fn here(engine_version: u32, analysis_version: u32) -> Self {
        Provenance {
            granflow: VERSION.to_string(),
            commit: COMMIT.to_string(),
            engine_version,
            analysis_version,
            host: host(),
            started: String::new(),
            finished: String::new(),
        }
    }

    /// Why a result made with this provenance is outdated for an engine now at physics version
    /// `engine_version` whose analysis is at `analysis_version` (None: current). Results from
    /// before provenance was recorded carry version 0: unknown, so outdated.
    pub fn outdated(&self, engine_version: u32, analysis_version: u32) -> Option<Outdated> {
        if self.engine_version != engine_version {
            Some(Outdated {
                engine_changed: true,
                reason: format!(
                    "made by engine version {}, now {engine_version}",
                    self.engine_version
                ),
            })
        } else if self.analysis_version != analysis_version {
            Some(Outdated {
                engine_changed: false,
                reason: format!(
                    "made by analysis version {}, now {analysis_version}",
                    self.analysis_version
                ),
            })
        } else {
            None
        }
    }

    /// "granflow 0.1.0 (abc123def456)".
    pub fn build() -> String {
        format!("granflow {VERSION} ({COMMIT})")
    }
}

/// Why a result is outdated, and whether its engine changed (then the run is redone from the
/// start; else only its analysis, from the records of its last checkpoint).
#[derive(Clone, Debug, PartialEq)]
pub struct Outdated {
    pub engine_changed: bool,
    pub reason: String,
}

/// The host name (Linux: /proc/sys/kernel/hostname; else $HOSTNAME; else "unknown").
pub fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// Now, UTC, RFC 3339 to the second.
pub fn now() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

/// Lower-case hex digits of bytes: the digests that name inputs (job ids, checkpoints'
/// records, LAMMPS dumps, bench states).
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
