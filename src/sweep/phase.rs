//! Phase diagrams: the structure label of every done job placed on a grid of two swept
//! parameters (or a strip for one), printed as a table and drawn as PNG and SVG (plotters):
//! one marker per structure, hump counts written beside S-wave markers (as thesis Fig. 5.25),
//! "3D" beside the markers of structures that vary along z.

use super::grid::PlannedJob;
use super::tables::GatheredJob;
use crate::engine::declare::ParamDefault;
use crate::engine::{EngineDef, ParamValue};
pub use crate::figure::marker_colour;
use crate::figure::text::Heading;
use crate::figure::ticks;
use crate::figure::{Scale, Sizing};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::collections::BTreeMap;
use std::path::Path;

/// One done job in a cell.
#[derive(Clone, Debug, PartialEq)]
pub struct CellJob {
    /// its label and humps as the job's analysis gave them
    pub label: String,
    pub humps: u32,
    /// (label with humps, fraction of its window's snapshots)
    pub probabilities: Vec<(String, f64)>,
    /// snapshots of its window (the weight of its probabilities when replicas merge)
    pub weight: f64,
    pub steady: bool,
    /// the collapse guard stayed within its validity limit
    pub guard_valid: bool,
    /// its structure varies along z (the analysis' `three_dimensional`)
    pub three_dimensional: bool,
}

/// One cell of the diagram: the done jobs at that point (one per seed) and how many jobs are
/// not done.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cell {
    pub jobs: Vec<CellJob>,
    pub not_done: usize,
}

/// What a cell shows: the label (the merged replicas' modal label when it holds a clear
/// majority, else "mixed"; "not-steady" when no replica is steady), its humps, its
/// probability, and whether any replica's collapse guard went beyond its validity.
#[derive(Clone, Debug, PartialEq)]
pub struct CellVerdict {
    pub label: String,
    pub humps: u32,
    pub probability: f64,
    /// the merged distribution over the steady replicas, most frequent first
    pub probabilities: Vec<(String, f64)>,
    pub guard_flagged: bool,
    /// most of the steady replicas vary along z (more than half)
    pub three_dimensional: bool,
}

/// "label p; label p" (the jobs table's `label_probabilities`) back into pairs.
pub fn parse_probabilities(text: &str) -> Vec<(String, f64)> {
    text.split("; ")
        .filter_map(|part| {
            let (label, p) = part.rsplit_once(' ')?;
            Some((label.to_string(), p.parse().ok()?))
        })
        .collect()
}

/// A label key `s-wave(2)` split into its label and humps.
fn split_key(key: &str) -> (String, u32) {
    match key.strip_suffix(')').and_then(|k| k.rsplit_once('(')) {
        Some((label, humps)) if humps.parse::<u32>().is_ok() => {
            (label.to_string(), humps.parse().unwrap_or(0))
        }
        _ => (key.to_string(), 0),
    }
}

impl Cell {
    /// The replicas merged into one probability table (weighted by their window snapshots),
    /// and the cell's verdict; None for a cell without done jobs.
    pub fn verdict(&self) -> Option<CellVerdict> {
        if self.jobs.is_empty() {
            return None;
        }
        let guard_flagged = self.jobs.iter().any(|j| !j.guard_valid);
        let steady: Vec<&CellJob> = self.jobs.iter().filter(|j| j.steady).collect();
        if steady.is_empty() {
            return Some(CellVerdict {
                label: "not-steady".into(),
                humps: 0,
                probability: f64::NAN,
                probabilities: Vec::new(),
                guard_flagged,
                three_dimensional: false,
            });
        }
        let total: f64 = steady.iter().map(|j| j.weight.max(1.0)).sum();
        let mut merged: Vec<(String, f64)> = Vec::new();
        for j in &steady {
            // jobs without probabilities (older results) count with their label
            let own = if j.probabilities.is_empty() {
                vec![(crate::analysis::labels::label_key(&j.label, j.humps), 1.0)]
            } else {
                j.probabilities.clone()
            };
            for (key, p) in own {
                let w = p * j.weight.max(1.0) / total;
                match merged.iter_mut().find(|(k, _)| *k == key) {
                    Some(m) => m.1 += w,
                    None => merged.push((key, w)),
                }
            }
        }
        merged.sort_by(|a, b| b.1.total_cmp(&a.1));
        let (top, mut p) = merged[0].clone();
        // a single replica of an analysis without per-snapshot labels has no probability
        let measured = steady.len() > 1 || steady.iter().any(|j| !j.probabilities.is_empty());
        let (label, humps) = if p >= crate::analysis::labels::CLEAR_MAJORITY {
            split_key(&top)
        } else {
            ("mixed".to_string(), 0)
        };
        if !measured {
            p = f64::NAN;
        }
        let three_d = steady.iter().filter(|j| j.three_dimensional).count();
        Some(CellVerdict {
            label,
            humps,
            probability: p,
            probabilities: merged,
            guard_flagged,
            three_dimensional: 2 * three_d > steady.len(),
        })
    }

    /// The labels of the cell's done jobs as each job gave it (with humps; "not-steady" for a
    /// job that is not steady, which the verdict leaves out) and how many jobs gave each, most
    /// first.
    pub fn job_labels(&self) -> Vec<(String, usize)> {
        let mut out: Vec<(String, usize)> = Vec::new();
        for j in &self.jobs {
            let key = if j.steady {
                crate::analysis::labels::label_key(&j.label, j.humps)
            } else {
                "not-steady".to_string()
            };
            match out.iter_mut().find(|(k, _)| *k == key) {
                Some(k) => k.1 += 1,
                None => out.push((key, 1)),
            }
        }
        out.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        out
    }

    /// Whether the cell pools jobs whose labels differ (seeds, or a parameter that is not an
    /// axis): its verdict then hides a disagreement and the cell is marked [`DISAGREE`].
    pub fn disagrees(&self) -> bool {
        self.job_labels().len() > 1
    }

