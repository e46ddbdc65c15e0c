//! The thesis' chapters 3 and 4 statistics of a particle channel (Malik 2008: velocity
//! distributions, pair and orientational correlations, velocity correlations, free paths and
//! Knudsen profiles, wall slip), gathered at snapshots for any engine whose snapshots carry
//! particles with velocities; opt-in per sweep (`run: (statistics: (...))`), so plain sweeps
//! keep their ids, speed and tables. docs/statistics.md is the reader's version of the choices
//! documented in these modules.
//!
//! - [`fluctuations`]: each particle's slab and fluctuations C, Omega about its cell's mean
//!   (cells: the slab cut into `cells` columns; default the whole slab, and why).
//! - [`vdf`]: VDFs of C_x .. Omega_z per slab, x / sigma with P(0) = 1, skewness and kurtosis.
//! - [`pairs`]: one cell-list pass over the pairs closer than r_max; [`pair_correlation`]:
//!   g(r) per slab and overall with the shell normalisation; [`velocity_correlation`]: C_ab(r).
//! - [`orientation`]: Lambda(y) = <cos^2 Psi>.
//! - [`free_path`]: P(l), lambda(y), Kn(y) from the free paths the engine tallies
//!   ([`crate::engine::free_paths`]).
//! - [`walls`]: slip, temperatures and gradients at the walls, sign-folded, from the profiles.
//! - [`tables`]: the Parquet tables and the `jobs.parquet` columns; `blocks`: batch-means errors.
//!
//! Slabs: `bins` slabs of equal width across [0, W] (thesis: 25; bin 1 at the wall y = 0 is
//! slab 0 here, its bin 13 the centre slab 12). A snapshot's statistics are its `sample`;
//! statistics snapshots are every `every`-th snapshot after the initial state (snapshot 0,
//! the placement, never counts) and, when the window is known before the run (a `window`
//! without `until_steady`), only those inside it; free paths are tallied throughout and handed
//! over at every snapshot. The window: the last `window` of the run's clock that the job
//! reached, or without `window` the structure analysis' window (its steady window, else the
//! final third).

/// Rows of the statistics are kept in `result.ron` as tuples (one line each, in field order)
/// rather than as structs (a field per line): tens of thousands of rows per job.
macro_rules! row_as_tuple {
    ($row:ident { $($f:ident: $t:ty),* $(,)? }) => {
        impl From<$row> for ($($t,)*) {
            fn from(r: $row) -> Self {
                ($(r.$f,)*)
            }
        }
        impl From<($($t,)*)> for $row {
            fn from(($($f,)*): ($($t,)*)) -> Self {
                $row { $($f),* }
            }
        }
    };
}

pub mod blocks;
mod fluctuations;
mod free_path;
mod orientation;
mod pair_correlation;
mod pairs;
pub mod tables;
pub mod vdf;
mod velocity_correlation;
mod walls;

use super::SnapshotRecord;
use crate::engine::{Clock, FreePathTally, Particles, Snapshot};
use serde::{Deserialize, Serialize};

/// Slabs across the channel unless set (the thesis' 25).
pub const DEFAULT_BINS: usize = 25;

/// The `statistics` block of a sweep's `run` section (every key optional).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StatisticsSettings {
    /// slabs across the channel (thesis: 25)
    pub bins: usize,
    /// the averaging window, the last `window` of the run's clock (thesis: 70 000 collisions
    /// per particle, 80 000 in its dense case, stated for Lambda and used here for all);
    /// none: the structure analysis' window (steady window, else the final third)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<f64>,
    /// statistics at every this many snapshots (1: all); free paths are counted throughout
    pub every: u32,
    /// fluctuation cells per slab along x and z ([1, 1]: the slab mean; see [`fluctuations`])
    pub cells: [usize; 2],
    /// range r_max of g(r) and C_ab(r), in d (capped at half the shortest periodic extent)
    pub r_max: f64,
    /// bin width of g(r), in d
    pub dr: f64,
    /// bin width of C_ab(r), in d (a whole multiple of dr)
    pub vcf_dr: f64,
    /// the VDF histograms reach +-vdf_max standard deviations
    pub vdf_max: f64,
    /// bin width of the VDF histograms, in standard deviations
    pub vdf_dx: f64,
}

