//! Analysis of DEM channel jobs (Debnath, Rao & Kumaran 2022, dem.md A2-A3): time-averaged
//! profiles across the channel with block errors, the per-job numbers of the paper (u_slip,
//! u_max, delta_0.95, the constant of eq. 3.1, sigma_xx, mu_wall), the exact wall-force
//! balance, the zones and the regime label, and the centre-of-mass series.
//!
//! Each record is one snapshot interval's sums ([`crate::engine::dem::Record`]). The window
//! is the last `window_fraction` of the records that hold samples, cut into `blocks`
//! contiguous blocks; every value is computed from the window's summed sums, its error is the
//! standard error of the values of the blocks (each computed from its own sums):
//! s / sqrt(B). The fields and their conventions: [`profiles`]; the zones: [`zones`]; the
//! regime rules: [`regime`]; the figures, tables and documentation: `docs/dem.md`.
//!
//! Per-job definitions (folded profiles: the mean of mirror bins, from the wall bin to the
//! centre; x measured from the centre of the wall bin, so that the scaled profile is 0 at
//! x = 0 as eq. 3.1 has it):
//! - u_slip: u_y of the wall bin (of width 1.5 d_p), u_max: u_y at the centre (the central
//!   bin, or the mean of the two central bins);
//! - delta_0.95: the x where (u_y - u_slip) / (u_max - u_slip) first reaches 0.95, linear
//!   between bin centres; the constant c of eq. 3.1, 1 - exp(-c x / delta_0.95), by least
//!   squares over the half channel (the paper: 3);
//! - sigma_xx: the mean of the sigma_xx profile over the bins between the wall bins;
//!   the wall normal stress: the mean normal force of the particles on a wall per area L B,
//!   over every step; mu_wall: sum over both walls of |F_flow| over sum of |F_normal|;
//! - the wall-force balance beta: both walls' flow-wise force over M g, every step;
//! - u_cm's relative fluctuation: the standard deviation of the records' mean u_cm over
//!   their mean (the paper's Fig. 3 reading);
//! - Q6 of the plug (the paper's check Q6 < 0.4, dem.md O22/N16): the global Q6 of the bonds
//!   with their midpoint in the plug's bins, pooled over the window's snapshots; without a
//!   plug, of the dense zone's bins (which reach the centre); without either, NaN
//!   ([`q6_region`]); likewise the mean local q6 of the region's bonded particles.

pub mod profiles;
mod regime;
mod zones;

use crate::engine::dem::Record;
use profiles::{BinFields, Geometry, QUANTITIES, Totals, fields, fold};
use regime::{Regime, RegimeInput, RegimeRules};
use serde::{Deserialize, Serialize};

/// What a DEM job records per snapshot.
pub type DenseRecord = Record;

/// Settings of the dense analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DenseSettings {
    /// blocks of the window for the errors
    pub blocks: usize,
    /// the window: this last fraction of the records
    pub window_fraction: f64,
    /// jammed below u_cm = jam_froude sqrt(g W)
    pub jam_froude: f64,
    /// steady only when the balance's standard error is at most this
    pub balance_tolerance: f64,
}

impl Default for DenseSettings {
    fn default() -> Self {
        DenseSettings {
            blocks: 5,
            window_fraction: 0.5,
            jam_froude: 1e-3,
            balance_tolerance: 0.05,
        }
    }
}

impl DenseSettings {
    pub fn validate(&self) -> Result<(), String> {
        if !(2..=10_000).contains(&self.blocks) {
            return Err(format!(
                "dense blocks = {} is out of range: allowed 2 to 10000",
                self.blocks
            ));
        }
        if !(self.window_fraction > 0.0 && self.window_fraction <= 1.0) {
            return Err(format!(
                "dense window_fraction = {} is out of range: allowed 0 < f <= 1",
                self.window_fraction
            ));
        }
        if !(self.jam_froude.is_finite() && self.jam_froude >= 0.0) {
            return Err(format!(
                "dense jam_froude = {} is out of range: allowed a finite value >= 0",
                self.jam_froude
            ));
        }
        if !(self.balance_tolerance.is_finite() && self.balance_tolerance > 0.0) {
            return Err(format!(
                "dense balance_tolerance = {} is out of range: allowed a finite value > 0",
                self.balance_tolerance
            ));
        }
        Ok(())
    }

