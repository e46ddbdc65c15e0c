//! Pieces of a job's result: the structure evolution from per-snapshot labels, spectrum rows,
//! the dominant modes and family peaks, and the empty summary.

use super::classify;
use super::modes::{DominantMode, FamilyPeak};
use super::spectrum::{folded_shape, multiplicity};
use super::{SnapshotRecord, SpectrumRow, StructureChange, Summary};

/// Minimum run of equal per-snapshot labels that counts as a change of structure (a single
/// snapshot that differs from its neighbours is a flicker near a threshold, not a change).
pub const MIN_LABEL_RUN: usize = 2;

/// Per-snapshot labels (each snapshot assessed alone) reduced to their changes: the first
/// entry is the first snapshot's label; a later entry marks the first snapshot of a run of at
/// least [`MIN_LABEL_RUN`] snapshots with a new (label, humps).
pub(super) fn structure_evolution(
    records: &[SnapshotRecord],
    verdicts: &[Option<classify::Assessment>],
) -> Vec<StructureChange> {
    let labels: Vec<(f64, &'static str, u32)> = records
        .iter()
        .zip(verdicts)
        .filter_map(|(r, a)| {
            a.as_ref()
                .map(|a| (r.collisions_per_particle, a.label, a.humps))
        })
        .collect();
    let mut out: Vec<StructureChange> = Vec::new();
    for (i, &(cpp, label, humps)) in labels.iter().enumerate() {
        let same_as_current = out
            .last()
            .is_some_and(|c| c.label == label && c.humps == humps);
        if same_as_current {
            continue;
        }
        let confirmed = out.is_empty()
            || labels[i..]
                .iter()
                .take(MIN_LABEL_RUN)
                .filter(|l| l.1 == label && l.2 == humps)
                .count()
                == MIN_LABEL_RUN;
        if confirmed {
            out.push(StructureChange {
                collisions_per_particle: cpp,
                label: label.into(),
                humps,
            });
        }
    }
    out
}

/// Each family's strongest mode against its peak-test threshold (families without modes
/// left out).
pub(super) fn family_peaks(a: &classify::Assessment) -> Vec<FamilyPeak> {
    classify::FAMILY_NAMES
        .iter()
        .zip(&a.peaks)
        .filter_map(|(name, p)| {
            p.map(|p| FamilyPeak {
                family: (*name).into(),
                plane: p.mode.plane.into(),
                k1: p.mode.k1 as u32,
                k2: p.mode.k2 as u32,
                ratio: p.ratio,
                threshold: p.threshold,
            })
        })
        .collect()
}

/// Grid sizes (first, second axis) of a plane.
pub(super) fn plane_dims(n: [usize; 3], plane: usize) -> (usize, usize) {
    match plane {
        0 => (n[0], n[1]),
        1 => (n[0], n[2]),
        _ => (n[1], n[2]),
    }
}

/// Rows of a folded spectrum (without the mean (0, 0)).
pub(super) fn spectrum_rows(folded: &[f64], n: [usize; 3], plane: usize) -> Vec<SpectrumRow> {
    let (a, b) = plane_dims(n, plane);
    let (m1, m2) = folded_shape(a, b);
    let name = ["xy", "xz", "yz"][plane];
    let mut rows = Vec::with_capacity(m1 * m2);
    for k1 in 0..m1 {
        for k2 in 0..m2 {
            if k1 + k2 > 0 && k1 * m2 + k2 < folded.len() {
                rows.push(SpectrumRow {
                    plane: name.into(),
                    k1: k1 as u32,
                    k2: k2 as u32,
                    power: folded[k1 * m2 + k2],
                });
            }
        }
    }
    rows
}

/// The `count` strongest modes of a folded xy spectrum with their power over noise.
pub(super) fn dominant_modes(
    folded: &[f64],
    n1: usize,
    n2: usize,
    p0: f64,
    count: usize,
) -> Vec<DominantMode> {
    let (m1, m2) = folded_shape(n1, n2);
    let mut modes: Vec<(usize, usize, f64)> = (0..m1)
        .flat_map(|k1| (0..m2).map(move |k2| (k1, k2)))
        .filter(|&(k1, k2)| k1 + k2 > 0)
        .map(|(k1, k2)| (k1, k2, folded[k1 * m2 + k2]))
        .collect();
    modes.sort_by(|a, b| b.2.total_cmp(&a.2).then((a.0, a.1).cmp(&(b.0, b.1))));
    modes
        .iter()
        .take(count)
        .map(|&(k1, k2, p)| {
            let noise = (multiplicity(k1, n1) * multiplicity(k2, n2)) as f64 * p0;
            DominantMode {
                plane: "xy".into(),
                k1: k1 as u32,
                k2: k2 as u32,
                power: p,
                ratio: p / noise,
            }
        })
        .collect()
}

/// A summary before anything is known.
pub(super) fn empty_summary() -> Summary {
    Summary {
        label: "not-steady".into(),
        label_probabilities: String::new(),
        candidate_label: String::new(),
        label_probability: f64::NAN,
        presence_transverse: f64::NAN,
        presence_along_flow: f64::NAN,
        presence_antisymmetric: f64::NAN,
        presence_symmetric_rest: f64::NAN,
        presence_spanwise: f64::NAN,
        momentum_balance: f64::NAN,
        momentum_balance_error: f64::NAN,
        energy_balance: f64::NAN,
        energy_balance_error: f64::NAN,
        window_tc_elastic_fraction: f64::NAN,
        window_suppressed_dissipation: f64::NAN,
        collapse_guard_valid: false,
        humps: 0,
        three_dimensional: false,
        shown_label: String::new(),
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
        window_start: f64::NAN,
        window_end: f64::NAN,
        ratio_transverse: f64::NAN,
        ratio_along_flow: f64::NAN,
        ratio_antisymmetric: f64::NAN,
        ratio_symmetric_rest: f64::NAN,
        ratio_spanwise: f64::NAN,
        threshold_transverse: f64::NAN,
        threshold_along_flow: f64::NAN,
        threshold_antisymmetric: f64::NAN,
        threshold_symmetric_rest: f64::NAN,
        threshold_spanwise: f64::NAN,
        significance_transverse: f64::NAN,
        significance_along_flow: f64::NAN,
        significance_antisymmetric: f64::NAN,
        significance_symmetric_rest: f64::NAN,
        significance_spanwise: f64::NAN,
        family_peaks: Vec::new(),
        antisymmetric_kx: 0,
        significance_slug: f64::NAN,
        antisymmetric_coherence: f64::NAN,
        dominant_modes: Vec::new(),
        grid_x: 0,
        grid_y: 0,
        grid_z: 0,
        particles: 0,
        note: String::new(),
    }
}