impl Default for StatisticsSettings {
    fn default() -> Self {
        StatisticsSettings {
            bins: DEFAULT_BINS,
            window: None,
            every: 1,
            cells: [1, 1],
            r_max: 5.0,
            dr: 0.02,
            vcf_dr: 0.2,
            vdf_max: 8.0,
            vdf_dx: 0.2,
        }
    }
}

/// The keys of a `statistics` block (for messages).
pub const KEYS: &str = "bins, window, every, cells, r_max, dr, vcf_dr, vdf_max, vdf_dx";

impl StatisticsSettings {
    /// Check the settings; the message names the key, its value and what is allowed.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        let finite_positive = |v: f64| v.is_finite() && v > 0.0;
        if self.bins == 0 || self.bins > 10_000 {
            return Err((
                "bins",
                format!("{} is out of range: allowed 1 to 10000", self.bins),
            ));
        }
        if let Some(w) = self.window
            && !finite_positive(w)
        {
            return Err((
                "window",
                format!("{w} is out of range: allowed a finite value > 0"),
            ));
        }
        if self.every == 0 {
            return Err((
                "every",
                "0 is out of range: allowed a whole number >= 1".into(),
            ));
        }
        if self.cells.iter().any(|&c| c == 0 || c > 1000) {
            return Err((
                "cells",
                format!(
                    "{:?} is out of range: allowed 1 to 1000 cells along x and z",
                    self.cells
                ),
            ));
        }
        if !(finite_positive(self.r_max) && self.r_max <= 1000.0) {
            return Err((
                "r_max",
                format!(
                    "{} is out of range: allowed 0 < r_max <= 1000 d",
                    self.r_max
                ),
            ));
        }
        if !(finite_positive(self.dr) && self.r_max / self.dr <= 100_000.0) {
            return Err((
                "dr",
                format!(
                    "{} is out of range: allowed dr > 0 with at most 100000 bins up to r_max",
                    self.dr
                ),
            ));
        }
        let per = (self.vcf_dr / self.dr).round();
        if !(finite_positive(self.vcf_dr)
            && per >= 1.0
            && (per * self.dr - self.vcf_dr).abs() <= 1e-9 * self.vcf_dr)
        {
            return Err((
                "vcf_dr",
                format!(
                    "{} is out of range: allowed a whole multiple of dr = {}",
                    self.vcf_dr, self.dr
                ),
            ));
        }
        if !(finite_positive(self.vdf_dx)
            && finite_positive(self.vdf_max)
            && self.vdf_max / self.vdf_dx <= 10_000.0
            && self.vdf_max >= self.vdf_dx)
        {
            return Err((
                "vdf_dx",
                format!(
                    "vdf_dx = {}, vdf_max = {}: allowed 0 < vdf_dx <= vdf_max with at most 10000 bins per side",
                    self.vdf_dx, self.vdf_max
                ),
            ));
        }
        Ok(())
    }

    /// g(r) bins per velocity-correlation bin.
    pub fn per_vcf_bin(&self) -> usize {
        ((self.vcf_dr / self.dr).round() as usize).max(1)
    }

    /// The settings that differ from the defaults, as JSON (what a job id holds).
    pub fn non_default(&self) -> serde_json::Map<String, serde_json::Value> {
        let now = serde_json::to_value(self).expect("settings serialise");
        let defaults =
            serde_json::to_value(StatisticsSettings::default()).expect("settings serialise");
        match now {
            serde_json::Value::Object(m) => m
                .into_iter()
                .filter(|(k, v)| defaults.get(k) != Some(v))
                .collect(),
            _ => serde_json::Map::new(),
        }
    }
}

/// The statistics of one job: its settings and which snapshots carry them.
#[derive(Clone, Debug, PartialEq)]
pub struct StatisticsPlan {
    pub settings: StatisticsSettings,
    /// the run's clock (windows and `skip_before` are readings of it)
    pub clock: Clock,
    /// snapshots before this reading of the clock carry no statistics (they cannot fall into
    /// the window); 0: every snapshot may
    pub skip_before: f64,
}

impl StatisticsPlan {
    /// Statistics at every `every`-th snapshot, the window decided at the end.
    pub fn every_snapshot(settings: StatisticsSettings) -> Self {
        StatisticsPlan {
            settings,
            clock: Clock::CollisionsPerParticle,
            skip_before: 0.0,
        }
    }

