//! Density-wave analysis of engine snapshots: coarse-grained fields, 2D power spectra,
//! cross-channel profiles, the steady-state detector and the structure classifier.
//!
//! Engine-agnostic: it sees only [`Snapshot`]s (positions, velocities, angular velocities and
//! the box). A job calls [`record_snapshot`] at every snapshot (the compact record is what a
//! checkpoint keeps) and [`analyse_job`] once at the end.
//!
//! Modules: [`fields`] (grid and cellwise averages), [`spectrum`] (2D FFT power spectra),
//! [`profiles`] (binwise profiles across the channel), [`steady`] (steady-state detector),
//! [`classify`] (family decomposition vs shot noise, labels), `report` (evolution, rows and
//! strings of the result), [`snapshot_io`] (XYZ and VTK files). The definitions, defaults and thresholds are documented in README.md, section
//! "Analysis and structure classifier".

pub mod classify;
pub mod fields;
pub mod profiles;
pub mod rarefied;
mod report;
pub mod snapshot_io;
pub mod spectrum;
pub mod steady;

pub use profiles::BinSums;
pub use report::MIN_LABEL_RUN;
pub use snapshot_io::{write_vtk_density, write_xyz};

use crate::engine::Snapshot;
use classify::{FamilyPowers, assess, family_powers, noise_per_mode};
use fields::{Grid, SPHERE_VOLUME, cell_counts, plane_counts};
use report::{dominant_modes, empty_summary, family_peaks, spectrum_rows, structure_evolution};
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
    /// mean number of particle centres per cell of the default grid (used when `grid` is None)
    pub cell_particles: f64,
    /// fewest snapshots in a steady window (fewer: the run counts as not steady)
    pub min_steady_snapshots: usize,
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        AnalysisSettings {
            grid: None,
            profile_bins: 25,
            cell_particles: 4.0,
            min_steady_snapshots: 4,
        }
    }
}

