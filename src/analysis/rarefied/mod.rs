//! Analysis of DSMC channel jobs (thesis ch. 3-5): time-averaged cross-channel profiles over
//! the layer cells and one summary per job (flow rate, slips, bimodality, normal-stress
//! differences, balances, mixture segregation), each with a statistical error from block
//! averages over the steady window.
//!
//! A job calls [`record`] at every snapshot (a compact [`RarefiedRecord`]: the interval's
//! summed raw moments per cell and species and its balances, a few kB) and [`analyse`] once
//! at the end. [`steady`] decides where the steady state begins from the records alone.
//!
//! *Errors.* The window's records are split into `blocks` contiguous blocks; every quantity is
//! computed from the whole window's sums (the value) and from each block's sums, and its error
//! is the standard error of the block values, s_B / sqrt(B). Blocks are independent when
//! each spans several relaxation times of the flow ([`DsmcParams::relaxation_steps`]).
//!
//! *Summary definitions* (centre: the middle cell, or the mean of the two middle cells; wall:
//! the mean of the two cells next to the walls, whose width sets how close to the wall the
//! "wall" values are, thesis 3.2.2; even profiles are folded about the centre first):
//! Q = <u_x> / (u_c a-hat) (eq. 3.22 with the mass-weighted mean velocity <u_x>; = G_P of the
//! BGK table), Q-hat = <u_x> / sqrt(a W) (eqs. 4.4, 5.8), u_s (eq. 3.26), T_fw (eq. 3.28),
//! Delta T (eq. 3.27), rho_o and rho_fw (eqs. 3.23-3.24), N1(0), N2(0) (eqs. 3.29-3.30),
//! gamma_o and gamma_avg (eqs. 5.12-5.14), I_so and I_sp (eqs. 5.15-5.16, I_sp about the global
//! species-2 fraction x_2, which is the thesis' 0.5 for its equal numbers).
//!
//! [`DsmcParams::relaxation_steps`]: crate::engine::dsmc::DsmcParams::relaxation_steps

mod fields;
mod steady;

use crate::engine::dsmc::sampling::{MOMENTS, Moments, moment as mo};
use crate::engine::dsmc::{Balances, DsmcEngine};
use fields::{CellFields, Scales, add_moments, cell_fields};
use serde::{Deserialize, Serialize};
use steady::{RecordTrace, mean_and_error};

/// Analysis settings of a DSMC job (all have documented defaults).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RarefiedSettings {
    /// blocks of the steady window for the statistical errors
    pub blocks: usize,
    /// fewest records in a steady window
    pub min_steady_records: usize,
    /// relative tolerance of the steady rule's plateau and balance tests
    pub steady_tolerance: f64,
}

impl Default for RarefiedSettings {
    fn default() -> Self {
        RarefiedSettings {
            blocks: 10,
            min_steady_records: 8,
            steady_tolerance: 0.01,
        }
    }
}

impl RarefiedSettings {
    /// Check the settings; the message names the key, its value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if self.blocks < 2 || self.blocks > 10_000 {
            return Err(format!(
                "rarefied blocks = {} is out of range: allowed 2 to 10000",
                self.blocks
            ));
        }
        if self.min_steady_records < 8 {
            return Err(format!(
                "rarefied min_steady_records = {} is out of range: allowed >= 8",
                self.min_steady_records
            ));
        }
        if !(self.steady_tolerance.is_finite() && self.steady_tolerance > 0.0) {
            return Err(format!(
                "rarefied steady_tolerance = {} is out of range: allowed a finite value > 0",
                self.steady_tolerance
            ));
        }
        Ok(())
    }
}

/// What one snapshot contributes: the constants of the run and the interval's sums (the
/// engine's [`Sample`](crate::engine::dsmc::channel::Sample)).
pub use crate::engine::dsmc::channel::Sample as RarefiedRecord;

/// Take the engine's sampling interval (read and reset) as a record.
pub fn record(engine: &mut DsmcEngine) -> RarefiedRecord {
    engine.take_sample()
}