    fn rules(&self) -> RegimeRules {
        RegimeRules {
            jam_froude: self.jam_froude,
            balance_tolerance: self.balance_tolerance,
        }
    }
}

/// The summary row of a DEM job (NaN: not measured).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenseSummary {
    /// steady, jammed, accelerating or not-steady (no `steady` flag: jammed and accelerating
    /// are decided regimes too, and phase diagrams show every label but `not-steady`)
    pub label: String,
    /// why the label (empty when steady)
    pub steady_reason: String,
    /// the window, in flow time
    pub window_start_time: f64,
    pub window_end_time: f64,
    pub window_records: u64,
    pub blocks: u64,
    /// <u_cm> (along the flow) over the window's samples
    pub com_velocity: f64,
    pub com_velocity_error: f64,
    /// std of the records' mean u_cm over their mean
    pub com_velocity_fluctuation: f64,
    /// beta: sum of both walls' flow-wise force over M g, averaged over every step
    pub wall_force_balance: f64,
    pub wall_force_balance_error: f64,
    /// u_slip, u_max, u_max / u_slip
    pub slip_velocity: f64,
    pub slip_velocity_error: f64,
    pub max_velocity: f64,
    pub max_velocity_error: f64,
    pub velocity_ratio: f64,
    pub velocity_ratio_error: f64,
    /// delta_0.95
    pub shear_layer_thickness: f64,
    pub shear_layer_thickness_error: f64,
    /// c of eq. 3.1 (the paper: 3)
    pub profile_constant: f64,
    pub profile_constant_error: f64,
    /// sigma_xx, mean over the interior bins
    pub normal_stress: f64,
    pub normal_stress_error: f64,
    /// mean normal force on a wall per area
    pub wall_normal_stress: f64,
    pub wall_normal_stress_error: f64,
    /// mu_wall
    pub wall_friction_coefficient: f64,
    pub wall_friction_coefficient_error: f64,
    /// zones (distances from the wall, d_p)
    pub wall_layer: f64,
    pub dense_start: f64,
    pub plug_start: f64,
    pub loose_width: f64,
    pub plug_width: f64,
    /// mean phi of the plug's folded bins (NaN: no plug)
    #[serde(default = "crate::analysis::nan")]
    pub plug_volume_fraction: f64,
    /// Q6 of the bonds in `q6_region`, pooled over the window's snapshots
    pub q6_plug: f64,
    pub q6_plug_error: f64,
    /// mean local q6 of the bonded particles in `q6_region`, over the window's snapshots
    pub local_q6_plug: f64,
    pub local_q6_plug_error: f64,
    /// which bins gave `q6_plug`: "plug", "dense" (no plug: the dense zone) or "none"
    pub q6_region: String,
    /// e_n of a d_p sphere against a wall, as the records' contact types state it: the pair's
    /// e_n under the paper's wall damping, less under LAMMPS' (0.755 at a pair e_n of 0.82)
    #[serde(default = "crate::analysis::nan")]
    pub wall_restitution: f64,
}

