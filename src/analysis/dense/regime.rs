//! The regime of a DEM channel job from its window (dem.md A3.1 N1): `steady`, `jammed`,
//! `accelerating`, or `not-steady` when the window decides none of them.
//!
//! The rules read the exact momentum balance (dem.md A3.2): over any interval,
//! M (u_cm(end) - u_cm(start)) = M g t - (impulse of the particles on the walls), so the
//! wall-force balance beta = <F_walls> / (M g) is 1 - <du_cm/dt> / g: beta < 1 is an
//! accelerating flow, beta > 1 a decelerating one, beta = 1 no mean acceleration. Its noise
//! is the standard error s_beta of the block values. In order:
//! 1. too short: fewer than two records per block -> `not-steady`;
//! 2. `jammed`: the last block's mean u_cm is below `jam_froude` sqrt(g W) (the flow has
//!    stopped: the free-fall scale of the width is the reference; a jammed packing only
//!    rattles);
//! 3. `accelerating`: 1 - beta > 3 s_beta (the walls carry significantly less than the
//!    weight; the centre-of-mass velocity keeps growing);
//! 4. `steady`: |beta - 1| <= 3 s_beta and s_beta <= `balance_tolerance` (the walls carry
//!    the weight within the noise, and the noise is small enough for that to mean something);
//! 5. otherwise `not-steady`, with the reason (decelerating: beta - 1 > 3 s_beta; or a
//!    balance too noisy to decide).

use serde::{Deserialize, Serialize};

/// What the rules read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegimeInput {
    /// records in the window and blocks
    pub records: usize,
    pub blocks: usize,
    /// beta and s_beta
    pub balance: f64,
    pub balance_error: f64,
    /// mean u_cm over the window's last block
    pub last_block_velocity: f64,
    /// W
    pub width: f64,
}

/// The thresholds of the rules.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegimeRules {
    pub jam_froude: f64,
    pub balance_tolerance: f64,
}

/// A regime label and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Regime {
    /// steady, jammed, accelerating or not-steady
    pub label: String,
    /// the rule's reading, in words
    pub reason: String,
}

/// Apply the rules.
pub fn regime(x: &RegimeInput, rules: &RegimeRules) -> Regime {
    let out = |label: &str, reason: String| Regime {
        label: label.into(),
        reason,
    };
    let (b, e) = (x.balance, x.balance_error);
    if x.records < 2 * x.blocks || x.blocks < 2 {
        return out(
            "not-steady",
            format!(
                "{} records in the window, fewer than two per block ({} blocks)",
                x.records, x.blocks
            ),
        );
    }
    let jam = rules.jam_froude * x.width.sqrt();
    if x.last_block_velocity.abs() < jam {
        return out(
            "jammed",
            format!(
                "u_cm = {:.3e} in the last block, below {} sqrt(g W) = {jam:.3e}",
                x.last_block_velocity, rules.jam_froude
            ),
        );
    }
    if !e.is_finite() || !b.is_finite() {
        return out(
            "not-steady",
            "the wall-force balance has no finite error".into(),
        );
    }
    let walls = format!("the walls carry {b:.4} +- {e:.4} of the weight");
    if 1.0 - b > 3.0 * e {
        return out(
            "accelerating",
            format!("{walls} (< 1 by more than 3 standard errors)"),
        );
    }
    if b - 1.0 > 3.0 * e {
        return out(
            "not-steady",
            format!("{walls} (> 1 by more than 3 standard errors: decelerating)"),
        );
    }
    if e > rules.balance_tolerance {
        return out(
            "not-steady",
            format!(
                "{walls}: its error is above the tolerance {}",
                rules.balance_tolerance
            ),
        );
    }
    out("steady", String::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULES: RegimeRules = RegimeRules {
        jam_froude: 1e-3,
        balance_tolerance: 0.05,
    };

    fn input(balance: f64, error: f64, u: f64) -> RegimeInput {
        RegimeInput {
            records: 20,
            blocks: 5,
            balance,
            balance_error: error,
            last_block_velocity: u,
            width: 100.0,
        }
    }

    #[test]
    fn each_rule_gives_its_label() {
        let l = |x: RegimeInput| regime(&x, &RULES).label;
        assert_eq!(l(input(1.01, 0.01, 3.0)), "steady");
        assert_eq!(l(input(0.95, 0.01, 3.0)), "accelerating");
        assert_eq!(l(input(1.05, 0.01, 3.0)), "not-steady");
        // a balance of 1 with a large error decides nothing
        assert_eq!(l(input(1.0, 0.2, 3.0)), "not-steady");
        // below 1e-3 sqrt(100) = 0.01: jammed, whatever the balance
        assert_eq!(l(input(1.0, 0.001, 0.009)), "jammed");
        assert_eq!(l(input(1.0, 0.001, 0.011)), "steady");
        let mut short = input(1.0, 0.001, 3.0);
        short.records = 9;
        assert_eq!(l(short), "not-steady");
    }
}
