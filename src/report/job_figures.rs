//! Per-job figures, drawn with plotters from a job's analysis and its records (rendered and
//! written by [`crate::figure`]; stored as `jobs/<id>/figures/<name>.png` and `.svg`):
//! - structure analysis (EDMD): `energy` (the kinetic-energy trace with the steady window),
//!   `profiles` (phi, U_x, omega_z, T, theta across the channel), `spectra` (xy, xz, yz
//!   power-spectrum maps with the modes that stand above shot noise outlined), `density` (phi
//!   of the last snapshot in the three planes, as thesis Figs. 5.2-5.24) and `labels` (the label
//!   of every snapshot along the run);
//! - lattice gas: `spacetime` (the seed's Fig. 1 picture; PNG only, a raster of up to 10^5
//!   cells; also as `jobs/<id>/spacetime.png`);
//! - rarefied gas (DSMC): `profiles` (density, velocity, temperature with their errors);
//! - the thesis' statistics (runs with `run.statistics`), in the thesis' layout
//!   ([`super::statistics_figures`]): `vdf` (panels a-f: C_x .. Omega_z at the wall, shear
//!   and centre slabs with the Gaussian), `pair_correlation`, `orientation` (Lambda(y) with
//!   1/3), `velocity_correlation` (C_xx, C_yy, C_zz) and `knudsen` (Kn(y), P(l)).
//!
//! Each figure is headed by its job: the engine, the seed, the id and the parameters by symbol
//! with their values (those at their defaults on a line of their own). A running job's
//! figures are drawn the same way from the records it has written so far.

use crate::analysis::classify::significant_plane_modes;
use crate::analysis::lattice::LatticeAnalysis;
use crate::analysis::rarefied::RarefiedAnalysis;
use crate::analysis::{Analysis, JobAnalysis, Record, SnapshotRecord, plane_fields};
use crate::figure::text::Heading;
use crate::figure::ticks::{self, Axis};
use crate::figure::{Scale, Sizing};
use crate::sweep::grid::PlannedJob;
use crate::sweep::phase::{fmt_value, marker_colour, symbol_of};
use crate::sweep::store::FIGURES_DIR;
use plotters::coord::Shift;
use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

/// One figure of a job.
pub struct JobFigure {
    /// file stem: `energy`, `profiles`, `spectra`, `density`, `evolution`, `labels`,
    /// `spacetime`, ...
    pub name: &'static str,
    /// what it shows, in one or two sentences (with the numbers a reader needs)
    pub caption: String,
    /// the job it is of ([`heading`]), drawn above the plot
    pub heading: Heading,
    plot: Plot,
}

