//! Curves over a swept parameter: a summary column of the jobs table (with its `_error` twin
//! as error bars) against one parameter, one curve per value of another (`granflow plot`),
//! printed as a table and drawn as PNG and SVG; the minimum of each curve (grid point and a
//! parabola through its neighbours); and the diagram of where an interior minimum exists over
//! two other parameters (the Knudsen-minimum diagram of Gupta 2017, Fig. 4.1), placed on the
//! phase-diagram grid.
//!
//! A point is valid only where its job's method was: a job that is not steady (or whose
//! collapse guard went beyond its validity) is drawn hollow, marked in the table, and never
//! decides a minimum.

use super::phase::{Cell, CellJob, DISAGREE, PhaseDiagram, fmt_value};
use super::tables::GatheredJob;
use super::vertex_fit::{self, VertexFit};
use crate::engine::{EngineDef, ParamValue};
use crate::figure::ticks::{self, Axis};
use crate::figure::{Scale, Sizing};
use plotters::coord::Shift;
use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::collections::BTreeMap;
use std::path::Path;

/// One point of a curve: the mean over the jobs (seeds) at one x.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    /// standard error: the jobs' own errors combined, sqrt(sum e^2) / n (NaN when the column
    /// has no `_error` twin)
    pub error: f64,
    pub jobs: usize,
    /// every job at the point was steady with a valid method
    pub valid: bool,
    /// the labels the point's jobs gave and how many gave each, most first (more than one:
    /// the mean pools jobs that disagree, marked [`DISAGREE`])
    pub labels: Vec<(String, usize)>,
}

impl Point {
    /// Whether the point averages jobs whose labels differ.
    pub fn disagrees(&self) -> bool {
        self.labels.len() > 1
    }
}

/// One job's value at a point: y, its error, whether the job is valid, its label.
#[derive(Clone, Debug, PartialEq)]
struct Sample {
    y: f64,
    error: f64,
    valid: bool,
    label: String,
}

/// The size of a curve plot unless one is asked for, CSS pixels.
const SIZE: (u32, u32) = (820, 560);
/// Its margin, the room for the x and y tick labels and axis names, and the font sizes of
/// caption and tick labels, CSS pixels.
const MARGIN: i32 = 14;
const X_AREA: i32 = 46;
const Y_AREA: i32 = 78;
const CAPTION: f64 = 18.0;
const LABEL: f64 = 13.0;

/// One curve: the points of one value of the `by` parameter, in increasing x.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<Point>,
}

/// Where a curve is smallest among its valid points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Minimum {
    /// the grid point of the smallest value
    pub at: f64,
    pub value: f64,
    /// the vertex of the parabola through it and its two neighbours (in log x on a log axis);
    /// None at an end of the curve
    pub vertex: Option<f64>,
    /// inside the curve, and below a value on each side by more than twice the combined
    /// standard error (or, without errors, by more than 1 %)
    pub interior: bool,
    /// the vertex of a weighted least-squares parabola through the valid points around the
    /// lowest one, with its 68 % interval ([`vertex_fit`](super::vertex_fit)); None without
    /// errors, at an end, or where no parabola fits
    pub fit: Option<VertexFit>,
}

/// A plot of `y` over `x`, one series per value of `by`.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePlot {
    pub x: String,
    pub y: String,
    pub by: Option<String>,
    /// the x axis label: symbol, unit and key, e.g. "Kn (knudsen_number)"
    pub x_label: String,
    /// the y axis label: the column and its unit, e.g. "slip_velocity [sqrt(g d)]"
    pub y_label: String,
    /// the symbol the legend names the curves by, e.g. "e_n" (the key when it has none)
    pub by_symbol: Option<String>,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
    /// jobs of the plan not done yet (not drawn)
    pub not_done: usize,
}

/// The numeric summary columns of an engine's jobs table (what `--y` may name), with the
/// statistics' columns where its analysis has them (jobs without statistics give no points).
pub fn numeric_columns(engine: &EngineDef) -> Vec<String> {
    use crate::analysis::columns::ColumnKind;
    let mut columns = crate::registry::analysis_of(engine).summary_columns();
    if crate::registry::analysis_of(engine).supports_statistics() {
        columns.extend(crate::analysis::statistics::tables::summary_columns());
    }
    columns
        .into_iter()
        .filter(|(_, k)| matches!(k, ColumnKind::F64 | ColumnKind::I64))
        .map(|(n, _)| n)
        .collect()
}

/// Whether a job's result is valid for plotting: steady, collapse guard within its validity.
fn valid(summary: &serde_json::Map<String, serde_json::Value>, label: &str) -> bool {
    let flag = |k: &str| summary.get(k).and_then(|v| v.as_bool());
    flag("steady").unwrap_or(label != "not-steady") && flag("collapse_guard_valid").unwrap_or(true)
}

