//! What `granflow bench` reports and how it measures memory: the result whose field names are
//! the `--json` keys ([`BenchResult`]), the neighbour search a workload uses, and the growth of
//! the process's peak resident memory per particle.

use clap::ValueEnum;
use serde::Serialize;

/// The neighbour search a benchmark uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SearchChoice {
    Auto,
    Cells,
    Lists,
}

/// One benchmark result; the field names are the JSON keys.
#[derive(Debug, Serialize, serde::Deserialize)]
pub struct BenchResult {
    pub workload: String,
    pub n: usize,
    /// null (NaN) where it does not apply
    #[serde(deserialize_with = "null_as_nan")]
    pub phi: f64,
    pub collisions_per_s: f64,
    pub events_per_s: f64,
    pub bytes_per_particle: f64,
    /// lattice gases only
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub site_updates_per_s: Option<f64>,
    /// DSMC only: simulator moves per second
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_per_s: Option<f64>,
    /// EDMD with --snapshots: wall seconds per snapshot spent on its analysis record (the
    /// statistics included with --statistics), inside the timed stretch
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record_seconds: Option<f64>,
    /// DEM only: particle-steps per second (N x steps / wall seconds)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub particle_steps_per_s: Option<f64>,
    /// DEM only: pair contacts per particle and step in the timed stretch
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts_per_particle: Option<f64>,
    /// DEM only: the threads it ran on
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
}

/// A number written as null (NaN in JSON) read back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Resident memory of the process, and its peak, in bytes (Linux; None elsewhere).
pub fn resident() -> Option<(f64, f64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb = |key: &str| {
        status
            .lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .map(|v| v * 1024.0)
    };
    Some((kb("VmRSS:")?, kb("VmHWM:")?))
}

/// Start measuring what a workload costs in memory: reset the peak-RSS mark (Linux) and
/// return the resident size now.
pub fn memory_baseline() -> Option<f64> {
    // give memory freed by an earlier workload back to the system first, so that this one's
    // allocations raise the peak instead of reusing it
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only returns free heap memory to the system
    unsafe {
        libc::malloc_trim(0);
    }
    // writing 5 to clear_refs resets VmHWM to the current RSS
    std::fs::write("/proc/self/clear_refs", b"5").ok()?;
    resident().map(|(rss, _)| rss)
}

/// Bytes per particle that a workload really cost: the growth of the process's peak resident
/// memory from `baseline` (set-up, warm-up, snapshots and all), over N; `fallback` where the
/// system cannot tell.
pub fn bytes_per_particle(baseline: Option<f64>, n: usize, fallback: f64) -> f64 {
    match (baseline, resident()) {
        (Some(b), Some((_, peak))) if peak > b => (peak - b) / n.max(1) as f64,
        _ => fallback,
    }
}
