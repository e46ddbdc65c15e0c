//! The figure of the rarefied analysis (DSMC; Gupta 2017): `profiles` (density, velocity and
//! temperature across the channel with their block-average errors).

use super::draw::CurvePanel;
use super::plot::{JobFigure, Plot};
use crate::analysis::rarefied::RarefiedAnalysis;
use crate::figure::text::Heading;

pub(super) fn rarefied_figures(a: &RarefiedAnalysis) -> Vec<JobFigure> {
    if a.profiles.is_empty() {
        return Vec::new();
    }
    let panel =
        |title: &str, f: &dyn Fn(&crate::analysis::rarefied::RarefiedProfileRow) -> (f64, f64)| {
            CurvePanel {
                marks: Vec::new(),
                title: title.into(),
                x_label: "y / W".into(),
                points: a
                    .profiles
                    .iter()
                    .map(|p| {
                        let (v, e) = f(p);
                        (p.y, v, e)
                    })
                    .collect(),
            }
        };
    vec![JobFigure {
        heading: Heading::default(),
        name: "profiles",
        caption: format!(
            "Time-averaged profiles across the channel with their block-average standard errors \
             ({}; window {} .. {} steps).",
            if a.summary.steady {
                "steady"
            } else {
                "not steady"
            },
            a.summary.window_start_step,
            a.summary.window_end_step
        ),
        plot: Plot::Curves(vec![
            panel("density rho / rho_avg", &|p| (p.density, p.density_error)),
            panel("velocity u_x / u_c", &|p| (p.velocity, p.velocity_error)),
            panel("temperature T / T_w", &|p| {
                (p.temperature, p.temperature_error)
            }),
        ]),
    }]
}
