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
//! mode lists of the result), [`modes`] (the dominant modes and family peaks), [`snapshot_io`] (XYZ and VTK files), [`milestones`] (the structure at given clock
//! readings). The definitions, defaults and thresholds are documented in docs/analysis.md.

mod balance;
pub mod classify;
pub mod columns;
pub mod dense;
pub mod fields;
mod kind;
pub mod labels;
pub mod lattice;
pub mod milestones;
pub mod modes;
mod profiles;
pub mod rarefied;
mod report;
mod snapshot_io;
pub mod spectrum;
pub mod statistics;
pub mod steady;

pub use kind::{
    Analyser, Analysis, AnalysisError, AnalysisKind, Record, StatisticsSnapshot, StopCheck,
};
pub use profiles::BinSums;
pub use report::MIN_LABEL_RUN;
pub use snapshot_io::{SnapshotNames, write_vtk_density, write_xyz};

use crate::engine::{Particles, Snapshot};
use classify::{FamilyPowers, assess, family_powers, noise_per_mode};
use fields::{Grid, SPHERE_VOLUME, cell_counts, plane_counts};
use modes::{DominantMode, FamilyPeak};
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
    /// the run's milestones (from its `run` section, not an analysis setting)
    #[serde(skip)]
    pub milestones: Option<milestones::MilestonePlan>,
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        AnalysisSettings {
            grid: None,
            profile_bins: 25,
            cell_particles: 4.0,
            min_steady_snapshots: 4,
            milestones: None,
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
    /// cumulative x-impulse delivered to both walls (the momentum balance; NaN: not recorded)
    #[serde(default = "nan")]
    pub wall_impulse_x: f64,
    /// total x-momentum sum m c_x
    #[serde(default = "nan")]
    pub momentum_x: f64,
    /// cumulative energy dissipated in collisions (the energy balance)
    #[serde(default = "nan")]
    pub energy_dissipated: f64,
    /// cumulative work of gravity
    #[serde(default = "nan")]
    pub gravity_work: f64,
    /// cumulative energy the collapse guard kept from being dissipated
    #[serde(default = "nan")]
    pub suppressed_dissipation: f64,
    /// pair collisions so far, and those the collapse guard (TC model) made elastic
    #[serde(default)]
    pub pair_collisions: u64,
    #[serde(default)]
    pub tc_elastic_collisions: u64,
}