impl Default for DenseSummary {
    fn default() -> Self {
        let nan = f64::NAN;
        DenseSummary {
            label: "not-steady".into(),
            steady_reason: "no records".into(),
            window_start_time: nan,
            window_end_time: nan,
            window_records: 0,
            blocks: 0,
            com_velocity: nan,
            com_velocity_error: nan,
            com_velocity_fluctuation: nan,
            wall_force_balance: nan,
            wall_force_balance_error: nan,
            slip_velocity: nan,
            slip_velocity_error: nan,
            max_velocity: nan,
            max_velocity_error: nan,
            velocity_ratio: nan,
            velocity_ratio_error: nan,
            shear_layer_thickness: nan,
            shear_layer_thickness_error: nan,
            profile_constant: nan,
            profile_constant_error: nan,
            normal_stress: nan,
            normal_stress_error: nan,
            wall_normal_stress: nan,
            wall_normal_stress_error: nan,
            wall_friction_coefficient: nan,
            wall_friction_coefficient_error: nan,
            wall_layer: zones::WALL_LAYER,
            dense_start: nan,
            plug_start: nan,
            loose_width: nan,
            plug_width: nan,
            plug_volume_fraction: nan,
            q6_plug: nan,
            q6_plug_error: nan,
            local_q6_plug: nan,
            local_q6_plug_error: nan,
            q6_region: "none".into(),
            wall_restitution: nan,
        }
    }
}

/// One row of the long profiles table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DenseProfileRow {
    pub quantity: String,
    pub bin: u32,
    /// bin centre / W from the wall at x = 0
    pub coordinate: f64,
    pub value: f64,
    pub error: f64,
}

/// One row of the series table: a record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeriesRow {
    /// flow time at the record's end
    pub time: f64,
    /// mean u_cm over the record's samples
    pub com_velocity: f64,
    /// beta over the record's steps
    pub wall_force_balance: f64,
    /// mean kinetic energies per particle (m v^2 / 2, I w^2 / 2)
    pub translational_energy: f64,
    pub rotational_energy: f64,
    /// mean contacts per particle, 2 (touching pairs) / N
    pub coordination_number: f64,
    /// in the analysis window
    pub in_window: bool,
}

/// A DEM job's analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenseAnalysis {
    pub dense_summary: DenseSummary,
    #[serde(default)]
    pub profiles: Vec<DenseProfileRow>,
    #[serde(default)]
    pub series: Vec<SeriesRow>,
}

/// The records with samples, and the index where the window starts.
fn usable<'a>(records: &'a [Record], settings: &DenseSettings) -> (Vec<&'a Record>, usize) {
    let usable: Vec<&Record> = records
        .iter()
        .filter(|r| r.sums.samples > 0 && r.sums.force_steps > 0)
        .collect();
    let n = usable.len();
    let start = n - ((n as f64 * settings.window_fraction).round() as usize).min(n);
    (usable, start)
}

/// beta of some summed records: both walls' flow-wise force over M g, per step.
fn balance(t: &Totals, r: &Record) -> f64 {
    let c = &r.constants;
    (t.wall_force[0][0] + t.wall_force[1][0]) / (c.total_mass * c.gravity[0]) / t.force_steps
}

/// The window's blocks (contiguous, as equal as the count allows).
fn blocks<'a>(window: &[&'a Record], blocks: usize) -> Vec<Vec<&'a Record>> {
    (0..blocks)
        .map(|k| window[k * window.len() / blocks..(k + 1) * window.len() / blocks].to_vec())
        .collect()
}

/// Standard error of the mean of independent block values: s / sqrt(B) (NaN for fewer than
/// two, or when a value is not finite).
pub fn standard_error(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    if values.len() < 2 {
        return f64::NAN;
    }
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (var / n).sqrt()
}