/// What a figure draws.
enum Plot {
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

/// A panel of curves: points (x, y, error; NaN error: none).
struct CurvePanel {
    title: String,
    x_label: String,
    points: Vec<(f64, f64, f64)>,
    /// x positions of dashed vertical lines (zone boundaries), with their colour
    marks: Vec<(f64, RGBColor)>,
}

/// A panel of named curves (x, y) with an optional dashed reference curve.
pub(crate) struct SeriesPanel {
    pub title: String,
    pub x_label: String,
    pub series: Vec<(String, Vec<(f64, f64)>)>,
    pub reference: Option<(String, Vec<(f64, f64)>)>,
    pub log_y: bool,
}

/// A panel of cells: `values[i * ny + j]` covers [x_edges[i], x_edges[i+1]] x
/// [y_edges[j], y_edges[j+1]]; NaN cells are left blank; `marks` are outlined.
struct MapPanel {
    title: String,
    x_label: String,
    y_label: String,
    x_edges: Vec<f64>,
    y_edges: Vec<f64>,
    values: Vec<f64>,
    marks: Vec<(usize, usize)>,
    /// integer wave numbers at the cell centres (spectra) rather than lengths
    wave_numbers: bool,
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The heading of a job's figures: its engine, seed and id; its parameters by symbol (those
/// its sweep varies, those the engine requires or derives, and those away from their
/// defaults); then those at their defaults, named as such (a swept parameter whose value is
/// its default is not: it was chosen).
pub fn heading(job: &PlannedJob) -> Heading {
    let def = job.params.def();
    let (mut set, mut defaults): (Vec<String>, Vec<String>) = (Vec::new(), Vec::new());
    for d in def.params {
        let Some(v) = job.params.values.get(d.name) else {
            continue;
        };
        let text = format!("{} = {}", symbol_of(def, d.name), heading_value(v));
        if d.default.value().as_ref() == Some(v) && !job.swept.contains(&d.name) {
            defaults.push(text);
        } else {
            set.push(text);
        }
    }
    let mut lines = vec![format!(
        "{}, seed {}, job {}",
        def.name, job.params.seed, job.id
    )];
    if !set.is_empty() {
        lines.push(set.join(", "));
    }
    if !defaults.is_empty() {
        lines.push(format!("at their defaults: {}", defaults.join(", ")));
    }
    Heading { lines }
}

/// A parameter value in a heading: as given, or to 4 significant digits when that is long
/// (a derived value such as phi from N).
fn heading_value(v: &crate::engine::ParamValue) -> String {
    let text = fmt_value(v);
    match v {
        crate::engine::ParamValue::Number(x) if text.len() > 8 => ticks::short(*x),
        _ => text,
    }
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
    fn also_at(&self) -> Option<&'static str> {
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

/// The figures of a job from its analysis and records (records of a running job: those so
/// far), headed by the job. Figures whose data are missing (no records, no spectra) are left
/// out.
pub fn figures(job: &PlannedJob, analysis: &Analysis, records: &[Record]) -> Vec<JobFigure> {
    let mut out = match analysis {
        Analysis::Structure(a) => {
            let records: Vec<&SnapshotRecord> =
                records.iter().filter_map(Record::structure).collect();
            structure_figures(a, &records)
        }
        Analysis::Lattice(a) if !a.spacetime.is_empty() => vec![JobFigure {
            name: "spacetime",
            caption: format!(
                "Particles per bin along the pipe (top to bottom, gravity down) over time (left \
                 to right), as the seed's Fig. 1: {}; label: {}.",
                crate::analysis::lattice::spacetime_span(a),
                a.summary.label
            ),
            heading: Heading::default(),
            plot: Plot::Spacetime(Box::new(a.clone())),
        }],
        Analysis::Lattice(_) => Vec::new(),
        Analysis::Rarefied(a) => rarefied_figures(a),
        Analysis::Dense(a) => dense_figures(a),
    };
    let heading = heading(job);
    for f in &mut out {
        f.heading = heading.clone();
    }
    out
}

/// Write figures into the job directory's `figures/` as `<name>.png` and `<name>.svg` (PNG
/// only for [`JobFigure::raster_only`] ones), at their own size and 96 dpi; the paths written.
pub fn write(job_dir: &Path, figures: &[JobFigure]) -> anyhow::Result<Vec<PathBuf>> {
    if figures.is_empty() {
        return Ok(Vec::new());
    }
    let sizing = Sizing::default();
    let dir = job_dir.join(FIGURES_DIR);
    std::fs::create_dir_all(&dir).map_err(|e| crate::fs::PathError::new(&dir, e))?;
    let mut written = Vec::new();
    for f in figures {
        let png = dir.join(format!("{}.png", f.name));
        let bytes = f.png(&sizing)?;
        crate::fs::write_atomic(&png, &bytes)?;
        written.push(png);
        if let Some(name) = f.also_at() {
            let also = job_dir.join(name);
            crate::fs::write_atomic(&also, &bytes)?;
            written.push(also);
        }
        if !f.raster_only() {
            let svg = dir.join(format!("{}.svg", f.name));
            crate::fs::write_atomic(&svg, f.svg(&sizing)?.as_bytes())?;
            written.push(svg);
        }
    }
    Ok(written)
}

/// Whether every figure is on disk in the job directory (in each of its formats).
pub fn all_written(job_dir: &Path, figures: &[JobFigure]) -> bool {
    let dir = job_dir.join(FIGURES_DIR);
    figures.iter().all(|f| {
        let formats: &[&str] = if f.raster_only() {
            &["png"]
        } else {
            &["png", "svg"]
        };
        formats
            .iter()
            .all(|ext| dir.join(format!("{}.{ext}", f.name)).exists())
            && f.also_at().is_none_or(|name| job_dir.join(name).exists())
    })
}

fn structure_figures(a: &JobAnalysis, records: &[&SnapshotRecord]) -> Vec<JobFigure> {
    let s = &a.summary;
    let window = (s.window_start.is_finite() && s.window_end.is_finite())
        .then_some((s.window_start, s.window_end));
    let window_text = match window {
        Some((w0, w1)) if s.steady => format!("steady window {w0} .. {w1} collisions per particle"),
        Some((w0, w1)) => format!("not steady: the final third {w0} .. {w1} is used"),
        None => "no window yet".into(),
    };
    let mut out = Vec::new();
    if !a.energy.is_empty() {
        out.push(JobFigure {
            heading: Heading::default(),
            name: "energy",
            caption: format!(
                "Translational and rotational kinetic energy per particle over the run; shaded: \
                 {window_text}."
            ),
            plot: Plot::Trace {
                points: a
                    .energy
                    .iter()
                    .map(|e| (e.collisions_per_particle, e.translational, e.rotational))
                    .collect(),
                window,
                steady: s.steady,
            },
        });
    }
    if !a.profiles.is_empty() {
        let width = records.last().map_or(f64::NAN, |r| r.box_extent[1]);
        out.push(JobFigure {
            heading: Heading::default(),
            name: "profiles",
            caption: format!(
                "Profiles across the channel (0 <= y <= W{}), averaged over the window ({window_text}); \
                 slip velocity {:.3} sqrt(gd).",
                if width.is_finite() {
                    format!(" = {width}")
                } else {
                    String::new()
                },
                s.slip_velocity
            ),
            plot: Plot::Curves(
                [
                    ("phi", "phi(y)"),
                    ("u_x", "U_x(y) / sqrt(gd)"),
                    ("omega_z", "omega_z(y) / sqrt(g/d)"),
                    ("T", "T(y) / (gd)"),
                    ("theta", "theta(y) / (gd)"),
                ]
                .iter()
                .map(|(q, title)| CurvePanel {
                    marks: Vec::new(),
                    title: (*title).into(),
                    x_label: "y / d".into(),
                    points: a
                        .profiles
                        .iter()
                        .filter(|p| p.quantity == *q)
                        .map(|p| (p.y, p.value, f64::NAN))
                        .collect(),
                })
                .collect(),
            ),
        });
    }
    if let Some(f) = spectra_figure(a) {
        out.push(f);
    }
    if let Some(f) = density_figure(records) {
        out.push(f);
    }
    if let Some(f) = evolution_figure(a, records) {
        out.push(f);
    }
    if let Some(st) = &a.statistics {
        let width = records.last().map_or(f64::NAN, |r| r.box_extent[1]);
        out.extend(
            super::statistics_figures::figures(st, width)
                .into_iter()
                .map(|(name, caption, panels)| JobFigure {
                    heading: Heading::default(),
                    name,
                    caption,
                    plot: Plot::Series(panels),
                }),
        );
    }
    let labels =
        crate::analysis::snapshot_labels(&records.iter().map(|r| (*r).clone()).collect::<Vec<_>>());
    if !labels.is_empty() {
        out.push(JobFigure {
            heading: Heading::default(),
            name: "labels",
            caption: format!(
                "The structure label of every snapshot on its own ({} snapshots); bar below: \
                 {window_text}; the job's label: {}.",
                labels.len(),
                crate::analysis::labels::label_key(&s.label, s.humps)
            ),
            plot: Plot::Labels {
                snapshots: labels,
                window,
                steady: s.steady,
            },
        });
    }
    out
}

/// The xy, xz, yz maps of log10(power / noise) of the window-averaged spectra, with the modes
/// above the peak test's threshold outlined.
fn spectra_figure(a: &JobAnalysis) -> Option<JobFigure> {
    let s = &a.summary;
    let n = [s.grid_x, s.grid_y, s.grid_z].map(|k| k as usize);
    let p0 = s.noise_level;
    if a.spectra.is_empty() || n.contains(&0) || p0.is_nan() || p0 <= 0.0 {
        return None;
    }
    let planes = [
        ("xy", n[0], n[1], "k_x", "k_y"),
        ("xz", n[0], n[2], "k_x", "k_z"),
        ("yz", n[1], n[2], "k_y", "k_z"),
    ];
    let mut panels = Vec::new();
    let mut significant = 0;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (plane, na, nb, xa, xb) in planes {
        let (m1, m2) = crate::analysis::spectrum::folded_shape(na, nb);
        let mut folded = vec![f64::NAN; m1 * m2];
        for r in a.spectra.iter().filter(|r| r.plane == plane) {
            let (k1, k2) = (r.k1 as usize, r.k2 as usize);
            if k1 < m1 && k2 < m2 {
                folded[k1 * m2 + k2] = r.power;
            }
        }
        let values: Vec<f64> = (0..m1 * m2)
            .map(|i| {
                let (k1, k2) = (i / m2, i % m2);
                let dims = crate::analysis::spectrum::multiplicity(k1, na)
                    * crate::analysis::spectrum::multiplicity(k2, nb);
                (folded[i] / (dims as f64 * p0)).log10()
            })
            .collect();
        for v in values.iter().filter(|v| v.is_finite()) {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let known: Vec<f64> = folded
            .iter()
            .map(|p| if p.is_nan() { 0.0 } else { *p })
            .collect();
        let marks: Vec<(usize, usize)> = significant_plane_modes(&known, na, nb, p0)
            .into_iter()
            .map(|(k1, k2, _, _)| (k1, k2))
            .collect();
        significant += marks.len();
        panels.push(MapPanel {
            title: format!("{plane} ({na} x {nb} cells)"),
            x_label: xa.into(),
            y_label: xb.into(),
            x_edges: (0..=m1).map(|k| k as f64 - 0.5).collect(),
            y_edges: (0..=m2).map(|k| k as f64 - 0.5).collect(),
            values,
            marks,
            wave_numbers: true,
        });
    }
    if !lo.is_finite() {
        return None;
    }
    Some(JobFigure {
        heading: Heading::default(),
        name: "spectra",
        caption: format!(
            "Window-averaged power spectra of the density in the xy, xz and yz planes, folded onto \
             non-negative wave numbers, as power over the shot noise of a random arrangement \
             (log10); outlined: the {significant} modes above the 5-sigma peak threshold \
             (false-alarm probability shared among the plane's modes). Dominant xy modes: {}.",
            if s.dominant_modes.is_empty() {
                "-".to_string()
            } else {
                crate::analysis::modes::joined(&s.dominant_modes)
            }
        ),
        plot: Plot::Maps {
            panels,
            quantity: "log10 P/noise".into(),
            range: (lo.min(0.0), hi.max(lo.min(0.0) + 1.0)),
        },
    })
}

/// The phi fields of the last record with fields in the xy, xz and yz planes (averages over
/// the third axis), in physical coordinates.
/// Whether a record carries the three plane fields of its coarse-graining grid.
fn has_fields(r: &SnapshotRecord) -> bool {
    let [n1, n2, n3] = r.grid.map(|k| k as usize);
    n1 * n2 * n3 > 0
        && r.grid_volume > 0.0
        && r.counts_xy.len() == n1 * n2
        && r.counts_xz.len() == n1 * n3
        && r.counts_yz.len() == n2 * n3
}

/// The volume fraction of a record in the xy, xz and yz planes (each averaged over the third
/// axis; titles prefixed by `prefix`), and the largest value.
fn density_panels(r: &SnapshotRecord, prefix: &str) -> (Vec<MapPanel>, f64) {
    let [n1, n2, n3] = r.grid.map(|k| k as usize);
    let [l, w, h] = r.box_extent;
    // the grid covers the region open to centres across the channel, [d/2, W - d/2]
    let edges = |from: f64, to: f64, n: usize| -> Vec<f64> {
        (0..=n)
            .map(|k| from + (to - from) * k as f64 / n as f64)
            .collect()
    };
    let (x, y, z) = (
        edges(0.0, l, n1),
        edges(0.5, w - 0.5, n2),
        edges(0.0, h, n3),
    );
    let [xy, xz, yz] = plane_fields(r);
    let hi = xy
        .iter()
        .chain(&xz)
        .chain(&yz)
        .copied()
        .fold(0.0f64, f64::max);
    let panel =
        |title: &str, xl: &str, yl: &str, xe: &Vec<f64>, ye: &Vec<f64>, v: Vec<f64>| MapPanel {
            title: format!("{prefix}{title}"),
            x_label: xl.into(),
            y_label: yl.into(),
            x_edges: xe.clone(),
            y_edges: ye.clone(),
            values: v,
            marks: Vec::new(),
            wave_numbers: false,
        };
    (
        vec![
            panel("xy (over z)", "x / d", "y / d", &x, &y, xy),
            panel("xz (over y)", "x / d", "z / d", &x, &z, xz),
            panel("yz (over x)", "y / d", "z / d", &y, &z, yz),
        ],
        hi,
    )
}

fn density_figure(records: &[&SnapshotRecord]) -> Option<JobFigure> {
    let r = records.iter().rev().find(|r| has_fields(r))?;
    let [n1, n2, n3] = r.grid.map(|k| k as usize);
    let (panels, hi) = density_panels(r, "");
    Some(JobFigure {
        heading: Heading::default(),
        name: "density",
        caption: format!(
            "Volume fraction of the last snapshot ({} collisions per particle) in the xy, xz and \
             yz planes, each averaged over the third axis, on the {n1} x {n2} x {n3} grid \
             (flow along x, walls at y = 0 and W, span z).",
            r.collisions_per_particle
        ),
        plot: Plot::Maps {
            panels,
            quantity: "phi".into(),
            range: (0.0, hi.max(1e-6)),
        },
    })
}

/// The evolution of the structure as the thesis shows it for its W/d = 50 boxes: the energy
/// trace with the milestones marked and, for each milestone, the density of the snapshot
/// nearest to it in the three planes with the label found over the milestone's window.
fn evolution_figure(a: &JobAnalysis, records: &[&SnapshotRecord]) -> Option<JobFigure> {
    if a.milestones.is_empty() || a.energy.is_empty() {
        return None;
    }
    let mut rows = Vec::new();
    let mut marks = Vec::new();
    let mut hi = 0.0f64;
    for m in &a.milestones {
        let found = format!("{} ({:.0} %)", m.structure, 100.0 * m.probability);
        marks.push((
            m.collisions_per_particle,
            format!("{}: {found}", m.milestone),
        ));
        let nearest = records.iter().filter(|r| has_fields(r)).min_by(|p, q| {
            let d = |r: &&&SnapshotRecord| {
                (r.collisions_per_particle - m.collisions_per_particle).abs()
            };
            d(p).total_cmp(&d(q))
        });
        if let Some(r) = nearest {
            let (panels, top) = density_panels(r, "");
            hi = hi.max(top);
            rows.push((
                format!(
                    "milestone {} {}: snapshot at {:.0} collisions per particle; {found} over {} snapshots",
                    m.milestone,
                    m.clock.replace('_', " "),
                    r.collisions_per_particle,
                    m.window_snapshots
                ),
                panels,
            ));
        }
    }
    Some(JobFigure {
        heading: Heading::default(),
        name: "evolution",
        caption: format!(
            "The structure at the run's milestones ({}), dated as the thesis dates its W/d = 50 \
             snapshots: energy per particle with the milestones marked (dashed; the label found \
             over each milestone's window and the share of its snapshots that carry it), and the \
             volume fraction of the snapshot nearest to each milestone in the xy, xz and yz \
             planes (each averaged over the third axis), on one colour scale.",
            a.milestones
                .iter()
                .map(|m| format!("{}", m.milestone))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        plot: Plot::Evolution {
            points: a
                .energy
                .iter()
                .map(|e| (e.collisions_per_particle, e.translational, e.rotational))
                .collect(),
            marks,
            rows,
            range: (0.0, hi.max(1e-6)),
        },
    })
}

fn rarefied_figures(a: &RarefiedAnalysis) -> Vec<JobFigure> {
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

/// The figures of a DEM job (Debnath, Rao & Kumaran 2022): the profiles of phi, u_y, the
/// shear rate, T and mu against log10 I with the zone boundaries marked (red: wall layer,
/// blue: dense zone, black: plug, as the paper's Figs. 8-11), and the centre-of-mass series
/// with the wall-force balance.
fn dense_figures(a: &crate::analysis::dense::DenseAnalysis) -> Vec<JobFigure> {
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

/// (lo, hi) of finite values, padded; `log` keeps only positive ones.
fn span(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return None;
    }
    Some(if log {
        (lo / 1.3, hi * 1.3)
    } else {
        let pad = 0.05 * (hi - lo).max(1e-9 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    })
}

/// The window's colour (shaded in the trace, a bar under the label strip): dark when steady.
fn window_colour(steady: bool) -> RGBColor {
    if steady {
        RGBColor(60, 60, 60)
    } else {
        RGBColor(170, 170, 170)
    }
}

/// A tick label of a linear axis ([`ticks::short`]).
fn tick(v: &f64) -> String {
    ticks::short(*v)
}

/// Height of the evolution figure's energy trace, CSS pixels.
const EVOLUTION_TRACE: u32 = 380;

/// A text's width in pixels at font size `size` (pixels), from an average glyph width of
/// 0.6 em (generous for the proportional figure font, so that estimated texts do not touch).
fn estimated_text_width(text: &str, size: f64) -> i32 {
    (0.6 * size * text.chars().count() as f64).ceil() as i32
}

/// Rows for texts spanning the given pixel ranges (in the order given): each takes the first
/// row in which it keeps `gap` pixels from every text already there.
fn stagger_rows(spans: &[(i32, i32)], gap: i32) -> Vec<usize> {
    let mut rows: Vec<Vec<(i32, i32)>> = Vec::new();
    spans
        .iter()
        .map(|&(a, b)| {
            let free =
                |row: &Vec<(i32, i32)>| row.iter().all(|&(c, d)| b + gap <= c || d + gap <= a);
            let k = rows.iter().position(free).unwrap_or(rows.len());
            if k == rows.len() {
                rows.push(Vec::new());
            }
            rows[k].push((a, b));
            k
        })
        .collect()
}

/// The energy trace: translational and rotational energy per particle against collisions per
/// particle, the analysis `window` shaded, `marks` (milestones: clock, text) as dashed
/// vertical lines with their text.
fn draw_trace<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    points: &[(f64, f64, f64)],
    window: Option<(f64, f64)>,
    steady: bool,
    marks: &[(f64, String)],
    s: Scale,
) -> DrawResult<DB> {
    let (x0, x1) = span(points.iter().map(|p| p.0), false).unwrap_or((0.0, 1.0));
    let log = points.iter().all(|p| p.1 > 0.0 && p.2 > 0.0);
    let ys = || points.iter().flat_map(|p| [p.1, p.2]);
    let (y0, y1) = span(ys(), log).unwrap_or((1.0, 10.0));
    let translational = RGBColor(214, 39, 40);
    let rotational = RGBColor(44, 160, 44);
    let shade = window_colour(steady);
    let (margin, x_area, y_area, label) = (12, 42, 72, 12.0);
    let (_, h) = root.dim_in_pixel();
    let plot_h = s.css(h) - f64::from(2 * margin + x_area) - 1.6 * 16.0;
    let (line, key) = (s.line(2.0), s.px(18));
    macro_rules! chart {
        ($yr:expr, $y_format:expr) => {{
            let mut chart = ChartBuilder::on(root)
                .caption("kinetic energy per particle", s.font(16.0))
                .margin(s.px(margin))
                .x_label_area_size(s.px(x_area))
                .y_label_area_size(s.px(y_area))
                .build_cartesian_2d(x0..x1, $yr)?;
            let mut mesh = chart.configure_mesh();
            crate::figure::mesh_style(&mut mesh, s, label)
                .x_desc("collisions per particle")
                .y_desc("E / N  (m g d)")
                .x_label_formatter(&tick)
                .y_label_formatter($y_format)
                .draw()?;
            if let Some((w0, w1)) = window {
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(w0, y0), (w1, y1)],
                        shade.mix(0.15).filled(),
                    )))?
                    .label(if steady {
                        "steady window"
                    } else {
                        "window (not steady)"
                    })
                    .legend(move |(x, y)| {
                        Rectangle::new(
                            [(x, y - s.px(5)), (x + key, y + s.px(5))],
                            shade.mix(0.3).filled(),
                        )
                    });
            }
            for (name, colour, pick) in [
                ("translational", translational, 0usize),
                ("rotational", rotational, 1),
            ] {
                let points: Vec<(f64, f64)> = points
                    .iter()
                    .map(|p| (p.0, if pick == 0 { p.1 } else { p.2 }))
                    .filter(|(_, v)| v.is_finite() && (!log || *v > 0.0))
                    .collect();
                chart
                    .draw_series(LineSeries::new(points, colour.stroke_width(line)))?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + key, y)], colour.stroke_width(line))
                    });
            }
            // each text stands right of its line (left of it in the right quarter, so that
            // it stays inside), in the highest row where it overlaps no other text
            let placed: Vec<(bool, (i32, i32))> = marks
                .iter()
                .map(|(at, text)| {
                    let px = chart.backend_coord(&(*at, y1)).0;
                    let width = estimated_text_width(text, s.px(11) as f64);
                    let right = *at > x0 + 0.75 * (x1 - x0);
                    let span = if right {
                        (px - s.px(3) - width, px - s.px(3))
                    } else {
                        (px + s.px(3), px + s.px(3) + width)
                    };
                    (right, span)
                })
                .collect();
            let rows = stagger_rows(&placed.iter().map(|p| p.1).collect::<Vec<_>>(), s.px(6));
            for ((at, text), ((right, _), row)) in marks.iter().zip(placed.iter().zip(rows)) {
                chart.draw_series(DashedLineSeries::new(
                    [(*at, y0), (*at, y1)],
                    s.px(5),
                    s.px(4),
                    BLACK.stroke_width(s.line(1.0)),
                ))?;
                let dy = s.px(4) + row as i32 * s.px(14);
                let (dx, anchor) = if *right {
                    (-s.px(3), HPos::Right)
                } else {
                    (s.px(3), HPos::Left)
                };
                let style = TextStyle::from(s.font(11.0)).pos(Pos::new(anchor, VPos::Top));
                chart.draw_series(std::iter::once(
                    EmptyElement::at((*at, y1)) + Text::new(text.clone(), (dx, dy), style),
                ))?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::LowerRight)
                .margin(s.px(10))
                .legend_area_size(s.px(30))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.stroke_width(s.line(1.0)))
                .label_font(s.font(label))
                .draw()?;
        }};
    }
    if log {
        let key_points = ticks::log_ticks(y0, y1, plot_h, label, Axis::Vertical);
        let format = |v: &f64| ticks::label(*v);
        chart!(
            (y0..y1)
                .log_scale()
                .with_key_points(key_points)
                .with_light_points(ticks::log_grid(y0, y1)),
            &format
        )
    } else {
        chart!(y0..y1, &tick)
    }
    Ok(())
}