pub(crate) fn nan() -> f64 {
    f64::NAN
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
    /// the structure at the run's milestones (the `evolution` table)
    #[serde(default)]
    pub milestones: Vec<milestones::MilestoneRow>,
    /// the thesis' statistics (runs with `run.statistics` only)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub statistics: Option<Box<statistics::Statistics>>,
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
    /// the label as shown: with its humps and ` 3d` for a three-dimensional structure
    /// (`s-wave(2) 3d`); results of older analysis versions lack it (empty)
    #[serde(default)]
    pub shown_label: String,
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
    /// each family's strongest folded mode against its peak-test threshold (results of older
    /// versions hold the text "family plane(k1,k2) ratio/threshold; ...")
    #[serde(deserialize_with = "modes::list_or_legacy_text")]
    pub family_peaks: Vec<FamilyPeak>,
    /// fundamental k_x = n of the antisymmetric excess power and the share of that excess in
    /// its odd harmonics n, 3n, 5n, ... (an S-wave's glide symmetry)
    pub antisymmetric_kx: u32,
    pub antisymmetric_coherence: f64,
    /// significance of the slug content: the along-flow modes without the S-wave's even
    /// harmonics 2n, 4n, ... (all along-flow modes without an S-wave)
    #[serde(default = "nan")]
    pub significance_slug: f64,
    /// the five strongest xy modes (results of older versions hold the text
    /// "(k_x,k_y) P [P/noise x]; ...")
    #[serde(deserialize_with = "modes::list_or_legacy_text")]
    pub dominant_modes: Vec<DominantMode>,
    /// the coarse-graining grid
    pub grid_x: u32,
    pub grid_y: u32,
    pub grid_z: u32,
    /// N
    pub particles: u64,
    /// why a run is not steady, or other caveats (empty when there are none)
    pub note: String,
    /// per-snapshot labels over the window: "label p; label p" (most frequent first)
    #[serde(default)]
    pub label_probabilities: String,
    /// the structure the families present in most snapshots name (the label unless mixed)
    #[serde(default)]
    pub candidate_label: String,
    /// fraction of the window's snapshots carrying the candidate label
    #[serde(default = "nan")]
    pub label_probability: f64,
    /// fraction of the window's snapshots in which each family is significant
    #[serde(default = "nan")]
    pub presence_transverse: f64,
    #[serde(default = "nan")]
    pub presence_along_flow: f64,
    #[serde(default = "nan")]
    pub presence_antisymmetric: f64,
    #[serde(default = "nan")]
    pub presence_symmetric_rest: f64,
    #[serde(default = "nan")]
    pub presence_spanwise: f64,
    /// wall x-impulse rate over N m g across the window (1 when steady), and its error
    #[serde(default = "nan")]
    pub momentum_balance: f64,
    #[serde(default = "nan")]
    pub momentum_balance_error: f64,
    /// dissipation over the work of gravity across the window (1 when steady), and its error
    #[serde(default = "nan")]
    pub energy_balance: f64,
    #[serde(default = "nan")]
    pub energy_balance_error: f64,
    /// over the window: fraction of pair collisions the TC model made elastic, and fraction of
    /// the dissipation of constant e that it suppressed
    #[serde(default = "nan")]
    pub window_tc_elastic_fraction: f64,
    #[serde(default = "nan")]
    pub window_suppressed_dissipation: f64,
    /// the collapse guard stayed within its validity limit over the window
    #[serde(default)]
    pub collapse_guard_valid: bool,
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
///
/// Panics when the snapshot carries no particles (the [`Analyser`] checks that first).
pub fn record_snapshot(snapshot: &Snapshot, settings: &AnalysisSettings) -> SnapshotRecord {
    let particles: &Particles = snapshot
        .particles()
        .expect("the structure analysis records snapshots that carry particles");
    let n = particles.len();
    let grid = Grid::new(&particles.geometry, n, settings);
    let [xy, xz, yz] = plane_counts(&cell_counts(&particles.positions, &grid), &grid);
    SnapshotRecord {
        collisions_per_particle: snapshot.progress.collisions_per_particle,
        time: snapshot.progress.time,
        translational_energy: particles.translational_energy / n.max(1) as f64,
        rotational_energy: particles.rotational_energy / n.max(1) as f64,
        particles: n as u64,
        box_extent: particles.geometry.extents(),
        gravity: particles.gravity,
        inertia_factor: particles.inertia_factor,
        grid: grid.n.map(|k| k as u32),
        grid_volume: grid.volume(),
        counts_xy: xy,
        counts_xz: xz,
        counts_yz: yz,
        profile: profiles::bin_sums(particles, &grid, settings.profile_bins),
        wall_impulse_x: particles.wall_momentum[0][0] + particles.wall_momentum[1][0],
        momentum_x: particles.velocities.iter().map(|v| v[0]).sum(),
        energy_dissipated: particles.energy_dissipated,
        gravity_work: particles.gravity_work,
        suppressed_dissipation: particles.suppressed_dissipation,
        pair_collisions: snapshot.counters.get("pair_collisions"),
        tc_elastic_collisions: snapshot.counters.get("tc_elastic_collisions"),
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

/// Per-snapshot verdicts kept between the checks of run-until-steady (a cache: they follow
/// from the records alone, so a resumed job recomputes them and decides the same).
#[derive(Clone, Debug, Default)]
pub struct SteadyCheck {
    verdicts: Vec<Option<(FamilyPowers, classify::Assessment)>>,
}

/// The family powers of one record and the verdict on them, on its own grid (None without
/// fields).
fn verdict(r: &SnapshotRecord) -> Option<(FamilyPowers, classify::Assessment)> {
    has_fields(r).then(|| {
        let n = r.grid.map(|k| k as usize);
        let [xy, xz, yz] = plane_fields(r);
        let f = family_powers(&xy, &xz, &yz, n);
        let a = assess(&f, n, noise_per_mode(r.particles as usize, r.grid_volume));
        (f, a)
    })
}

/// Run-until-steady's question after a snapshot: is the run steady by the documented rule
/// (energy plateau confirmed by the balances) over a window at least `window` long on
/// `clock`, with a label that holds a clear majority of the window's snapshots? Returns why it
/// may stop, or None to go on.
pub fn steady_over(
    records: &[SnapshotRecord],
    settings: &AnalysisSettings,
    clock: crate::engine::Clock,
    window: f64,
    check: &mut SteadyCheck,
) -> Option<String> {
    let on = |r: &SnapshotRecord| match clock {
        crate::engine::Clock::Time => r.time,
        _ => r.collisions_per_particle,
    };
    let cpp: Vec<f64> = records.iter().map(|r| r.collisions_per_particle).collect();
    let trace: Vec<f64> = records.iter().map(|r| r.translational_energy).collect();
    let plateau = steady::detect(&cpp, &trace, settings.min_steady_snapshots);
    if !plateau.steady {
        return None;
    }
    let in_window = &records[plateau.start..];
    let span = on(in_window.last()?) - on(in_window.first()?);
    if span < window {
        return None;
    }
    let confirmed = balance::confirm_by_balances(
        plateau,
        &[
            ("momentum", balance::momentum_balance(in_window)),
            ("energy", balance::energy_balance(in_window)),
        ],
    );
    if !confirmed.steady {
        return None;
    }
    while check.verdicts.len() < records.len() {
        let next = &records[check.verdicts.len()];
        check.verdicts.push(verdict(next));
    }
    let window_verdicts: Vec<&(FamilyPowers, classify::Assessment)> =
        check.verdicts[confirmed.start..].iter().flatten().collect();
    let last = records.last()?;
    let n = last.grid.map(|k| k as usize);
    let mut avg = FamilyPowers::zero(n);
    for (f, _) in &window_verdicts {
        avg.add_scaled(f, 1.0 / window_verdicts.len() as f64);
    }
    let average = assess(
        &avg,
        n,
        noise_per_mode(last.particles as usize, last.grid_volume),
    );
    let verdicts: Vec<classify::Assessment> =
        window_verdicts.iter().map(|(_, a)| a.clone()).collect();
    let stats = labels::statistics(&verdicts, &average);
    (stats.probability >= labels::CLEAR_MAJORITY).then(|| {
        format!(
            "steady over {} .. {} ({} snapshots, {} {}), label {} in {:.0} % of them",
            clock_reading(on(&in_window[0])),
            clock_reading(on(in_window.last().expect("non-empty"))),
            in_window.len(),
            span,
            clock.key(),
            stats.candidate,
            100.0 * stats.probability
        )
    })
}

/// A clock reading as a person writes it: at most six decimals, no trailing zeros
/// (124 for 124.000000, 0.25 for 0.250000).
fn clock_reading(x: f64) -> String {
    let text = format!("{x:.6}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// True when a record carries a usable grid (all plane counts present).
pub(crate) fn has_fields(r: &SnapshotRecord) -> bool {
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

/// The reference record (the last with fields) and the family powers of every record on its
/// grid (None for records without fields or on another grid).
fn common_grid_families(
    records: &[SnapshotRecord],
) -> (Option<&SnapshotRecord>, Vec<Option<FamilyPowers>>) {
    let reference = records.iter().rev().find(|r| has_fields(r));
    let families = records
        .iter()
        .map(|r| {
            let same = has_fields(r)
                && reference.is_some_and(|q| q.grid == r.grid && q.particles == r.particles);
            same.then(|| {
                let [xy, xz, yz] = plane_fields(r);
                family_powers(&xy, &xz, &yz, r.grid.map(|k| k as usize))
            })
        })
        .collect();
    (reference, families)
}

/// The label of every snapshot assessed on its own (as in the evolution and the label
/// probabilities: same grid, same thresholds), in order: (collisions per particle, label key
/// such as `s-wave(2)`). Records without fields on the common grid are left out.
pub fn snapshot_labels(records: &[SnapshotRecord]) -> Vec<(f64, String)> {
    let (reference, families) = common_grid_families(records);
    let Some(q) = reference else {
        return Vec::new();
    };
    let n = q.grid.map(|k| k as usize);
    let p0 = noise_per_mode(q.particles as usize, q.grid_volume);
    records
        .iter()
        .zip(&families)
        .filter_map(|(r, f)| {
            let a = assess(f.as_ref()?, n, p0);
            Some((
                r.collisions_per_particle,
                labels::label_key(a.label, a.humps),
            ))
        })
        .collect()
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
    let plateau = steady::detect(&clock, &trace, settings.min_steady_snapshots);
    let in_window = &records[plateau.start.min(records.len())..];
    let momentum = balance::momentum_balance(in_window);
    let energy_balance = balance::energy_balance(in_window);
    let window = balance::confirm_by_balances(
        plateau,
        &[("momentum", momentum), ("energy", energy_balance)],
    );

    // per-snapshot family powers and verdicts (records with a usable grid, same grid as the
    // last record)
    let (reference, families) = common_grid_families(records);
    let same_grid = |r: &SnapshotRecord| {
        has_fields(r) && reference.is_some_and(|q| q.grid == r.grid && q.particles == r.particles)
    };

    let mut summary = empty_summary();
    let mut spectra = Vec::new();
    let mut evolution = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    if let Some(q) = reference {
        let n = q.grid.map(|k| k as usize);
        let p0 = noise_per_mode(q.particles as usize, q.grid_volume);
        let verdicts: Vec<Option<classify::Assessment>> = families
            .iter()
            .map(|f| f.as_ref().map(|f| assess(f, n, p0)))
            .collect();
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
            spectra = summarise_families(
                &mut summary,
                &mut notes,
                &avg,
                (n, p0),
                &verdicts[window.start..],
                window.steady,
            );
        }
        summary.noise_level = p0;
        [summary.grid_x, summary.grid_y, summary.grid_z] = q.grid;
        summary.particles = q.particles;
        evolution = structure_evolution(records, &verdicts);
    }
    if window.steady && reference.is_none() {
        summary.label = "unclassified".into();
        notes.push("the records carry no density fields".into());
    }
    if !window.steady {
        notes.insert(0, format!("not steady: {}", window.reason));
    }
    summarise_balances(
        &mut summary,
        &mut notes,
        (momentum, energy_balance),
        in_window,
    );
    summary.steady = window.steady;
    summarise_window(&mut summary, in_window, window.steady);
    let with_profiles: Vec<&SnapshotRecord> =
        in_window.iter().filter(|r| !r.profile.is_empty()).collect();
    let (profiles, slip) = profiles::profiles(&with_profiles);
    summary.slip_velocity = slip;
    summary.shown_label = labels::shown(&summary.label, summary.humps, summary.three_dimensional);
    summary.note = notes.join("; ");
    JobAnalysis {
        summary,
        spectra,
        profiles,
        energy,
        evolution,
        milestones: settings
            .milestones
            .as_ref()
            .map_or_else(Vec::new, |plan| milestones::milestone_rows(records, plan)),
        statistics: None,
    }
}

/// The window's families and label into the summary: the window-averaged families `avg`
/// against shot noise `p0` and the per-snapshot verdicts of the window; the spectra rows.
fn summarise_families(
    summary: &mut Summary,
    notes: &mut Vec<String>,
    avg: &FamilyPowers,
    (n, p0): ([usize; 3], f64),
    window_verdicts: &[Option<classify::Assessment>],
    steady: bool,
) -> Vec<SpectrumRow> {
    let a = assess(&avg, n, p0);
    let in_window_verdicts: Vec<classify::Assessment> =
        window_verdicts.iter().flatten().cloned().collect();
    let stats = labels::statistics(&in_window_verdicts, &a);
    summary.dominant_modes = dominant_modes(&avg.xy, n[0], n[1], p0, 5);
    let spectra = [&avg.xy, &avg.xz, &avg.yz]
        .into_iter()
        .enumerate()
        .flat_map(|(plane, folded)| spectrum_rows(folded, n, plane))
        .collect();
    [
        summary.significance_transverse,
        summary.significance_along_flow,
        summary.significance_antisymmetric,
        summary.significance_symmetric_rest,
        summary.significance_spanwise,
    ] = a.significance;
    [
        summary.presence_transverse,
        summary.presence_along_flow,
        summary.presence_antisymmetric,
        summary.presence_symmetric_rest,
        summary.presence_spanwise,
    ] = stats.presence;
    summary.label_probabilities = labels::probabilities_text(&stats.probabilities);
    summary.candidate_label = labels::label_key(&stats.candidate, stats.humps);
    summary.label_probability = stats.probability;
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
    summary.significance_slug = a.slug;
    if steady {
        summary.label = stats.label.clone();
        summary.humps = stats.humps;
        summary.three_dimensional = a.three_dimensional;
        if stats.label == "mixed" {
            notes.push(format!(
                "mixed: no label holds in {:.0} % of the snapshots ({}); the families present in most snapshots name \"{}\" ({:.2})",
                100.0 * labels::CLEAR_MAJORITY,
                summary.label_probabilities,
                stats.candidate,
                stats.probability
            ));
        }
    } else {
        notes.push(format!(
            "the final window alone would read \"{}\"{} ({})",
            stats.label,
            if a.three_dimensional { " (3D)" } else { "" },
            summary.label_probabilities
        ));
    }
    spectra
}

/// The window's balances and the collapse guard's share of the dissipation into the summary.
fn summarise_balances(
    summary: &mut Summary,
    notes: &mut Vec<String>,
    (momentum, energy_balance): (Option<balance::Balance>, Option<balance::Balance>),
    in_window: &[SnapshotRecord],
) {
    for (b, (ratio, error)) in [
        (
            momentum,
            (
                &mut summary.momentum_balance,
                &mut summary.momentum_balance_error,
            ),
        ),
        (
            energy_balance,
            (
                &mut summary.energy_balance,
                &mut summary.energy_balance_error,
            ),
        ),
    ] {
        if let Some(b) = b {
            (*ratio, *error) = (b.ratio, b.error);
        }
    }
    let (tc_count, tc_energy) = balance::collapse_guard_fractions(in_window);
    summary.window_tc_elastic_fraction = tc_count;
    summary.window_suppressed_dissipation = tc_energy;
    let unrecorded = in_window.iter().any(|r| r.suppressed_dissipation.is_nan());
    let beyond = tc_energy > balance::COLLAPSE_GUARD_LIMIT;
    summary.collapse_guard_valid = !unrecorded && !beyond;
    if beyond {
        notes.push(format!(
            "collapse guard beyond its validity: the TC model suppressed {:.1} % of the dissipation of constant e over the window (limit {:.0} %); lower tc",
            100.0 * tc_energy,
            100.0 * balance::COLLAPSE_GUARD_LIMIT
        ));
    } else if unrecorded {
        notes.push("the collapse guard's suppressed dissipation was not recorded".into());
    }
}

/// The window's extent and mean energies into the summary.
fn summarise_window(summary: &mut Summary, in_window: &[SnapshotRecord], steady: bool) {
    if let (Some(first), Some(last)) = (in_window.first(), in_window.last()) {
        summary.window_start = first.collisions_per_particle;
        summary.window_end = last.collisions_per_particle;
        if steady {
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
}