    /// The plan of a run of `length` on `clock` (stopping early when `until_steady`).
    pub fn for_run(
        settings: StatisticsSettings,
        clock: Clock,
        length: f64,
        until_steady: bool,
    ) -> Self {
        let skip_before = match settings.window {
            Some(w) if !until_steady => (length - w).max(0.0),
            _ => 0.0,
        };
        StatisticsPlan {
            settings,
            clock,
            skip_before,
        }
    }

    /// Whether snapshot `index` (0: the initial state) reading `reading` on the clock carries
    /// statistics.
    pub fn samples(&self, index: u32, reading: f64) -> bool {
        index > 0 && index.is_multiple_of(self.settings.every) && reading >= self.skip_before
    }
}

/// What one snapshot contributes to the statistics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatisticsRecord {
    /// the snapshot's statistics (None: not a statistics snapshot)
    pub sample: Option<Box<Sample>>,
    /// the free paths ended since the previous snapshot (None: the engine tallies none, or
    /// the snapshot is before the window)
    pub free_paths: Option<FreePathTally>,
}

/// The statistics of one snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// slabs
    pub bins: u32,
    /// walls at y = 0 and W (else y is periodic)
    pub walls: bool,
    pub vdf: vdf::VdfSample,
    pub orientation: orientation::OrientationSample,
    pub pairs: pairs::PairSample,
}

/// The statistics of one snapshot's particles.
pub fn sample(p: &Particles, settings: &StatisticsSettings) -> Sample {
    let slabs = settings.bins;
    let f = fluctuations::fluctuations(p, slabs, settings.cells);
    let spins = p.angular_velocities.len() == p.len() && !p.is_empty();
    let half = (settings.vdf_max / settings.vdf_dx).round() as u32;
    Sample {
        bins: slabs as u32,
        walls: p.geometry.walls,
        vdf: vdf::VdfSample::of(&f, slabs, spins, half, settings.vdf_dx),
        orientation: if spins {
            orientation::OrientationSample::of(&f, slabs)
        } else {
            orientation::OrientationSample {
                sum_cos2: vec![0.0; slabs],
                count: vec![0; slabs],
            }
        },
        pairs: pairs::sample(
            p,
            &f,
            slabs,
            settings.r_max,
            settings.dr,
            settings.per_vcf_bin(),
        ),
    }
}

impl StatisticsPlan {
    /// The record of snapshot `index`, with the free paths the engine handed over after it.
    pub fn record(
        &self,
        index: u32,
        snapshot: &Snapshot,
        free_paths: Option<FreePathTally>,
    ) -> StatisticsRecord {
        let reading = snapshot.progress.on(self.clock);
        let sample = match snapshot.particles() {
            Some(p) if self.samples(index, reading) => Some(Box::new(sample(p, &self.settings))),
            _ => None,
        };
        StatisticsRecord {
            sample,
            free_paths: free_paths.filter(|_| reading >= self.skip_before),
        }
    }
}

/// The statistics of a job over its window.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Statistics {
    pub summary: StatisticsSummary,
    pub vdf: Vec<vdf::VdfRow>,
    pub vdf_moments: Vec<vdf::MomentRow>,
    pub pair_correlation: Vec<pair_correlation::PairCorrelationRow>,
    pub orientation: Vec<orientation::OrientationRow>,
    pub velocity_correlation: Vec<velocity_correlation::VelocityCorrelationRow>,
    pub free_paths: Vec<free_path::FreePathRow>,
    pub knudsen: Vec<free_path::KnudsenRow>,
}