fn draw_curves<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &CurvePanel,
    s: Scale,
) -> DrawResult<DB> {
    let (x0, x1) = span(panel.points.iter().map(|p| p.0), false).unwrap_or((0.0, 1.0));
    let with_errors = |p: &(f64, f64, f64)| {
        let e = if p.2.is_finite() { p.2 } else { 0.0 };
        [p.1 - e, p.1 + e]
    };
    let (y0, y1) = span(panel.points.iter().flat_map(with_errors), false).unwrap_or((0.0, 1.0));
    let mut chart = ChartBuilder::on(area)
        .caption(panel.title.clone(), s.font(14.0))
        .margin(s.px(8))
        .x_label_area_size(s.px(36))
        .y_label_area_size(s.px(62))
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let mut mesh = chart.configure_mesh();
    crate::figure::mesh_style(&mut mesh, s, PANEL_LABEL)
        .x_desc(panel.x_label.clone())
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .draw()?;
    let colour = RGBColor(31, 119, 180);
    let finite: Vec<(f64, f64, f64)> = panel
        .points
        .iter()
        .copied()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect();
    chart.draw_series(LineSeries::new(
        finite.iter().map(|p| (p.0, p.1)),
        colour.stroke_width(s.line(2.0)),
    ))?;
    for p in finite.iter().filter(|p| p.2.is_finite() && p.2 > 0.0) {
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(p.0, p.1 - p.2), (p.0, p.1 + p.2)],
            colour.stroke_width(s.line(1.0)),
        )))?;
    }
    chart.draw_series(
        finite
            .iter()
            .map(|p| Circle::new((p.0, p.1), s.px(2), colour.filled())),
    )?;
    for &(x, c) in panel.marks.iter().filter(|m| m.0 >= x0 && m.0 <= x1) {
        chart.draw_series(DashedLineSeries::new(
            [(x, y0), (x, y1)],
            s.px(5),
            s.px(4),
            c.stroke_width(s.line(1.5)),
        ))?;
    }
    Ok(())
}