/// A value with its statistical error (standard error of the block values; NaN when the
/// quantity does not apply, e.g. mixture measures of a monodisperse run).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    pub value: f64,
    pub error: f64,
}

/// One job's summary.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RarefiedSummary {
    /// the steady rule passed
    pub steady: bool,
    /// why not (empty when steady)
    pub reason: String,
    /// the window all averages use: steps, records, blocks
    pub window_start_step: u64,
    pub window_end_step: u64,
    pub window_records: u32,
    pub blocks: u32,
    /// Q, eq. 3.22 (NaN without forcing)
    pub flow_rate: Estimate,
    /// Q-hat, eq. 4.4 (mixtures: eq. 5.8)
    pub flow_rate_hat: Estimate,
    /// <u_x> / u_c, the mass-weighted mean velocity
    pub mean_velocity: Estimate,
    /// u_o / u_c, centreline velocity
    pub centre_velocity: Estimate,
    /// u_s / u_c, eq. 3.26
    pub slip_velocity: Estimate,
    /// rho_o / rho_avg, eq. 3.23
    pub centre_density: Estimate,
    /// rho_fw / rho_avg, eq. 3.24
    pub wall_density: Estimate,
    /// T(0) / T_w
    pub centre_temperature: Estimate,
    /// T_fw / T_w, eq. 3.28
    pub temperature_slip: Estimate,
    /// Delta T = (T_max - T(0)) / T(0), eq. 3.27
    pub bimodality: Estimate,
    /// N1(0), N2(0), eqs. 3.29-3.30 at the centreline
    pub n1_centre: Estimate,
    pub n2_centre: Estimate,
    /// x-momentum delivered to the walls per unit time / (sum m_s N_s a): 1 in a steady state
    pub momentum_balance: Estimate,
    /// (heat to the walls + collisional dissipation) per unit time / (sum m_s N_s a <u_x>):
    /// 1 in a steady state
    pub energy_balance: Estimate,
    /// largest |work - heat - dissipation - change of kinetic energy| / work of a record
    /// (an exact identity: round-off only)
    pub energy_identity_residual: f64,
    /// gamma_o = T_2(0) / T_1(0), eq. 5.14
    pub temperature_ratio_centre: Estimate,
    /// gamma_avg = T_2,avg / T_1,avg, eq. 5.13
    pub temperature_ratio_mean: Estimate,
    /// Delta u_o = (u_2(0) - u_1(0)) / u_c
    pub species_velocity_difference: Estimate,
    /// I_so, eq. 5.15 (intensity of total-density segregation)
    pub density_segregation: Estimate,
    /// I_sp, eq. 5.16 (intensity of species segregation)
    pub species_segregation: Estimate,
    /// largest layer-cell width over the local mean free path, max_y Delta y / lambda(y) with
    /// lambda(y) = lambda n_avg / n(y) over the window (Bird's rule: at most 1/3; the a priori
    /// cell choice meets it at the mean density, clustering can break it)
    #[serde(default = "crate::analysis::nan")]
    pub cell_width_over_mean_free_path: f64,
    /// largest time step over the local mean collision time, max_y dt / tau(y) with
    /// tau(y) = lambda(y) / sqrt(8 k T(y) / (pi m_1)) over the window (should stay well below 1)
    #[serde(default = "crate::analysis::nan")]
    pub time_step_over_collision_time: f64,
}

