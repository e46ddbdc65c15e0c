//! The figure of the lattice-gas analysis (Peng & Herrmann 1994): `spacetime`, the seed's
//! Fig. 1 picture (PNG only, a raster of up to 10^5 cells; also as `jobs/<id>/spacetime.png`).

use super::plot::{JobFigure, Plot};
use crate::analysis::lattice::LatticeAnalysis;
use crate::figure::text::Heading;

/// The space-time picture, once the analysis has one.
pub(super) fn lattice_figures(a: &LatticeAnalysis) -> Vec<JobFigure> {
    if a.spacetime.is_empty() {
        return Vec::new();
    }
    vec![JobFigure {
        name: "spacetime",
        caption: format!(
            "Particles per bin along the pipe (top to bottom, gravity down) over time (left \
         to right), as the seed's Fig. 1: {}; label: {}.",
            crate::analysis::lattice::spacetime_span(a),
            a.summary.label
        ),
        heading: Heading::default(),
        plot: Plot::Spacetime(Box::new(a.clone())),
    }]
}
