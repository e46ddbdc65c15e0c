//! The panels of a job's statistics figures, in the thesis' layout (Figs. 3.12-3.21,
//! 4.7-4.20): the wall, shear and centre slabs (the thesis' bins 1, 4 and 13 of 25; for other
//! slab counts the same fractions of the width), each figure a few panels of curves with a
//! dashed reference. Drawn by [`super::structure`].

use super::draw::SeriesPanel;
use crate::analysis::statistics::Statistics;
use crate::analysis::statistics::vdf::COMPONENTS;

/// The slabs shown: (name, slab) for the wall (slab 0), the shear layer (the thesis' bin 4
/// of 25: 3/25 of the width) and the centre.
pub fn shown_slabs(slabs: usize) -> Vec<(String, usize)> {
    let shear = ((3.0 * slabs as f64 / 25.0).round() as usize).min(slabs.saturating_sub(1));
    let centre = (slabs - 1) / 2;
    let mut out = vec![("wall".to_string(), 0usize)];
    for (name, s) in [("shear", shear), ("centre", centre)] {
        if !out.iter().any(|(_, t)| *t == s) {
            out.push((name.to_string(), s));
        }
    }
    out.into_iter()
        .map(|(name, s)| (format!("{name} (bin {})", s + 1), s))
        .collect()
}

fn slab_count(s: &Statistics) -> usize {
    let from = |v: Option<u32>| v.map_or(0, |b| b as usize + 1);
    [
        s.vdf.iter().map(|r| from(Some(r.slab))).max().unwrap_or(0),
        s.orientation
            .iter()
            .map(|r| from(Some(r.slab)))
            .max()
            .unwrap_or(0),
        s.knudsen
            .iter()
            .map(|r| from(Some(r.slab)))
            .max()
            .unwrap_or(0),
        s.pair_correlation
            .iter()
            .map(|r| from(r.slab))
            .max()
            .unwrap_or(0),
    ]
    .into_iter()
    .max()
    .unwrap_or(0)
}

