//! Per-job figures, drawn with plotters from a job's analysis and its records (rendered and
//! written by [`crate::figure`]; stored as `jobs/<id>/figures/<name>.png` and `.svg`), one file
//! per analysis:
//! - [`structure`] (EDMD): `energy`, `profiles`, `spectra`, `density`, `evolution`, `labels`,
//!   and with `run.statistics` the thesis' statistics in its layout ([`statistics`]): `vdf`,
//!   `pair_correlation`, `orientation`, `velocity_correlation`, `knudsen`;
//! - [`lattice`] (lattice gas): `spacetime`;
//! - [`rarefied`] (DSMC): `profiles`;
//! - [`dense`] (DEM): `profiles`, `series`.
//!
//! [`plot`] holds a figure and what it plots, [`draw`] the drawing every analysis shares. Each
//! figure is headed by its job: the engine, the seed, the id and the parameters by symbol with
//! their values (those at their defaults on a line of their own). A running job's figures are
//! drawn the same way from the records it has written so far.

mod dense;
mod draw;
mod lattice;
mod plot;
mod rarefied;
mod statistics;
mod structure;

pub use draw::colour_map;
pub use plot::JobFigure;

use crate::analysis::{Analysis, Record, SnapshotRecord};
use crate::figure::Sizing;
use crate::figure::text::Heading;
use std::path::{Path, PathBuf};

/// The folder of a job's figures inside its job directory.
pub const FIGURES_DIR: &str = "figures";

/// The figures of a job from its analysis and records (records of a running job: those so
/// far), headed by `heading` (the job's: `PlannedJob::heading`). Figures whose data are missing (no records, no spectra) are left
/// out.
pub fn figures(heading: &Heading, analysis: &Analysis, records: &[Record]) -> Vec<JobFigure> {
    let mut out = match analysis {
        Analysis::Structure(a) => {
            let records: Vec<&SnapshotRecord> =
                records.iter().filter_map(Record::structure).collect();
            structure::structure_figures(a, &records)
        }
        Analysis::Lattice(a) => lattice::lattice_figures(a),
        Analysis::Rarefied(a) => rarefied::rarefied_figures(a),
        Analysis::Dense(a) => dense::dense_figures(a),
    };
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