    /// Text of the cell: `label[p]` (`label(humps)[p]`), `mixed[a/b]`, `not-steady`, with
    /// ` 3d` when most replicas vary along z, `!tc` when a collapse guard went beyond its validity, [`DISAGREE`] when its jobs' labels
    /// differ, and `[n not done]`.
    pub fn text(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        if let Some(v) = self.verdict() {
            let mut t = match v.label.as_str() {
                "not-steady" => v.label.clone(),
                "mixed" => format!(
                    "mixed[{}]",
                    v.probabilities
                        .iter()
                        .take(2)
                        .map(|(k, p)| format!("{k}:{p:.2}"))
                        .collect::<Vec<_>>()
                        .join("/")
                ),
                _ if v.probability.is_nan() => {
                    crate::analysis::labels::label_key(&v.label, v.humps)
                }
                _ => format!(
                    "{}[{:.2}]",
                    crate::analysis::labels::label_key(&v.label, v.humps),
                    v.probability
                ),
            };
            if v.three_dimensional {
                t.push_str(crate::analysis::labels::THREE_D_MARK);
            }
            if v.guard_flagged {
                t.push_str("!tc");
            }
            if self.disagrees() {
                t.push_str(DISAGREE);
            }
            parts.push(t);
        }
        if self.not_done > 0 {
            parts.push(format!("[{}-not-done]", self.not_done));
        }
        if parts.is_empty() {
            "-".into()
        } else {
            parts.join("+")
        }
    }
}

/// The mark of a cell (or curve point) whose jobs' labels differ, in the text tables and the
/// pictures.
pub const DISAGREE: &str = "\u{2260}";

/// A phase diagram over parameter `x` (and `y`, or a strip).
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseDiagram {
    pub x: String,
    pub y: Option<String>,
    pub xs: Vec<ParamValue>,
    pub ys: Vec<ParamValue>,
    /// cells by (x index, y index)
    pub cells: BTreeMap<(usize, usize), Cell>,
    /// axis labels: symbol, unit and key of each parameter ([`axis_label`])
    pub x_label: String,
    pub y_label: Option<String>,
    /// some points were added by refinement (`refine`): numeric axes are drawn to scale, each
    /// point in the cell of its share, with the estimated boundaries
    pub refined: bool,
    /// size, resolution and title of the picture
    pub frame: Frame,
}

/// How a diagram is framed: its size and resolution, and its title.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// size in CSS pixels (None: from the grid, the title and the legend) and PNG resolution
    pub size: Sizing,
    /// title lines, each wrapped to the width at ", " ([`title`])
    pub title: Vec<String>,
}

/// The swept parameters that vary independently of the shown `axes`: a parameter linked to a
/// shown axis (H/d following W/d) moves with it, so its jobs never share a cell.
pub fn varying_besides(sweep: &super::Sweep, axes: &[&str]) -> Vec<&'static str> {
    swept_in(sweep)
        .into_iter()
        .filter(|name| !axes.contains(name) && !follows_an_axis(sweep, name, axes))
        .collect()
}

/// True when `name` is linked to one of `axes` (`linked: [(param: name, follows: axis)]`).
fn follows_an_axis(sweep: &super::Sweep, name: &str, axes: &[&str]) -> bool {
    sweep
        .spec
        .linked
        .iter()
        .any(|l| l.param == name && axes.contains(&l.follows.as_str()))
}

/// Parameters that take more than one value over the jobs (the ones worth plotting). Derived
/// parameters (N and phi of EDMD) count only when the sweep itself varies them (not when they
/// follow from the box).
pub fn swept_in(sweep: &super::Sweep) -> Vec<&'static str> {
    let Some(engine) = super::spec::engine_of(&sweep.spec) else {
        return Vec::new();
    };
    let in_points = |name: &str| sweep.spec.points.iter().any(|p| p.0.contains_key(name));
    engine
        .params
        .iter()
        .filter(|d| {
            let derived = d.default == ParamDefault::Derived;
            (!derived || sweep.spec.axes.0.contains_key(d.name) || in_points(d.name))
                && distinct(sweep.plan.iter().map(|j| &j.params), d.name).len() > 1
        })
        .map(|d| d.name)
        .collect()
}

/// The axes of a diagram: `x` and `y` as asked, else the first two swept parameters (only `x`
/// asked: a strip), never `exclude` (the curve axis of a minimum diagram). An axis the sweep
/// does not vary is refused, as is a sweep that varies nothing when no `x` is asked.
pub fn choose_axes(
    sweep: &super::Sweep,
    x: Option<&str>,
    y: Option<&str>,
    exclude: Option<&str>,
) -> Result<(String, Option<String>), String> {
    let swept: Vec<&str> = swept_in(sweep)
        .into_iter()
        .filter(|s| Some(*s) != exclude)
        .collect();
    let y = match (x, y) {
        (_, Some(y)) => Some(y.to_string()),
        (Some(_), None) => None,
        (None, None) => swept.get(1).map(|s| s.to_string()),
    };
    let x = match x.or_else(|| swept.first().copied()) {
        Some(x) => x.to_string(),
        None => return Err("nothing is swept: give --x".into()),
    };
    for axis in std::iter::once(x.as_str()).chain(y.as_deref()) {
        if sweep.engine().param(axis).is_some() && !swept.contains(&axis) {
            return Err(format!(
                "`{axis}` does not vary in this sweep (one value for every job): a diagram over it \
                 would merge different points; swept: {}",
                if swept.is_empty() {
                    "nothing".to_string()
                } else {
                    swept.join(", ")
                }
            ));
        }
    }
    Ok((x, y))
}