impl AnalysisSettings {
    /// Check the settings; the message names the key, its value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(g) = self.grid
            && g.iter().any(|&k| k == 0 || k > 4096)
        {
            return Err(format!(
                "analysis grid = {g:?} is out of range: allowed 1 to 4096 cells per axis"
            ));
        }
        if self.profile_bins == 0 || self.profile_bins > 100_000 {
            return Err(format!(
                "analysis profile_bins = {} is out of range: allowed 1 to 100000",
                self.profile_bins
            ));
        }
        if !(self.cell_particles.is_finite() && self.cell_particles > 0.0) {
            return Err(format!(
                "analysis cell_particles = {} is out of range: allowed a finite value > 0",
                self.cell_particles
            ));
        }
        if self.min_steady_snapshots < 2 {
            return Err(format!(
                "analysis min_steady_snapshots = {} is out of range: allowed >= 2",
                self.min_steady_snapshots
            ));
        }
        Ok(())
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
    /// N, number of particles
    #[serde(default)]
    pub particles: u64,
    /// box extents [L, W, H]
    #[serde(default)]
    pub box_extent: [f64; 3],
    /// g of the snapshot (scales the profiles)
    #[serde(default)]
    pub gravity: f64,
    /// K = 4 I / (m d^2)
    #[serde(default)]
    pub inertia_factor: f64,
    /// coarse-graining grid N1 x N2 x N3
    #[serde(default)]
    pub grid: [u32; 3],
    /// volume of the gridded region (the region open to particle centres)
    #[serde(default)]
    pub grid_volume: f64,
    /// centres per column of the xy plane (summed over z), index i N2 + j
    #[serde(default)]
    pub counts_xy: Vec<u32>,
    /// centres per column of the xz plane (summed over y), index i N3 + k
    #[serde(default)]
    pub counts_xz: Vec<u32>,
    /// centres per column of the yz plane (summed over x), index j N3 + k
    #[serde(default)]
    pub counts_yz: Vec<u32>,
    /// per-bin sums of the cross-channel profiles
    #[serde(default)]
    pub profile: Vec<BinSums>,
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
    /// the window all averages use, in collisions per particle: the steady window, or for a
    /// run that is not steady its final third
    pub window_start: f64,
    pub window_end: f64,
    /// power / expected shot-noise power of each family (1 for a random arrangement)
    pub ratio_transverse: f64,
    pub ratio_along_flow: f64,
    pub ratio_antisymmetric: f64,
    pub ratio_symmetric_rest: f64,
    pub ratio_spanwise: f64,
    /// the ratio above which each family counts as structure (5-sigma noise quantile, >= 2)
    pub threshold_transverse: f64,
    pub threshold_along_flow: f64,
    pub threshold_antisymmetric: f64,
    pub threshold_symmetric_rest: f64,
    pub threshold_spanwise: f64,
    /// max(ratio / threshold, peak ratio / peak threshold) of each family: > 1 is significant
    /// (the sum test over the whole family or the peak test on its strongest mode)
    pub significance_transverse: f64,
    pub significance_along_flow: f64,
    pub significance_antisymmetric: f64,
    pub significance_symmetric_rest: f64,
    pub significance_spanwise: f64,
    /// each family's strongest folded mode: "family plane(k1,k2) ratio/threshold" joined by "; "
    pub family_peaks: String,
    /// dominant |k_x| of the antisymmetric excess power and the fraction of that excess in it
    pub antisymmetric_kx: u32,
    pub antisymmetric_coherence: f64,
    /// the five strongest xy modes: "(k_x,k_y) P [P/noise]" separated by "; "
    pub dominant_modes: String,
    /// the coarse-graining grid
    pub grid_x: u32,
    pub grid_y: u32,
    pub grid_z: u32,
    /// N
    pub particles: u64,
    /// why a run is not steady, or other caveats (empty when there are none)
    pub note: String,
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

/// Reduce one snapshot to what the analysis keeps of it: energies, the plane counts of the
/// coarse-graining grid and the profile bin sums (no particles).
pub fn record_snapshot(snapshot: &Snapshot, settings: &AnalysisSettings) -> SnapshotRecord {
    let n = snapshot.len();
    let grid = Grid::new(&snapshot.geometry, n, settings);
    let [xy, xz, yz] = plane_counts(&cell_counts(&snapshot.positions, &grid), &grid);
    SnapshotRecord {
        collisions_per_particle: snapshot.collisions_per_particle,
        time: snapshot.time,
        translational_energy: snapshot.translational_energy / n.max(1) as f64,
        rotational_energy: snapshot.rotational_energy / n.max(1) as f64,
        particles: n as u64,
        box_extent: snapshot.geometry.extents(),
        gravity: snapshot.gravity,
        inertia_factor: snapshot.inertia_factor,
        grid: grid.n.map(|k| k as u32),
        grid_volume: grid.volume(),
        counts_xy: xy,
        counts_xz: xz,
        counts_yz: yz,
        profile: profiles::bin_sums(snapshot, &grid, settings.profile_bins),
    }
}

/// The xy, xz and yz plane fields of phi of a record (averages over the third axis).
pub fn plane_fields(record: &SnapshotRecord) -> [Vec<f64>; 3] {
    let [n1, n2, n3] = record.grid.map(|k| k as usize);
    let v = record.grid_volume;
    let field = |counts: &[u32], cells: usize| -> Vec<f64> {
        let c = SPHERE_VOLUME * cells as f64 / v;
        counts.iter().map(|&k| c * k as f64).collect()
    };
    [
        field(&record.counts_xy, n1 * n2),
        field(&record.counts_xz, n1 * n3),
        field(&record.counts_yz, n2 * n3),
    ]
}

/// True when a record carries a usable grid (all plane counts present).
fn has_fields(r: &SnapshotRecord) -> bool {
    let [n1, n2, n3] = r.grid.map(|k| k as usize);
    n1 > 0
        && n2 > 0
        && n3 > 0
        && r.particles > 0
        && r.grid_volume > 0.0
        && r.counts_xy.len() == n1 * n2
        && r.counts_xz.len() == n1 * n3
        && r.counts_yz.len() == n2 * n3
}

/// Analyse a job's snapshot records (in order of simulated time): energy trace, steady window,
/// window-averaged spectra, families and profiles, the label, and its evolution per snapshot.
/// Never panics; with fewer than `min_steady_snapshots` records the run is "not-steady".
pub fn analyse_job(records: &[SnapshotRecord], settings: &AnalysisSettings) -> JobAnalysis {
    let energy: Vec<EnergyRow> = records
        .iter()
        .map(|r| EnergyRow {
            collisions_per_particle: r.collisions_per_particle,
            time: r.time,
            translational: r.translational_energy,
            rotational: r.rotational_energy,
        })
        .collect();
    let clock: Vec<f64> = records.iter().map(|r| r.collisions_per_particle).collect();
    let trace: Vec<f64> = records.iter().map(|r| r.translational_energy).collect();
    let window = steady::detect(&clock, &trace, settings.min_steady_snapshots);
    let in_window = &records[window.start.min(records.len())..];

    // per-snapshot family powers (records with a usable grid, same grid as the last record)
    let reference = records.iter().rev().find(|r| has_fields(r));
    let same_grid = |r: &SnapshotRecord| {
        has_fields(r) && reference.is_some_and(|q| q.grid == r.grid && q.particles == r.particles)
    };
    let families: Vec<Option<FamilyPowers>> = records
        .iter()
        .map(|r| {
            same_grid(r).then(|| {
                let [xy, xz, yz] = plane_fields(r);
                family_powers(&xy, &xz, &yz, r.grid.map(|k| k as usize))
            })
        })
        .collect();

    let mut summary = empty_summary();
    let mut spectra = Vec::new();
    let mut evolution = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    if let Some(q) = reference {
        let n = q.grid.map(|k| k as usize);
        let p0 = noise_per_mode(q.particles as usize, q.grid_volume);
        // window average of the families and the spectra
        let used: Vec<&SnapshotRecord> = in_window.iter().filter(|r| same_grid(r)).collect();
        let mut avg = FamilyPowers::zero(n);
        for (r, f) in records.iter().zip(&families).skip(window.start) {
            if let Some(f) = f {
                debug_assert!(same_grid(r));
                avg.add_scaled(f, 1.0 / used.len() as f64);
            }
        }
        if used.len() < in_window.len() {
            notes.push(format!(
                "{} snapshots of the window lack fields on the common grid and were skipped",
                in_window.len() - used.len()
            ));
        }
        if !used.is_empty() {
            let a = assess(&avg, n, p0);
            summary.dominant_modes = dominant_modes(&avg.xy, n[0], n[1], p0, 5);
            for (plane, folded) in [&avg.xy, &avg.xz, &avg.yz].into_iter().enumerate() {
                spectra.extend(spectrum_rows(folded, n, plane));
            }
            [
                summary.significance_transverse,
                summary.significance_along_flow,
                summary.significance_antisymmetric,
                summary.significance_symmetric_rest,
                summary.significance_spanwise,
            ] = a.significance;
            summary.family_peaks = family_peaks(&a);
            summary.power_transverse = avg.transverse;
            summary.power_along_flow = avg.along_flow;
            summary.power_antisymmetric = avg.antisymmetric;
            summary.power_symmetric_rest = avg.symmetric_rest;
            summary.power_spanwise = avg.spanwise;
            [
                summary.ratio_transverse,
                summary.ratio_along_flow,
                summary.ratio_antisymmetric,
                summary.ratio_symmetric_rest,
                summary.ratio_spanwise,
            ] = a.ratios;
            [
                summary.threshold_transverse,
                summary.threshold_along_flow,
                summary.threshold_antisymmetric,
                summary.threshold_symmetric_rest,
                summary.threshold_spanwise,
            ] = a.thresholds;
            summary.antisymmetric_kx = a.antisymmetric_kx;
            summary.antisymmetric_coherence = a.coherence;
            if window.steady {
                summary.label = a.label.into();
                summary.humps = a.humps;
                summary.three_dimensional = a.three_dimensional;
            } else {
                notes.push(format!(
                    "the final window alone would read \"{}\"{}",
                    a.label,
                    if a.three_dimensional { " (3D)" } else { "" }
                ));
            }
        }
        summary.noise_level = p0;
        [summary.grid_x, summary.grid_y, summary.grid_z] = q.grid;
        summary.particles = q.particles;
        evolution = structure_evolution(records, &families, n, p0);
    }
    if window.steady && reference.is_none() {
        summary.label = "unclassified".into();
        notes.push("the records carry no density fields".into());
    }
    if !window.steady {
        notes.insert(0, format!("not steady: {}", window.reason));
    }
    summary.steady = window.steady;
    if let (Some(first), Some(last)) = (in_window.first(), in_window.last()) {
        summary.window_start = first.collisions_per_particle;
        summary.window_end = last.collisions_per_particle;
        if window.steady {
            summary.steady_start = summary.window_start;
            summary.steady_end = summary.window_end;
            summary.steady_snapshots = in_window.len() as u32;
        }
        let m = in_window.len() as f64;
        summary.mean_translational_energy = in_window
            .iter()
            .map(|r| r.translational_energy)
            .sum::<f64>()
            / m;
        summary.mean_rotational_energy =
            in_window.iter().map(|r| r.rotational_energy).sum::<f64>() / m;
    }
    let with_profiles: Vec<&SnapshotRecord> =
        in_window.iter().filter(|r| !r.profile.is_empty()).collect();
    let (profiles, slip) = profiles::profiles(&with_profiles);
    summary.slip_velocity = slip;
    summary.note = notes.join("; ");
    JobAnalysis {
        summary,
        spectra,
        profiles,
        energy,
        evolution,
    }
}