/// The scalar readings of one set of summed records, in [`SCALARS`] order.
fn scalars(t: &Totals, f: &[BinFields], g: &Geometry, r: &Record) -> [f64; SCALARS.len()] {
    let u: Vec<f64> = fold(&f.iter().map(|f| f.velocity).collect::<Vec<_>>(), false);
    let centres = g.centres();
    let x: Vec<f64> = centres[..u.len()].iter().map(|c| c - centres[0]).collect();
    let (u_slip, u_max) = (u[0], u[u.len() - 1]);
    let (delta, constant) = shear_layer(&x, &u);
    let n = f.len();
    let interior: Vec<f64> = f[1..n.saturating_sub(1)]
        .iter()
        .map(|f| f.stress[0][0])
        .collect();
    let normal = interior.iter().sum::<f64>() / interior.len() as f64;
    let wf = &t.wall_force;
    let wall_normal = 0.5 * (wf[0][1].abs() + wf[1][1].abs()) / (t.force_steps * g.area);
    let mu_wall = (wf[0][0].abs() + wf[1][0].abs()) / (wf[0][1].abs() + wf[1][1].abs());
    [
        t.com_velocity / t.samples,
        balance(t, r),
        u_slip,
        u_max,
        u_max / u_slip,
        delta,
        constant,
        normal,
        wall_normal,
        mu_wall,
    ]
}

const SCALARS: [&str; 10] = [
    "com_velocity",
    "wall_force_balance",
    "slip_velocity",
    "max_velocity",
    "velocity_ratio",
    "shear_layer_thickness",
    "profile_constant",
    "normal_stress",
    "wall_normal_stress",
    "wall_friction_coefficient",
];

/// delta_0.95 and the constant c of eq. 3.1 from a half profile u (wall bin first) at
/// distances x from the wall bin's centre (x[0] = 0); NaN when u_max = u_slip or the
/// profile never reaches 0.95.
pub fn shear_layer(x: &[f64], u: &[f64]) -> (f64, f64) {
    let (us, um) = (u[0], u[u.len() - 1]);
    let s: Vec<f64> = u.iter().map(|u| (u - us) / (um - us)).collect();
    if !(um - us).is_finite() || um == us {
        return (f64::NAN, f64::NAN);
    }
    let Some(k) = (1..s.len()).find(|&k| s[k] >= 0.95) else {
        return (f64::NAN, f64::NAN);
    };
    let t = (0.95 - s[k - 1]) / (s[k] - s[k - 1]);
    let delta = x[k - 1] + t * (x[k] - x[k - 1]);
    // least squares in c by golden section over ln c in [ln 0.05, ln 50]
    let cost = |c: f64| -> f64 {
        (1..s.len())
            .map(|k| (s[k] - 1.0 + (-c * x[k] / delta).exp()).powi(2))
            .sum()
    };
    let (mut a, mut b) = (0.05f64.ln(), 50f64.ln());
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (c1, c2) = (b - r * (b - a), a + r * (b - a));
        if cost(c1.exp()) < cost(c2.exp()) {
            b = c2;
        } else {
            a = c1;
        }
    }
    (delta, (0.5 * (a + b)).exp())
}

/// The regime of the window's records (the scalar part of the analysis: what a run until
/// steady asks after every snapshot), with the window's start and end times.
pub fn regime_of(records: &[Record], settings: &DenseSettings) -> Option<(Regime, f64, f64)> {
    let (usable, start) = usable(records, settings);
    let window = &usable[start..];
    let first = window.first()?;
    let dt = first.constants.time_step;
    let blocks = blocks(window, settings.blocks.min(window.len()));
    let betas: Vec<f64> = blocks
        .iter()
        .map(|b| balance(&Totals::of(b), first))
        .collect();
    let t = Totals::of(window);
    let last = Totals::of(blocks.last()?);
    let x = RegimeInput {
        records: window.len(),
        blocks: settings.blocks,
        balance: balance(&t, first),
        balance_error: standard_error(&betas),
        last_block_velocity: last.com_velocity / last.samples,
        width: first.constants.width,
    };
    Some((
        regime::regime(&x, &settings.rules()),
        first.sums.start_step as f64 * dt,
        window[window.len() - 1].sums.end_step as f64 * dt,
    ))
}