/// A job's values of the given parameters, as "L/W=3 W/d=15" (symbols of the declaration).
pub fn point_text(engine: &EngineDef, params: &super::JobParams, names: &[&str]) -> String {
    names
        .iter()
        .filter_map(|n| {
            let symbol = engine.param(n).map_or(*n, |d| d.symbol);
            params
                .values
                .get(*n)
                .map(|v| format!("{symbol}={}", fmt_value(v)))
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Numbers before names; numbers by value, names alphabetically.
fn value_order(a: &ParamValue, b: &ParamValue) -> std::cmp::Ordering {
    match (a, b) {
        (ParamValue::Number(x), ParamValue::Number(y)) => x.total_cmp(y),
        (ParamValue::Number(_), ParamValue::Text(_)) => std::cmp::Ordering::Less,
        (ParamValue::Text(_), ParamValue::Number(_)) => std::cmp::Ordering::Greater,
        (ParamValue::Text(x), ParamValue::Text(y)) => x.cmp(y),
    }
}

fn distinct<'a>(jobs: impl Iterator<Item = &'a super::JobParams>, name: &str) -> Vec<ParamValue> {
    let mut vals: Vec<ParamValue> = jobs.filter_map(|p| p.values.get(name).cloned()).collect();
    vals.sort_by(value_order);
    vals.dedup();
    vals
}

/// A done job as a cell sees it.
fn cell_job(analysis: &crate::analysis::Analysis) -> CellJob {
    let (label, humps) = analysis.label();
    CellJob::from_summary(label, humps, &analysis.summary())
}

impl CellJob {
    /// A done job's entry from its label, humps and summary (the jobs table's row).
    pub fn from_summary(
        label: &str,
        humps: u32,
        summary: &serde_json::Map<String, serde_json::Value>,
    ) -> CellJob {
        let text = |k: &str| summary.get(k).and_then(|v| v.as_str()).unwrap_or("");
        let number = |k: &str| summary.get(k).and_then(|v| v.as_f64());
        CellJob {
            label: label.to_string(),
            humps,
            probabilities: parse_probabilities(text("label_probabilities")),
            weight: number("steady_snapshots").unwrap_or(1.0),
            steady: summary
                .get("steady")
                .and_then(|v| v.as_bool())
                .unwrap_or(label != "not-steady"),
            guard_valid: summary
                .get("collapse_guard_valid")
                .and_then(|v| v.as_bool())
                .unwrap_or(true),
            three_dimensional: summary
                .get("three_dimensional")
                .and_then(|v| v.as_bool())
                .unwrap_or(false),
        }
    }
}

impl PhaseDiagram {
    /// Place the jobs. `x` and `y` must be parameters of the engine of the jobs.
    pub fn build(
        engine: &EngineDef,
        jobs: &[GatheredJob],
        x: &str,
        y: Option<&str>,
    ) -> Result<Self, String> {
        for name in std::iter::once(x).chain(y) {
            if engine.param(name).is_none() {
                return Err(format!(
                    "`{name}` is not a parameter of the {} engine; allowed: {}",
                    engine.name,
                    engine.param_names()
                ));
            }
        }
        let params = || jobs.iter().map(|j| &j.job.params);
        let xs = distinct(params(), x);
        let ys = match y {
            Some(y) => distinct(params(), y),
            None => vec![ParamValue::Number(0.0)],
        };
        let mut cells: BTreeMap<(usize, usize), Cell> = BTreeMap::new();
        let index = |axis: &[ParamValue], j: &GatheredJob, name: &str| {
            j.job
                .params
                .values
                .get(name)
                .and_then(|v| axis.iter().position(|a| a == v))
                .unwrap_or(0)
        };
        for j in jobs {
            let xi = index(&xs, j, x);
            let yi = y.map_or(0, |y| index(&ys, j, y));
            let cell = cells.entry((xi, yi)).or_default();
            match &j.result {
                Some(r) => cell.jobs.push(cell_job(&r.analysis)),
                None => cell.not_done += 1,
            }
        }
        Ok(PhaseDiagram {
            x: x.into(),
            y: y.map(str::to_string),
            xs,
            ys,
            cells,
            x_label: axis_label(engine, x),
            y_label: y.map(|y| axis_label(engine, y)),
            refined: jobs.iter().any(|j| j.job.level > 0),
            frame: Frame::default(),
        })
    }

    /// The boundaries a refined diagram estimates along x: in each row (y index), between
    /// neighbouring done points whose labels differ, the midpoint of their x values and half
    /// their distance (the uncertainty: half the last bisection interval). Empty for an axis
    /// that is not numeric.
    pub fn boundaries(&self) -> Vec<(usize, f64, f64)> {
        let Some(xs) = numbers(&self.xs) else {
            return Vec::new();
        };
        let mut order: Vec<usize> = (0..xs.len()).collect();
        order.sort_by(|&a, &b| xs[a].total_cmp(&xs[b]));
        let mut out = Vec::new();
        for yi in 0..self.ys.len().max(1) {
            let done: Vec<(f64, String)> = order
                .iter()
                .filter_map(|&xi| {
                    let v = self.cells.get(&(xi, yi))?.verdict()?;
                    Some((xs[xi], v.label))
                })
                .collect();
            for w in done.windows(2) {
                if w[0].1 != w[1].1 {
                    out.push((yi, 0.5 * (w[0].0 + w[1].0), 0.5 * (w[1].0 - w[0].0)));
                }
            }
        }
        out
    }

    /// The grid as a text table: rows y (largest on top), columns x.
    pub fn table(&self) -> String {
        let mut rows: Vec<Vec<String>> = Vec::new();
        let corner = match &self.y {
            Some(y) => format!("{y} \\ {}", self.x),
            None => self.x.clone(),
        };
        rows.push(
            std::iter::once(corner)
                .chain(self.xs.iter().map(fmt_value))
                .collect(),
        );
        for yi in (0..self.ys.len()).rev() {
            let head = match &self.y {
                Some(_) => fmt_value(&self.ys[yi]),
                None => "structure".into(),
            };
            let mut row = vec![head];
            for xi in 0..self.xs.len() {
                row.push(self.cells.get(&(xi, yi)).map_or("-".into(), Cell::text));
            }
            rows.push(row);
        }
        let widths: Vec<usize> = (0..rows[0].len())
            .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
            .collect();
        let mut out = String::new();
        for (i, row) in rows.iter().enumerate() {
            let line: Vec<String> = row
                .iter()
                .zip(&widths)
                .map(|(t, w)| format!("{t:>w$}"))
                .collect();
            out.push_str(line.join("  ").trim_end());
            out.push('\n');
            if i == 0 {
                out.push_str(&"-".repeat(widths.iter().sum::<usize>() + 2 * (widths.len() - 1)));
                out.push('\n');
            }
        }
        out.push_str(&self.disagreements());
        out
    }

    /// The legend of the [`DISAGREE`] mark under the text table: per marked cell, its point
    /// and the labels its jobs gave (empty when no cell is marked).
    pub fn disagreements(&self) -> String {
        let marked: Vec<(&(usize, usize), &Cell)> =
            self.cells.iter().filter(|(_, c)| c.disagrees()).collect();
        if marked.is_empty() {
            return String::new();
        }
        let mut out = format!(
            "{DISAGREE} the cell pools jobs whose labels differ (seeds, or parameters that are not \
             axes); its label is the pooled verdict:\n"
        );
        for ((xi, yi), cell) in marked {
            let mut at = format!("{} = {}", self.x, fmt_value(&self.xs[*xi]));
            if let Some(y) = &self.y {
                at.push_str(&format!(", {y} = {}", fmt_value(&self.ys[*yi])));
            }
            let labels: Vec<String> = cell
                .job_labels()
                .iter()
                .map(|(l, n)| format!("{l} ({n} {})", if *n == 1 { "job" } else { "jobs" }))
                .collect();
            out.push_str(&format!("  {at}: {}\n", labels.join(", ")));
        }
        out
    }

    /// Write the diagram as SVG (at its size in CSS pixels; vector, so the resolution does
    /// not apply).
    pub fn write_svg(&self, path: &Path) -> anyhow::Result<()> {
        crate::figure::save_svg(path, self.size(), |root, s| self.draw(root, s))
    }

    /// Write the diagram as PNG (RGB, 8 bit) at the frame's resolution.
    pub fn write_png(&self, path: &Path) -> anyhow::Result<()> {
        let bytes = self
            .png()
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        crate::sweep::write_atomic(path, &bytes)?;
        Ok(())
    }

    /// The diagram as PNG bytes at the frame's resolution.
    pub fn png(&self) -> anyhow::Result<Vec<u8>> {
        crate::figure::render_png(self.size(), self.frame.size.scale(), |root, s| {
            self.draw(root, s)
        })
    }

    /// The picture's size in CSS pixels: the frame's, or from the grid, the title and the
    /// legend.
    pub fn size(&self) -> (u32, u32) {
        // a refined axis is drawn to scale: its width does not grow with its points
        let columns = if self.refined {
            self.xs.len().min(10)
        } else {
            self.xs.len()
        };
        let w =
            self.frame.size.width.unwrap_or_else(|| {
                (LEFT + LEGEND_WIDTH + 20 + 110 * columns as i32).max(700) as u32
            });
        let h = self.frame.size.height.unwrap_or_else(|| {
            let legend = 24 * self.legend().len() as i32 + 20;
            let plot = (90 * self.ys.len() as i32).max(legend).max(160);
            (self.top(w) + plot + BOTTOM) as u32
        });
        (w, h)
    }

    /// The title as a heading.
    fn heading(&self) -> Heading {
        Heading {
            lines: self.frame.title.clone(),
        }
    }

    /// Height above the plot (the title and a gap), in CSS pixels.
    fn top(&self, width: u32) -> i32 {
        self.heading().height(width) as i32 + 14
    }

    /// What the legend explains, in order: each marker shown, then the numbers and marks
    /// drawn beside them.
    fn legend(&self) -> Vec<Legend> {
        let verdicts: Vec<Option<CellVerdict>> = self.cells.values().map(Cell::verdict).collect();
        let mut labels: Vec<String> = verdicts.iter().flatten().map(|v| v.label.clone()).collect();
        labels.sort();
        labels.dedup();
        let mut out: Vec<Legend> = labels.into_iter().map(Legend::Marker).collect();
        if verdicts.iter().flatten().any(|v| v.humps > 0) {
            out.push(Legend::Humps);
        }
        if verdicts.iter().flatten().any(|v| v.three_dimensional) {
            out.push(Legend::ThreeD);
        }
        if verdicts
            .iter()
            .flatten()
            .any(|v| v.probability.is_finite() && v.label != "mixed")
        {
            out.push(Legend::Probability);
        }
        if verdicts.iter().any(Option::is_none) {
            out.push(Legend::NotDone);
        }
        if verdicts.iter().flatten().any(|v| v.guard_flagged) {
            out.push(Legend::Guard);
        }
        if self.cells.values().any(Cell::disagrees) {
            out.push(Legend::Disagree);
        }
        out
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        s: Scale,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let f = self.layout(s);
        self.heading().draw(root, f.w, s)?;
        root.draw(&Rectangle::new(
            [
                (s.px(LEFT), s.px(f.top)),
                (s.px(LEFT + f.plot_w), s.px(f.top + f.plot_h)),
            ],
            BLACK.stroke_width(s.line(1.0)),
        ))?;
        self.draw_shares(root, &f)?;
        self.draw_boundaries(root, &f)?;
        self.draw_x_axis(root, &f)?;
        self.draw_y_axis(root, &f)?;
        self.draw_cells(root, &f)?;
        self.draw_legend(root, &f)
    }

    /// The layout in CSS pixels: the plot's place and the axes (to scale in a refined diagram,
    /// 40 px in from each end; one column or row per value otherwise).
    fn layout(&self, s: Scale) -> Layout {
        let (w, h) = self.size();
        let top = self.top(w);
        let plot_w = (w as i32 - LEFT - LEGEND_WIDTH).max(40);
        let plot_h = (h as i32 - top - BOTTOM).max(40);
        let scaled = |vals: &[ParamValue], len: i32| {
            numbers(vals)
                .filter(|_| self.refined && vals.len() > 1)
                .map(|v| Scaled::new(v, len))
        };
        Layout {
            s,
            w,
            top,
            plot_w,
            plot_h,
            nx: self.xs.len().max(1) as i32,
            ny: self.ys.len().max(1) as i32,
            sx: scaled(&self.xs, plot_w),
            sy: self.y_label.as_ref().and(scaled(&self.ys, plot_h)),
        }
    }

    /// Each point's share in a refined diagram: the cell between the midpoints to its neighbours.
    fn draw_shares<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let light = RGBColor(215, 215, 215).stroke_width(f.s.line(1.0));
        if let Some(a) = &f.sx {
            for m in a.midpoints() {
                let x = f.u(LEFT + m);
                root.draw(&PathElement::new(
                    vec![(x, f.u(f.top)), (x, f.u(f.bottom()))],
                    light,
                ))?;
            }
        }
        if let Some(a) = &f.sy {
            for m in a.midpoints() {
                let y = f.u(f.bottom() - m);
                root.draw(&PathElement::new(
                    vec![(f.u(LEFT), y), (f.u(LEFT + f.plot_w), y)],
                    light,
                ))?;
            }
        }
        Ok(())
    }

    /// The estimated boundaries with their uncertainty (a band of +- half the last interval).
    fn draw_boundaries<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let Some(a) = &f.sx else { return Ok(()) };
        let band = RGBColor(31, 119, 180);
        for (yi, x, half) in self.boundaries() {
            // the row's share: to scale, or one row of an unscaled y axis
            let (y0, y1) = match &f.sy {
                Some(b) => b.share(yi),
                None => (
                    (2 * yi as i32) * f.plot_h / (2 * f.ny),
                    (2 * yi as i32 + 2) * f.plot_h / (2 * f.ny),
                ),
            };
            let (top, bottom) = (f.u(f.bottom() - y1), f.u(f.bottom() - y0));
            let (x0, x1) = (a.to(x - half), a.to(x + half));
            root.draw(&Rectangle::new(
                [(f.u(LEFT + x0), top), (f.u(LEFT + x1), bottom)],
                band.mix(0.15).filled(),
            ))?;
            let xm = f.u(LEFT + a.to(x));
            root.draw(&PathElement::new(
                vec![(xm, top), (xm, bottom)],
                band.stroke_width(f.s.line(2.0)),
            ))?;
        }
        Ok(())
    }

    /// Ticks, values and the name of the x axis.
    fn draw_x_axis<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let bottom = f.bottom();
        let mut last_label: Option<i32> = None;
        // left to right, so that the spacing rule below compares neighbours on the axis
        let mut ticks: Vec<(i32, &ParamValue)> = self
            .xs
            .iter()
            .enumerate()
            .map(|(xi, v)| (f.px(xi), v))
            .collect();
        ticks.sort_by_key(|&(at, _)| at);
        for (at, v) in ticks {
            root.draw(&PathElement::new(
                vec![(f.u(at), f.u(bottom)), (f.u(at), f.u(bottom + 5))],
                f.black(),
            ))?;
            // refined points crowd the axis: a value at least 60 px from the last one shown
            if f.sx.is_some() {
                if last_label.is_some_and(|last| at - last < 60) {
                    continue;
                }
                last_label = Some(at);
            }
            root.draw(&Text::new(
                fmt_value(v),
                (f.u(at), f.u(bottom + 9)),
                f.centred(13.0, VPos::Top),
            ))?;
        }
        root.draw(&Text::new(
            self.x_label.clone(),
            (f.u(LEFT + f.plot_w / 2), f.u(bottom + 34)),
            f.centred(15.0, VPos::Top),
        ))?;
        Ok(())
    }

    /// Ticks, values and the name of the y axis, if there is one.
    fn draw_y_axis<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let Some(y_label) = &self.y_label else {
            return Ok(());
        };
        for (yi, v) in self.ys.iter().enumerate() {
            let at = f.u(f.py(yi));
            root.draw(&PathElement::new(
                vec![(f.u(LEFT - 5), at), (f.u(LEFT), at)],
                f.black(),
            ))?;
            root.draw(&Text::new(
                fmt_value(v),
                (f.u(LEFT - 8), at),
                TextStyle::from(f.s.font(13.0)).pos(Pos::new(HPos::Right, VPos::Center)),
            ))?;
        }
        root.draw(&Text::new(
            y_label.clone(),
            (f.u(12), f.u(f.top + f.plot_h / 2)),
            TextStyle::from(f.s.font(15.0).transform(FontTransform::Rotate270))
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
        Ok(())
    }

    /// One marker per point with its humps, 3D mark, probability and flags; a grey dot where no job is done.
    fn draw_cells<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let u = |v: i32| f.u(v);
        for (&(xi, yi), cell) in &self.cells {
            let (x, y) = (u(f.px(xi)), u(f.py(yi)));
            let Some(v) = cell.verdict() else {
                root.draw(&Circle::new((x, y), u(4), GREY_DOT.filled()))?;
                continue;
            };
            draw_marker(root, &v.label, (x, y), u(11))?;
            if v.humps > 0 {
                root.draw(&Text::new(
                    format!("{}", v.humps),
                    (x + u(14), y - u(20)),
                    f.s.font(15.0),
                ))?;
            }
            if v.three_dimensional {
                root.draw(&Text::new(
                    THREE_D_TEXT,
                    (x + u(13), y + u(2)),
                    f.s.font(12.0),
                ))?;
            }
            if v.probability.is_finite() && v.label != "mixed" {
                root.draw(&Text::new(
                    format!("{:.2}", v.probability),
                    (x, y + u(15)),
                    f.centred(13.0, VPos::Top),
                ))?;
            }
            if v.guard_flagged {
                root.draw(&Circle::new((x, y), u(16), f.red()))?;
            }
            if cell.disagrees() {
                // left of the marker, where neither humps nor probability go
                root.draw(&Text::new(
                    DISAGREE,
                    (x - u(16), y),
                    TextStyle::from(f.s.font(DISAGREE_SIZE))
                        .pos(Pos::new(HPos::Right, VPos::Center)),
                ))?;
            }
        }
        Ok(())
    }

    /// The legend: one line per marker and mark the diagram uses.
    fn draw_legend<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        f: &Layout,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let lx = LEFT + f.plot_w + 20;
        for (i, entry) in self.legend().iter().enumerate() {
            let ly = f.top + 12 + 24 * i as i32;
            let at = (f.u(lx + 8), f.u(ly));
            let text = match entry {
                Legend::Marker(label) => {
                    draw_marker(root, label, at, f.u(8))?;
                    label.clone()
                }
                Legend::Humps => {
                    root.draw(&Text::new("2", at, f.centred(15.0, VPos::Center)))?;
                    "humps of the S-wave".into()
                }
                Legend::ThreeD => {
                    root.draw(&Text::new(THREE_D_TEXT, at, f.centred(12.0, VPos::Center)))?;
                    "varies along z (3D)".into()
                }
                Legend::Probability => {
                    root.draw(&Text::new("0.9", at, f.centred(12.0, VPos::Center)))?;
                    "share of snapshots with the label".into()
                }
                Legend::NotDone => {
                    root.draw(&Circle::new(at, f.u(4), GREY_DOT.filled()))?;
                    "no job done yet".into()
                }
                Legend::Guard => {
                    root.draw(&Circle::new(at, f.u(9), f.red()))?;
                    "collapse guard beyond validity".into()
                }
                Legend::Disagree => {
                    root.draw(&Text::new(
                        DISAGREE,
                        at,
                        f.centred(DISAGREE_SIZE, VPos::Center),
                    ))?;
                    DISAGREE_LEGEND.into()
                }
            };
            root.draw(&Text::new(
                text,
                (f.u(lx + 24), f.u(ly)),
                TextStyle::from(f.s.font(12.0)).pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}

/// The values of an axis if all are numbers.
fn numbers(vals: &[ParamValue]) -> Option<Vec<f64>> {
    vals.iter().map(ParamValue::as_f64).collect()
}

/// Where a phase diagram draws, in CSS pixels: the plot's place and its axes.
struct Layout {
    s: Scale,
    w: u32,
    top: i32,
    plot_w: i32,
    plot_h: i32,
    /// columns and rows of an unscaled diagram
    nx: i32,
    ny: i32,
    /// the axes drawn to scale (a refined diagram's numeric axes)
    sx: Option<Scaled>,
    sy: Option<Scaled>,
}

impl Layout {
    /// CSS pixels to the picture's pixels.
    fn u(&self, css: i32) -> i32 {
        self.s.px(css)
    }

    /// The plot's lower edge, in CSS pixels.
    fn bottom(&self) -> i32 {
        self.top + self.plot_h
    }

    /// Text of `size` centred horizontally, placed vertically by `v`.
    fn centred(&self, size: f64, v: VPos) -> TextStyle<'static> {
        TextStyle::from(self.s.font(size)).pos(Pos::new(HPos::Center, v))
    }

    /// The axes' ticks: black, one CSS pixel wide.
    fn black(&self) -> ShapeStyle {
        BLACK.stroke_width(self.s.line(1.0))
    }

    /// The collapse guard's ring: red, two CSS pixels wide.
    fn red(&self) -> ShapeStyle {
        RGBColor(214, 39, 40).stroke_width(self.s.line(2.0))
    }

    /// The x pixel of the `xi`-th value.
    fn px(&self, xi: usize) -> i32 {
        match &self.sx {
            Some(a) => LEFT + a.at(xi),
            None => LEFT + (2 * xi as i32 + 1) * self.plot_w / (2 * self.nx),
        }
    }

    /// The y pixel of the `yi`-th value.
    fn py(&self, yi: usize) -> i32 {
        match &self.sy {
            Some(a) => self.top + self.plot_h - a.at(yi),
            None => self.top + self.plot_h - (2 * yi as i32 + 1) * self.plot_h / (2 * self.ny),
        }
    }
}

/// A numeric axis drawn to scale over `len` pixels, 40 px in from each end.
struct Scaled {
    values: Vec<f64>,
    lo: f64,
    hi: f64,
    len: i32,
}

impl Scaled {
    const PAD: i32 = 40;

    fn new(values: Vec<f64>, len: i32) -> Self {
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Scaled {
            values,
            lo,
            hi,
            len,
        }
    }

    /// Pixels from the axis' start to value `v`.
    fn to(&self, v: f64) -> i32 {
        let span = (self.hi - self.lo).max(f64::MIN_POSITIVE);
        Self::PAD + ((v - self.lo) / span * f64::from(self.len - 2 * Self::PAD)).round() as i32
    }

    /// Pixels to the `i`-th value.
    fn at(&self, i: usize) -> i32 {
        self.to(self.values[i])
    }

    /// Pixels to the midpoints between neighbouring values (the cells' edges).
    fn midpoints(&self) -> Vec<i32> {
        let mut v = self.values.clone();
        v.sort_by(f64::total_cmp);
        v.windows(2).map(|w| self.to(0.5 * (w[0] + w[1]))).collect()
    }

    /// The pixel range of the `i`-th value's cell (to the midpoints, or the ends).
    fn share(&self, i: usize) -> (i32, i32) {
        let x = self.values[i];
        let below = self
            .values
            .iter()
            .copied()
            .filter(|&v| v < x)
            .fold(f64::NAN, f64::max);
        let above = self
            .values
            .iter()
            .copied()
            .filter(|&v| v > x)
            .fold(f64::NAN, f64::min);
        let lo = if below.is_nan() {
            0
        } else {
            self.to(0.5 * (below + x))
        };
        let hi = if above.is_nan() {
            self.len
        } else {
            self.to(0.5 * (above + x))
        };
        (lo, hi)
    }
}

/// Layout of a diagram in CSS pixels: room left of the plot (y ticks and label), below it (x
/// ticks and label), and for the legend right of it.
const LEFT: i32 = 110;
const BOTTOM: i32 = 70;
const LEGEND_WIDTH: i32 = 290;
/// Font size of the [`DISAGREE`] mark, CSS pixels.
const DISAGREE_SIZE: f64 = 20.0;
/// The legend line of the [`DISAGREE`] mark.
pub const DISAGREE_LEGEND: &str = "jobs in the cell disagree (labels differ)";
/// The mark beside a marker whose structure varies along z.
const THREE_D_TEXT: &str = "3D";
/// The dot of a cell without a done job.
const GREY_DOT: RGBColor = RGBColor(180, 180, 180);

/// One entry of a diagram's legend.
#[derive(Clone, Debug, PartialEq)]
enum Legend {
    /// the marker of this label
    Marker(String),
    /// the number beside S-wave markers
    Humps,
    /// the "3D" beside markers of structures that vary along z
    ThreeD,
    /// the number under a marker
    Probability,
    /// the grey dot of a cell without a done job
    NotDone,
    /// the red ring of a flagged collapse guard
    Guard,
    /// the mark of a cell whose jobs' labels differ
    Disagree,
}

/// The axis label of a parameter: its symbol, unit (when it has one) and key, e.g.
/// "L/W (length_over_width)", "t_c [sqrt(d/g)] (tc)".
pub fn axis_label(engine: &EngineDef, name: &str) -> String {
    match engine.param(name) {
        Some(d) if has_symbol(d.symbol) => match d.unit {
            "1" | "-" | "" => format!("{} ({name})", d.symbol),
            unit => format!("{} [{unit}] ({name})", d.symbol),
        },
        _ => name.to_string(),
    }
}

/// A parameter's symbol (e.g. "e_n"), or its key when it has none.
pub fn symbol_of(engine: &EngineDef, name: &str) -> String {
    match engine.param(name) {
        Some(d) if has_symbol(d.symbol) => d.symbol.to_string(),
        _ => name.to_string(),
    }
}

/// Declarations write "-" (or nothing) for a parameter without a symbol.
fn has_symbol(symbol: &str) -> bool {
    symbol != "-" && !symbol.is_empty()
}

impl PlannedJob {
    /// The heading of a job's figures: its engine, seed and id; its parameters by symbol (those
    /// its sweep varies, those the engine requires or derives, and those away from their
    /// defaults); then those at their defaults, named as such (a swept parameter whose value is
    /// its default is not: it was chosen).
    pub fn heading(&self) -> Heading {
        let job = self;
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
}

/// A parameter value in a heading: as given, or to 4 significant digits when that is long
/// (a derived value such as phi from N).
fn heading_value(v: &ParamValue) -> String {
    let text = fmt_value(v);
    match v {
        ParamValue::Number(x) if text.len() > 8 => ticks::short(*x),
        _ => text,
    }
}

/// The title of a diagram of `sweep` over `axes`: the sweep, its engine, jobs and run length;
/// the parameters held fixed (given in the sweep, linked, or away from their defaults), and
/// those that vary without being an axis (their jobs share cells).
pub fn title(sweep: &super::Sweep, axes: &[&str]) -> Vec<String> {
    let Some(engine) = super::spec::engine_of(&sweep.spec) else {
        return Vec::new();
    };
    let run = &sweep.spec.run;
    let seeds = &sweep.spec.seeds;
    let mut first = format!(
        "{} ({}): {} jobs, {} {} per job, a snapshot every {}",
        sweep.name,
        engine.name,
        sweep.plan.len(),
        run.length(),
        run.clock().key().replace('_', " "),
        run.snapshot_interval
    );
    if let Some(u) = &run.until_steady {
        first.push_str(&format!(", until steady over {}", u.window));
    }
    if seeds.len() > 1 {
        first.push_str(&format!(
            ", seeds {}",
            seeds
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(" ")
        ));
    }
    let mut fixed: Vec<String> = Vec::new();
    let mut varying: Vec<&str> = Vec::new();
    let linked = |name: &str| sweep.spec.linked.iter().any(|l| l.param == name);
    for d in engine.params {
        if axes.contains(&d.name) {
            continue;
        }
        if d.default == ParamDefault::Derived && !sweep.spec.axes.0.contains_key(d.name) {
            // derived from others (EDMD: phi from N and the box): as given, if given
            if let Some(v) = sweep.spec.fixed.0.get(d.name) {
                fixed.push(format!("{} = {}", d.symbol, fmt_value(v)));
            }
            continue;
        }
        let values = distinct(sweep.plan.iter().map(|j| &j.params), d.name);
        match values.as_slice() {
            [v] => {
                let given = sweep.spec.fixed.0.contains_key(d.name)
                    || linked(d.name)
                    || d.default == ParamDefault::Required;
                let away = d.default.value().is_some_and(|dv| dv != *v);
                if given || away {
                    fixed.push(format!("{} = {}", d.symbol, fmt_value(v)));
                }
            }
            [] => {}
            _ if follows_an_axis(sweep, d.name, axes) => {
                let link = sweep.spec.linked.iter().find(|l| l.param == d.name);
                if let Some(l) = link {
                    let of = symbol_of(engine, &l.follows);
                    fixed.push(if l.factor == 1.0 {
                        format!("{} = {of}", d.symbol)
                    } else {
                        format!("{} = {} {of}", d.symbol, l.factor)
                    });
                }
            }
            _ => varying.push(d.symbol),
        }
    }
    let mut lines = vec![first];
    if !fixed.is_empty() {
        lines.push(format!("fixed: {}", fixed.join(", ")));
    }
    if !varying.is_empty() {
        lines.push(format!(
            "also varying (merged in the cells): {}",
            varying.join(", ")
        ));
    }
    lines
}

/// The marker of a structure label (shape and colour), thesis-like, of radius `r` pixels.
pub(crate) fn draw_marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    label: &str,
    (x, y): (i32, i32),
    r: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let c = marker_colour(label);
    // line width of open markers: 2 px at the diagram's radius of 11
    let line = |k: f64| ((r as f64 * k / 5.5).round() as u32).max(1);
    match label {
        "homogeneous" | "no waves" => root.draw(&Circle::new((x, y), r, c.stroke_width(line(1.0)))),
        "plug" | "density waves" => root.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            c.filled(),
        )),
        "s-wave" => root.draw(&Polygon::new(
            vec![(x, y - r - 2), (x - r - 1, y + r), (x + r + 1, y + r)],
            c.filled(),
        )),
        "slug" | "steady" => root.draw(&Circle::new((x, y), r, c.filled())),
        "wavy-slug" => root.draw(&Polygon::new(
            vec![
                (x, y - r - 2),
                (x + r + 2, y),
                (x, y + r + 2),
                (x - r - 2, y),
            ],
            c.filled(),
        )),
        "s-wave+slug" => {
            root.draw(&Circle::new((x, y), r, c.filled()))?;
            root.draw(&Polygon::new(
                vec![
                    (x, y - r / 2 - 2),
                    (x - r / 2 - 1, y + r / 2),
                    (x + r / 2 + 1, y + r / 2),
                ],
                marker_colour("s-wave").filled(),
            ))
        }
        "not-steady" => root.draw(&Cross::new((x, y), r, c.stroke_width(line(1.0)))),
        "mixed" => root.draw(&Circle::new((x, y), r, c.stroke_width(line(1.5)))),
        // DSMC minimum diagram: where a curve has an interior minimum, or none
        "minimum" => root.draw(&Polygon::new(
            vec![(x - r - 1, y - r), (x + r + 1, y - r), (x, y + r + 2)],
            c.filled(),
        )),
        "maximum" => root.draw(&Polygon::new(
            vec![(x, y - r - 2), (x - r - 1, y + r), (x + r + 1, y + r)],
            c.filled(),
        )),
        "monotonic" => root.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            c.stroke_width(line(1.0)),
        )),
        _ => root.draw(&Circle::new((x, y), r, c.stroke_width(line(1.0)))),
    }
}