/// Check that `name` is a numeric parameter of the engine.
fn numeric_param(engine: &EngineDef, name: &str) -> Result<(), String> {
    match engine.param(name) {
        None => Err(format!(
            "`{name}` is not a parameter of the {} engine; allowed: {}",
            engine.name,
            engine.param_names()
        )),
        Some(d) if matches!(d.kind, crate::engine::declare::ParamKind::Choice(_)) => Err(format!(
            "`{name}` is a choice, not a number: use it as --by"
        )),
        Some(_) => Ok(()),
    }
}

/// Combine the jobs at one x into a point.
fn point(x: f64, values: &[Sample]) -> Point {
    let n = values.len() as f64;
    let y = values.iter().map(|v| v.y).sum::<f64>() / n;
    let error = values.iter().map(|v| v.error * v.error).sum::<f64>().sqrt() / n;
    let mut labels: Vec<(String, usize)> = Vec::new();
    for v in values {
        match labels.iter_mut().find(|(l, _)| *l == v.label) {
            Some(l) => l.1 += 1,
            None => labels.push((v.label.clone(), 1)),
        }
    }
    labels.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    Point {
        x,
        y,
        error,
        jobs: values.len(),
        valid: values.iter().all(|v| v.valid),
        labels,
    }
}

/// A job's label as a point pools it: its label with humps, "not-steady" when not steady.
fn job_label(analysis: &crate::analysis::Analysis) -> String {
    let (label, humps) = analysis.label();
    let steady = analysis
        .summary()
        .get("steady")
        .and_then(|v| v.as_bool())
        .unwrap_or(label != "not-steady");
    if steady {
        crate::analysis::labels::label_key(label, humps)
    } else {
        "not-steady".into()
    }
}

impl CurvePlot {
    /// Gather the points. `x` must be a numeric parameter, `by` any parameter, `y` a numeric
    /// summary column of the engine's jobs table.
    pub fn build(
        engine: &EngineDef,
        jobs: &[GatheredJob],
        x: &str,
        y: &str,
        by: Option<&str>,
    ) -> Result<Self, String> {
        let refs: Vec<&GatheredJob> = jobs.iter().collect();
        Self::build_of(engine, &refs, x, y, by)
    }

