//! Milestones: the structure of a run at given readings of a clock, dated as the thesis dates
//! its snapshots (in collisions per particle: 4000, 8000, 10 000, 11 000 and 14 000 for its
//! W/d = 50 boxes), independently of whether or when the run becomes steady.
//!
//! A milestone m is read off the job's records alone (nothing changes in the run): the
//! `window` records whose clock is nearest to m (centred on the nearest one, shifted inwards
//! at the ends of the run) are the milestone's window. It is *reached* when the nearest record
//! lies within one record spacing of m. Over the window:
//! - the label, as the run's label is decided (per-snapshot verdicts, the candidate the
//!   families present in most snapshots name, `mixed` without a clear majority), with the
//!   fraction of snapshots carrying the candidate, marked ` 3d` when the window-averaged
//!   spanwise family stands above noise;
//! - the strongest modes of each plane (xy, xz, yz) of the window-averaged folded spectrum,
//!   with their power over shot noise;
//! - the mean translational and rotational energy per particle.

use super::classify::{FamilyPowers, assess, noise_per_mode};
use super::spectrum::{folded_shape, multiplicity};
use super::{SnapshotRecord, labels, plane_fields};
use crate::engine::Clock;
use serde::{Deserialize, Serialize};

/// Strongest modes listed per plane.
pub const PEAKS_PER_PLANE: usize = 2;

/// Which readings are milestones.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MilestonePlan {
    /// the clock the readings are on (collisions per particle or time)
    pub clock: Clock,
    /// the readings, increasing
    pub readings: Vec<f64>,
    /// also every multiple of this reading up to the end of the run (0: none)
    pub every: f64,
    /// records per milestone window
    pub window: usize,
}

/// The structure at one milestone.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MilestoneRow {
    /// the reading asked for, on the plan's clock
    pub milestone: f64,
    /// the clock of the reading ("collisions_per_particle" or "time")
    pub clock: String,
    /// collisions per particle and simulated time of the record nearest to the reading
    pub collisions_per_particle: f64,
    pub time: f64,
    /// records in the window
    pub window_snapshots: u32,
    /// the window's label as shown: with its humps and ` 3d` for a three-dimensional
    /// structure (`s-wave(2) 3d`), `mixed` without a clear majority
    pub structure: String,
    /// structure along z stands above noise in the window-averaged spectrum
    #[serde(default)]
    pub three_dimensional: bool,
    /// the candidate label (what the families present in most snapshots name)
    pub candidate: String,
    /// fraction of the window's snapshots whose own label is the candidate
    pub probability: f64,
    /// the strongest modes of each plane of the window-averaged spectrum
    pub peaks: Vec<PlanePeak>,
    /// mean translational and rotational kinetic energy per particle over the window
    pub translational: f64,
    pub rotational: f64,
}

/// A strong mode of one plane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanePeak {
    /// xy, xz or yz
    pub plane: String,
    pub k1: u32,
    pub k2: u32,
    /// power over its shot-noise power (1 for a random arrangement)
    pub ratio: f64,
}

fn reading(r: &SnapshotRecord, clock: Clock) -> f64 {
    match clock {
        Clock::Time => r.time,
        _ => r.collisions_per_particle,
    }
}

impl MilestonePlan {
    /// The readings up to `end` (listed ones and multiples of `every`), sorted, without
    /// duplicates.
    pub fn readings_up_to(&self, end: f64) -> Vec<f64> {
        let mut all = self.readings.clone();
        if self.every > 0.0 {
            let mut k = 1.0;
            while k * self.every <= end * (1.0 + 1e-12) {
                all.push(k * self.every);
                k += 1.0;
            }
        }
        all.sort_by(f64::total_cmp);
        all.dedup();
        all
    }
}

/// The rows of the milestones the records reach (records in order of the clock, all on one
/// coarse-graining grid where they carry fields; records without fields are left out).
pub fn milestone_rows(records: &[SnapshotRecord], plan: &MilestonePlan) -> Vec<MilestoneRow> {
    let usable: Vec<&SnapshotRecord> = records.iter().filter(|r| super::has_fields(r)).collect();
    let Some(last) = usable.last() else {
        return Vec::new();
    };
    let same: Vec<&SnapshotRecord> = usable
        .iter()
        .copied()
        .filter(|r| r.grid == last.grid && r.particles == last.particles)
        .collect();
    let clocks: Vec<f64> = same.iter().map(|r| reading(r, plan.clock)).collect();
    let end = *clocks.last().expect("non-empty");
    let n = last.grid.map(|k| k as usize);
    let p0 = noise_per_mode(last.particles as usize, last.grid_volume);
    let window = plan.window.clamp(1, same.len());
    plan.readings_up_to(end)
        .into_iter()
        .filter_map(|m| {
            let nearest = (0..same.len())
                .min_by(|&a, &b| (clocks[a] - m).abs().total_cmp(&(clocks[b] - m).abs()))?;
            let spacing = spacing_at(&clocks, nearest);
            if (clocks[nearest] - m).abs() > spacing * (1.0 + 1e-9) {
                return None;
            }
            let start = nearest.saturating_sub(window / 2).min(same.len() - window);
            let in_window = &same[start..start + window];
            Some(row(m, plan.clock, same[nearest], in_window, n, p0))
        })
        .collect()
}

