//! The steady-state rule of a DSMC job, decided from its records (simulated progress only,
//! never wall time).
//!
//! Each record (one sampling interval) gives traces: the mean temperature, and with a body
//! force the flow rate Q and the energy storage fraction (work - wall heat - dissipation) /
//! work (the kinetic energy gained per unit of energy put in; 0 on average in a steady state).
//!
//! 1. *start*: each trace is truncated by the marginal standard error rule (MSER, White
//!    1997): the start s in [0, n/2] that minimises sum_{i >= s} (x_i - mean_s)^2 / (n - s)^2,
//!    i.e. the standard error of the remaining mean; a transient inflates that error until it
//!    is cut off. The window starts at the latest of the traces' starts.
//! 2. *length*: the window holds at least `min_records` records (and at least 8).
//! 3. *plateau*: for the temperature and Q, the mean of the window's first quarter differs from
//!    that of its second half by at most max(Z sigma, tolerance |mean|), sigma the standard
//!    error of the difference from the record-to-record scatter of each part, inflated by
//!    1 + 2 rho_1 for the correlation rho_1 > 0 of consecutive records;
//! 4. *balance*: the mean storage fraction of the first quarter and of the whole window are
//!    within max(Z standard errors, tolerance) of 0 (a gas still heating up or cooling down
//!    stores or releases energy).
//!
//! A run that fails 2-4 is not steady, and the analysis uses the last third of its records.

/// Z of the tests (3: 99.7 % of Gaussian fluctuations pass).
pub const STEADY_SIGMAS: f64 = 3.0;

/// Traces of one record that the rule inspects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordTrace {
    /// mean temperature over the record
    pub temperature: f64,
    /// flow rate Q of the record (NaN without forcing)
    pub flow_rate: f64,
    /// (work - wall heat - dissipation) / work (NaN without forcing)
    pub storage: f64,
}

/// Reads one trace of a record.
type Trace = fn(&RecordTrace) -> f64;

/// The window the rule found.
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// first record of the window (it runs to the last record)
    pub start: usize,
    pub steady: bool,
    /// why the run is not steady (empty when it is)
    pub reason: String,
}

/// Find the steady window of `traces` (see the module documentation).
pub fn detect(traces: &[RecordTrace], min_records: usize, tolerance: f64) -> Window {
    let n = traces.len();
    let min_records = min_records.max(8);
    let fallback = Window {
        start: (n - n / 3).min(n.saturating_sub(1)),
        steady: false,
        reason: String::new(),
    };
    if n < min_records {
        return Window {
            reason: format!("only {n} records (the steady rule needs at least {min_records})"),
            ..fallback
        };
    }
    let getters: [Trace; 3] = [|r| r.temperature, |r| r.flow_rate, |r| r.storage];
    let start = getters
        .iter()
        .map(|get| traces.iter().map(get).collect::<Vec<f64>>())
        .filter(|x| !x.iter().any(|v| v.is_nan()))
        .map(|x| mser_start(&x))
        .max()
        .unwrap_or(0);
    if n - start < min_records {
        return Window {
            reason: format!(
                "the transient lasts until record {start}, leaving {} records (need \
                 {min_records})",
                n - start
            ),
            ..fallback
        };
    }
    match test_window(&traces[start..], tolerance) {
        Ok(()) => Window {
            start,
            steady: true,
            reason: String::new(),
        },
        Err(why) => Window {
            reason: format!("from record {start} on: {why}"),
            ..fallback
        },
    }
}

/// MSER truncation point of a trace: the s in [0, n/2] minimising the squared standard error
/// proxy sum_{i >= s} (x_i - mean_s)^2 / (n - s)^2.
pub fn mser_start(x: &[f64]) -> usize {
    let n = x.len();
    let mut best = (f64::INFINITY, 0);
    // suffix sums make every candidate O(1)
    let (mut sum, mut sum2) = (0.0, 0.0);
    let mut stats = vec![(0.0, 0.0); n + 1];
    for i in (0..n).rev() {
        sum += x[i];
        sum2 += x[i] * x[i];
        stats[i] = (sum, sum2);
    }
    for (s, &(sum, sum2)) in stats.iter().enumerate().take(n / 2 + 1) {
        let m = (n - s) as f64;
        let spread = (sum2 - sum * sum / m).max(0.0);
        let value = spread / (m * m);
        if value < best.0 {
            best = (value, s);
        }
    }
    best.1
}