/// The statistics' columns of `jobs.parquet` (NaN, written as null, where a measure does not
/// apply: e.g. Lambda without spins, free paths of an engine that tallies none).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatisticsSummary {
    /// statistics snapshots in the window
    pub statistics_snapshots: u64,
    /// the window, in collisions per particle
    pub statistics_window_start: f64,
    pub statistics_window_end: f64,
    /// free paths counted in the window
    pub free_paths: u64,
    /// lambda over every path of the window, d
    pub mean_free_path: f64,
    /// Kn = lambda / W in the centre slab(s) and in the two wall slabs (mean)
    pub knudsen_centre: f64,
    pub knudsen_wall: f64,
    /// fraction of the paths ended by a wall collision
    pub wall_path_fraction: f64,
    /// omega_z at the walls, sign-folded, sqrt(g/d)
    pub slip_rotational: f64,
    /// T and theta at the walls, g d
    pub wall_temperature: f64,
    pub wall_rotational_temperature: f64,
    /// gradients into the channel at the walls, sign-folded
    pub wall_gradient_u_x: f64,
    pub wall_gradient_omega_z: f64,
    pub wall_gradient_temperature: f64,
    pub wall_gradient_rotational_temperature: f64,
    /// Lambda in the centre slab(s), its error, and the mean of Lambda(y) over the slabs
    pub lambda_centre: f64,
    pub lambda_centre_error: f64,
    pub lambda_mean: f64,
    /// g(d+) over all slabs and in the centre slab(s)
    pub contact_value: f64,
    pub contact_value_centre: f64,
}

impl Default for StatisticsSummary {
    fn default() -> Self {
        StatisticsSummary {
            statistics_snapshots: 0,
            statistics_window_start: f64::NAN,
            statistics_window_end: f64::NAN,
            free_paths: 0,
            mean_free_path: f64::NAN,
            knudsen_centre: f64::NAN,
            knudsen_wall: f64::NAN,
            wall_path_fraction: f64::NAN,
            slip_rotational: f64::NAN,
            wall_temperature: f64::NAN,
            wall_rotational_temperature: f64::NAN,
            wall_gradient_u_x: f64::NAN,
            wall_gradient_omega_z: f64::NAN,
            wall_gradient_temperature: f64::NAN,
            wall_gradient_rotational_temperature: f64::NAN,
            lambda_centre: f64::NAN,
            lambda_centre_error: f64::NAN,
            lambda_mean: f64::NAN,
            contact_value: f64::NAN,
            contact_value_centre: f64::NAN,
        }
    }
}

/// The slabs at the centre: the middle one, or the two middle ones of an even count.
pub fn centre_slabs(slabs: usize) -> Vec<usize> {
    if slabs % 2 == 1 {
        vec![slabs / 2]
    } else {
        vec![slabs / 2 - 1, slabs / 2]
    }
}

/// Mean of `value` over the slabs in `which` that have one (NaN when none has).
fn mean_over<T>(
    rows: &[T],
    which: &[usize],
    slab: impl Fn(&T) -> usize,
    value: impl Fn(&T) -> f64,
) -> f64 {
    let v: Vec<f64> = rows
        .iter()
        .filter(|r| which.contains(&slab(r)))
        .map(value)
        .filter(|v| v.is_finite())
        .collect();
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// One record of the window: the structure record (clocks, box) and its statistics.
pub struct WindowRecord<'a> {
    pub structure: &'a SnapshotRecord,
    pub statistics: &'a StatisticsRecord,
}