/// Colours of the curves of a series panel, in order.
const SERIES_COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

fn draw_series_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &SeriesPanel,
    s: Scale,
) -> DrawResult<DB> {
    let all = || {
        panel
            .series
            .iter()
            .flat_map(|(_, p)| p.iter())
            .chain(panel.reference.iter().flat_map(|(_, p)| p.iter()))
    };
    let log = panel.log_y;
    // x spans the curves (the reference is drawn where they are)
    let xs = panel.series.iter().flat_map(|(_, p)| p.iter().map(|q| q.0));
    let (x0, x1) = span(xs, false)
        .or_else(|| span(all().map(|p| p.0), false))
        .unwrap_or((0.0, 1.0));
    // a log axis shows down to 1e-4 of the largest value (the VDFs' far tails are noise)
    let ys: Vec<f64> = panel
        .series
        .iter()
        .flat_map(|(_, p)| p.iter().map(|q| q.1))
        .collect();
    let top = ys
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let (y0, y1) = span(all().map(|p| p.1).filter(|v| !log || *v >= top * 1e-4), log)
        .unwrap_or(if log { (1e-3, 1.0) } else { (0.0, 1.0) });
    let keep = |v: f64| v.is_finite() && (!log || (v > 0.0 && v >= y0));
    macro_rules! chart {
        ($yr:expr) => {{
            let mut chart = ChartBuilder::on(area)
                .caption(panel.title.clone(), s.font(14.0))
                .margin(s.px(8))
                .x_label_area_size(s.px(36))
                .y_label_area_size(s.px(62))
                .build_cartesian_2d(x0..x1, $yr)?;
            let mut mesh = chart.configure_mesh();
            crate::figure::mesh_style(&mut mesh, s, PANEL_LABEL)
                .x_desc(panel.x_label.clone())
                .x_labels(6)
                .y_labels(6)
                .x_label_formatter(&tick)
                .y_label_formatter(&tick)
                .draw()?;
            if let Some((name, points)) = &panel.reference {
                let line: Vec<(f64, f64)> = points
                    .iter()
                    .copied()
                    .filter(|p| keep(p.1) && p.0 >= x0 && p.0 <= x1)
                    .collect();
                chart
                    .draw_series(DashedLineSeries::new(
                        line,
                        s.px(6),
                        s.px(4),
                        BLACK.stroke_width(s.line(1.0)),
                    ))?
                    .label(name.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + s.px(18), y)], BLACK));
            }
            for (k, (name, points)) in panel.series.iter().enumerate() {
                let colour = SERIES_COLOURS[k % SERIES_COLOURS.len()];
                let line: Vec<(f64, f64)> = points
                    .iter()
                    .copied()
                    .filter(|p| p.0.is_finite() && keep(p.1))
                    .collect();
                chart
                    .draw_series(LineSeries::new(line, colour.stroke_width(s.line(2.0))))?
                    .label(name.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(
                            vec![(x, y), (x + s.px(18), y)],
                            colour.stroke_width(s.line(2.0)),
                        )
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(s.font(11.0))
                .draw()?;
        }};
    }
    if log {
        chart!((y0..y1).log_scale())
    } else {
        chart!(y0..y1)
    }
    Ok(())
}