/// The clock distance from record `i` to its neighbours (the larger one; 0 with one record).
fn spacing_at(clocks: &[f64], i: usize) -> f64 {
    let before = i.checked_sub(1).map_or(0.0, |j| clocks[i] - clocks[j]);
    let after = clocks.get(i + 1).map_or(0.0, |c| c - clocks[i]);
    before.max(after)
}

fn row(
    milestone: f64,
    clock: Clock,
    nearest: &SnapshotRecord,
    window: &[&SnapshotRecord],
    n: [usize; 3],
    p0: f64,
) -> MilestoneRow {
    let mut avg = FamilyPowers::zero(n);
    let mut verdicts = Vec::with_capacity(window.len());
    for r in window {
        let [xy, xz, yz] = plane_fields(r);
        let f = super::classify::family_powers(&xy, &xz, &yz, n);
        verdicts.push(assess(&f, n, p0));
        avg.add_scaled(&f, 1.0 / window.len() as f64);
    }
    let average = assess(&avg, n, p0);
    let stats = labels::statistics(&verdicts, &average);
    let three_dimensional = average.three_dimensional;
    let m = window.len() as f64;
    MilestoneRow {
        milestone,
        clock: clock.key().to_string(),
        collisions_per_particle: nearest.collisions_per_particle,
        time: nearest.time,
        window_snapshots: window.len() as u32,
        structure: labels::shown(&stats.label, stats.humps, three_dimensional),
        three_dimensional,
        candidate: stats.candidate,
        probability: stats.probability,
        peaks: [&avg.xy, &avg.xz, &avg.yz]
            .into_iter()
            .enumerate()
            .flat_map(|(plane, folded)| strongest(folded, n, plane, p0))
            .collect(),
        translational: window.iter().map(|r| r.translational_energy).sum::<f64>() / m,
        rotational: window.iter().map(|r| r.rotational_energy).sum::<f64>() / m,
    }
}

/// The [`PEAKS_PER_PLANE`] strongest modes of one folded plane spectrum (the mean (0, 0)
/// left out), power over shot noise.
fn strongest(folded: &[f64], n: [usize; 3], plane: usize, p0: f64) -> Vec<PlanePeak> {
    let (a, b) = super::report::plane_dims(n, plane);
    let (m1, m2) = folded_shape(a, b);
    let mut modes: Vec<PlanePeak> = (0..m1)
        .flat_map(|k1| (0..m2).map(move |k2| (k1, k2)))
        .filter(|&(k1, k2)| k1 + k2 > 0 && k1 * m2 + k2 < folded.len())
        .map(|(k1, k2)| PlanePeak {
            plane: ["xy", "xz", "yz"][plane].into(),
            k1: k1 as u32,
            k2: k2 as u32,
            ratio: folded[k1 * m2 + k2] / ((multiplicity(k1, a) * multiplicity(k2, b)) as f64 * p0),
        })
        .collect();
    modes.sort_by(|x, y| {
        y.ratio
            .total_cmp(&x.ratio)
            .then((x.k1, x.k2).cmp(&(y.k1, y.k2)))
    });
    modes.truncate(PEAKS_PER_PLANE);
    modes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readings_merge_the_list_and_the_multiples() {
        let plan = MilestonePlan {
            clock: Clock::CollisionsPerParticle,
            readings: vec![4000.0, 11000.0],
            every: 5000.0,
            window: 3,
        };
        assert_eq!(
            plan.readings_up_to(12000.0),
            [4000.0, 5000.0, 10000.0, 11000.0]
        );
    }

    #[test]
    fn the_spacing_is_the_larger_gap() {
        assert_eq!(spacing_at(&[0.0, 1.0, 3.0], 1), 2.0);
        assert_eq!(spacing_at(&[0.0, 1.0, 3.0], 0), 1.0);
        assert_eq!(spacing_at(&[5.0], 0), 0.0);
    }
}