impl RarefiedSummary {
    /// The numeric columns as (name, value), each estimate as `name` and `name_error`.
    pub fn columns(&self) -> Vec<(String, f64)> {
        let mut out = vec![
            ("steady".to_string(), f64::from(u8::from(self.steady))),
            ("window_start_step".into(), self.window_start_step as f64),
            ("window_end_step".into(), self.window_end_step as f64),
            ("window_records".into(), f64::from(self.window_records)),
            ("blocks".into(), f64::from(self.blocks)),
        ];
        for (name, e) in [
            ("flow_rate", self.flow_rate),
            ("flow_rate_hat", self.flow_rate_hat),
            ("mean_velocity", self.mean_velocity),
            ("centre_velocity", self.centre_velocity),
            ("slip_velocity", self.slip_velocity),
            ("centre_density", self.centre_density),
            ("wall_density", self.wall_density),
            ("centre_temperature", self.centre_temperature),
            ("temperature_slip", self.temperature_slip),
            ("bimodality", self.bimodality),
            ("n1_centre", self.n1_centre),
            ("n2_centre", self.n2_centre),
            ("momentum_balance", self.momentum_balance),
            ("energy_balance", self.energy_balance),
            ("temperature_ratio_centre", self.temperature_ratio_centre),
            ("temperature_ratio_mean", self.temperature_ratio_mean),
            (
                "species_velocity_difference",
                self.species_velocity_difference,
            ),
            ("density_segregation", self.density_segregation),
            ("species_segregation", self.species_segregation),
        ] {
            out.push((name.to_string(), e.value));
            out.push((format!("{name}_error"), e.error));
        }
        out.push((
            "energy_identity_residual".into(),
            self.energy_identity_residual,
        ));
        out.push((
            "cell_width_over_mean_free_path".into(),
            self.cell_width_over_mean_free_path,
        ));
        out.push((
            "time_step_over_collision_time".into(),
            self.time_step_over_collision_time,
        ));
        out
    }
}

/// One layer cell of the time-averaged profiles (normalisation: [`fields`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RarefiedProfileRow {
    /// y / W about the centre, in (-1/2, 1/2)
    pub y: f64,
    /// rho / rho_avg
    pub density: f64,
    pub density_error: f64,
    /// u_x / u_c
    pub velocity: f64,
    pub velocity_error: f64,
    /// u_x / sqrt(a W) (athermal walls, ch. 4)
    pub velocity_hat: f64,
    /// T / T_w
    pub temperature: f64,
    pub temperature_error: f64,
    /// T / T(0)
    pub temperature_over_centre: f64,
    /// p / P_c and P_ab / P_c
    pub pressure: f64,
    pub pxx: f64,
    pub pyy: f64,
    pub pzz: f64,
    pub pxy: f64,
    pub pxy_error: f64,
    /// q_a / q_c
    pub qx: f64,
    pub qx_error: f64,
    pub qy: f64,
    pub qy_error: f64,
    /// N1, N2 (eqs. 3.29-3.30)
    pub n1: f64,
    pub n2: f64,
    /// Kn_y, eq. 3.25
    pub local_knudsen: f64,
    /// n_s / n_avg of species 1 and 2 (n_avg the mean total number density)
    pub species1_density: f64,
    pub species2_density: f64,
    /// T_s / T_w (eqs. 5.9-5.10)
    pub species1_temperature: f64,
    pub species2_temperature: f64,
    /// u_x,s / u_c
    pub species1_velocity: f64,
    pub species2_velocity: f64,
}

impl RarefiedProfileRow {
    /// The quantities of the long `profiles` table: (name, value, standard error; NaN where
    /// none is estimated), in field order.
    pub fn quantities(&self) -> [(&'static str, f64, f64); 21] {
        let none = f64::NAN;
        [
            ("density", self.density, self.density_error),
            ("velocity", self.velocity, self.velocity_error),
            ("velocity_hat", self.velocity_hat, none),
            ("temperature", self.temperature, self.temperature_error),
            (
                "temperature_over_centre",
                self.temperature_over_centre,
                none,
            ),
            ("pressure", self.pressure, none),
            ("pxx", self.pxx, none),
            ("pyy", self.pyy, none),
            ("pzz", self.pzz, none),
            ("pxy", self.pxy, self.pxy_error),
            ("qx", self.qx, self.qx_error),
            ("qy", self.qy, self.qy_error),
            ("n1", self.n1, none),
            ("n2", self.n2, none),
            ("local_knudsen", self.local_knudsen, none),
            ("species1_density", self.species1_density, none),
            ("species2_density", self.species2_density, none),
            ("species1_temperature", self.species1_temperature, none),
            ("species2_temperature", self.species2_temperature, none),
            ("species1_velocity", self.species1_velocity, none),
            ("species2_velocity", self.species2_velocity, none),
        ]
    }
}

/// One job's analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RarefiedAnalysis {
    pub summary: RarefiedSummary,
    pub profiles: Vec<RarefiedProfileRow>,
}