    fn build_of(
        engine: &EngineDef,
        jobs: &[&GatheredJob],
        x: &str,
        y: &str,
        by: Option<&str>,
    ) -> Result<Self, String> {
        numeric_param(engine, x)?;
        if let Some(by) = by
            && engine.param(by).is_none()
        {
            return Err(format!(
                "`{by}` is not a parameter of the {} engine; allowed: {}",
                engine.name,
                engine.param_names()
            ));
        }
        let columns = numeric_columns(engine);
        if !columns.iter().any(|c| c == y) {
            let hint = super::suggest::did_you_mean(y, columns.iter().map(String::as_str))
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "`{y}` is not a numeric column of the {} engine's jobs table{hint}; allowed: {}",
                engine.name,
                columns.join(", ")
            ));
        }
        let error_column = format!("{y}_error");
        // by value -> x -> the jobs' samples
        let mut groups: BTreeMap<String, BTreeMap<u64, (f64, Vec<Sample>)>> = BTreeMap::new();
        let mut order: Vec<(ParamValue, String)> = Vec::new();
        let mut not_done = 0;
        for j in jobs {
            let Some(r) = &j.result else {
                not_done += 1;
                continue;
            };
            let Some(xv) = j.job.params.values.get(x).and_then(ParamValue::as_f64) else {
                continue;
            };
            let summary = r.analysis.summary();
            let Some(yv) = summary.get(y).and_then(|v| v.as_f64()) else {
                continue;
            };
            let ev = summary
                .get(&error_column)
                .and_then(|v| v.as_f64())
                .unwrap_or(f64::NAN);
            let name = match by.and_then(|b| j.job.params.values.get(b)) {
                Some(v) => {
                    let name = fmt_value(v);
                    if !order.iter().any(|(_, n)| *n == name) {
                        order.push((v.clone(), name.clone()));
                    }
                    name
                }
                None => y.to_string(),
            };
            let ok = valid(&summary, r.analysis.label().0);
            groups
                .entry(name)
                .or_default()
                .entry(xv.to_bits())
                .or_insert((xv, Vec::new()))
                .1
                .push(Sample {
                    y: yv,
                    error: ev,
                    valid: ok,
                    label: job_label(&r.analysis),
                });
        }
        order.sort_by(|a, b| match (&a.0, &b.0) {
            (ParamValue::Number(p), ParamValue::Number(q)) => p.total_cmp(q),
            _ => a.1.cmp(&b.1),
        });
        let names: Vec<String> = if by.is_some() {
            order.into_iter().map(|(_, n)| n).collect()
        } else {
            groups.keys().cloned().collect()
        };
        let series = names
            .into_iter()
            .filter_map(|name| {
                let g = groups.remove(&name)?;
                let mut points: Vec<Point> = g.into_values().map(|(x, v)| point(x, &v)).collect();
                points.sort_by(|a, b| a.x.total_cmp(&b.x));
                Some(Series { name, points })
            })
            .collect();
        Ok(CurvePlot {
            x: x.into(),
            y: y.into(),
            by: by.map(str::to_string),
            x_label: super::phase::axis_label(engine, x),
            y_label: match super::tables::column_docs::unit_for("jobs", engine.name, y) {
                Some(unit) => format!("{y} [{unit}]"),
                None => y.to_string(),
            },
            by_symbol: by.map(|b| super::phase::symbol_of(engine, b)),
            log_x: false,
            log_y: false,
            series,
            not_done,
        })
    }

    /// The points as a text table (one block per series, invalid points marked), with each
    /// curve's minimum.
    pub fn table(&self) -> String {
        let mut out = String::new();
        // an error column only where the column has errors (its `_error` twin)
        let errors = self
            .series
            .iter()
            .flat_map(|s| &s.points)
            .any(|p| p.error.is_finite());
        for s in &self.series {
            if let Some(by) = &self.by {
                out.push_str(&format!("{by} = {}\n", s.name));
            }
            out.push_str(&format!("  {:>12}  {:>14}", self.x, self.y));
            if errors {
                out.push_str(&format!("  {:>12}", "error"));
            }
            out.push_str("  jobs\n");
            for p in &s.points {
                out.push_str(&format!(
                    "  {:>12}  {:>14.6}",
                    fmt_value(&ParamValue::Number(p.x)),
                    p.y
                ));
                if errors {
                    let e = if p.error.is_finite() {
                        format!("{:.3e}", p.error)
                    } else {
                        "-".into()
                    };
                    out.push_str(&format!("  {e:>12}"));
                }
                out.push_str(&format!(
                    "  {}{}{}\n",
                    p.jobs,
                    if p.valid {
                        ""
                    } else {
                        "  not steady: not a result"
                    },
                    if p.disagrees() {
                        format!("  {DISAGREE} labels differ: {}", labels_text(&p.labels))
                    } else {
                        String::new()
                    }
                ));
            }
            // the lowest point, and whether it is a dip: below points on both sides beyond
            // twice their errors (the rule of [`minimum`])
            match minimum(&s.points, self.log_x) {
                Some(m) => out.push_str(&format!(
                    "  lowest at {} = {} ({} = {:.6}){}\n",
                    self.x,
                    fmt_value(&ParamValue::Number(m.at)),
                    self.y,
                    m.value,
                    if m.interior {
                        format!(
                            ": a dip, below points on both sides{}{}",
                            m.vertex
                                .map(|v| format!(" (parabola vertex at {v:.3})"))
                                .unwrap_or_default(),
                            m.fit.map(|f| fit_text(&self.x, &f)).unwrap_or_default()
                        )
                    } else {
                        String::new()
                    }
                )),
                None => out.push_str("  no valid points\n"),
            }
        }
        if self.not_done > 0 {
            out.push_str(&format!("({} jobs not done)\n", self.not_done));
        }
        if self.disagrees() {
            out.push_str(&format!("{DISAGREE} {POINT_DISAGREE_LEGEND}\n"));
        }
        out
    }

    /// Whether any point averages jobs whose labels differ.
    pub fn disagrees(&self) -> bool {
        self.series
            .iter()
            .any(|s| s.points.iter().any(Point::disagrees))
    }

    /// The file stem `plot-<y>-<x>[-by-<by>]`.
    pub fn stem(&self) -> String {
        match &self.by {
            Some(by) => format!("plot-{}-{}-by-{by}", self.y, self.x),
            None => format!("plot-{}-{}", self.y, self.x),
        }
    }

    /// The plot as PNG bytes at the size and resolution asked (pages that inline it).
    pub fn png(&self, sizing: &Sizing) -> anyhow::Result<Vec<u8>> {
        let css = sizing.css(SIZE);
        crate::figure::render_png(css, sizing.scale(), |root, s| self.draw(root, css, s))
    }

    /// Write the plot as PNG at the size and resolution asked.
    pub fn write_png(&self, path: &Path, sizing: &Sizing) -> anyhow::Result<()> {
        let css = sizing.css(SIZE);
        crate::figure::save_png(path, css, sizing.scale(), |root, s| self.draw(root, css, s))
    }

    /// Write the plot as SVG at the size asked.
    pub fn write_svg(&self, path: &Path, sizing: &Sizing) -> anyhow::Result<()> {
        let css = sizing.css(SIZE);
        crate::figure::save_svg(path, css, |root, s| self.draw(root, css, s))
    }

    /// The plot as SVG text at the size asked.
    pub fn svg(&self, sizing: &Sizing) -> anyhow::Result<String> {
        let css = sizing.css(SIZE);
        crate::figure::render_svg(css, |root, s| self.draw(root, css, s))
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pts = || self.series.iter().flat_map(|s| s.points.iter());
        let usable = |v: f64, log: bool| v.is_finite() && (!log || v > 0.0);
        let span = |vals: Vec<f64>, log: bool| -> (f64, f64) {
            let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if !lo.is_finite() {
                return if log { (0.1, 10.0) } else { (0.0, 1.0) };
            }
            if log {
                let (a, b) = (lo.ln(), hi.ln().max(lo.ln() + 1e-3));
                let pad = 0.05 * (b - a);
                ((a - pad).exp(), (b + pad).exp())
            } else {
                let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
                (lo - pad, hi + pad)
            }
        };
        let xs: Vec<f64> = pts()
            .map(|p| p.x)
            .filter(|&v| usable(v, self.log_x))
            .collect();
        let mut ys: Vec<f64> = Vec::new();
        for p in pts() {
            let e = if p.error.is_finite() { p.error } else { 0.0 };
            for v in [p.y - e, p.y + e] {
                if usable(v, self.log_y) {
                    ys.push(v);
                }
            }
        }
        (span(xs, self.log_x), span(ys, self.log_y))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        (w, h): (u32, u32),
        s: Scale,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let ((x0, x1), (y0, y1)) = self.ranges();
        let caption = match &self.by {
            Some(by) => format!(
                "{} over {} by {}",
                self.y,
                self.x_label,
                self.by_symbol.as_deref().unwrap_or(by)
            ),
            None => format!("{} over {}", self.y, self.x_label),
        };
        // the plotting area's extent in CSS pixels, for the ticks of log axes
        let plot_w = f64::from(w) - f64::from(2 * MARGIN + Y_AREA);
        let plot_h = f64::from(h) - f64::from(2 * MARGIN + X_AREA) - 1.6 * CAPTION;
        let x_ticks = ticks::log_ticks(x0, x1, plot_w, LABEL, Axis::Horizontal);
        let y_ticks = ticks::log_ticks(y0, y1, plot_h, LABEL, Axis::Vertical);
        let x_format = |v: &f64| {
            if self.log_x {
                ticks::label(*v)
            } else {
                ticks::short(*v)
            }
        };
        let y_format = |v: &f64| {
            if self.log_y {
                ticks::label(*v)
            } else {
                ticks::short(*v)
            }
        };
        // four coordinate kinds (linear or log on each axis) share one drawing routine
        macro_rules! chart {
            ($xr:expr, $yr:expr) => {{
                let mut chart = ChartBuilder::on(root)
                    .caption(caption.clone(), s.font(CAPTION))
                    .margin(s.px(MARGIN))
                    .x_label_area_size(s.px(X_AREA))
                    .y_label_area_size(s.px(Y_AREA))
                    .build_cartesian_2d($xr, $yr)?;
                let mut mesh = chart.configure_mesh();
                crate::figure::mesh_style(&mut mesh, s, LABEL)
                    .x_desc(self.x_label.clone())
                    .y_desc(self.y_label.clone())
                    .x_label_formatter(&x_format)
                    .y_label_formatter(&y_format)
                    .draw()?;
                self.draw_series(&mut chart, s, (y0, y1))?;
            }};
        }
        let log = |lo: f64, hi: f64, ticks: Vec<f64>| {
            (lo..hi)
                .log_scale()
                .with_key_points(ticks)
                .with_light_points(ticks::log_grid(lo, hi))
        };
        match (self.log_x, self.log_y) {
            (false, false) => chart!(x0..x1, y0..y1),
            (true, false) => chart!(log(x0, x1, x_ticks), y0..y1),
            (false, true) => chart!(x0..x1, log(y0, y1, y_ticks)),
            (true, true) => chart!(log(x0, x1, x_ticks), log(y0, y1, y_ticks)),
        }
        Ok(())
    }

    fn draw_series<'a, DB, CT>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        s: Scale,
        (y0, y1): (f64, f64),
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
    where
        DB: DrawingBackend + 'a,
        CT: CoordTranslate<From = (f64, f64)>,
    {
        let mut any_fit = false;
        let mut any_invalid = false;
        let mut any_disagree = false;
        let (radius, key) = (s.px(4), s.px(18));
        for (i, series) in self.series.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let drawable: Vec<&Point> = series
                .points
                .iter()
                .filter(|p| p.y.is_finite() && (!self.log_x || p.x > 0.0))
                .collect();
            let valid_line: Vec<(f64, f64)> = drawable
                .iter()
                .filter(|p| p.valid)
                .map(|p| (p.x, p.y))
                .collect();
            let label = match &self.by {
                Some(by) => format!(
                    "{} = {}",
                    self.by_symbol.as_deref().unwrap_or(by),
                    series.name
                ),
                None => series.name.clone(),
            };
            // behind the curve: the fitted minimum's 68 % band and its vertex
            if let Some(f) = minimum(&series.points, self.log_x)
                .filter(|m| m.interior)
                .and_then(|m| m.fit)
            {
                any_fit = true;
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(f.low, y0), (f.high, y1)],
                    colour.mix(0.15).filled(),
                )))?;
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(f.vertex, y0), (f.vertex, y1)],
                    colour.mix(0.6).stroke_width(s.line(1.0)),
                )))?;
            }
            let line = s.line(2.0);
            chart
                .draw_series(LineSeries::new(valid_line, colour.stroke_width(line)))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + key, y)], colour.stroke_width(line))
                });
            for p in &drawable {
                if p.error.is_finite() && p.error > 0.0 {
                    chart.draw_series(std::iter::once(PathElement::new(
                        vec![(p.x, p.y - p.error), (p.x, p.y + p.error)],
                        colour.stroke_width(s.line(1.0)),
                    )))?;
                }
                let style = if p.valid {
                    colour.filled()
                } else {
                    any_invalid = true;
                    colour.stroke_width(s.line(1.0))
                };
                chart.draw_series(std::iter::once(Circle::new((p.x, p.y), radius, style)))?;
                if p.disagrees() {
                    any_disagree = true;
                    // beside the point, on the side towards the middle of the plot
                    let (px, _) = chart.plotting_area().map_coordinate(&(p.x, p.y));
                    let span = chart.plotting_area().get_pixel_range().0;
                    let (dx, h) = if px < (span.start + span.end) / 2 {
                        (s.px(7), HPos::Left)
                    } else {
                        (-s.px(7), HPos::Right)
                    };
                    let style =
                        TextStyle::from(s.font(DISAGREE_SIZE)).pos(Pos::new(h, VPos::Center));
                    chart.draw_series(std::iter::once(
                        EmptyElement::at((p.x, p.y)) + Text::new(DISAGREE, (dx, 0), style),
                    ))?;
                }
            }
        }
        let grey = RGBColor(90, 90, 90);
        if any_fit {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label("band: minimum of a weighted parabola, 68 %")
                .legend(move |(x, y)| {
                    Rectangle::new(
                        [(x, y - s.px(5)), (x + key, y + s.px(5))],
                        grey.mix(0.25).filled(),
                    )
                });
        }
        if any_invalid {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label("hollow: not steady (not a result)")
                .legend(move |(x, y)| {
                    Circle::new((x + key / 2, y), radius, grey.stroke_width(s.line(1.0)))
                });
        }
        if any_disagree {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label(POINT_DISAGREE_LEGEND)
                .legend(move |(x, y)| {
                    Text::new(
                        DISAGREE,
                        (x + key / 2, y),
                        TextStyle::from(s.font(DISAGREE_SIZE))
                            .pos(Pos::new(HPos::Center, VPos::Center)),
                    )
                });
        }
        let mut labels: Vec<String> = self
            .series
            .iter()
            .map(|series| match &self.by {
                Some(by) => format!(
                    "{} = {}",
                    self.by_symbol.as_deref().unwrap_or(by),
                    series.name
                ),
                None => series.name.clone(),
            })
            .collect();
        if any_invalid {
            labels.push("hollow: not steady (not a result)".into());
        }
        if any_disagree {
            labels.push(POINT_DISAGREE_LEGEND.into());
        }
        let corner = self.legend_corner(chart, &labels, s);
        chart
            .configure_series_labels()
            .position(corner)
            .margin(s.px(10))
            .legend_area_size(s.px(30))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.stroke_width(s.line(1.0)))
            .label_font(s.font(LABEL))
            .draw()?;
        Ok(())
    }

    /// Where in the plot the legend box (entries `labels`) covers the fewest points and
    /// pieces of line: a corner, else the middle of a side, else the centre; upper right
    /// first.
    fn legend_corner<'a, DB, CT>(
        &self,
        chart: &ChartContext<'a, DB, CT>,
        labels: &[String],
        s: Scale,
    ) -> SeriesLabelPosition
    where
        DB: DrawingBackend + 'a,
        CT: CoordTranslate<From = (f64, f64)>,
    {
        use SeriesLabelPosition as At;
        let (xs, ys) = chart.plotting_area().get_pixel_range();
        // the box: key area, widest label and margins; a line per entry
        let widest = labels
            .iter()
            .map(|l| crate::figure::text::width(l, LABEL))
            .fold(0.0, f64::max);
        let (w, h) = (
            s.px(widest + 30.0 + 30.0),
            s.px(20.0 + 18.0 * labels.len() as f64),
        );
        // the points and 16 samples along each segment between drawn points, device pixels
        let mut ink: Vec<(i32, i32)> = Vec::new();
        for series in &self.series {
            let at: Vec<(i32, i32)> = series
                .points
                .iter()
                .filter(|p| {
                    p.y.is_finite() && (!self.log_x || p.x > 0.0) && (!self.log_y || p.y > 0.0)
                })
                .map(|p| chart.plotting_area().map_coordinate(&(p.x, p.y)))
                .collect();
            for pair in at.windows(2) {
                for k in 1..16 {
                    let t = f64::from(k) / 16.0;
                    let lerp = |a: i32, b: i32| a + (t * f64::from(b - a)).round() as i32;
                    ink.push((lerp(pair[0].0, pair[1].0), lerp(pair[0].1, pair[1].1)));
                }
            }
            ink.extend(at);
        }
        let span = |range: &std::ops::Range<i32>, size: i32, side: i8| match side {
            -1 => (range.start, range.start + size),
            1 => (range.end - size, range.end),
            _ => {
                let mid = (range.start + range.end) / 2;
                (mid - size / 2, mid + size / 2)
            }
        };
        let pad = s.px(8);
        let covered = |horizontal: i8, vertical: i8| {
            let (x0, x1) = span(&xs, w, horizontal);
            let (y0, y1) = span(&ys, h, vertical);
            ink.iter()
                .filter(|(x, y)| {
                    (x0 - pad..=x1 + pad).contains(x) && (y0 - pad..=y1 + pad).contains(y)
                })
                .count()
        };
        [
            (1, -1, At::UpperRight),
            (-1, -1, At::UpperLeft),
            (1, 1, At::LowerRight),
            (-1, 1, At::LowerLeft),
            (1, 0, At::MiddleRight),
            (-1, 0, At::MiddleLeft),
            (0, -1, At::UpperMiddle),
            (0, 1, At::LowerMiddle),
            (0, 0, At::MiddleMiddle),
        ]
        .into_iter()
        .min_by_key(|(h, v, _)| covered(*h, *v))
        .map_or(At::UpperRight, |c| c.2)
    }
}

