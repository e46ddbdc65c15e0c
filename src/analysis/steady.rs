//! The steady-state detector: the plateau of the translational kinetic-energy trace
//! E(t) per particle against collisions per particle (thesis 2.3 and 5.2: the energy rises
//! from the cold start until gain by gravity and collisional loss balance).
//!
//! Rule (all averages of a job use the window it finds):
//! 1. the reference plateau is the tail of the trace, the last max(3, ceil(n/3)) snapshots,
//!    with mean mu and standard deviation sigma;
//! 2. the band is mu +- max(BAND_SIGMAS sigma, RELATIVE_TOLERANCE mu);
//! 3. the window starts after the last snapshot outside the band;
//! 4. the run is steady when the window holds at least `min_snapshots` snapshots and the
//!    linear drift of E over the window, |slope| x span, is below
//!    max(BAND_SIGMAS x its standard error, RELATIVE_TOLERANCE mu).
//!
//! A run that is still rising (or falling) fails step 4 (a ramp has a drift far above its
//! residual scatter); a run too short fails step 4's snapshot count.

/// Band half-width in standard deviations of the tail (3: 99.7 % of Gaussian fluctuations).
pub const BAND_SIGMAS: f64 = 3.0;

/// Relative tolerance: changes of the energy level below 5 % count as a plateau.
pub const RELATIVE_TOLERANCE: f64 = 0.05;

/// Where the plateau of a trace starts, and whether the run is steady.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyWindow {
    /// first snapshot of the window (the window runs to the end of the trace)
    pub start: usize,
    pub steady: bool,
    /// why a run is not steady (empty when it is)
    pub reason: String,
}

/// Find the steady window of the trace `energy` sampled at clock values `clock`.
pub fn detect(clock: &[f64], energy: &[f64], min_snapshots: usize) -> SteadyWindow {
    let n = energy.len().min(clock.len());
    let min_snapshots = min_snapshots.max(2);
    let tail_start = n.saturating_sub((n.div_ceil(3)).max(3));
    if n < min_snapshots || n < 3 {
        return SteadyWindow {
            start: tail_start,
            steady: false,
            reason: format!("only {n} snapshots (the detector needs at least {min_snapshots})"),
        };
    }
    let (mu, sigma) = mean_std(&energy[tail_start..n]);
    let band = (BAND_SIGMAS * sigma).max(RELATIVE_TOLERANCE * mu.abs());
    let start = (0..n)
        .rev()
        .find(|&i| (energy[i] - mu).abs() > band)
        .map_or(0, |i| i + 1);
    let m = n - start;
    if m < min_snapshots {
        return SteadyWindow {
            start: start.min(tail_start),
            steady: false,
            reason: format!(
                "the energy has not settled: only {m} final snapshots lie within \
                 {mu:.4e} +- {band:.2e} (need {min_snapshots})"
            ),
        };
    }
    let (drift, se) = linear_drift(&clock[start..n], &energy[start..n]);
    let allowed = (BAND_SIGMAS * se).max(RELATIVE_TOLERANCE * mu.abs());
    if drift.abs() > allowed {
        return SteadyWindow {
            start,
            steady: false,
            reason: format!(
                "the energy still drifts by {drift:.3e} over the final window \
                 (allowed {allowed:.3e})"
            ),
        };
    }
    SteadyWindow {
        start,
        steady: true,
        reason: String::new(),
    }
}

/// Mean and sample standard deviation.
pub fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mean = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

/// Least-squares drift slope x span of y(x), and its standard error (from the residuals).
fn linear_drift(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len();
    let (mx, _) = mean_std(x);
    let (my, _) = mean_std(y);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    if n < 3 || sxx <= 0.0 {
        return (0.0, 0.0);
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    let res: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    let sigma = (res / (n - 2) as f64).sqrt();
    let span = x[n - 1] - x[0];
    (slope * span, sigma / sxx.sqrt() * span.abs())
}
