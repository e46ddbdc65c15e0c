//! Where a noisy curve is lowest: the vertex of a weighted least-squares parabola through the
//! points around its lowest point, with the vertex's standard error, on the largest window the
//! parabola describes within the points' errors.
//!
//! Near a flat minimum the lowest grid point is set by noise (the DSMC flow rate over Kn varies
//! by a few of its errors over a factor 1.5 in Kn): bisection alone cannot place the minimum
//! closer than the noise allows, while a fit through many points can. The model
//! y = a + b t + c t^2 (t = x, or ln x on a logarithmic axis) is fitted with weights 1 / s_i^2
//! (s_i the points' standard errors); the vertex t0 = -b / (2 c) has the variance
//! J C J^T with J = (0, -1 / (2c), b / (2c^2)) and C the parameters' covariance
//! (A^T W A)^-1, scaled by chi^2 / dof when that exceeds 1 (the usual inflation when the model
//! fits worse than the errors say). The window: the lowest point and k points on each side
//! (fewer at an end), k = 2, 3, ...: the widest window whose parabola fits, i.e. whose chi^2
//! is below the upper 5 % point of the chi^2 distribution with dof = points - 3 (far from the
//! minimum the curve is no parabola, nor symmetric, and wider windows fail). The estimate is the
//! widest such window whose parabola opens upwards with its vertex inside the window (a narrow
//! window across a flat minimum may not, within its noise).

use nalgebra::{Matrix3, Vector3};

/// One point of a curve for the fit: position, value, standard error of the value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub x: f64,
    pub y: f64,
    pub error: f64,
}

/// The fitted minimum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexFit {
    /// the vertex, x0
    pub vertex: f64,
    /// the 68 % interval of x0: t0 -+ one standard error, mapped back to x (asymmetric on a
    /// logarithmic axis)
    pub low: f64,
    pub high: f64,
    /// chi^2 per degree of freedom of the chosen window
    pub chi2_per_dof: f64,
    /// the points fitted and the window's ends in x
    pub points: usize,
    pub from: f64,
    pub to: f64,
}

impl VertexFit {
    /// Half the 68 % interval relative to the vertex: the precision the fit places it to.
    pub fn relative_half_width(&self) -> f64 {
        0.5 * (self.high - self.low) / self.vertex.abs()
    }
}

/// The fit around `lowest` (an index into `samples`, which are in increasing x and all with
/// finite values and positive finite errors); None when no window of at least four points
/// gives a parabola that fits, opens upwards and has its vertex inside the window.
pub fn fit_vertex(samples: &[Sample], lowest: usize, log_x: bool) -> Option<VertexFit> {
    let usable = samples
        .iter()
        .all(|s| s.y.is_finite() && s.error.is_finite() && s.error > 0.0)
        && (!log_x || samples.iter().all(|s| s.x > 0.0));
    if !usable || lowest >= samples.len() {
        return None;
    }
    let t = |x: f64| if log_x { x.ln() } else { x };
    let back = |v: f64| if log_x { v.exp() } else { v };
    let mut best = None;
    for k in 2..samples.len() {
        let (first, last) = (
            lowest.saturating_sub(k),
            (lowest + k).min(samples.len() - 1),
        );
        let window = &samples[first..=last];
        if window.len() < 4 {
            continue;
        }
        let Some(fit) = fit_window(window, t(samples[lowest].x), &t) else {
            break;
        };
        let dof = (window.len() - 3) as f64;
        let fits = fit.chi2 <= chi2_upper_5_percent(dof);
        // a narrow window of a flat minimum may open downwards within its noise: no estimate
        // from it, but a wider one may give one
        let inside = fit.t0 >= t(window[0].x) && fit.t0 <= t(window[window.len() - 1].x);
        let spread = fit.t0_error * (fit.chi2 / dof).max(1.0).sqrt();
        if fits && fit.curvature > 0.0 && inside {
            best = Some(VertexFit {
                vertex: back(fit.t0),
                low: back(fit.t0 - spread),
                high: back(fit.t0 + spread),
                chi2_per_dof: fit.chi2 / dof,
                points: window.len(),
                from: window[0].x,
                to: window[window.len() - 1].x,
            });
        }
        if first == 0 && last == samples.len() - 1 {
            break;
        }
    }
    best
}