/// One statistics figure: its name, caption and panels.
pub type StatisticsFigure = (&'static str, String, Vec<SeriesPanel>);

/// The statistics figures: (name, caption, panels). `width`: W, for captions.
pub fn figures(s: &Statistics, width: f64) -> Vec<StatisticsFigure> {
    let slabs = slab_count(s);
    if slabs == 0 {
        return Vec::new();
    }
    let shown = shown_slabs(slabs);
    let window = format!(
        "over {} statistics snapshots ({} .. {} collisions per particle)",
        s.summary.statistics_snapshots,
        s.summary.statistics_window_start,
        s.summary.statistics_window_end
    );
    [
        vdf_figure(s, &shown, &window),
        pair_correlation_figure(s, &shown, &window),
        orientation_figure(s, &window, width),
        velocity_correlation_figure(s, &shown, &window),
        knudsen_figure(s, &window),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The velocity distributions (thesis Figs. 3.12-3.17): panels a-f, C_x .. Omega_z at the shown slabs with the Gaussian.
fn vdf_figure(s: &Statistics, shown: &[(String, usize)], window: &str) -> Option<StatisticsFigure> {
    if s.vdf.is_empty() {
        return None;
    }
    let gaussian: Vec<(f64, f64)> = (-80..=80)
        .map(|k| {
            let x = k as f64 * 0.1;
            (x, (-0.5 * x * x).exp())
        })
        .collect();
    let letters = ["a", "b", "c", "d", "e", "f"];
    let panels: Vec<SeriesPanel> = COMPONENTS
        .iter()
        .enumerate()
        .filter(|(_, c)| s.vdf.iter().any(|r| r.component == **c))
        .map(|(k, c)| SeriesPanel {
            title: format!("({}) P({c})", letters[k]),
            x_label: format!("{c} / sigma"),
            series: shown
                .iter()
                .map(|(name, slab)| {
                    (
                        name.clone(),
                        s.vdf
                            .iter()
                            .filter(|r| r.slab as usize == *slab && r.component == *c)
                            .map(|r| (r.x, r.p))
                            .collect(),
                    )
                })
                .collect(),
            reference: Some(("Gaussian".into(), gaussian.clone())),
            log_y: true,
        })
        .collect();
    let centre = shown.last().map_or(0, |c| c.1);
    let kurtosis: Vec<String> = s
        .vdf_moments
        .iter()
        .filter(|m| m.slab as usize == centre)
        .map(|m| format!("{} {:.2}", m.component, m.kurtosis))
        .collect();
    Some((
        "vdf",
        format!(
            "Velocity distributions of the translational (a-c) and rotational (d-f) \
             fluctuations about the slab mean, x scaled by the slab's standard deviation and \
             P(0) = 1 as in the thesis' Figs. 3.12-3.17; dashed: the Gaussian exp(-x^2/2); \
             {window}. Kurtosis in the centre (3 for a Gaussian; new, not in the thesis): {}.",
            kurtosis.join(", ")
        ),
        panels,
    ))
}

/// The pair correlation g(r) at the shown slabs and over all slabs (thesis Figs. 3.18-3.20).
fn pair_correlation_figure(
    s: &Statistics,
    shown: &[(String, usize)],
    window: &str,
) -> Option<StatisticsFigure> {
    if s.pair_correlation.is_empty() {
        return None;
    }
    let mut series: Vec<(String, Vec<(f64, f64)>)> = shown
        .iter()
        .map(|(name, slab)| {
            (
                name.clone(),
                s.pair_correlation
                    .iter()
                    .filter(|r| r.slab == Some(*slab as u32))
                    .map(|r| (r.r, r.g))
                    .collect(),
            )
        })
        .collect();
    series.push((
        "all slabs".into(),
        s.pair_correlation
            .iter()
            .filter(|r| r.slab.is_none())
            .map(|r| (r.r, r.g))
            .collect(),
    ));
    let r_max = s.pair_correlation.iter().map(|r| r.r).fold(0.0, f64::max);
    Some((
        "pair_correlation",
        format!(
            "Pair correlation g(r) of the particles of a slab with partners anywhere, over an \
             uncorrelated gas with the same density profile (thesis Figs. 3.18-3.20, 4.10, \
             4.17; dashed: 1); contact value g(d+) = {:.3} over all slabs, {:.3} in the \
             centre; {window}.",
            s.summary.contact_value, s.summary.contact_value_centre
        ),
        vec![SeriesPanel {
            title: "g(r)".into(),
            x_label: "r / d".into(),
            series,
            reference: Some(("1".into(), vec![(0.0, 1.0), (r_max, 1.0)])),
            log_y: false,
        }],
    ))
}

/// The orientational correlation Lambda(y) with 1/3 (thesis Figs. 3.21, 4.11, 4.20).
fn orientation_figure(s: &Statistics, window: &str, width: f64) -> Option<StatisticsFigure> {
    if s.orientation.is_empty() {
        return None;
    }
    let ys: Vec<(f64, f64)> = s.orientation.iter().map(|r| (r.y, r.lambda)).collect();
    Some((
        "orientation",
        format!(
            "Orientational correlation Lambda(y) = <cos^2 Psi> across the channel \
             (0 <= y <= W = {width}; thesis Figs. 3.21, 4.11, 4.20, there with y vertical); \
             dashed: 1/3, a molecular gas. Lambda(0) = {:.4} +- {:.4}, mean {:.4}; {window}.",
            s.summary.lambda_centre, s.summary.lambda_centre_error, s.summary.lambda_mean
        ),
        vec![SeriesPanel {
            title: "Lambda(y)".into(),
            x_label: "y / d".into(),
            series: vec![("Lambda".into(), ys)],
            reference: Some(("1/3".into(), vec![(0.0, 1.0 / 3.0), (width, 1.0 / 3.0)])),
            log_y: false,
        }],
    ))
}

/// The velocity correlations C_xx, C_yy, C_zz at the shown slabs (thesis Figs. 4.12-4.14).
fn velocity_correlation_figure(
    s: &Statistics,
    shown: &[(String, usize)],
    window: &str,
) -> Option<StatisticsFigure> {
    if s.velocity_correlation.is_empty() {
        return None;
    }
    let r_max = s
        .velocity_correlation
        .iter()
        .map(|r| r.r)
        .fold(0.0, f64::max);
    let panels = ["xx", "yy", "zz"]
        .iter()
        .map(|pair| SeriesPanel {
            title: format!("C_{pair}(r)"),
            x_label: "r / d".into(),
            series: shown
                .iter()
                .map(|(name, slab)| {
                    (
                        name.clone(),
                        s.velocity_correlation
                            .iter()
                            .filter(|r| r.slab as usize == *slab && r.pair == *pair)
                            .map(|r| (r.r, r.c))
                            .collect(),
                    )
                })
                .collect(),
            reference: Some(("0".into(), vec![(0.0, 0.0), (r_max, 0.0)])),
            log_y: false,
        })
        .collect();
    Some((
        "velocity_correlation",
        format!(
            "Velocity correlations C_aa(r) of the fluctuations (thesis Figs. 4.12-4.14, \
             4.19; eq. 4.1 read as the mean product over the pairs at r, normalised by the \
             one-particle variance: 0 for an uncorrelated gas); {window}."
        ),
        panels,
    ))
}

/// Kn(y) and the distribution of free paths P(l) with the exponential of the same mean (thesis Figs. 3.8, 3.9).
fn knudsen_figure(s: &Statistics, window: &str) -> Option<StatisticsFigure> {
    if s.knudsen.is_empty() {
        return None;
    }
    let kn: Vec<(f64, f64)> = s.knudsen.iter().map(|r| (r.y, r.knudsen)).collect();
    let all: Vec<(f64, f64)> = s
        .free_paths
        .iter()
        .filter(|r| r.slab.is_none())
        .map(|r| (r.l, r.p))
        .collect();
    let lambda = s.summary.mean_free_path;
    let l_max = all.iter().map(|p| p.0).fold(0.0, f64::max);
    let exponential: Vec<(f64, f64)> = (0..=100)
        .map(|k| {
            let l = l_max * k as f64 / 100.0;
            (l, (-l / lambda).exp() / lambda)
        })
        .collect();
    Some((
        "knudsen",
        format!(
            "Knudsen number Kn(y) = lambda(y) / W across the channel (thesis Figs. 3.8, 4.2f) \
             and the distribution of free paths over all slabs (Fig. 3.9; dashed: the \
             exponential of the same mean, a molecular gas' tail). lambda = {:.3} d, Kn = \
             {:.4} in the centre and {:.4} at the walls; {} paths, {:.1} % ended by a wall; \
             {window}.",
            lambda,
            s.summary.knudsen_centre,
            s.summary.knudsen_wall,
            s.summary.free_paths,
            100.0 * s.summary.wall_path_fraction
        ),
        vec![
            SeriesPanel {
                title: "Kn(y)".into(),
                x_label: "y / d".into(),
                series: vec![("Kn".into(), kn)],
                reference: None,
                log_y: false,
            },
            SeriesPanel {
                title: "P(l)".into(),
                x_label: "l / d".into(),
                series: vec![("all slabs".into(), all)],
                reference: Some(("exponential".into(), exponential)),
                log_y: true,
            },
        ],
    ))
}