/// Sums over a run of records.
struct Window {
    samples: f64,
    duration: f64,
    /// time steps covered
    steps: u64,
    moments: Vec<Moments>,
    balances: Balances,
}

impl Window {
    fn of(records: &[RarefiedRecord]) -> Window {
        let first = &records[0].sums;
        let mut w = Window {
            samples: 0.0,
            duration: 0.0,
            steps: 0,
            moments: vec![[0.0; MOMENTS]; first.moments.len()],
            balances: Balances::default(),
        };
        for r in records {
            w.samples += r.sums.samples as f64;
            w.duration += r.sums.duration;
            w.steps += r.sums.end_step - r.sums.start_step;
            add_moments(&mut w.moments, &r.sums.moments);
            w.balances.add(&r.sums.balances);
        }
        w
    }
}

/// The scalars of a window (the summary's values, or one block's).
#[derive(Clone, Copy, Debug, Default)]
struct Scalars {
    flow_rate: f64,
    flow_rate_hat: f64,
    mean_velocity: f64,
    centre_velocity: f64,
    slip_velocity: f64,
    centre_density: f64,
    wall_density: f64,
    centre_temperature: f64,
    temperature_slip: f64,
    bimodality: f64,
    n1_centre: f64,
    n2_centre: f64,
    momentum_balance: f64,
    energy_balance: f64,
    temperature_ratio_centre: f64,
    temperature_ratio_mean: f64,
    species_velocity_difference: f64,
    density_segregation: f64,
    species_segregation: f64,
}

/// Number of fields of [`Scalars`], in declaration order for [`Scalars::values`].
const SCALARS: usize = 19;

impl Scalars {
    fn values(&self) -> [f64; SCALARS] {
        [
            self.flow_rate,
            self.flow_rate_hat,
            self.mean_velocity,
            self.centre_velocity,
            self.slip_velocity,
            self.centre_density,
            self.wall_density,
            self.centre_temperature,
            self.temperature_slip,
            self.bimodality,
            self.n1_centre,
            self.n2_centre,
            self.momentum_balance,
            self.energy_balance,
            self.temperature_ratio_centre,
            self.temperature_ratio_mean,
            self.species_velocity_difference,
            self.density_segregation,
            self.species_segregation,
        ]
    }
}

