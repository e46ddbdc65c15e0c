//! The drawing of job figures, whatever the analysis: the energy trace, panels of curves with
//! error bars, panels of named series with a dashed reference, cell maps on one colour scale,
//! the label strip; the shapes they draw ([`CurvePanel`], [`SeriesPanel`], [`MapPanel`]) and
//! their helpers (axis spans, tick labels, staggered texts, the colour map).

use crate::figure::Scale;
use crate::figure::marker_colour;
use crate::figure::ticks::{self, Axis};
use plotters::coord::Shift;
use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A panel of curves: points (x, y, error; NaN error: none).
pub(super) struct CurvePanel {
    pub title: String,
    pub x_label: String,
    pub points: Vec<(f64, f64, f64)>,
    /// x positions of dashed vertical lines (zone boundaries), with their colour
    pub marks: Vec<(f64, RGBColor)>,
}

/// A panel of named curves (x, y) with an optional dashed reference curve.
pub(super) struct SeriesPanel {
    pub title: String,
    pub x_label: String,
    pub series: Vec<(String, Vec<(f64, f64)>)>,
    pub reference: Option<(String, Vec<(f64, f64)>)>,
    pub log_y: bool,
}

/// A panel of cells: `values[i * ny + j]` covers [x_edges[i], x_edges[i+1]] x
/// [y_edges[j], y_edges[j+1]]; NaN cells are left blank; `marks` are outlined.
pub(super) struct MapPanel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_edges: Vec<f64>,
    pub y_edges: Vec<f64>,
    pub values: Vec<f64>,
    pub marks: Vec<(usize, usize)>,
    /// integer wave numbers at the cell centres (spectra) rather than lengths
    pub wave_numbers: bool,
}

pub(super) type DrawResult<DB> =
    Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// (lo, hi) of finite values, padded; `log` keeps only positive ones.
pub(super) fn span(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
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
pub(super) fn window_colour(steady: bool) -> RGBColor {
    if steady {
        RGBColor(60, 60, 60)
    } else {
        RGBColor(170, 170, 170)
    }
}

/// A tick label of a linear axis ([`ticks::short`]).
pub(super) fn tick(v: &f64) -> String {
    ticks::short(*v)
}

/// Height of the evolution figure's energy trace, CSS pixels.
pub(super) const EVOLUTION_TRACE: u32 = 380;

/// A text's width in pixels at font size `size` (pixels), from an average glyph width of
/// 0.6 em (generous for the proportional figure font, so that estimated texts do not touch).
pub(super) fn estimated_text_width(text: &str, size: f64) -> i32 {
    (0.6 * size * text.chars().count() as f64).ceil() as i32
}

/// Rows for texts spanning the given pixel ranges (in the order given): each takes the first
/// row in which it keeps `gap` pixels from every text already there.
pub(super) fn stagger_rows(spans: &[(i32, i32)], gap: i32) -> Vec<usize> {
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
pub(super) fn draw_trace<DB: DrawingBackend>(
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

pub(super) fn draw_curves<DB: DrawingBackend>(
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
pub(super) const SERIES_COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

pub(super) fn draw_series_panel<DB: DrawingBackend>(
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
pub(super) const PANEL_LABEL: f64 = 12.0;

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

pub(super) fn draw_maps<DB: DrawingBackend>(
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

pub(super) fn draw_labels<DB: DrawingBackend>(
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