/// A parameter value as written in tables and plots (numbers in shortest round-trip form,
/// names as they are).
pub fn fmt_value(v: &ParamValue) -> String {
    match v {
        ParamValue::Number(x) => format!("{x}"),
        ParamValue::Text(s) => s.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(probabilities: &str, weight: f64, steady: bool, guard_valid: bool) -> CellJob {
        let probabilities = parse_probabilities(probabilities);
        let (label, humps) = split_key(&probabilities[0].0);
        CellJob {
            label,
            humps,
            probabilities,
            weight,
            steady,
            guard_valid,
            three_dimensional: false,
        }
    }

    #[test]
    fn a_refined_diagram_places_boundaries_between_differing_neighbours() {
        // L/W 1, 2 (base) and 1.5, 1.25 (refined), in no order; plug below 1.5, slug from it;
        // the point at 3 is not done and does not count
        let xs: Vec<ParamValue> = [2.0, 1.0, 1.5, 1.25, 3.0]
            .into_iter()
            .map(ParamValue::Number)
            .collect();
        let labels = ["slug 1.00", "plug 1.00", "slug 1.00", "plug 1.00"];
        let mut cells: BTreeMap<(usize, usize), Cell> = labels
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let cell = Cell {
                    jobs: vec![job(l, 1.0, true, true)],
                    not_done: 0,
                };
                ((i, 0), cell)
            })
            .collect();
        cells.insert(
            (4, 0),
            Cell {
                jobs: Vec::new(),
                not_done: 1,
            },
        );
        let diagram = PhaseDiagram {
            x: "length_over_width".into(),
            y: None,
            xs,
            ys: vec![ParamValue::Number(0.0)],
            cells,
            x_label: "L/W".into(),
            y_label: None,
            refined: true,
            frame: Frame::default(),
        };
        assert_eq!(diagram.boundaries(), vec![(0, 1.375, 0.125)]);
        // drawn to scale: 1.25 sits a quarter of the way from 1 to 2
        let a = Scaled::new(vec![1.0, 2.0, 1.25, 3.0], 440);
        assert_eq!((a.at(0), a.at(2), a.at(1), a.at(3)), (40, 85, 220, 400));
        assert_eq!(a.share(2), (63, 153));
        diagram.png().expect("a refined diagram draws");
        // the x axis names its values, those closer than 60 px to the last one shown left out
        let svg = std::env::temp_dir().join(format!("phase-refined-{}.svg", std::process::id()));
        diagram.write_svg(&svg).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        let _ = std::fs::remove_file(&svg);
        let texts: Vec<&str> = text
            .split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .map(str::trim)
            .collect();
        for value in ["1", "1.5", "2", "3"] {
            assert!(
                texts.contains(&value),
                "x value {value} not drawn: {texts:?}"
            );
        }
    }

    #[test]
    fn replicas_merge_into_one_probability_table() {
        let agree = Cell {
            jobs: vec![
                job("slug 1.00", 10.0, true, true),
                job("slug 0.70; s-wave+slug(1) 0.30", 10.0, true, true),
            ],
            not_done: 0,
        };
        let v = agree.verdict().unwrap();
        assert_eq!((v.label.as_str(), v.humps), ("slug", 0));
        assert!((v.probability - 0.85).abs() < 1e-12);
        assert_eq!(agree.text(), "slug[0.85]");

        // 0.6 / 0.4 after weighting: no clear majority
        let split = Cell {
            jobs: vec![
                job("slug 0.80; wavy-slug 0.20", 10.0, true, true),
                job("wavy-slug 0.60; slug 0.40", 10.0, true, true),
            ],
            not_done: 1,
        };
        let v = split.verdict().unwrap();
        assert_eq!(v.label, "mixed");
        // the two replicas gave different labels: marked
        assert_eq!(
            split.text(),
            format!("mixed[slug:0.60/wavy-slug:0.40]{DISAGREE}+[1-not-done]")
        );

        // weights: a long window counts more; a not-steady replica does not count, a flagged
        // collapse guard is shown
        let weighted = Cell {
            jobs: vec![
                job("s-wave(2) 1.00", 30.0, true, false),
                job("plug 1.00", 10.0, true, true),
                job("slug 1.00", 50.0, false, true),
            ],
            not_done: 0,
        };
        let v = weighted.verdict().unwrap();
        assert_eq!((v.label.as_str(), v.humps), ("s-wave", 2));
        assert!((v.probability - 0.75).abs() < 1e-12);
        assert!(v.guard_flagged);
        assert_eq!(weighted.text(), format!("s-wave(2)[0.75]!tc{DISAGREE}"));
        assert_eq!(
            weighted.job_labels(),
            [("not-steady", 1), ("plug", 1), ("s-wave(2)", 1)].map(|(l, n)| (l.to_string(), n))
        );

        let unsteady = Cell {
            jobs: vec![job("slug 1.00", 10.0, false, true)],
            not_done: 0,
        };
        assert_eq!(unsteady.text(), "not-steady");
    }
}