/// Analyse a job's records (in order) with `settings`.
pub fn analyse(
    records: &[RarefiedRecord],
    settings: &RarefiedSettings,
) -> Result<RarefiedAnalysis, String> {
    settings.validate()?;
    let first = records
        .first()
        .ok_or_else(|| "no DSMC records to analyse".to_string())?;
    let sc = Scales {
        cells: first.sums.cells,
        species: first.sums.species,
        masses: first.masses,
        counts: [first.counts[0] as f64, first.counts[1] as f64],
        acceleration: 2.0 * first.forcing,
        knudsen_number: first.knudsen_number,
    };
    if let Some(i) = records.iter().position(|r| {
        r.sums.cells != sc.cells
            || r.sums.species != sc.species
            || r.sums.moments.len() != sc.cells * sc.species
            || r.counts != first.counts
    }) {
        return Err(format!(
            "DSMC record {i} does not belong to the run of record 0 (cells, species or counts \
             differ)"
        ));
    }
    let usable: Vec<usize> = (0..records.len())
        .filter(|&i| records[i].sums.samples > 0)
        .collect();
    if usable.is_empty() {
        return Err("no DSMC record holds a sample".into());
    }
    let usable_records: Vec<RarefiedRecord> = usable.iter().map(|&i| records[i].clone()).collect();
    let traces: Vec<RecordTrace> = usable_records
        .iter()
        .map(|r| trace(r, &sc, first.forcing))
        .collect();
    let window = steady::detect(
        &traces,
        settings.min_steady_records,
        settings.steady_tolerance,
    );
    let chosen = &usable_records[window.start..];
    let whole = Window::of(chosen);
    let whole_fields = cell_fields(&whole.moments, whole.samples, &sc);
    let value = scalars(&whole, &whole_fields, &sc, first.forcing);
    let blocks = settings.blocks.min(chosen.len());
    let mut block_values = Vec::new();
    let mut block_fields = Vec::new();
    if blocks >= 2 {
        let mut begin = 0;
        for b in 0..blocks {
            let len = chosen.len() / blocks + usize::from(b < chosen.len() % blocks);
            let w = Window::of(&chosen[begin..begin + len]);
            let f = cell_fields(&w.moments, w.samples, &sc);
            block_values.push(scalars(&w, &f, &sc, first.forcing).values());
            block_fields.push(f);
            begin += len;
        }
    }
    let error_of = |k: usize| -> f64 {
        if block_values.len() < 2 {
            return f64::NAN;
        }
        let x: Vec<f64> = block_values.iter().map(|v| v[k]).collect();
        mean_and_error(&x).1
    };
    let v = value.values();
    let est = |k: usize| Estimate {
        value: v[k],
        error: error_of(k),
    };
    let identity = usable_records
        .iter()
        .map(|r| {
            let b = &r.sums.balances;
            let heat = b.walls[0].energy + b.walls[1].energy;
            let stored = r.sums.kinetic_energy[1] - r.sums.kinetic_energy[0];
            let scale = b.work.abs().max(heat.abs()).max(b.dissipated).max(1e-300);
            (b.work - heat - b.dissipated - stored).abs() / scale
        })
        .fold(0.0, f64::max);
    let time_step = whole.duration / (whole.steps as f64).max(1.0);
    let (cell_width_over_mean_free_path, time_step_over_collision_time) =
        resolution(&whole_fields, &sc, time_step);
    let summary = RarefiedSummary {
        steady: window.steady,
        reason: window.reason,
        window_start_step: chosen[0].sums.start_step,
        window_end_step: chosen[chosen.len() - 1].sums.end_step,
        window_records: chosen.len() as u32,
        blocks: block_values.len() as u32,
        flow_rate: est(0),
        flow_rate_hat: est(1),
        mean_velocity: est(2),
        centre_velocity: est(3),
        slip_velocity: est(4),
        centre_density: est(5),
        wall_density: est(6),
        centre_temperature: est(7),
        temperature_slip: est(8),
        bimodality: est(9),
        n1_centre: est(10),
        n2_centre: est(11),
        momentum_balance: est(12),
        energy_balance: est(13),
        energy_identity_residual: identity,
        temperature_ratio_centre: est(14),
        temperature_ratio_mean: est(15),
        species_velocity_difference: est(16),
        density_segregation: est(17),
        species_segregation: est(18),
        cell_width_over_mean_free_path,
        time_step_over_collision_time,
    };
    let profiles = profile_rows(&whole_fields, &block_fields, &sc, value.centre_temperature);
    Ok(RarefiedAnalysis { summary, profiles })
}

/// lambda(y) / W = Kn n_avg / n(y), the a priori mean free path scaled by the local number
/// density (Kn_y of eq. 3.25; in a mixture with the diameter of species 1); infinite in an
/// empty cell.
fn local_mean_free_path(f: &CellFields, sc: &Scales) -> f64 {
    sc.knudsen_number / (f.species_density[0] + f.species_density[1])
}

