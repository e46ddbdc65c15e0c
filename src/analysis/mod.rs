//! Density-wave analysis of engine snapshots: coarse-grained fields, 2D power spectra,
//! cross-channel profiles, the steady-state detector and the structure classifier.
//!
//! Engine-agnostic: it sees only [`Snapshot`]s (positions, velocities, angular velocities and
//! the box). A job calls [`record_snapshot`] at every snapshot (the compact record is what a
//! checkpoint keeps) and [`analyse_job`] once at the end.
//!
//! (Signatures fixed here so that the job runner can be written against them.)

use crate::engine::Snapshot;
use serde::{Deserialize, Serialize};

/// Analysis settings of a sweep or job (all have documented defaults).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AnalysisSettings {
    /// coarse-graining grid N1 x N2 x N3 (x, y, z); None: sized so that a cell holds several
    /// particles on average
    pub grid: Option<[usize; 3]>,
    /// number of bins across the channel for profiles (thesis: 25)
    pub profile_bins: usize,
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        AnalysisSettings {
            grid: None,
            profile_bins: 25,
        }
    }
}

/// What one snapshot contributes to the analysis: compact, serialisable (kept in checkpoints).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SnapshotRecord {
    /// collisions per particle at the snapshot
    pub collisions_per_particle: f64,
    /// simulated time at the snapshot
    pub time: f64,
    /// translational kinetic energy per particle
    pub translational_energy: f64,
    /// rotational kinetic energy per particle
    pub rotational_energy: f64,
}

/// One job's analysis, in the shape the sweep tables need.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JobAnalysis {
    pub summary: Summary,
    pub spectra: Vec<SpectrumRow>,
    pub profiles: Vec<ProfileRow>,
    pub energy: Vec<EnergyRow>,
    /// per-snapshot labels where the structure changed (first entry: the initial label)
    pub evolution: Vec<StructureChange>,
}

/// The one-row summary of a job's structure.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// structure label of the steady window: "homogeneous", "plug", "s-wave", "slug",
    /// "wavy-slug", "s-wave+slug", or "not-steady" when the run never became steady
    pub label: String,
    /// humps of an S-wave along L (0 when there is none)
    pub humps: u32,
    /// structure along z (spanwise) stands above noise
    pub three_dimensional: bool,
    /// the run reached a steady state
    pub steady: bool,
    /// steady window in collisions per particle
    pub steady_start: f64,
    pub steady_end: f64,
    /// number of snapshots in the steady window
    pub steady_snapshots: u32,
    /// power of each family (xy plane): transverse (plug), along-flow symmetric (slug),
    /// antisymmetric x-varying (S-wave), symmetric x-varying remainder; spanwise (z) power
    pub power_transverse: f64,
    pub power_along_flow: f64,
    pub power_antisymmetric: f64,
    pub power_symmetric_rest: f64,
    pub power_spanwise: f64,
    /// shot-noise power of a random arrangement with the same counts, per family mode
    pub noise_level: f64,
    /// mean translational and rotational kinetic energy per particle over the steady window
    pub mean_translational_energy: f64,
    pub mean_rotational_energy: f64,
    /// wall slip velocity U_x at the wall, in sqrt(g d)
    pub slip_velocity: f64,
}

/// One row of a folded, window-averaged power spectrum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpectrumRow {
    /// "xy", "xz" or "yz"
    pub plane: String,
    pub k1: u32,
    pub k2: u32,
    pub power: f64,
}

/// One bin of a cross-channel profile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ProfileRow {
    /// "phi", "u_x", "omega_z", "T", "theta"
    pub quantity: String,
    pub bin: u32,
    /// bin centre in units of d
    pub y: f64,
    pub value: f64,
}

/// One point of the kinetic-energy trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnergyRow {
    pub collisions_per_particle: f64,
    pub time: f64,
    /// per particle
    pub translational: f64,
    /// per particle
    pub rotational: f64,
}

/// A change of the per-snapshot structure label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StructureChange {
    pub collisions_per_particle: f64,
    pub label: String,
    pub humps: u32,
}

/// Reduce one snapshot to what the analysis keeps of it.
pub fn record_snapshot(snapshot: &Snapshot, _settings: &AnalysisSettings) -> SnapshotRecord {
    let n = snapshot.len().max(1) as f64;
    SnapshotRecord {
        collisions_per_particle: snapshot.collisions_per_particle,
        time: snapshot.time,
        translational_energy: snapshot.translational_energy / n,
        rotational_energy: snapshot.rotational_energy / n,
    }
}

/// Analyse a job's snapshot records (in order of simulated time).
///
/// Interim version (until the classifier lands): the energy trace only, label "unclassified".
pub fn analyse_job(records: &[SnapshotRecord], _settings: &AnalysisSettings) -> JobAnalysis {
    let energy: Vec<EnergyRow> = records
        .iter()
        .map(|r| EnergyRow {
            collisions_per_particle: r.collisions_per_particle,
            time: r.time,
            translational: r.translational_energy,
            rotational: r.rotational_energy,
        })
        .collect();
    let summary = Summary {
        label: "unclassified".into(),
        humps: 0,
        three_dimensional: false,
        steady: false,
        steady_start: f64::NAN,
        steady_end: f64::NAN,
        steady_snapshots: 0,
        power_transverse: f64::NAN,
        power_along_flow: f64::NAN,
        power_antisymmetric: f64::NAN,
        power_symmetric_rest: f64::NAN,
        power_spanwise: f64::NAN,
        noise_level: f64::NAN,
        mean_translational_energy: f64::NAN,
        mean_rotational_energy: f64::NAN,
        slip_velocity: f64::NAN,
    };
    JobAnalysis {
        summary,
        spectra: Vec::new(),
        profiles: Vec::new(),
        energy,
        evolution: Vec::new(),
    }
}
