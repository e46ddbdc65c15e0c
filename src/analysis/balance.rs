//! The exact balances of channel flow as evidence of a steady state (oracles.md section 4).
//! At every time the x-impulse the walls have taken equals N m g t minus the growth of the
//! x-momentum, and the energy dissipated equals the work of gravity minus the growth of the
//! kinetic energy. So over a window, with Delta the change across it:
//!
//! - `momentum_balance` = Delta(wall x-impulse) / (N m g Delta t),
//! - `energy_balance` = Delta(energy dissipated) / Delta(work of gravity),
//!
//! are both 1 in a steady state (on average) and fall below 1 while the flow still
//! accelerates or heats up. They are dimensionless and need no tuned constant. Their errors
//! come from batch means: the window is cut into [`BLOCKS`] blocks of consecutive snapshot
//! intervals, each block gives its own ratio, and the standard error is the standard deviation
//! of the block ratios over sqrt(blocks) (the blocks are long compared with the time between
//! snapshots, so their ratios are nearly independent).

use super::SnapshotRecord;
use super::steady::{BAND_SIGMAS, SteadyWindow, mean_std};

/// Number of blocks of the batch-means error (the usual 10; fewer when the window has fewer
/// snapshot intervals).
pub const BLOCKS: usize = 10;

/// The collapse guard's validity limit: the share of the dissipation of constant restitution
/// that it may suppress over a window (1 %: the energy sink that drives structure formation is
/// then the model's own to within 1 %).
pub const COLLAPSE_GUARD_LIMIT: f64 = 0.01;

/// Fewest snapshot intervals for an error estimate.
pub const MIN_INTERVALS: usize = 4;

/// A balance ratio over a window with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Balance {
    /// the ratio over the whole window (1 in a steady state)
    pub ratio: f64,
    /// standard error from the block ratios
    pub error: f64,
    /// blocks used
    pub blocks: usize,
}

impl Balance {
    /// Whether the ratio is within `sigmas` standard errors of 1.
    pub fn consistent_with_one(&self, sigmas: f64) -> bool {
        (self.ratio - 1.0).abs() <= sigmas * self.error
    }
}

/// Ratio num/den over the window and over each block, where `num(r)` and `den(r)` are
/// cumulative totals of a record.
fn ratio_with_blocks(
    records: &[SnapshotRecord],
    num: impl Fn(&SnapshotRecord) -> f64,
    den: impl Fn(&SnapshotRecord) -> f64,
) -> Option<Balance> {
    let intervals = records.len().checked_sub(1)?;
    if intervals < MIN_INTERVALS {
        return None;
    }
    let (first, last) = (&records[0], &records[intervals]);
    let total_den = den(last) - den(first);
    let ratio = (num(last) - num(first)) / total_den;
    if !ratio.is_finite() || total_den <= 0.0 {
        return None;
    }
    let blocks = BLOCKS.min(intervals);
    let block_ratios: Vec<f64> = (0..blocks)
        .map(|b| {
            let (i, j) = (b * intervals / blocks, (b + 1) * intervals / blocks);
            (num(&records[j]) - num(&records[i])) / (den(&records[j]) - den(&records[i]))
        })
        .collect();
    if block_ratios.iter().any(|r| !r.is_finite()) {
        return None;
    }
    let (_, sd) = mean_std(&block_ratios);
    Some(Balance {
        ratio,
        error: sd / (blocks as f64).sqrt(),
        blocks,
    })
}

/// The momentum balance of a window: wall x-impulse per unit time over N m g (m = 1). None
/// without gravity, without recorded impulses, or with fewer than [`MIN_INTERVALS`] intervals.
pub fn momentum_balance(records: &[SnapshotRecord]) -> Option<Balance> {
    let first = records.first()?;
    let weight = first.particles as f64 * first.gravity;
    if weight <= 0.0 {
        return None;
    }
    ratio_with_blocks(records, |r| r.wall_impulse_x, |r| weight * r.time)
}

/// The energy balance of a window: energy dissipated over the work of gravity. None without
/// gravity work or recorded totals, or with fewer than [`MIN_INTERVALS`] intervals.
pub fn energy_balance(records: &[SnapshotRecord]) -> Option<Balance> {
    ratio_with_blocks(records, |r| r.energy_dissipated, |r| r.gravity_work)
}

/// Over a window: the fraction of pair collisions the collapse guard made elastic, and the
/// fraction of the dissipation that constant restitution prescribes that it suppressed,
/// suppressed / (dissipated + suppressed). NaN where not recorded.
pub fn collapse_guard_fractions(records: &[SnapshotRecord]) -> (f64, f64) {
    let (Some(first), Some(last)) = (records.first(), records.last()) else {
        return (f64::NAN, f64::NAN);
    };
    let pairs = last.pair_collisions.saturating_sub(first.pair_collisions);
    let elastic = last
        .tc_elastic_collisions
        .saturating_sub(first.tc_elastic_collisions);
    let count = if pairs > 0 {
        elastic as f64 / pairs as f64
    } else {
        f64::NAN
    };
    let suppressed = last.suppressed_dissipation - first.suppressed_dissipation;
    let dissipated = last.energy_dissipated - first.energy_dissipated;
    let energy = if dissipated + suppressed > 0.0 {
        suppressed / (dissipated + suppressed)
    } else {
        f64::NAN
    };
    (count, energy)
}

/// Confirm a plateau with the exact balances (the balances of this module): a window stays steady only
/// if every balance that could be measured over it is within [`BAND_SIGMAS`] standard errors
/// of 1 (balances that cannot be measured, e.g. without gravity, do not count).
pub fn confirm_by_balances(
    window: SteadyWindow,
    balances: &[(&str, Option<Balance>)],
) -> SteadyWindow {
    if !window.steady {
        return window;
    }
    for (name, b) in balances {
        if let Some(b) = b
            && !b.consistent_with_one(BAND_SIGMAS)
        {
            return SteadyWindow {
                steady: false,
                reason: format!(
                    "the {name} balance over the window is {:.4} +- {:.4}, not 1 within {BAND_SIGMAS} standard errors",
                    b.ratio, b.error
                ),
                ..window
            };
        }
    }
    window
}