/// How finely the run resolved the gas where it is densest and hottest: the largest cell width
/// over the local mean free path and the largest time step over the local mean collision
/// time, (max_y Delta y / lambda(y), max_y dt / tau(y)), lambda(y) from
/// [`local_mean_free_path`], tau(y) = lambda(y) / sqrt(8 k T(y) / (pi m_1)). Empty cells do
/// not count.
fn resolution(fields: &[CellFields], sc: &Scales, time_step: f64) -> (f64, f64) {
    let width = 1.0 / sc.cells as f64;
    let mean_speed_at_wall_temperature = (8.0 / std::f64::consts::PI).sqrt();
    let mut widest: f64 = 0.0;
    let mut longest: f64 = 0.0;
    for f in fields {
        let mean_free_path = local_mean_free_path(f, sc);
        if !mean_free_path.is_finite() {
            continue; // an empty cell
        }
        widest = widest.max(width / mean_free_path);
        if f.temperature.is_finite() && f.temperature > 0.0 {
            let collision_time =
                mean_free_path / (mean_speed_at_wall_temperature * f.temperature.sqrt());
            longest = longest.max(time_step / collision_time);
        }
    }
    (widest, longest)
}

/// The steady rule's traces of one record.
fn trace(r: &RarefiedRecord, sc: &Scales, forcing: f64) -> RecordTrace {
    let f = cell_fields(&r.sums.moments, r.sums.samples as f64, sc);
    let counts: Vec<f64> = (0..sc.cells)
        .map(|c| {
            (0..sc.species)
                .map(|s| r.sums.moments[c * sc.species + s][mo::COUNT])
                .sum()
        })
        .collect();
    let total: f64 = counts.iter().sum();
    let temperature = f
        .iter()
        .zip(&counts)
        .filter(|(_, n)| **n > 0.0)
        .map(|(f, n)| f.temperature * n)
        .sum::<f64>()
        / total;
    let b = &r.sums.balances;
    let (flow_rate, storage) = if forcing > 0.0 {
        let heat = b.walls[0].energy + b.walls[1].energy;
        (
            mean_velocity(&r.sums.moments, sc) / forcing,
            (b.work - heat - b.dissipated) / b.work,
        )
    } else {
        (f64::NAN, f64::NAN)
    };
    RecordTrace {
        temperature,
        flow_rate,
        storage,
    }
}

/// <u_x> / u_c, the mass-weighted mean velocity of all samples.
fn mean_velocity(moments: &[Moments], sc: &Scales) -> f64 {
    let (mut momentum, mut mass) = (0.0, 0.0);
    for (i, m) in moments.iter().enumerate() {
        let ms = sc.masses[i % sc.species];
        momentum += ms * m[mo::VX];
        mass += ms * m[mo::COUNT];
    }
    momentum / mass / Scales::VELOCITY
}

/// Centre value of a profile: the middle cell, or the mean of the two middle cells.
fn centre(f: &[CellFields], get: impl Fn(&CellFields) -> f64) -> f64 {
    let n = f.len();
    if n % 2 == 1 {
        get(&f[n / 2])
    } else {
        0.5 * (get(&f[n / 2 - 1]) + get(&f[n / 2]))
    }
}

/// Wall value of a profile: the mean of the two cells next to the walls.
fn wall(f: &[CellFields], get: impl Fn(&CellFields) -> f64) -> f64 {
    0.5 * (get(&f[0]) + get(&f[f.len() - 1]))
}

