//! A job figure ([`JobFigure`]): its name, caption and heading, and what it plots ([`Plot`]),
//! sized and rendered to PNG or SVG by [`crate::figure`] with the drawing of [`super::draw`].

use super::draw::{
    CurvePanel, DrawResult, EVOLUTION_TRACE, MapPanel, SeriesPanel, draw_curves, draw_labels,
    draw_maps, draw_series_panel, draw_trace,
};
use crate::analysis::lattice::LatticeAnalysis;
use crate::figure::text::Heading;
use crate::figure::{Scale, Sizing};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One figure of a job.
pub struct JobFigure {
    /// file stem: `energy`, `profiles`, `spectra`, `density`, `evolution`, `labels`,
    /// `spacetime`, ...
    pub name: &'static str,
    /// what it shows, in one or two sentences (with the numbers a reader needs)
    pub caption: String,
    /// the job it is of ([`heading`]), drawn above the plot
    pub heading: Heading,
    pub(super) plot: Plot,
}

/// What a figure draws.
pub(super) enum Plot {
    /// the energies per particle over collisions per particle, the analysis window shaded
    Trace {
        points: Vec<(f64, f64, f64)>,
        window: Option<(f64, f64)>,
        steady: bool,
    },
    /// the energy trace with the milestones marked (clock, what was found there) above the
    /// density maps of each milestone's snapshot, a row of three planes per milestone
    Evolution {
        points: Vec<(f64, f64, f64)>,
        marks: Vec<(f64, String)>,
        rows: Vec<(String, Vec<MapPanel>)>,
        range: (f64, f64),
    },
    /// panels of curves with optional error bars
    Curves(Vec<CurvePanel>),
    /// panels of cell maps on one colour scale
    Maps {
        panels: Vec<MapPanel>,
        /// what the colour shows
        quantity: String,
        range: (f64, f64),
    },
    /// panels of named curves with a dashed reference
    Series(Vec<SeriesPanel>),
    /// a coloured strip, one cell per snapshot
    Labels {
        snapshots: Vec<(f64, String)>,
        window: Option<(f64, f64)>,
        steady: bool,
    },
    Spacetime(Box<LatticeAnalysis>),
}

impl JobFigure {
    /// Its own size in CSS pixels, without the heading.
    fn natural(&self) -> (u32, u32) {
        match &self.plot {
            Plot::Trace { .. } => (760, 420),
            Plot::Evolution { rows, .. } => (1040, EVOLUTION_TRACE + 300 * rows.len() as u32),
            Plot::Curves(panels) => (960, 260 * panels.len().div_ceil(3).max(1) as u32),
            Plot::Series(panels) => (
                if panels.len() < 3 {
                    480 * panels.len().max(1) as u32
                } else {
                    1200
                },
                320 * panels.len().div_ceil(3).max(1) as u32,
            ),
            Plot::Maps { .. } => (1040, 380),
            Plot::Labels { .. } => (900, 210),
            Plot::Spacetime(a) => crate::analysis::lattice::spacetime_size(a),
        }
    }

    /// Size in CSS pixels: as asked, else its own with the heading above.
    pub fn size(&self, sizing: &Sizing) -> (u32, u32) {
        let (w, h) = self.natural();
        let w = sizing.width.unwrap_or(w);
        (w, sizing.height.unwrap_or(h + self.heading.height(w)))
    }

    /// The figure as PNG bytes at the size and resolution asked.
    pub fn png(&self, sizing: &Sizing) -> anyhow::Result<Vec<u8>> {
        let css = self.size(sizing);
        crate::figure::render_png(css, sizing.scale(), |root, s| self.draw(root, css, s))
    }

    /// Whether the figure is a picture of many cells better kept as a raster only (the
    /// lattice gas' space-time picture: up to 10^5 cells, megabytes as SVG).
    pub fn raster_only(&self) -> bool {
        matches!(self.plot, Plot::Spacetime(_))
    }

    /// The figure as SVG text at the size asked.
    pub fn svg(&self, sizing: &Sizing) -> anyhow::Result<String> {
        let css = self.size(sizing);
        crate::figure::render_svg(css, |root, s| self.draw(root, css, s))
    }

    /// Where else in the job directory the figure is kept: the space-time picture also as
    /// `spacetime.png` beside the job's files, where it was before figures had a folder.
    pub(super) fn also_at(&self) -> Option<&'static str> {
        matches!(self.plot, Plot::Spacetime(_)).then_some("spacetime.png")
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        (w, _): (u32, u32),
        s: Scale,
    ) -> DrawResult<DB> {
        root.fill(&WHITE)?;
        let area = self.heading.draw(root, w, s)?;
        let root = &area;
        match &self.plot {
            Plot::Trace {
                points,
                window,
                steady,
            } => draw_trace(root, points, *window, *steady, &[], s),
            Plot::Evolution {
                points,
                marks,
                rows,
                range,
            } => {
                let (top, maps) = root.split_vertically(s.upx(EVOLUTION_TRACE));
                draw_trace(&top, points, None, false, marks, s)?;
                for ((title, panels), area) in
                    rows.iter().zip(maps.split_evenly((rows.len().max(1), 1)))
                {
                    let area = area.titled(title, s.font(14.0))?;
                    draw_maps(&area, panels, "phi", *range, s)?;
                }
                Ok(())
            }
            Plot::Curves(panels) => {
                let rows = panels.len().div_ceil(3).max(1);
                let areas = root.split_evenly((rows, 3));
                for (panel, area) in panels.iter().zip(&areas) {
                    draw_curves(area, panel, s)?;
                }
                Ok(())
            }
            Plot::Maps {
                panels,
                quantity,
                range,
            } => draw_maps(root, panels, quantity, *range, s),
            Plot::Series(panels) => {
                let columns = panels.len().clamp(1, 3);
                let rows = panels.len().div_ceil(3).max(1);
                let areas = root.split_evenly((rows, columns));
                for (panel, area) in panels.iter().zip(&areas) {
                    draw_series_panel(area, panel, s)?;
                }
                Ok(())
            }
            Plot::Labels {
                snapshots,
                window,
                steady,
            } => draw_labels(root, snapshots, *window, *steady, s),
            Plot::Spacetime(a) => crate::analysis::lattice::draw_spacetime(a, root, s),
        }
    }
}