/// Why a run until steady may stop after this snapshot: steady or jammed over a window of
/// at least `span` flow time; None otherwise.
pub fn stop_reason(records: &[Record], settings: &DenseSettings, span: f64) -> Option<String> {
    let (r, a, b) = regime_of(records, settings)?;
    if b - a < span || !(r.label == "steady" || r.label == "jammed") {
        return None;
    }
    Some(if r.reason.is_empty() {
        format!("{} over {a:.1} .. {b:.1}", r.label)
    } else {
        format!("{} over {a:.1} .. {b:.1}: {}", r.label, r.reason)
    })
}

/// Where Q6 is read: the plug's folded bins ("plug"), or without a plug the dense zone's
/// ("dense": it reaches the centre, so these are the central bins within it), or nowhere
/// ("none": the centre is looser than phi_ad); with the first folded bin of the region.
pub fn q6_region(z: &zones::Zones) -> (&'static str, Option<usize>) {
    match (z.plug_from, z.dense_from) {
        (Some(k), _) => ("plug", Some(k)),
        (None, Some(k)) => ("dense", Some(k)),
        (None, None) => ("none", None),
    }
}

/// e_n of a d_p sphere against a wall (of the mix's middle size when it has no d_p), from a
/// record's contact types.
fn wall_restitution(r: &Record) -> f64 {
    let walls: Vec<_> = r
        .constants
        .contact_types
        .iter()
        .filter(|t| t.other.is_none())
        .collect();
    walls
        .iter()
        .find(|t| t.diameter == 1.0)
        .or(walls.get(walls.len() / 2))
        .map_or(f64::NAN, |t| t.restitution)
}

/// The series rows of the usable records.
fn series(usable: &[&Record], start: usize) -> Vec<SeriesRow> {
    usable
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let s = &r.sums;
            let c = &r.constants;
            let n = s.samples as f64;
            let particles = c.particles as f64;
            SeriesRow {
                time: s.end_step as f64 * c.time_step,
                com_velocity: s.com_velocity[0] / n,
                wall_force_balance: (s.wall_force[0][0] + s.wall_force[1][0])
                    / (c.total_mass * c.gravity[0])
                    / s.force_steps as f64,
                translational_energy: s.kinetic_energy[0] / n / particles,
                rotational_energy: s.kinetic_energy[1] / n / particles,
                coordination_number: 2.0 * s.contacts / n / particles,
                in_window: k >= start,
            }
        })
        .collect()
}