/// The upper 5 % point of chi^2 with `dof` degrees of freedom (Wilson & Hilferty 1931, the
/// cube-root normal approximation: within 1 % of the exact point from dof = 2 on, 2.5 % low at dof = 1).
fn chi2_upper_5_percent(dof: f64) -> f64 {
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + 1.644_853_6 * a.sqrt()).powi(3)
}

/// A parabola fitted to one window: its vertex t0 and standard error (unscaled), its
/// curvature c and chi^2.
struct WindowFit {
    t0: f64,
    t0_error: f64,
    curvature: f64,
    chi2: f64,
}

/// Weighted least squares of y = a + b u + c u^2 with u = t(x) - centre (centred for a
/// well-conditioned normal matrix).
fn fit_window(window: &[Sample], centre: f64, t: &dyn Fn(f64) -> f64) -> Option<WindowFit> {
    let mut normal = Matrix3::<f64>::zeros();
    let mut rhs = Vector3::<f64>::zeros();
    for s in window {
        let u = t(s.x) - centre;
        let row = Vector3::new(1.0, u, u * u);
        let w = 1.0 / (s.error * s.error);
        normal += w * row * row.transpose();
        rhs += w * s.y * row;
    }
    let covariance = normal.try_inverse()?;
    let beta = covariance * rhs;
    let (b, c) = (beta[1], beta[2]);
    let chi2 = window
        .iter()
        .map(|s| {
            let u = t(s.x) - centre;
            ((s.y - (beta[0] + b * u + c * u * u)) / s.error).powi(2)
        })
        .sum();
    let jacobian = Vector3::new(0.0, -1.0 / (2.0 * c), b / (2.0 * c * c));
    let variance = (jacobian.transpose() * covariance * jacobian)[(0, 0)];
    (c != 0.0 && variance.is_finite() && variance >= 0.0).then(|| WindowFit {
        t0: centre - b / (2.0 * c),
        t0_error: variance.sqrt(),
        curvature: c,
        chi2,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::dsmc::kernel::normal_pair;
    use rand::SeedableRng;
    use rand_pcg::Pcg64Mcg;

    fn lowest(samples: &[Sample]) -> usize {
        (0..samples.len())
            .min_by(|&a, &b| samples[a].y.total_cmp(&samples[b].y))
            .unwrap()
    }

    #[test]
    fn an_exact_parabola_gives_its_vertex() {
        // y = 2 (x - 1.3)^2 + 5 on x = 0, 0.25, ..., 3: every window fits exactly
        let samples: Vec<Sample> = (0..13)
            .map(|i| {
                let x = 0.25 * i as f64;
                Sample {
                    x,
                    y: 2.0 * (x - 1.3f64).powi(2) + 5.0,
                    error: 0.01,
                }
            })
            .collect();
        let fit = fit_vertex(&samples, lowest(&samples), false).unwrap();
        assert!((fit.vertex - 1.3).abs() < 1e-9, "{fit:?}");
        assert_eq!(fit.points, 13, "the whole curve is a parabola: {fit:?}");
        // in log x, a parabola in ln x
        let samples: Vec<Sample> = (0..9)
            .map(|i| {
                let x = 0.2 * 1.35f64.powi(i);
                Sample {
                    x,
                    y: (x.ln() - 0.1f64).powi(2),
                    error: 0.001,
                }
            })
            .collect();
        let fit = fit_vertex(&samples, lowest(&samples), true).unwrap();
        assert!((fit.vertex - 0.1f64.exp()).abs() < 1e-9, "{fit:?}");
        assert!(fit.low < fit.vertex && fit.vertex < fit.high);
    }

    #[test]
    fn the_window_stops_where_the_curve_is_no_parabola() {
        // a parabola near x = 1 and a steep wall below x = 0.5 (as Q at small Kn): the window
        // must leave the wall out
        let samples: Vec<Sample> = (0..16)
            .map(|i| {
                let x = 0.1 + 0.1 * i as f64;
                let wall = if x < 0.45 { 5.0 * (0.45 - x) } else { 0.0 };
                Sample {
                    x,
                    y: (x - 1.0).powi(2) + wall,
                    error: 0.001,
                }
            })
            .collect();
        let fit = fit_vertex(&samples, lowest(&samples), false).unwrap();
        assert!(fit.from > 0.4, "{fit:?}");
        assert!((fit.vertex - 1.0).abs() < 1e-6, "{fit:?}");
    }

    #[test]
    fn the_stated_error_covers_the_vertex_as_often_as_it_says() {
        // a flat minimum with noise, as Q(Kn): 400 noisy curves, the true vertex within the
        // 68 % interval in 68 % of them (binomial sd 2.4 %: allow 60-76 %; seen: 73 %, the
        // sqrt(chi^2/dof) inflation errs on the wide side), and the lowest
        // point farther from it on average than the fit
        let mut rng = Pcg64Mcg::seed_from_u64(7);
        let (mut covered, mut fits) = (0, 0);
        let (mut fit_miss, mut lowest_miss) = (0.0, 0.0);
        for _ in 0..400 {
            let error = 0.003;
            let samples: Vec<Sample> = (0..19)
                .map(|i| {
                    let x = 0.6 + 0.05 * i as f64;
                    let y = 1.35 + 0.05 * (x - 1.1f64).powi(2) + error * normal_pair(&mut rng).0;
                    Sample { x, y, error }
                })
                .collect();
            let at = lowest(&samples);
            let Some(fit) = fit_vertex(&samples, at, false) else {
                continue;
            };
            fits += 1;
            covered += usize::from(fit.low <= 1.1 && 1.1 <= fit.high);
            fit_miss += (fit.vertex - 1.1).abs();
            lowest_miss += (samples[at].x - 1.1).abs();
        }
        assert!(fits >= 380, "{fits}");
        let share = covered as f64 / fits as f64;
        assert!((0.60..=0.76).contains(&share), "coverage {share}");
        assert!(fit_miss < 0.5 * lowest_miss, "{fit_miss} {lowest_miss}");
    }

    #[test]
    fn the_chi2_point_is_the_tabulated_one() {
        // upper 5 % points of chi^2 (Abramowitz & Stegun, Table 26.8): dof 2, 3, 10, 30
        for (dof, point) in [(2.0, 5.991), (3.0, 7.815), (10.0, 18.307), (30.0, 43.773)] {
            let ours = chi2_upper_5_percent(dof);
            assert!(
                (ours / point - 1.0).abs() < 0.01,
                "dof {dof}: {ours} against {point}"
            );
        }
    }

    #[test]
    fn no_estimate_without_errors_or_without_a_minimum() {
        let flat_errors: Vec<Sample> = (0..6)
            .map(|i| Sample {
                x: i as f64,
                y: (i as f64 - 2.5).powi(2),
                error: f64::NAN,
            })
            .collect();
        assert_eq!(fit_vertex(&flat_errors, 2, false), None);
        let falling: Vec<Sample> = (0..6)
            .map(|i| Sample {
                x: i as f64,
                y: -(i as f64),
                error: 0.01,
            })
            .collect();
        assert_eq!(fit_vertex(&falling, 5, false), None);
        let hump: Vec<Sample> = (0..7)
            .map(|i| Sample {
                x: i as f64,
                y: -(i as f64 - 3.0).powi(2),
                error: 0.01,
            })
            .collect();
        assert_eq!(fit_vertex(&hump, 0, false), None);
    }
}
