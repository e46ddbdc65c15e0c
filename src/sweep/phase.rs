//! Phase diagrams: the structure label of every done job placed on a grid of two swept
//! parameters (or a strip for one), printed as a table and drawn as PNG and SVG (plotters):
//! one marker per structure, hump counts written beside S-wave markers (as thesis Fig. 5.25).

use super::tables::GatheredJob;
use crate::engine::declare::ParamDefault;
use crate::engine::{EngineDef, ParamValue};
use plotters::coord::Shift;
use plotters::prelude::*;
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
        Some(CellVerdict {
            label,
            humps,
            probability: p,
            probabilities: merged,
            guard_flagged,
        })
    }

    /// Text of the cell: `label[p]` (`label(humps)[p]`), `mixed[a/b]`, `not-steady`, with
    /// `!tc` when a collapse guard went beyond its validity, and `[n not done]`.
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
            if v.guard_flagged {
                t.push_str("!tc");
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

/// A phase diagram over parameter `x` (and `y`, or a strip).
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseDiagram {
    pub x: String,
    pub y: Option<String>,
    pub xs: Vec<ParamValue>,
    pub ys: Vec<ParamValue>,
    /// cells by (x index, y index)
    pub cells: BTreeMap<(usize, usize), Cell>,
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
    let summary = analysis.summary();
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
        })
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
        out
    }

    /// Write the diagram as SVG.
    pub fn write_svg(&self, path: &Path) -> anyhow::Result<()> {
        crate::figure::save_svg(path, self.size(), |root| self.draw(root))
    }

    /// Write the diagram as PNG (RGB, 8 bit).
    pub fn write_png(&self, path: &Path) -> anyhow::Result<()> {
        crate::figure::save_png(path, self.size(), |root| self.draw(root))
    }

    fn size(&self) -> (u32, u32) {
        let w = 260 + 110 * self.xs.len() as u32;
        let h = 170 + 90 * self.ys.len() as u32;
        (w.max(560), h.max(300))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (w, h) = root.dim_in_pixel();
        let (left, right, top, bottom) = (100i32, 170i32, 30i32, 70i32);
        let plot_w = w as i32 - left - right;
        let plot_h = h as i32 - top - bottom;
        let nx = self.xs.len().max(1) as i32;
        let ny = self.ys.len().max(1) as i32;
        let px = |xi: usize| left + (2 * xi as i32 + 1) * plot_w / (2 * nx);
        let py = |yi: usize| top + plot_h - (2 * yi as i32 + 1) * plot_h / (2 * ny);
        let font = ("sans-serif", 15).into_font();
        let small = ("sans-serif", 13).into_font();
        root.draw(&Rectangle::new(
            [(left, top), (left + plot_w, top + plot_h)],
            BLACK.stroke_width(1),
        ))?;
        for (xi, v) in self.xs.iter().enumerate() {
            root.draw(&PathElement::new(
                vec![(px(xi), top + plot_h), (px(xi), top + plot_h + 5)],
                BLACK,
            ))?;
            root.draw(&Text::new(
                fmt_value(v),
                (px(xi) - 12, top + plot_h + 10),
                small.clone(),
            ))?;
        }
        root.draw(&Text::new(
            self.x.clone(),
            (left + plot_w / 2 - 60, top + plot_h + 38),
            font.clone(),
        ))?;
        if let Some(y) = &self.y {
            for (yi, v) in self.ys.iter().enumerate() {
                root.draw(&PathElement::new(
                    vec![(left - 5, py(yi)), (left, py(yi))],
                    BLACK,
                ))?;
                root.draw(&Text::new(
                    fmt_value(v),
                    (left - 45, py(yi) - 3),
                    small.clone(),
                ))?;
            }
            root.draw(&Text::new(
                y.clone(),
                (8, top + plot_h / 2),
                font.clone().transform(FontTransform::Rotate270),
            ))?;
        }
        let mut legend: Vec<String> = Vec::new();
        let mut flagged = false;
        for (&(xi, yi), cell) in &self.cells {
            let (x, y) = (px(xi), py(yi));
            match cell.verdict() {
                Some(v) => {
                    draw_marker(root, &v.label, (x, y), 11)?;
                    if v.humps > 0 {
                        root.draw(&Text::new(
                            format!("{}", v.humps),
                            (x + 14, y - 20),
                            font.clone(),
                        ))?;
                    }
                    if v.probability.is_finite() {
                        // the label's probability, under the marker
                        root.draw(&Text::new(
                            format!("{:.2}", v.probability),
                            (x - 14, y + 14),
                            small.clone(),
                        ))?;
                    }
                    if v.guard_flagged {
                        root.draw(&Circle::new(
                            (x, y),
                            16,
                            RGBColor(214, 39, 40).stroke_width(2),
                        ))?;
                        flagged = true;
                    }
                    if !legend.contains(&v.label) {
                        legend.push(v.label);
                    }
                }
                None => {
                    root.draw(&Circle::new((x, y), 4, RGBColor(180, 180, 180).filled()))?;
                }
            }
        }
        if flagged {
            legend.push("collapse guard beyond validity".into());
        }
        legend.sort();
        let lx = left + plot_w + 20;
        for (i, label) in legend.iter().enumerate() {
            let ly = top + 12 + 26 * i as i32;
            draw_marker(root, label, (lx + 8, ly), 8)?;
            root.draw(&Text::new(label.clone(), (lx + 24, ly - 8), small.clone()))?;
        }
        Ok(())
    }
}

