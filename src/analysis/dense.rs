//! A first, small analysis of DEM channel jobs (Debnath, Rao & Kumaran 2022): over the second
//! half of a job's records, the mean centre-of-mass velocity and the wall-force balance
//! (the total force of the particles on both walls along the flow over the weight, 1 in a
//! steady flow, dem.md A3.2), each with the standard error of its block means, and a label.
//!
//! Each record is one snapshot interval's sums ([`crate::engine::dem::Record`]). The window
//! is the second half of the records that hold samples, cut into `blocks` contiguous blocks;
//! a value is the ratio of the window's sums, its error the standard deviation of the block
//! values over sqrt(blocks). Label: `steady` when the window has at least two records per
//! block and the balance is within three standard errors of 1, else `not-steady` (with the
//! reason). The profiles, zones and regimes of the paper come later.

use crate::engine::dem::Record;
use serde::{Deserialize, Serialize};

/// What a DEM job records per snapshot.
pub type DenseRecord = Record;

/// Settings of the dense analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DenseSettings {
    /// blocks of the window for the errors
    pub blocks: usize,
}

impl Default for DenseSettings {
    fn default() -> Self {
        DenseSettings { blocks: 5 }
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
        Ok(())
    }
}

/// The summary row of a DEM job.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenseSummary {
    /// steady or not-steady
    pub label: String,
    pub steady: bool,
    /// why not steady (empty when steady)
    pub steady_reason: String,
    /// the window, in flow time
    pub window_start_time: f64,
    pub window_end_time: f64,
    pub window_records: u64,
    pub blocks: u64,
    /// <u_cm,x> over the window's samples
    pub com_velocity: f64,
    pub com_velocity_error: f64,
    /// sum of both walls' x force over M g, averaged over every step of the window
    pub wall_force_balance: f64,
    pub wall_force_balance_error: f64,
}

impl Default for DenseSummary {
    fn default() -> Self {
        DenseSummary {
            label: "not-steady".into(),
            steady: false,
            steady_reason: "no records".into(),
            window_start_time: f64::NAN,
            window_end_time: f64::NAN,
            window_records: 0,
            blocks: 0,
            com_velocity: f64::NAN,
            com_velocity_error: f64::NAN,
            wall_force_balance: f64::NAN,
            wall_force_balance_error: f64::NAN,
        }
    }
}

/// A DEM job's analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DenseAnalysis {
    pub dense_summary: DenseSummary,
}

/// (sum of values, sum of weights) of the window's u_cm and balance over some records.
fn sums(records: &[&Record]) -> ([f64; 2], [f64; 2]) {
    let mut u = [0.0; 2];
    let mut b = [0.0; 2];
    for r in records {
        let s = &r.sums;
        let c = &r.constants;
        u[0] += s.com_velocity[0];
        u[1] += s.samples as f64;
        b[0] += (s.wall_force[0][0] + s.wall_force[1][0]) / (c.total_mass * c.gravity[0]);
        b[1] += s.force_steps as f64;
    }
    (u, b)
}

/// Analyse a job's records (in time order).
pub fn analyse(records: &[Record], settings: &DenseSettings) -> DenseAnalysis {
    let usable: Vec<&Record> = records
        .iter()
        .filter(|r| r.sums.samples > 0 && r.sums.force_steps > 0)
        .collect();
    let window = &usable[usable.len() / 2..];
    let mut s = DenseSummary::default();
    if window.is_empty() {
        return DenseAnalysis { dense_summary: s };
    }
    let dt = window[0].constants.time_step;
    s.window_start_time = window[0].sums.start_step as f64 * dt;
    s.window_end_time = window[window.len() - 1].sums.end_step as f64 * dt;
    s.window_records = window.len() as u64;
    let (u, b) = sums(window);
    s.com_velocity = u[0] / u[1];
    s.wall_force_balance = b[0] / b[1];
    let blocks = settings.blocks.min(window.len());
    s.blocks = blocks as u64;
    if blocks >= 2 {
        let mut ub = Vec::new();
        let mut bb = Vec::new();
        for k in 0..blocks {
            let (lo, hi) = (k * window.len() / blocks, (k + 1) * window.len() / blocks);
            let (u, b) = sums(&window[lo..hi]);
            ub.push(u[0] / u[1]);
            bb.push(b[0] / b[1]);
        }
        s.com_velocity_error = standard_error(&ub);
        s.wall_force_balance_error = standard_error(&bb);
    }
    let reason = if window.len() < 2 * settings.blocks {
        format!(
            "{} records in the window, fewer than two per block ({} blocks)",
            window.len(),
            settings.blocks
        )
    } else if !s.wall_force_balance_error.is_finite() {
        "the wall-force balance has no finite error".into()
    } else if (s.wall_force_balance - 1.0).abs() > 3.0 * s.wall_force_balance_error {
        format!(
            "the walls carry {:.4} +- {:.4} of the weight (not 1 within 3 standard errors)",
            s.wall_force_balance, s.wall_force_balance_error
        )
    } else {
        String::new()
    };
    s.steady = reason.is_empty();
    s.label = if s.steady { "steady" } else { "not-steady" }.into();
    s.steady_reason = reason;
    DenseAnalysis { dense_summary: s }
}

/// Standard error of the mean of independent block values: s / sqrt(B).
fn standard_error(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (var / n).sqrt()
}