fn test_window(w: &[RecordTrace], tolerance: f64) -> Result<(), String> {
    let first = &w[..w.len() / 4];
    let second = &w[w.len() - w.len() / 2..];
    let getters: [(&str, Trace); 2] = [
        ("temperature", |r| r.temperature),
        ("flow rate", |r| r.flow_rate),
    ];
    for (name, get) in getters {
        let a: Vec<f64> = first.iter().map(get).collect();
        let b: Vec<f64> = second.iter().map(get).collect();
        if a.iter().chain(&b).any(|x| x.is_nan()) {
            continue;
        }
        let (ma, ea) = mean_and_correlated_error(&a);
        let (mb, eb) = mean_and_correlated_error(&b);
        let allowed =
            (STEADY_SIGMAS * (ea * ea + eb * eb).sqrt()).max(tolerance * (0.5 * (ma + mb)).abs());
        if (ma - mb).abs() > allowed {
            return Err(format!(
                "{name} changes from {ma:.5} (first quarter) to {mb:.5} (second half) (allowed \
                 {allowed:.2e})"
            ));
        }
    }
    for part in [first, w] {
        let storage: Vec<f64> = part.iter().map(|r| r.storage).collect();
        if storage.iter().any(|x| x.is_nan()) {
            continue;
        }
        let (m, e) = mean_and_correlated_error(&storage);
        let allowed = (STEADY_SIGMAS * e).max(tolerance);
        if m.abs() > allowed {
            return Err(format!(
                "the gas stores a fraction {m:.2e} of the energy put in (allowed {allowed:.2e})"
            ));
        }
    }
    Ok(())
}

/// Mean and its standard error for serially correlated values: the independent-sample error
/// times sqrt(1 + 2 rho_1), rho_1 >= 0 the lag-one autocorrelation (an AR(1) estimate).
fn mean_and_correlated_error(x: &[f64]) -> (f64, f64) {
    let (mean, error) = mean_and_error(x);
    let n = x.len();
    let var: f64 = x.iter().map(|v| (v - mean).powi(2)).sum();
    let lag: f64 = (1..n).map(|i| (x[i] - mean) * (x[i - 1] - mean)).sum();
    let rho = if var > 0.0 { (lag / var).max(0.0) } else { 0.0 };
    (mean, error * (1.0 + 2.0 * rho).sqrt())
}

/// Mean and its standard error from the scatter of independent values (error NaN for one).
pub fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trace(temperature: f64, flow_rate: f64, storage: f64) -> RecordTrace {
        RecordTrace {
            temperature,
            flow_rate,
            storage,
        }
    }

    /// Seeded Gaussian noise of unit variance standing in for record-to-record scatter.
    fn noise(seed: u64) -> impl FnMut() -> f64 {
        let mut rng = rand_pcg::Pcg64Mcg::new(u128::from(seed) * 0x9e37_79b9 + 1);
        move || crate::engine::dsmc::kernel::normal_pair(&mut rng).0
    }

    #[test]
    fn a_relaxing_run_becomes_steady_after_its_transient() {
        // heats up over ~20 records (storing energy), then fluctuates about a plateau
        let mut wiggle = noise(1);
        let traces: Vec<RecordTrace> = (0..60)
            .map(|i| {
                let relax = (-(i as f64) / 4.0).exp();
                trace(
                    1.2 - 0.2 * relax + 0.002 * wiggle(),
                    1.5 - 0.5 * relax + 0.01 * wiggle(),
                    0.3 * relax + 0.002 * wiggle(),
                )
            })
            .collect();
        let w = detect(&traces, 8, 0.01);
        assert!(w.steady, "{}", w.reason);
        assert!(w.start > 8 && w.start <= 30, "start {}", w.start);
        // a single start-up record is cut off
        let mut jump: Vec<RecordTrace> = (0..40)
            .map(|_| {
                trace(
                    1.0 + 0.002 * wiggle(),
                    1.0 + 0.01 * wiggle(),
                    0.001 * wiggle(),
                )
            })
            .collect();
        jump[0] = trace(0.8, 0.6, 0.4);
        let w = detect(&jump, 8, 0.01);
        assert!(w.steady && w.start >= 1, "{w:?}");
        let clean: Vec<f64> = (0..40)
            .map(|i| if i == 0 { 5.0 } else { 1.0 + 0.01 * wiggle() })
            .collect();
        assert!(mser_start(&clean) >= 1);
    }

    #[test]
    fn a_ramp_or_a_short_run_is_not_steady() {
        let ramp: Vec<RecordTrace> = (0..40)
            .map(|i| trace(1.0 + 0.01 * i as f64, 1.0 + 0.05 * i as f64, 0.05))
            .collect();
        let w = detect(&ramp, 8, 0.01);
        assert!(!w.steady && w.start == 40 - 40 / 3, "{w:?}");
        assert!(!detect(&ramp[..5], 8, 0.01).steady);
        // a plateau that keeps storing 5 % of the input is not steady either
        let mut wiggle = noise(2);
        let storing: Vec<RecordTrace> = (0..40)
            .map(|_| trace(1.0 + 0.001 * wiggle(), 1.0, 0.05 + 0.001 * wiggle()))
            .collect();
        let w = detect(&storing, 8, 0.01);
        assert!(!w.steady && w.reason.contains("stores"), "{w:?}");
    }
}