/// Font size of the [`DISAGREE`] mark beside a point, CSS pixels.
const DISAGREE_SIZE: f64 = 18.0;

/// The legend line of the [`DISAGREE`] mark of a curve point.
pub const POINT_DISAGREE_LEGEND: &str = "the point averages jobs whose labels differ";

/// "plug (2 jobs), homogeneous (1 job)".
fn labels_text(labels: &[(String, usize)]) -> String {
    labels
        .iter()
        .map(|(l, n)| format!("{l} ({n} {})", if *n == 1 { "job" } else { "jobs" }))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The weighted parabola's line of a curve's table: where it puts the minimum, how precisely,
/// from which points and how well it fits.
fn fit_text(x: &str, f: &VertexFit) -> String {
    format!(
        "\n  weighted parabola through the {} points {x} = {} ... {}: minimum at {x} = {:.4} \
         (68 %: {:.4} ... {:.4}, +-{:.1} %), chi^2/dof = {:.2}",
        f.points,
        fmt_value(&ParamValue::Number(f.from)),
        fmt_value(&ParamValue::Number(f.to)),
        f.vertex,
        f.low,
        f.high,
        100.0 * f.relative_half_width(),
        f.chi2_per_dof
    )
}

/// The minimum of a curve over its valid points (in increasing x); None without valid points.
/// A curve has an *interior* minimum where some inner point lies below a point on each side
/// by more than twice their combined standard error (a significant dip: the flow rate falls,
/// then rises again, as in the thesis' "non-monotonic" region of Fig. 4.1); of such points the
/// lowest is reported, even when the curve falls again later below it (a minimum followed by a
/// maximum). Without one, the smallest value (then at an end or within the errors) is reported.
pub fn minimum(points: &[Point], log_x: bool) -> Option<Minimum> {
    let pts: Vec<&Point> = points
        .iter()
        .filter(|p| p.valid && p.y.is_finite())
        .collect();
    let (smallest, _) = pts
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.y.total_cmp(&b.1.y))?;
    let clear_below = |best: &Point, side: &[&Point]| {
        side.iter().any(|p| {
            let e = (p.error * p.error + best.error * best.error).sqrt();
            let margin = if e.is_finite() && e > 0.0 {
                2.0 * e
            } else {
                0.01 * best.y.abs()
            };
            p.y - best.y > margin
        })
    };
    let dip = (1..pts.len().saturating_sub(1))
        .filter(|&i| clear_below(pts[i], &pts[..i]) && clear_below(pts[i], &pts[i + 1..]))
        .min_by(|&a, &b| pts[a].y.total_cmp(&pts[b].y));
    let (i, interior) = match dip {
        Some(i) => (i, true),
        None => (smallest, false),
    };
    let best = pts[i];
    let at_end = i == 0 || i + 1 == pts.len();
    let vertex = if at_end {
        None
    } else {
        let t = |x: f64| if log_x { x.ln() } else { x };
        let (a, b, c) = (pts[i - 1], pts[i], pts[i + 1]);
        let (xa, xb, xc) = (t(a.x), t(b.x), t(c.x));
        // vertex of the parabola through three points (Lagrange form)
        let num = (xb - xa).powi(2) * (b.y - c.y) - (xb - xc).powi(2) * (b.y - a.y);
        let den = (xb - xa) * (b.y - c.y) - (xb - xc) * (b.y - a.y);
        (den != 0.0).then(|| {
            let v = xb - 0.5 * num / den;
            if log_x { v.exp() } else { v }
        })
    };
    let samples: Vec<vertex_fit::Sample> = pts
        .iter()
        .map(|p| vertex_fit::Sample {
            x: p.x,
            y: p.y,
            error: p.error,
        })
        .collect();
    let fit = if at_end {
        None
    } else {
        vertex_fit::fit_vertex(&samples, i, log_x)
    };
    Some(Minimum {
        at: best.x,
        value: best.y,
        vertex,
        interior,
        fit,
    })
}