/// The marker of a structure label (shape and colour), thesis-like.
fn draw_marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    label: &str,
    (x, y): (i32, i32),
    r: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let blue = RGBColor(31, 119, 180);
    let red = RGBColor(214, 39, 40);
    let green = RGBColor(44, 160, 44);
    let orange = RGBColor(255, 127, 14);
    let purple = RGBColor(148, 103, 189);
    let grey = RGBColor(120, 120, 120);
    match label {
        "homogeneous" => root.draw(&Circle::new((x, y), r, grey.stroke_width(2))),
        "plug" => root.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            blue.filled(),
        )),
        "s-wave" => root.draw(&Polygon::new(
            vec![(x, y - r - 2), (x - r - 1, y + r), (x + r + 1, y + r)],
            red.filled(),
        )),
        "slug" => root.draw(&Circle::new((x, y), r, green.filled())),
        "wavy-slug" => root.draw(&Polygon::new(
            vec![
                (x, y - r - 2),
                (x + r + 2, y),
                (x, y + r + 2),
                (x - r - 2, y),
            ],
            orange.filled(),
        )),
        "s-wave+slug" => {
            root.draw(&Circle::new((x, y), r, green.filled()))?;
            root.draw(&Polygon::new(
                vec![
                    (x, y - r / 2 - 2),
                    (x - r / 2 - 1, y + r / 2),
                    (x + r / 2 + 1, y + r / 2),
                ],
                red.filled(),
            ))
        }
        "not-steady" => root.draw(&Cross::new((x, y), r, grey.stroke_width(2))),
        "mixed" => root.draw(&Circle::new((x, y), r, orange.stroke_width(3))),
        // lattice gas (Peng & Herrmann 1994)
        "density waves" => root.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            red.filled(),
        )),
        "no waves" => root.draw(&Circle::new((x, y), r, grey.stroke_width(2))),
        // DSMC: a valid steady run; where a curve has an interior minimum, or none
        "steady" => root.draw(&Circle::new((x, y), r, blue.filled())),
        "minimum" => root.draw(&Polygon::new(
            vec![(x - r - 1, y - r), (x + r + 1, y - r), (x, y + r + 2)],
            red.filled(),
        )),
        "monotonic" => root.draw(&Rectangle::new(
            [(x - r, y - r), (x + r, y + r)],
            grey.stroke_width(2),
        )),
        _ => root.draw(&Circle::new((x, y), r, purple.stroke_width(2))),
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
        assert_eq!(split.text(), "mixed[slug:0.60/wavy-slug:0.40]+[1-not-done]");

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
        assert_eq!(weighted.text(), "s-wave(2)[0.75]!tc");

        let unsteady = Cell {
            jobs: vec![job("slug 1.00", 10.0, false, true)],
            not_done: 0,
        };
        assert_eq!(unsteady.text(), "not-steady");
    }
}
