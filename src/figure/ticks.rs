//! Axis ticks: values as tick labels (the shortest decimal that reads back as the value, never
//! `0.30000000000000004`), and the ticks of a logarithmic axis at 1, 2 and 5 x 10^k as far as
//! their labels fit without overlapping, else fewer.

use super::text;

/// A value as a tick label: the shortest decimal that reads back as the same number ("0.3",
/// "25", "-2"); in exponent form ("1e-5", "2.5e7") below 1e-4 and from 1e6 on.
pub fn label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v.is_nan() { "NaN".into() } else { "0".into() };
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A value of a linear axis as a tick label: at most 4 significant digits, no trailing zeros,
/// round-off about zero (e.g. -5.6e-17 on a symmetric axis) as 0; exponent form below 1e-3
/// and from 1e5 on.
pub fn short(v: f64) -> String {
    if v.abs() < 1e-10 || !v.is_finite() {
        return "0".into();
    }
    if v.abs() >= 1e5 || v.abs() < 1e-3 {
        return format!("{v:.1e}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
    let text = format!("{v:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// m x 10^k as the number nearest to that decimal (so that its label is "m" with the point
/// moved, not a product's round-off).
fn decimal(m: i64, k: i32) -> f64 {
    format!("{m}e{k}").parse().unwrap_or(f64::NAN)
}

/// Which way an axis runs: a horizontal axis sets its labels side by side, a vertical one
/// stacks them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Axis {
    Horizontal,
    Vertical,
}

/// The ticks of a logarithmic axis over [lo, hi] that is `length` CSS pixels long, with
/// labels of `size` CSS pixels: 1, 2 and 5 x 10^k where those labels fit side by side (with
/// a gap of most of a letter), else 1 x 10^k, else every second, third, ... decade. An axis
/// shorter than a decade that holds fewer than two of them gets evenly spaced round values
/// (steps of 1, 2 or 5 x 10^j) instead. Empty for an axis that is not positive.
pub fn log_ticks(lo: f64, hi: f64, length: f64, size: f64, axis: Axis) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (k0, k1) = (lo.log10().floor() as i32 - 1, hi.log10().ceil() as i32 + 1);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let decades = |mantissas: &[i64], every: i32| -> Vec<f64> {
        (k0..=k1)
            .filter(|k| k.rem_euclid(every) == 0)
            .flat_map(|k| mantissas.iter().map(move |&m| decimal(m, k)))
            .filter(inside)
            .collect()
    };
    let fits = |values: &[f64]| fits(values, lo, hi, length, size, axis);
    let dense = decades(&[1, 2, 5], 1);
    if dense.len() >= 2 {
        if fits(&dense) {
            return dense;
        }
        let mut coarsest = dense;
        for every in [1, 2, 3, 5, 10, 20, 50, 100] {
            let ticks = decades(&[1], every);
            if ticks.is_empty() {
                break;
            }
            if (ticks.len() >= 2 && fits(&ticks)) || ticks.len() == 1 {
                return ticks;
            }
            coarsest = ticks;
        }
        return coarsest;
    }
    // less than a decade: round values at the finest step whose labels fit
    let top = (hi - lo).log10().ceil() as i32;
    for j in (top - 3)..=top {
        for m in [1, 2, 5] {
            let step = decimal(m, j);
            let (n0, n1) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
            if n1 - n0 + 1 < 2 || n1 - n0 + 1 > 12 {
                continue;
            }
            let ticks: Vec<f64> = (n0..=n1)
                .map(|n| decimal(n * m, j))
                .filter(inside)
                .collect();
            if ticks.len() >= 2 && fits(&ticks) {
                return ticks;
            }
        }
    }
    dense
}

/// Unlabelled grid lines of a logarithmic axis: 1 .. 9 x 10^k within [lo, hi].
pub fn log_grid(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (k0..=k1)
        .flat_map(|k| (1..10).map(move |m| decimal(m, k)))
        .filter(|v| *v >= lo && *v <= hi)
        .collect()
}

/// Whether the labels of `values` (increasing) on a log axis over [lo, hi], `length` CSS
/// pixels long, stand apart: side by side with a gap of 0.8 letter heights, or stacked with
/// half a letter height between them.
fn fits(values: &[f64], lo: f64, hi: f64, length: f64, size: f64, axis: Axis) -> bool {
    let at = |v: f64| length * (v.ln() - lo.ln()) / (hi.ln() - lo.ln());
    values.windows(2).all(|p| {
        let room = at(p[1]) - at(p[0]);
        let need = match axis {
            Axis::Horizontal => {
                0.5 * (text::width(&label(p[0]), size) + text::width(&label(p[1]), size))
                    + 0.8 * size
            }
            Axis::Vertical => 1.5 * size,
        };
        room >= need
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(ticks: &[f64]) -> Vec<String> {
        ticks.iter().map(|&v| label(v)).collect()
    }

    #[test]
    fn labels_are_the_shortest_decimals() {
        // 0.1 + 0.2 is not 0.3: the label says so rather than rounding it away, and a tick
        // made as a decimal reads as one
        assert_eq!(label(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(label(decimal(3, -1)), "0.3");
        assert_eq!(label(decimal(5, -5)), "5e-5");
        assert_eq!(label(decimal(2, 7)), "2e7");
        assert_eq!(label(250.0), "250");
        assert_eq!(label(-0.5), "-0.5");
        assert_eq!(short(0.1 + 0.2), "0.3");
        assert_eq!(short(-5.6e-17), "0");
        assert_eq!(short(1234.5678), "1235");
    }

    #[test]
    fn a_short_log_axis_thins_its_ticks_to_what_fits() {
        // 1e-3 .. 1e3 on 150 px cannot hold 1, 2, 5 per decade side by side
        let ticks = log_ticks(1e-3, 1e3, 150.0, 12.0, Axis::Horizontal);
        assert!(ticks.len() >= 2, "{ticks:?}");
        assert!(fits(&ticks, 1e-3, 1e3, 150.0, 12.0, Axis::Horizontal));
        assert!(
            ticks
                .iter()
                .all(|v| (v.log10() - v.log10().round()).abs() < 1e-9),
            "only powers of ten: {ticks:?}"
        );
        // a long one holds them all
        let long = log_ticks(1e-3, 1e3, 2000.0, 12.0, Axis::Horizontal);
        assert_eq!(long.len(), 3 * 6 + 1, "{long:?}");
    }

    #[test]
    fn less_than_a_decade_gets_round_values() {
        let ticks = log_ticks(310.0, 460.0, 400.0, 12.0, Axis::Vertical);
        assert!(ticks.len() >= 2, "{ticks:?}");
        assert!(ticks.iter().all(|v| (310.0..=460.0).contains(v)));
        assert!(labels(&ticks).iter().all(|l| l.len() <= 3), "{ticks:?}");
    }
}
