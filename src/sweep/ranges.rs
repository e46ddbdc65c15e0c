//! Ranges of swept values: `linspace(start, stop, count)`, `logspace(start, stop, count)` and
//! `range(start, stop[, step])`, written as an axis of a sweep file or as a `--set` value, and
//! expanded to a list of numbers that is canonical (the same range always gives bitwise the
//! same values, and round values come out round, so a range and the same values written as a
//! list give the same job ids).

use std::fmt;

/// What a range may be, for error messages.
pub const RANGE_SYNTAX: &str =
    "linspace(start, stop, count), logspace(start, stop, count) or range(start, stop[, step])";

/// Significant digits the computed values are rounded to (start and stop are kept as written):
/// relative to the range's largest end for linspace and range, to each value for logspace.
pub const SIGNIFICANT_DIGITS: i32 = 12;

/// Most values one range may give.
pub const MAX_VALUES: usize = 10_000;

/// The kinds of range.
const NAMES: [&str; 3] = ["linspace", "logspace", "range"];

/// A range as written: its name and its arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeCall {
    pub name: String,
    pub args: Vec<f64>,
}

impl fmt::Display for RangeCall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let args: Vec<String> = self.args.iter().map(|a| a.to_string()).collect();
        write!(f, "{}({})", self.name, args.join(", "))
    }
}

impl RangeCall {
    /// Read `name(a, b, c)` (a `--set` value). None when `text` is not written as a call (a
    /// plain value or a comma-separated list); an error naming what is wrong when it is one but
    /// a bad one.
    pub fn parse(text: &str) -> Option<Result<RangeCall, String>> {
        let text = text.trim();
        let open = text.find('(')?;
        let name = text[..open].trim();
        if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return None;
        }
        let Some(inner) = text[open + 1..].strip_suffix(')') else {
            return Some(Err(format!(
                "`{text}`: a range ends with `)`; allowed: {RANGE_SYNTAX}"
            )));
        };
        let args = inner
            .split(',')
            .map(|a| {
                let a = a.trim();
                a.parse::<f64>()
                    .map_err(|_| format!("`{text}`: `{a}` is not a number"))
            })
            .collect::<Result<Vec<f64>, String>>();
        Some(args.and_then(|args| RangeCall::new(name, args)))
    }

    /// A range of this name with these arguments, checked for its name and argument count.
    pub fn new(name: &str, args: Vec<f64>) -> Result<RangeCall, String> {
        let call = RangeCall {
            name: name.to_string(),
            args,
        };
        if !NAMES.contains(&name) {
            let hint = super::suggest::did_you_mean(name, NAMES)
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "`{call}`: no range `{name}`{hint}; allowed: {RANGE_SYNTAX}"
            ));
        }
        let arity_ok = match name {
            "range" => (2..=3).contains(&call.args.len()),
            _ => call.args.len() == 3,
        };
        if !arity_ok {
            let form = match name {
                "linspace" => "linspace(start, stop, count)",
                "logspace" => "logspace(start, stop, count)",
                _ => "range(start, stop) or range(start, stop, step)",
            };
            return Err(format!("`{call}`: expected {form}"));
        }
        if let Some(a) = call.args.iter().find(|a| !a.is_finite()) {
            return Err(format!("`{call}`: {a} is not a finite number"));
        }
        Ok(call)
    }

    /// The values of the range (see the "Ranges" in docs/sweeps.md for the rules).
    pub fn expand(&self) -> Result<Vec<f64>, String> {
        let bad = |m: String| Err(format!("`{self}`: {m}"));
        let a = &self.args;
        let (start, stop) = (a[0], a[1]);
        let count = |c: f64| -> Result<usize, String> {
            if c.fract() != 0.0 || c < 2.0 {
                return Err(format!(
                    "`{self}`: count must be a whole number >= 2 (for one value write it alone)"
                ));
            }
            if c > MAX_VALUES as f64 {
                return Err(format!("`{self}`: count is at most {MAX_VALUES}"));
            }
            Ok(c as usize)
        };
        let values = match self.name.as_str() {
            "linspace" => {
                let n = count(a[2])?;
                let step = (stop - start) / (n - 1) as f64;
                let scale = start.abs().max(stop.abs());
                interior(start, stop, n, |i| {
                    round_to_scale(start + i as f64 * step, scale)
                })
            }
            "logspace" => {
                let n = count(a[2])?;
                if !(start > 0.0 && stop > 0.0) {
                    return bad(
                        "start and stop are the first and last values (not exponents) and \
                         must be > 0"
                            .into(),
                    );
                }
                let (l0, l1) = (libm::log(start), libm::log(stop));
                interior(start, stop, n, |i| {
                    let v = libm::exp(l0 + i as f64 / (n - 1) as f64 * (l1 - l0));
                    round_to_scale(v, v)
                })
            }
            _ => {
                let step = a.get(2).copied().unwrap_or(1.0);
                if step == 0.0 {
                    return bad("step must not be 0".into());
                }
                let steps = (stop - start) / step;
                if steps < -1e-9 {
                    return bad(format!(
                        "no values: a step of {step} does not lead from {start} to {stop}"
                    ));
                }
                // stop is included when a step lands on it (to 1e-9 of a step)
                let last = (steps + 1e-9).floor();
                if last + 1.0 > MAX_VALUES as f64 {
                    return bad(format!("gives more than {MAX_VALUES} values"));
                }
                let n = last as usize + 1;
                let scale = start.abs().max(stop.abs()).max(step.abs());
                let mut v: Vec<f64> = (0..n)
                    .map(|i| match i {
                        0 => start,
                        _ => round_to_scale(start + i as f64 * step, scale),
                    })
                    .collect();
                if (steps - last).abs() <= 1e-9 && n > 1 {
                    v[n - 1] = stop;
                }
                v
            }
        };
        for (i, v) in values.iter().enumerate() {
            if values[..i].contains(v) {
                return bad(format!(
                    "gives {v} twice (the values are rounded to {SIGNIFICANT_DIGITS} \
                     significant digits): widen the range or take fewer values"
                ));
            }
        }
        Ok(values)
    }
}

