//! The report of a sweep: one self-contained HTML file
//! ([`html`]) with the phase diagram, a sortable table of the jobs and, per job, its
//! parameters, provenance, figures and structure evolution. Read from the job directories
//! alone (through the store), so it works while the sweep runs: a running or partial job shows
//! what the records it has written so far give.

mod html;

use crate::analysis::Analysis;
use crate::figure::Sizing;
use crate::job_figures::{self, JobFigure};
use crate::sweep::phase::{PhaseDiagram, choose_axes, swept_in, title};
use crate::sweep::store::{self, JobState};
use crate::sweep::tables::{self, GatheredJob};
use crate::sweep::{BadInput, Sweep, SweepDirs};
use rayon::prelude::*;
use std::path::PathBuf;

/// File name of the report inside a sweep's results directory.
pub const REPORT_FILE: &str = "report.html";

/// What the report shows of one job.
pub struct JobView<'a> {
    pub gathered: &'a GatheredJob<'a>,
    /// the run's clock at the result, or at the last checkpoint
    pub progress: Option<f64>,
    /// records written so far (snapshots)
    pub records: usize,
    /// the result's analysis, or for a running or partial job the analysis of its records so
    /// far
    pub analysis: Option<Analysis>,
    /// figures with their pictures
    pub figures: Vec<(JobFigure, Picture)>,
    /// what could not be read or drawn
    pub problems: Vec<String>,
}

impl JobView<'_> {
    /// True when the analysis is of the records so far, not a result.
    pub fn provisional(&self) -> bool {
        self.gathered.result.is_none() && self.analysis.is_some()
    }

    /// The structure label with its humps and 3D mark (e.g. "s-wave(2) 3d"), empty without
    /// an analysis.
    pub fn label(&self) -> String {
        self.analysis
            .as_ref()
            .map(|a| a.shown_label())
            .unwrap_or_default()
    }
}

/// A figure as the page shows it: its PNG at the resolution asked and its size in CSS pixels
/// (the page draws it at that size whatever the resolution, so 192 dpi is sharper, not
/// larger).
pub struct Picture {
    pub png: Vec<u8>,
    pub css: (u32, u32),
}

/// The phase diagram the report shows: the picture and its text table.
pub struct DiagramView {
    pub picture: Picture,
    pub table: String,
    pub x: String,
    pub y: Option<String>,
}

/// Read one job for the report: its analysis (the result's, or the records so far), its
/// figures rendered as PNG at `sizing`; the figure files of a done job are written into its
/// directory where they are missing (jobs finished before figures existed; at their own size
/// and 96 dpi, as a job writes them).
pub fn view_job<'a>(
    dirs: &SweepDirs,
    gathered: &'a GatheredJob<'a>,
    sizing: &Sizing,
) -> JobView<'a> {
    let job = gathered.job;
    let dir = dirs.job_dir(&job.id);
    let clock = job.params.run.clock();
    let mut problems = Vec::new();
    let progress = match &gathered.state {
        JobState::Done => gathered.result.as_ref().map(|r| r.clock(clock)),
        JobState::Partial(p) => Some(p.on(clock)),
        JobState::Running => store::checkpoint_progress(&dir).map(|p| p.on(clock)),
        _ => None,
    };
    let looks = matches!(
        gathered.state,
        JobState::Done | JobState::Running | JobState::Partial(_)
    );
    let records = if looks {
        store::records_so_far(&dir).unwrap_or_else(|e| {
            problems.push(format!("records: {e:#}"));
            Vec::new()
        })
    } else {
        Vec::new()
    };
    let analysis = match &gathered.result {
        Some(r) => Some(r.analysis.clone()),
        None if !records.is_empty() => job
            .params
            .analyser()
            .and_then(|a| a.analyse(&records))
            .map_err(|e| problems.push(format!("analysis of the records so far: {e}")))
            .ok(),
        None => None,
    };
    let drawn = analysis
        .as_ref()
        .map(|a| job_figures::figures(&job.heading(), a, &records))
        .unwrap_or_default();
    if gathered.result.is_some()
        && !job_figures::all_written(&dir, &drawn)
        && let Err(e) = job_figures::write(&dir, &drawn)
    {
        problems.push(format!("writing the figure files: {e:#}"));
    }
    let mut figures = Vec::new();
    for f in drawn {
        match f.png(sizing) {
            Ok(png) => {
                let css = f.size(sizing);
                figures.push((f, Picture { png, css }))
            }
            Err(e) => problems.push(format!("figure {}: {e:#}", f.name)),
        }
    }
    JobView {
        gathered,
        progress,
        records: records.len(),
        analysis,
        figures,
        problems,
    }
}