/// True when the curve rises to a significant interior maximum (the minimum rule applied to -y).
fn has_interior_maximum(points: &[Point], log_x: bool) -> bool {
    let flipped: Vec<Point> = points
        .iter()
        .map(|p| Point {
            y: -p.y,
            ..p.clone()
        })
        .collect();
    minimum(&flipped, log_x).is_some_and(|m| m.interior)
}

/// The diagram of where `y` has an interior minimum along `along`, over the parameters `x`
/// and `y_axis` (each cell: the jobs sharing its values, one curve per value of every other
/// swept parameter merged by mean). Labels: "minimum" (an interior minimum), "maximum" (no
/// minimum on the grid but an interior maximum: not monotonic), "monotonic"
/// (none), "not-steady" (a point of the curve is not a result).
pub fn minimum_diagram(
    engine: &EngineDef,
    jobs: &[GatheredJob],
    along: &str,
    column: &str,
    x: &str,
    y: Option<&str>,
    log_along: bool,
) -> Result<PhaseDiagram, String> {
    numeric_param(engine, along)?;
    for name in std::iter::once(x).chain(y) {
        if name == along {
            return Err(format!(
                "`{along}` is the curve's axis (--along): the diagram's axes must be others"
            ));
        }
    }
    // the phase-diagram grid places the jobs; each cell's jobs make one curve
    let mut diagram = PhaseDiagram::build(engine, jobs, x, y)?;
    let index = |axis: &[ParamValue], j: &GatheredJob, name: &str| {
        j.job
            .params
            .values
            .get(name)
            .and_then(|v| axis.iter().position(|a| a == v))
            .unwrap_or(0)
    };
    let mut by_cell: BTreeMap<(usize, usize), Vec<&GatheredJob>> = BTreeMap::new();
    for j in jobs {
        let key = (
            index(&diagram.xs, j, x),
            y.map_or(0, |y| index(&diagram.ys, j, y)),
        );
        by_cell.entry(key).or_default().push(j);
    }
    for (key, cell_jobs) in by_cell {
        let curve = CurvePlot::build_of(engine, &cell_jobs, along, column, None)?;
        let points: Vec<Point> = curve.series.into_iter().flat_map(|s| s.points).collect();
        let not_done = curve.not_done;
        let steady = !points.is_empty() && points.iter().all(|p| p.valid);
        let label = match minimum(&points, log_along) {
            _ if !steady => "not-steady",
            Some(m) if m.interior => "minimum",
            // no dip on the grid, yet a significant hump: not monotonic either (the flow rate
            // rises to a maximum and falls; its minimum lies beyond the grid)
            _ if has_interior_maximum(&points, log_along) => "maximum",
            _ => "monotonic",
        };
        diagram.cells.insert(
            key,
            Cell {
                jobs: if points.is_empty() {
                    Vec::new()
                } else {
                    vec![CellJob {
                        label: label.into(),
                        humps: 0,
                        probabilities: Vec::new(),
                        weight: 1.0,
                        steady,
                        guard_valid: true,
                        three_dimensional: false,
                    }]
                },
                not_done,
            },
        );
    }
    Ok(diagram)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, error: f64) -> Point {
        Point {
            x,
            y,
            error,
            jobs: 1,
            valid: true,
            labels: vec![("plug".into(), 1)],
        }
    }

    fn sample(y: f64, error: f64, valid: bool, label: &str) -> Sample {
        Sample {
            y,
            error,
            valid,
            label: label.into(),
        }
    }

    #[test]
    fn an_interior_minimum_is_found_and_its_vertex_refined() {
        // y = (ln x)^2 + 1 sampled at x = 0.1 ... 10: minimum at x = 1, vertex exactly 1 in log x
        let pts: Vec<Point> = [0.1, 0.3, 1.0, 3.0, 10.0]
            .iter()
            .map(|&x: &f64| p(x, x.ln().powi(2) + 1.0, 0.01))
            .collect();
        let m = minimum(&pts, true).unwrap();
        assert_eq!(m.at, 1.0);
        assert!(m.interior);
        // the three points around x = 1 are symmetric in ln x: the vertex is x = 1
        assert!((m.vertex.unwrap() - 1.0).abs() < 1e-12, "{m:?}");
        // and the weighted parabola through all five (they lie on one) says the same
        let fit = m.fit.expect("a parabola through five points of a parabola");
        assert_eq!(fit.points, 5);
        assert!((fit.vertex - 1.0).abs() < 1e-9, "{fit:?}");
    }

    #[test]
    fn a_dip_within_the_errors_is_not_a_minimum() {
        // a flat curve with a dip of 1 error bar: not a minimum
        let pts = vec![p(0.1, 1.0, 0.01), p(1.0, 0.99, 0.01), p(10.0, 1.0, 0.01)];
        assert!(!minimum(&pts, true).unwrap().interior);
        // the same dip with errors ten times smaller is one
        let pts = vec![p(0.1, 1.0, 0.001), p(1.0, 0.99, 0.001), p(10.0, 1.0, 0.001)];
        assert!(minimum(&pts, true).unwrap().interior);
    }

    #[test]
    fn a_monotonic_curve_has_its_smallest_value_at_an_end() {
        let pts: Vec<Point> = (1..6).map(|i| p(i as f64, 10.0 / i as f64, 0.01)).collect();
        let m = minimum(&pts, false).unwrap();
        assert_eq!(m.at, 5.0);
        assert!(!m.interior && m.vertex.is_none());
    }

    #[test]
    fn a_minimum_followed_by_a_maximum_is_a_minimum() {
        // the thesis' Fig. 4.1(b) shape: falls, rises to a maximum, falls below the dip again
        let ys = [10.0, 8.0, 9.0, 9.5, 7.0];
        let pts: Vec<Point> = ys
            .iter()
            .enumerate()
            .map(|(i, &y)| p(i as f64 + 1.0, y, 0.05))
            .collect();
        let m = minimum(&pts, false).unwrap();
        assert!(m.interior, "{m:?}");
        assert_eq!(m.at, 2.0);
        // the same shape with a dip inside the errors is monotonic in effect
        let pts: Vec<Point> = [10.0, 8.0, 8.05, 7.5, 7.0]
            .iter()
            .enumerate()
            .map(|(i, &y)| p(i as f64 + 1.0, y, 0.05))
            .collect();
        assert!(!minimum(&pts, false).unwrap().interior);
    }

    #[test]
    fn invalid_points_never_decide_the_minimum() {
        let mut pts = vec![p(0.1, 2.0, 0.01), p(1.0, 0.5, 0.01), p(10.0, 2.0, 0.01)];
        pts[1].valid = false;
        let m = minimum(&pts, true).unwrap();
        assert!(!m.interior, "{m:?}");
        assert_eq!(m.value, 2.0);
    }

    #[test]
    fn replicas_combine_into_a_mean_with_a_combined_error() {
        let pt = point(
            1.0,
            &[
                sample(1.0, 0.1, true, "plug"),
                sample(3.0, 0.1, true, "plug"),
            ],
        );
        assert_eq!(pt.y, 2.0);
        assert!((pt.error - 0.1 / 2f64.sqrt()).abs() < 1e-15);
        assert!(!pt.disagrees());
        let pooled = point(
            1.0,
            &[
                sample(1.0, 0.1, true, "plug"),
                sample(3.0, 0.1, false, "homogeneous"),
            ],
        );
        assert!(!pooled.valid);
        // jobs whose labels differ are counted apart and the point is marked
        assert!(pooled.disagrees());
        assert_eq!(
            pooled.labels,
            [("homogeneous".to_string(), 1), ("plug".to_string(), 1)]
        );
    }
}