/// `n` values from `start` to `stop` (both as written), the ones between from `value(i)`.
fn interior(start: f64, stop: f64, n: usize, value: impl Fn(usize) -> f64) -> Vec<f64> {
    (0..n)
        .map(|i| match i {
            0 => start,
            i if i == n - 1 => stop,
            i => value(i),
        })
        .collect()
}

/// `x` rounded (in decimal) to [`SIGNIFICANT_DIGITS`] significant digits of `scale`, zero
/// without a sign: with scale 0.9, 0.5 + 3 x 0.1 = 0.8000000000000002 becomes 0.8 and
/// -0.2 + 2 x 0.1 = -5.6e-17 becomes 0.
pub fn round_to_scale(x: f64, scale: f64) -> f64 {
    // the decimal exponent of scale, exactly (1e3 -> 3, 0.9 -> -1)
    let exponent: i32 = format!("{scale:e}")
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    let decimals = (SIGNIFICANT_DIGITS - 1 - exponent).max(0) as usize;
    let rounded: f64 = format!("{x:.decimals$}")
        .parse()
        .expect("a formatted number parses");
    if rounded == 0.0 { 0.0 } else { rounded }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(text: &str) -> Result<Vec<f64>, String> {
        RangeCall::parse(text).expect("a call")?.expand()
    }

    #[test]
    fn ranges_give_round_values() {
        assert_eq!(
            values("linspace(0.5, 0.9, 5)").unwrap(),
            [0.5, 0.6, 0.7, 0.8, 0.9]
        );
        assert_eq!(
            values("logspace(0.01, 10, 4)").unwrap(),
            [0.01, 0.1, 1.0, 10.0]
        );
        assert_eq!(values("logspace(1, 100, 3)").unwrap(), [1.0, 10.0, 100.0]);
        assert_eq!(
            values("range(1, 10, 2)").unwrap(),
            [1.0, 3.0, 5.0, 7.0, 9.0]
        );
        assert_eq!(values("range(1, 9, 2)").unwrap(), [1.0, 3.0, 5.0, 7.0, 9.0]);
        assert_eq!(values("range(1,4)").unwrap(), [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(
            values("range(0.9, 0.5, -0.1)").unwrap(),
            [0.9, 0.8, 0.7, 0.6, 0.5]
        );
        assert_eq!(
            values("range(-0.2, 0.2, 0.1)").unwrap(),
            [-0.2, -0.1, 0.0, 0.1, 0.2]
        );
        assert_eq!(
            values("linspace(-1, 1, 3)").unwrap()[1].to_bits(),
            0f64.to_bits()
        );
        // a step that does not land on stop stops before it
        assert_eq!(values("range(0, 1, 0.3)").unwrap(), [0.0, 0.3, 0.6, 0.9]);
    }

    #[test]
    fn bad_ranges_say_what_is_allowed() {
        for (text, expect) in [
            ("linspace(0.5, 0.9, 1)", "count must be a whole number >= 2"),
            (
                "linspace(0.5, 0.9, 2.5)",
                "count must be a whole number >= 2",
            ),
            (
                "linspace(0.5, 0.9)",
                "expected linspace(start, stop, count)",
            ),
            ("logspace(0, 10, 3)", "must be > 0"),
            ("range(1, 5, 0)", "step must not be 0"),
            ("range(5, 1, 1)", "no values"),
            ("range(0, 1e9, 1)", "more than 10000"),
            ("lnspace(1, 2, 3)", "did you mean `linspace`?"),
            ("linspace(1, x, 3)", "`x` is not a number"),
            ("linspace(1, 2, 3", "ends with `)`"),
            ("linspace(1, 1, 3)", "twice"),
        ] {
            let err = RangeCall::parse(text)
                .expect("a call")
                .and_then(|c| c.expand());
            let err = err.expect_err(text);
            assert!(err.contains(expect), "{text}: {err}");
        }
        assert!(RangeCall::parse("0.5,0.7").is_none());
        assert!(RangeCall::parse("thermal").is_none());
    }

    #[test]
    fn values_are_rounded_to_twelve_digits_of_their_scale() {
        assert_eq!(round_to_scale(0.5 + 3.0 * 0.1, 0.9), 0.8);
        assert_eq!(round_to_scale(0.1 + 0.2, 0.3), 0.3);
        assert_eq!(round_to_scale(1.0 / 3.0, 1.0 / 3.0), 0.333333333333);
        assert_eq!(round_to_scale(1.0 / 3.0, 10.0), 0.3333333333);
        assert_eq!(
            round_to_scale(-0.2 + 2.0 * 0.1, 0.2).to_bits(),
            0f64.to_bits()
        );
        assert_eq!(round_to_scale(1234.5678, 1e15), 1235.0);
        assert_eq!(round_to_scale(2.5e-7, 1e-6), 2.5e-7);
        // logspace keeps 12 digits of each value
        assert_eq!(
            values("logspace(0.01, 10, 7)").unwrap(),
            [
                0.01,
                0.0316227766017,
                0.1,
                0.316227766017,
                1.0,
                3.16227766017,
                10.0
            ]
        );
    }
}