/// The diagram over `x` and `y` (defaults: the first two swept parameters) at `sizing`, None
/// when the sweep varies nothing and no axis is asked.
pub fn diagram(
    sweep: &Sweep,
    jobs: &[GatheredJob],
    x: Option<&str>,
    y: Option<&str>,
    sizing: &Sizing,
) -> Result<Option<DiagramView>, anyhow::Error> {
    if x.is_none() && swept_in(sweep).is_empty() {
        return Ok(None);
    }
    let (x, y) = choose_axes(sweep, x, y, None).map_err(BadInput)?;
    let mut d = PhaseDiagram::build(sweep.engine(), jobs, &x, y.as_deref()).map_err(BadInput)?;
    d.frame.size = *sizing;
    d.frame.title = title(
        sweep,
        &std::iter::once(x.as_str())
            .chain(y.as_deref())
            .collect::<Vec<_>>(),
    );
    Ok(Some(DiagramView {
        picture: Picture {
            png: d.png()?,
            css: d.size(),
        },
        table: d.table(),
        x,
        y,
    }))
}

/// The statistics' columns compared across a sweep (thesis Figs. 3.8, 3.10, 3.11, 3.21
/// insets): each against e, one curve per beta.
pub const COMPARED: &[(&str, &str)] = &[
    (
        "slip_velocity",
        "translational slip U_x at the walls (thesis Fig. 3.10a)",
    ),
    (
        "slip_rotational",
        "rotational slip omega_z at the walls, sign-folded (Fig. 3.10b)",
    ),
    ("wall_temperature", "T at the walls (Fig. 3.10c)"),
    (
        "wall_rotational_temperature",
        "theta at the walls (Fig. 3.10d)",
    ),
    ("knudsen_centre", "Kn in the centre (Fig. 3.8)"),
    (
        "lambda_centre",
        "Lambda(0), orientational correlation in the centre (Fig. 3.21 insets; 1/3: molecular gas)",
    ),
    (
        "lambda_mean",
        "mean of Lambda(y) over the slabs (Fig. 3.21 insets)",
    ),
    ("contact_value", "g(d+) over all slabs"),
];

/// A figure comparing one column across the sweep: its caption and PNG.
pub struct Comparison {
    pub name: String,
    pub caption: String,
    pub png: Vec<u8>,
}

/// The comparison figures of a sweep with statistics: each column of [`COMPARED`] against the
/// restitution (else the first swept number), one curve per value of the roughness (else of
/// the other swept parameter); none without statistics or without a swept number.
pub fn statistics_comparisons(
    sweep: &Sweep,
    jobs: &[GatheredJob],
    sizing: &Sizing,
) -> Vec<Comparison> {
    if !tables::has_statistics(sweep) {
        return Vec::new();
    }
    let engine = sweep.engine();
    let swept = swept_in(sweep);
    let numeric = |name: &str| {
        engine
            .param(name)
            .is_some_and(|d| !matches!(d.kind, crate::engine::declare::ParamKind::Choice(_)))
    };
    let Some(x) = swept
        .iter()
        .find(|s| **s == "restitution")
        .or_else(|| swept.iter().find(|s| numeric(s)))
        .map(|s| s.to_string())
    else {
        return Vec::new();
    };
    let by = swept
        .iter()
        .find(|s| **s == "roughness" && **s != x)
        .or_else(|| swept.iter().find(|s| **s != x))
        .map(|s| s.to_string());
    COMPARED
        .iter()
        .filter_map(|(y, what)| {
            let plot =
                crate::sweep::curves::CurvePlot::build(engine, jobs, &x, y, by.as_deref()).ok()?;
            if plot.series.iter().all(|s| s.points.is_empty()) {
                return None;
            }
            let png = plot.png(sizing).ok()?;
            Some(Comparison {
                name: y.to_string(),
                caption: format!(
                    "{what} against {x}{}; hollow points: not steady.",
                    by.as_ref()
                        .map(|b| format!(", one curve per {b}"))
                        .unwrap_or_default()
                ),
                png,
            })
        })
        .collect()
}

/// Write the report of a sweep into its results directory (`report.html`), its figures at
/// `sizing`; its path.
pub fn write_report(
    sweep: &Sweep,
    dirs: &SweepDirs,
    x: Option<&str>,
    y: Option<&str>,
    sizing: &Sizing,
) -> anyhow::Result<PathBuf> {
    let jobs = tables::collect(sweep, dirs);
    let diagram = diagram(sweep, &jobs, x, y, sizing)?;
    let views: Vec<JobView> = jobs.par_iter().map(|j| view_job(dirs, j, sizing)).collect();
    let comparisons = statistics_comparisons(sweep, &jobs, sizing);
    let page = html::page(sweep, dirs, diagram.as_ref(), &views, &comparisons);
    std::fs::create_dir_all(&dirs.tables)
        .map_err(|e| anyhow::anyhow!("{}: {e}", dirs.tables.display()))?;
    let path = dirs.tables.join(REPORT_FILE);
    crate::fs::write_atomic(&path, page.as_bytes())?;
    Ok(path)
}
