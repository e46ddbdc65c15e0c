//! The figures of the dense analysis (DEM; Debnath, Rao & Kumaran 2022): the profiles with
//! the zone boundaries and the centre-of-mass series with the wall-force balance.

use super::draw::{CurvePanel, SeriesPanel};
use super::plot::{JobFigure, Plot};
use crate::figure::text::Heading;
use plotters::prelude::*;

/// The figures of a DEM job (Debnath, Rao & Kumaran 2022): the profiles of phi, u_y, the
/// shear rate, T and mu against log10 I with the zone boundaries marked (red: wall layer,
/// blue: dense zone, black: plug, as the paper's Figs. 8-11), and the centre-of-mass series
/// with the wall-force balance.
pub(super) fn dense_figures(a: &crate::analysis::dense::DenseAnalysis) -> Vec<JobFigure> {
    let s = &a.dense_summary;
    let mut out = Vec::new();
    if !a.profiles.is_empty() {
        // W from the wall bin's centre, 0.75 d_p (x / W in the table)
        let w = a
            .profiles
            .iter()
            .find(|r| r.bin == 0)
            .map(|r| 0.75 / r.coordinate)
            .unwrap_or(f64::NAN);
        let mut marks = Vec::new();
        for (x, colour) in [
            (s.wall_layer, RGBColor(214, 39, 40)),
            (s.dense_start, RGBColor(31, 119, 180)),
            (s.plug_start, BLACK),
        ] {
            if x.is_finite() && w.is_finite() && x > 0.0 {
                marks.push((x / w, colour));
                marks.push((1.0 - x / w, colour));
            }
        }
        let of = |q: &str| -> Vec<(f64, f64, f64)> {
            a.profiles
                .iter()
                .filter(|r| r.quantity == q)
                .map(|r| (r.coordinate, r.value, r.error))
                .collect()
        };
        let panel = |q: &str, title: &str| CurvePanel {
            title: title.into(),
            x_label: "x / W".into(),
            points: of(q),
            marks: marks.clone(),
        };
        // mu against log10 I (a linear axis of the logarithm)
        let mu = of("mu");
        let i = of("inertial_number");
        // (sorted by I: the two halves of the channel on one curve)
        let mut mu_of_i: Vec<(f64, f64, f64)> = i
            .iter()
            .zip(&mu)
            .filter(|(i, m)| i.1 > 0.0 && m.1.is_finite())
            .map(|(i, m)| (i.1.log10(), m.1, m.2))
            .collect();
        mu_of_i.sort_by(|a, b| a.0.total_cmp(&b.0));
        out.push(JobFigure {
            heading: Heading::default(),
            name: "profiles",
            caption: format!(
                "Time-averaged profiles across the channel (paper's axes: x wall-normal, u_y \
                 along the flow) over t = {:.0} .. {:.0} with block standard errors; label {}. \
                 Dashed: the wall layer (red), the start of the dense zone phi >= 0.587 (blue) \
                 and of the plug (black). u_max / u_slip = {:.3}, delta_0.95 = {:.2} d_p, \
                 eq. 3.1 constant {:.2}, balance {:.3} +- {:.3}.",
                s.window_start_time,
                s.window_end_time,
                s.label,
                s.velocity_ratio,
                s.shear_layer_thickness,
                s.profile_constant,
                s.wall_force_balance,
                s.wall_force_balance_error
            ),
            plot: Plot::Curves(vec![
                panel("volume_fraction", "volume fraction phi"),
                panel("velocity", "u_y / sqrt(g d_p)"),
                panel("shear_rate", "du_y/dx / sqrt(g/d_p)"),
                panel("temperature", "T / (m g d_p)"),
                panel("mu", "mu = |sigma_xy / sigma_xx|"),
                CurvePanel {
                    title: "mu against log10 I".into(),
                    x_label: "log10 I".into(),
                    points: mu_of_i,
                    marks: Vec::new(),
                },
            ]),
        });
    }
    if !a.series.is_empty() {
        let pick = |f: &dyn Fn(&crate::analysis::dense::SeriesRow) -> f64| -> Vec<(f64, f64)> {
            a.series.iter().map(|r| (r.time, f(r))).collect()
        };
        let t0 = a.series.first().map_or(0.0, |r| r.time);
        let t1 = a.series.last().map_or(1.0, |r| r.time);
        out.push(JobFigure {
            heading: Heading::default(),
            name: "series",
            caption: format!(
                "Centre-of-mass velocity and wall-force balance per record (the window starts at \
                 t = {:.0}); label {}: {}",
                s.window_start_time,
                s.label,
                if s.steady_reason.is_empty() {
                    "the walls carry the weight within 3 standard errors"
                } else {
                    &s.steady_reason
                }
            ),
            plot: Plot::Series(vec![
                SeriesPanel {
                    title: "u_cm / sqrt(g d_p)".into(),
                    x_label: "t / sqrt(d_p/g)".into(),
                    series: vec![("u_cm".into(), pick(&|r| r.com_velocity))],
                    reference: None,
                    log_y: false,
                },
                SeriesPanel {
                    title: "wall force / weight".into(),
                    x_label: "t / sqrt(d_p/g)".into(),
                    series: vec![("balance".into(), pick(&|r| r.wall_force_balance))],
                    reference: Some(("1 (steady)".into(), vec![(t0, 1.0), (t1, 1.0)])),
                    log_y: false,
                },
            ]),
        });
    }
    out
}
