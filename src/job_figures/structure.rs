//! The figures of the structure analysis (EDMD; thesis ch. 3 and 5): `energy` (the
//! kinetic-energy trace with the steady window), `profiles` (phi, U_x, omega_z, T, theta across
//! the channel), `spectra` (xy, xz, yz power-spectrum maps with the modes that stand above shot
//! noise outlined), `density` (phi of the last snapshot in the three planes, as thesis Figs.
//! 5.2-5.24), `evolution` (the structure at the run's milestones), the statistics figures
//! ([`super::statistics`]) and `labels` (the label of every snapshot along the run).

use super::draw::{CurvePanel, MapPanel};
use super::plot::{JobFigure, Plot};
use crate::analysis::classify::significant_plane_modes;
use crate::analysis::{JobAnalysis, SnapshotRecord, plane_fields};
use crate::figure::text::Heading;

pub(super) fn structure_figures(a: &JobAnalysis, records: &[&SnapshotRecord]) -> Vec<JobFigure> {
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
        out.extend(super::statistics::figures(st, width).into_iter().map(
            |(name, caption, panels)| JobFigure {
                heading: Heading::default(),
                name,
                caption,
                plot: Plot::Series(panels),
            },
        ));
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
                crate::analysis::labels::shown(&s.label, s.humps, s.three_dimensional)
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
pub(super) fn spectra_figure(a: &JobAnalysis) -> Option<JobFigure> {
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
pub(super) fn has_fields(r: &SnapshotRecord) -> bool {
    let [n1, n2, n3] = r.grid.map(|k| k as usize);
    n1 * n2 * n3 > 0
        && r.grid_volume > 0.0
        && r.counts_xy.len() == n1 * n2
        && r.counts_xz.len() == n1 * n3
        && r.counts_yz.len() == n2 * n3
}

/// The volume fraction of a record in the xy, xz and yz planes (each averaged over the third
/// axis; titles prefixed by `prefix`), and the largest value.
pub(super) fn density_panels(r: &SnapshotRecord, prefix: &str) -> (Vec<MapPanel>, f64) {
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

pub(super) fn density_figure(records: &[&SnapshotRecord]) -> Option<JobFigure> {
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
pub(super) fn evolution_figure(a: &JobAnalysis, records: &[&SnapshotRecord]) -> Option<JobFigure> {
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