/// Tick labels of the panels of curves and maps, CSS pixels.
const PANEL_LABEL: f64 = 12.0;

/// A perceptually ordered colour map (viridis, five stops, linear between them), t in [0, 1].
pub fn colour_map(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn draw_maps<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[MapPanel],
    quantity: &str,
    (lo, hi): (f64, f64),
    s: Scale,
) -> DrawResult<DB> {
    let (w, _) = root.dim_in_pixel();
    let (maps, bar) = root.split_horizontally(w.saturating_sub(s.upx(110)));
    let areas = maps.split_evenly((1, panels.len().max(1)));
    let scale = |v: f64| (v - lo) / (hi - lo);
    for (panel, area) in panels.iter().zip(&areas) {
        let (x0, x1) = (panel.x_edges[0], *panel.x_edges.last().unwrap_or(&1.0));
        let (y0, y1) = (panel.y_edges[0], *panel.y_edges.last().unwrap_or(&1.0));
        // keep the aspect ratio of lengths (not of wave numbers); device pixels
        let (aw, ah) = area.dim_in_pixel();
        let (label_x, label_y, caption, margin) = (s.px(36), s.px(50), s.px(24), s.px(8));
        let (mut extra_w, mut extra_h) = (0i32, 0i32);
        if !panel.wave_numbers {
            let room_w = (aw as i32 - label_y - 2 * margin).max(10) as f64;
            let room_h = (ah as i32 - label_x - caption - 2 * margin).max(10) as f64;
            let k = (room_w / (x1 - x0)).min(room_h / (y1 - y0));
            extra_w = (room_w - k * (x1 - x0)).max(0.0) as i32;
            extra_h = (room_h - k * (y1 - y0)).max(0.0) as i32;
        }
        let mut chart = ChartBuilder::on(area)
            .caption(panel.title.clone(), s.font(14.0))
            .margin(margin)
            .margin_right(margin + extra_w)
            .margin_top(margin + extra_h / 2)
            .margin_bottom(margin + extra_h - extra_h / 2)
            .x_label_area_size(label_x)
            .y_label_area_size(label_y)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let integer = |v: &f64| {
            if (v - v.round()).abs() < 1e-6 {
                format!("{}", v.round())
            } else {
                String::new()
            }
        };
        let mut mesh = chart.configure_mesh();
        crate::figure::mesh_style(&mut mesh, s, PANEL_LABEL)
            .disable_mesh()
            .x_desc(panel.x_label.clone())
            .y_desc(panel.y_label.clone());
        if panel.wave_numbers {
            mesh.x_label_formatter(&integer).y_label_formatter(&integer);
        } else {
            // about one tick per 50 px of a panel's width (a narrow yz panel gets fewer)
            let plot_w = aw as i32 - label_y - 2 * margin - extra_w;
            let x_ticks = (plot_w / s.px(50)).clamp(2, 5) as usize;
            mesh.x_labels(x_ticks)
                .y_labels(5)
                .x_label_formatter(&tick)
                .y_label_formatter(&tick);
        }
        mesh.draw()?;
        let ny = panel.y_edges.len() - 1;
        chart.draw_series(panel.values.iter().enumerate().filter_map(|(k, v)| {
            let (i, j) = (k / ny, k % ny);
            v.is_finite().then(|| {
                Rectangle::new(
                    [
                        (panel.x_edges[i], panel.y_edges[j]),
                        (panel.x_edges[i + 1], panel.y_edges[j + 1]),
                    ],
                    colour_map(scale(*v)).filled(),
                )
            })
        }))?;
        chart.draw_series(panel.marks.iter().map(|&(i, j)| {
            Rectangle::new(
                [
                    (panel.x_edges[i], panel.y_edges[j]),
                    (panel.x_edges[i + 1], panel.y_edges[j + 1]),
                ],
                RGBColor(214, 39, 40).stroke_width(s.line(2.0)),
            )
        }))?;
    }
    // the colour bar, laid out in CSS pixels
    let (_, bh) = bar.dim_in_pixel();
    let (top, bottom) = (40i32, s.css(bh) as i32 - 50);
    let steps = 64;
    for k in 0..steps {
        let y_hi = bottom - (bottom - top) * (k + 1) / steps;
        let y_lo = bottom - (bottom - top) * k / steps;
        bar.draw(&Rectangle::new(
            [s.at((20, y_hi)), s.at((44, y_lo))],
            colour_map((k as f64 + 0.5) / steps as f64).filled(),
        ))?;
    }
    let font = s.font(PANEL_LABEL);
    bar.draw(&Text::new(
        format!("{hi:.3}"),
        s.at((48, top - 6)),
        font.clone(),
    ))?;
    bar.draw(&Text::new(
        format!("{lo:.3}"),
        s.at((48, bottom - 6)),
        font.clone(),
    ))?;
    bar.draw(&Text::new(quantity.to_string(), s.at((6, top - 26)), font))?;
    Ok(())
}