/// Analyse a job's records (in time order).
pub fn analyse(records: &[Record], settings: &DenseSettings) -> DenseAnalysis {
    let mut s = DenseSummary::default();
    let (usable, start) = usable(records, settings);
    let window = &usable[start..];
    let Some((regime, t0, t1)) = regime_of(records, settings) else {
        return DenseAnalysis {
            dense_summary: s,
            profiles: Vec::new(),
            series: Vec::new(),
        };
    };
    let first = window[0];
    s.wall_restitution = wall_restitution(first);
    let g = Geometry::of(first);
    s.window_start_time = t0;
    s.window_end_time = t1;
    s.window_records = window.len() as u64;
    s.label = regime.label;
    s.steady_reason = regime.reason;
    // the window and its blocks
    let nb = settings.blocks.min(window.len());
    s.blocks = nb as u64;
    let total = Totals::of(window);
    let whole = fields(&total, &g);
    let parts: Vec<(Totals, Vec<BinFields>)> = blocks(window, nb)
        .iter()
        .map(|b| {
            let t = Totals::of(b);
            let f = fields(&t, &g);
            (t, f)
        })
        .collect();
    // scalars
    let value = scalars(&total, &whole, &g, first);
    let block_values: Vec<[f64; SCALARS.len()]> = parts
        .iter()
        .map(|(t, f)| scalars(t, f, &g, first))
        .collect();
    let error = |k: usize| standard_error(&block_values.iter().map(|v| v[k]).collect::<Vec<_>>());
    let mut pairs = [(0.0, 0.0); SCALARS.len()];
    for k in 0..SCALARS.len() {
        pairs[k] = (value[k], error(k));
    }
    (s.com_velocity, s.com_velocity_error) = pairs[0];
    (s.wall_force_balance, s.wall_force_balance_error) = pairs[1];
    (s.slip_velocity, s.slip_velocity_error) = pairs[2];
    (s.max_velocity, s.max_velocity_error) = pairs[3];
    (s.velocity_ratio, s.velocity_ratio_error) = pairs[4];
    (s.shear_layer_thickness, s.shear_layer_thickness_error) = pairs[5];
    (s.profile_constant, s.profile_constant_error) = pairs[6];
    (s.normal_stress, s.normal_stress_error) = pairs[7];
    (s.wall_normal_stress, s.wall_normal_stress_error) = pairs[8];
    (
        s.wall_friction_coefficient,
        s.wall_friction_coefficient_error,
    ) = pairs[9];
    let u: Vec<f64> = series(window, 0).iter().map(|r| r.com_velocity).collect();
    s.com_velocity_fluctuation = standard_error(&u) * (u.len() as f64).sqrt()
        / (u.iter().sum::<f64>() / u.len() as f64).abs();
    // profiles with block errors
    let centres = g.centres();
    let width = g.width();
    let mut rows = Vec::new();
    for (name, get) in QUANTITIES {
        for (bin, f) in whole.iter().enumerate() {
            let blocks: Vec<f64> = parts.iter().map(|(_, p)| get(&p[bin])).collect();
            let e = standard_error(&blocks);
            rows.push(DenseProfileRow {
                quantity: (*name).into(),
                bin: bin as u32,
                coordinate: centres[bin] / width,
                value: get(f),
                error: e,
            });
        }
    }
    // scaled velocity (u_y - u_slip) / (u_max - u_slip) (no error: see u_slip, u_max)
    for (bin, f) in whole.iter().enumerate() {
        rows.push(DenseProfileRow {
            quantity: "scaled_velocity".into(),
            bin: bin as u32,
            coordinate: centres[bin] / width,
            value: (f.velocity - s.slip_velocity) / (s.max_velocity - s.slip_velocity),
            error: f64::NAN,
        });
    }
    // zones from the folded profiles
    let phi = fold(
        &whole.iter().map(|f| f.volume_fraction).collect::<Vec<_>>(),
        false,
    );
    let shear = fold(
        &whole.iter().map(|f| f.shear_rate).collect::<Vec<_>>(),
        true,
    );
    let half = phi.len();
    let z = zones::zones(&centres[..half], &g.edges[..half], &phi, &shear, width);
    s.dense_start = z.dense_start;
    s.plug_start = z.plug_start;
    s.loose_width = z.loose_width;
    s.plug_width = z.plug_width;
    s.plug_volume_fraction = z.plug_volume_fraction;
    // Q6 of the plug (else of the dense zone), with the block error
    let (region, from) = q6_region(&z);
    s.q6_region = region.into();
    if let Some(k) = from {
        let bins = k..whole.len() - k;
        let pooled = |t: &Totals| {
            let mut s = crate::engine::dem::BondSums::default();
            for b in t.bonds.get(bins.clone()).unwrap_or_default() {
                s.add(b);
            }
            (s.q6(), s.mean_local_q6())
        };
        let blocks: Vec<(f64, f64)> = parts.iter().map(|(t, _)| pooled(t)).collect();
        (s.q6_plug, s.local_q6_plug) = pooled(&total);
        s.q6_plug_error = standard_error(&blocks.iter().map(|b| b.0).collect::<Vec<_>>());
        s.local_q6_plug_error = standard_error(&blocks.iter().map(|b| b.1).collect::<Vec<_>>());
    }
    DenseAnalysis {
        dense_summary: s,
        profiles: rows,
        series: series(&usable, start),
    }
}