/// The statistics over a job's records (in order). `window`: the structure analysis' window
/// in collisions per particle, used when the settings give none; `profiles`: its
/// window-averaged profiles (for the wall values).
pub fn analyse(
    records: &[WindowRecord],
    plan: &StatisticsPlan,
    window: (f64, f64),
    profiles: &[super::ProfileRow],
) -> Statistics {
    let reading = |r: &SnapshotRecord| match plan.clock {
        Clock::Time => r.time,
        _ => r.collisions_per_particle,
    };
    let in_window: Vec<&WindowRecord> = match (plan.settings.window, records.last()) {
        (Some(w), Some(last)) => {
            let end = reading(last.structure);
            records
                .iter()
                .filter(|r| reading(r.structure) >= end - w)
                .collect()
        }
        _ => records
            .iter()
            .filter(|r| {
                let c = r.structure.collisions_per_particle;
                c >= window.0 && c <= window.1
            })
            .collect(),
    };
    let mut out = Statistics::default();
    let s = &mut out.summary;
    let walls = walls::wall_values(profiles);
    s.slip_rotational = walls.slip_rotational;
    s.wall_temperature = walls.temperature;
    s.wall_rotational_temperature = walls.rotational_temperature;
    s.wall_gradient_u_x = walls.gradient_u_x;
    s.wall_gradient_omega_z = walls.gradient_omega_z;
    s.wall_gradient_temperature = walls.gradient_temperature;
    s.wall_gradient_rotational_temperature = walls.gradient_rotational_temperature;
    let (Some(first), Some(last)) = (in_window.first(), in_window.last()) else {
        return out;
    };
    s.statistics_window_start = first.structure.collisions_per_particle;
    s.statistics_window_end = last.structure.collisions_per_particle;
    let structure = last.structure;
    let [l, w, h] = structure.box_extent;
    let g = structure.gravity;
    let (velocity_scale, spin_scale) = if g > 0.0 {
        (g.sqrt(), g.sqrt())
    } else {
        (1.0, 1.0)
    };
    let samples: Vec<&Sample> = in_window
        .iter()
        .filter_map(|r| r.statistics.sample.as_deref())
        .filter(|x| x.bins as usize == plan.settings.bins)
        .collect();
    let slabs = plan.settings.bins;
    let y_of = |b: usize| (b as f64 + 0.5) * w / slabs as f64;
    s.statistics_snapshots = samples.len() as u64;
    // free paths of the intervals inside the window: those handed over after its first record
    let tallies: Vec<&FreePathTally> = in_window
        .iter()
        .skip(1)
        .filter_map(|r| r.statistics.free_paths.as_ref())
        .filter(|t| t.slabs == slabs)
        .collect();
    if let Some(fp) = free_path::analyse(&tallies, w, &y_of) {
        s.free_paths = fp.paths;
        s.mean_free_path = fp.mean;
        s.wall_path_fraction = fp.wall_fraction;
        s.knudsen_centre = mean_over(
            &fp.profile,
            &centre_slabs(slabs),
            |r| r.slab as usize,
            |r| r.knudsen,
        );
        s.knudsen_wall = mean_over(
            &fp.profile,
            &[0, slabs - 1],
            |r| r.slab as usize,
            |r| r.knudsen,
        );
        out.free_paths = fp.distribution;
        out.knudsen = fp.profile;
    }
    if samples.is_empty() {
        return out;
    }
    let vdfs: Vec<&vdf::VdfSample> = samples.iter().map(|x| &x.vdf).collect();
    (out.vdf, out.vdf_moments) = vdf::analyse(&vdfs, slabs, &y_of, velocity_scale, spin_scale);
    let orientations: Vec<&orientation::OrientationSample> =
        samples.iter().map(|x| &x.orientation).collect();
    out.orientation = orientation::analyse(&orientations, slabs, &y_of);
    let centre = centre_slabs(slabs);
    out.summary.lambda_centre =
        mean_over(&out.orientation, &centre, |r| r.slab as usize, |r| r.lambda);
    out.summary.lambda_centre_error = {
        let e = mean_over(
            &out.orientation,
            &centre,
            |r| r.slab as usize,
            |r| r.error * r.error,
        );
        (e / centre.len() as f64).sqrt()
    };
    out.summary.lambda_mean = mean_over(
        &out.orientation,
        &(0..slabs).collect::<Vec<_>>(),
        |r| r.slab as usize,
        |r| r.lambda,
    );
    let pair_samples: Vec<&pairs::PairSample> = samples.iter().map(|x| &x.pairs).collect();
    let pair_box = pair_correlation::PairBox {
        extent: [l, w, h],
        walls: samples[0].walls,
        particles: structure.particles as usize,
    };
    out.pair_correlation = pair_correlation::analyse(&pair_samples, slabs, pair_box, &y_of);
    let dr = plan.settings.dr;
    let overall: Vec<&pair_correlation::PairCorrelationRow> = out
        .pair_correlation
        .iter()
        .filter(|r| r.slab.is_none())
        .collect();
    out.summary.contact_value = pair_correlation::contact_value(&overall, dr);
    let centres: Vec<f64> = centre
        .iter()
        .map(|&c| {
            let rows: Vec<&pair_correlation::PairCorrelationRow> = out
                .pair_correlation
                .iter()
                .filter(|r| r.slab == Some(c as u32))
                .collect();
            pair_correlation::contact_value(&rows, dr)
        })
        .collect();
    out.summary.contact_value_centre = centres.iter().sum::<f64>() / centres.len() as f64;
    out.velocity_correlation = velocity_correlation::analyse(&pair_samples, slabs, &y_of);
    out
}