fn scalars(w: &Window, f: &[CellFields], sc: &Scales, forcing: f64) -> Scalars {
    let n = f.len();
    let mean_u = mean_velocity(&w.moments, sc);
    let a = sc.acceleration;
    let total_mass = sc.total_mass();
    let wall_x = w.balances.walls[0].momentum[0] + w.balances.walls[1].momentum[0];
    let heat = w.balances.walls[0].energy + w.balances.walls[1].energy;
    // T folded about the centre, for T_max
    let folded_max = (0..n.div_ceil(2))
        .map(|j| 0.5 * (f[j].temperature + f[n - 1 - j].temperature))
        .fold(f64::NEG_INFINITY, f64::max);
    let t0 = centre(f, |c| c.temperature);
    let (pxx, pyy, pzz) = (
        centre(f, |c| c.pxx),
        centre(f, |c| c.pyy),
        centre(f, |c| c.pzz),
    );
    let p0 = (pxx + pyy + pzz) / 3.0;
    // quantities scaled by the body force are undefined without it
    let forced = |x: f64| if forcing > 0.0 { x } else { f64::NAN };
    let mut s = Scalars {
        flow_rate: forced(mean_u / forcing),
        flow_rate_hat: forced(mean_u * Scales::VELOCITY / a.sqrt()),
        mean_velocity: mean_u,
        centre_velocity: centre(f, |c| c.velocity),
        slip_velocity: wall(f, |c| c.velocity),
        centre_density: centre(f, |c| c.density),
        wall_density: wall(f, |c| c.density),
        centre_temperature: t0,
        temperature_slip: wall(f, |c| c.temperature) - 1.0,
        bimodality: (folded_max - t0) / t0,
        n1_centre: (pxx - pyy) / p0,
        n2_centre: (pyy - pzz) / p0,
        momentum_balance: forced(wall_x / (total_mass * a * w.duration)),
        energy_balance: forced(
            (heat + w.balances.dissipated)
                / (total_mass * a * mean_u * Scales::VELOCITY * w.duration),
        ),
        temperature_ratio_centre: f64::NAN,
        temperature_ratio_mean: f64::NAN,
        species_velocity_difference: f64::NAN,
        density_segregation: f64::NAN,
        species_segregation: f64::NAN,
    };
    if sc.species == 2 {
        let x2 = sc.counts[1] / sc.total_count();
        s.temperature_ratio_centre =
            centre(f, |c| c.species_temperature[1]) / centre(f, |c| c.species_temperature[0]);
        let mean = |k: usize| f.iter().map(|c| c.species_temperature[k]).sum::<f64>() / n as f64;
        s.temperature_ratio_mean = mean(1) / mean(0);
        s.species_velocity_difference =
            centre(f, |c| c.species_velocity[1]) - centre(f, |c| c.species_velocity[0]);
        s.density_segregation = f
            .iter()
            .map(|c| (c.species_density[0] + c.species_density[1] - 1.0).powi(2))
            .sum::<f64>()
            / n as f64;
        s.species_segregation = f
            .iter()
            .map(|c| {
                let total = c.species_density[0] + c.species_density[1];
                (c.species_density[1] / total - x2).powi(2)
            })
            .sum::<f64>()
            / n as f64;
    }
    s
}

fn profile_rows(
    whole: &[CellFields],
    blocks: &[Vec<CellFields>],
    sc: &Scales,
    centre_temperature: f64,
) -> Vec<RarefiedProfileRow> {
    let n = whole.len();
    let err = |c: usize, get: fn(&CellFields) -> f64| -> f64 {
        if blocks.len() < 2 {
            return f64::NAN;
        }
        let x: Vec<f64> = blocks.iter().map(|b| get(&b[c])).collect();
        mean_and_error(&x).1
    };
    let hat = Scales::VELOCITY / sc.acceleration.sqrt();
    let second = |x: [f64; 2]| if sc.species == 2 { x[1] } else { f64::NAN };
    whole
        .iter()
        .enumerate()
        .map(|(c, f)| RarefiedProfileRow {
            y: (c as f64 + 0.5) / n as f64 - 0.5,
            density: f.density,
            density_error: err(c, |f| f.density),
            velocity: f.velocity,
            velocity_error: err(c, |f| f.velocity),
            velocity_hat: f.velocity * hat,
            temperature: f.temperature,
            temperature_error: err(c, |f| f.temperature),
            temperature_over_centre: f.temperature / centre_temperature,
            pressure: f.pressure(),
            pxx: f.pxx,
            pyy: f.pyy,
            pzz: f.pzz,
            pxy: f.pxy,
            pxy_error: err(c, |f| f.pxy),
            qx: f.qx,
            qx_error: err(c, |f| f.qx),
            qy: f.qy,
            qy_error: err(c, |f| f.qy),
            n1: f.n1(),
            n2: f.n2(),
            local_knudsen: local_mean_free_path(f, sc),
            species1_density: f.species_density[0],
            species2_density: second(f.species_density),
            species1_temperature: f.species_temperature[0],
            species2_temperature: second(f.species_temperature),
            species1_velocity: f.species_velocity[0],
            species2_velocity: second(f.species_velocity),
        })
        .collect()
}