fn draw_labels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    snapshots: &[(f64, String)],
    window: Option<(f64, f64)>,
    steady: bool,
    s: Scale,
) -> DrawResult<DB> {
    let (w, _) = root.dim_in_pixel();
    let (strip, legend) = root.split_horizontally(w.saturating_sub(s.upx(220)));
    let first = snapshots.first().map_or(0.0, |s| s.0);
    let last = snapshots.last().map_or(1.0, |s| s.0);
    // each snapshot's cell reaches to the next one; the last one is as wide as the one before
    let step = if snapshots.len() > 1 {
        last - snapshots[snapshots.len() - 2].0
    } else {
        1.0
    };
    let (x0, x1) = (first, (last + step).max(first + 1e-9));
    let mut chart = ChartBuilder::on(&strip)
        .caption("label of each snapshot", s.font(15.0))
        .margin(s.px(10))
        .x_label_area_size(s.px(38))
        .y_label_area_size(s.px(10))
        .build_cartesian_2d(x0..x1, 0.0..1.0)?;
    let mut mesh = chart.configure_mesh();
    crate::figure::mesh_style(&mut mesh, s, PANEL_LABEL)
        .disable_mesh()
        .disable_y_axis()
        .x_desc("collisions per particle")
        .x_label_formatter(&tick)
        .draw()?;
    let base = |key: &str| key.split('(').next().unwrap_or(key).to_string();
    chart.draw_series(snapshots.iter().enumerate().map(|(i, (c, key))| {
        let end = snapshots.get(i + 1).map_or(c + step, |n| n.0);
        Rectangle::new(
            [(*c, 0.35), (end, 0.95)],
            marker_colour(&base(key)).filled(),
        )
    }))?;
    if let Some((w0, w1)) = window {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(w0, 0.08), (w1.max(w0) + step, 0.2)],
            window_colour(steady).filled(),
        )))?;
    }
    // legend: each label with its share of the snapshots (CSS pixels)
    let mut keys: Vec<(String, usize)> = Vec::new();
    for (_, key) in snapshots {
        match keys.iter_mut().find(|(k, _)| k == key) {
            Some(k) => k.1 += 1,
            None => keys.push((key.clone(), 1)),
        }
    }
    keys.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let font = s.font(12.0);
    let mut y = 30;
    for (key, count) in keys.iter().take(7) {
        legend.draw(&Rectangle::new(
            [s.at((6, y - 6)), s.at((20, y + 6))],
            marker_colour(&base(key)).filled(),
        ))?;
        legend.draw(&Text::new(
            format!(
                "{key} {:.0} %",
                100.0 * *count as f64 / snapshots.len() as f64
            ),
            s.at((26, y - 7)),
            font.clone(),
        ))?;
        y += 20;
    }
    legend.draw(&Rectangle::new(
        [s.at((6, y - 3)), s.at((20, y + 3))],
        window_colour(steady).filled(),
    ))?;
    legend.draw(&Text::new(
        if steady {
            "steady window"
        } else {
            "window (not steady)"
        },
        s.at((26, y - 7)),
        font,
    ))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::stagger_rows;

    /// Texts that would overlap go to lower rows; a text takes the first row where it fits
    /// (the thesis' milestones 10 000 and 11 000 sit close together, 14 000 fits beside 4000).
    #[test]
    fn overlapping_texts_are_staggered_and_free_rows_are_reused() {
        let spans = [(0, 100), (50, 150), (90, 200), (104, 130), (210, 260)];
        assert_eq!(stagger_rows(&spans, 5), vec![0, 1, 2, 3, 0]);
        // with room, everything stays in the first row
        assert_eq!(
            stagger_rows(&[(0, 10), (20, 30), (40, 50)], 5),
            vec![0, 0, 0]
        );
        // a gap narrower than asked is an overlap
        assert_eq!(stagger_rows(&[(0, 10), (13, 30)], 5), vec![0, 1]);
    }
}
