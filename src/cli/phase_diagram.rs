//! `granflow phase-diagram results/<sweep> --x P [--y Q]`: print the grid of structure labels
//! and write PNG and SVG plots into the results directory; with `--minimum-of C --along R`
//! the grid of where column C has an interior minimum along parameter R.

use super::figure_size::FigureSize;
use super::out::{out, outln};
use super::source::SweepSource;
use crate::sweep::phase::{Frame, PhaseDiagram, choose_axes, title};
use crate::sweep::{BadInput, tables};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow phase-diagram results/quick --x length_over_width --y restitution
  granflow phase-diagram results/dsmc-knudsen-minimum --minimum-of flow_rate_hat \\
      --along knudsen_number --x restitution")]
pub struct PhaseDiagramArgs {
    #[command(flatten)]
    pub source: SweepSource,
    /// parameter along x (default: the first swept one)
    #[arg(long)]
    pub x: Option<String>,
    /// parameter along y (default: the second swept one; none gives a strip)
    #[arg(long)]
    pub y: Option<String>,
    /// instead of structure labels, whether this jobs-table column has an interior minimum
    /// along `--along` in each cell (e.g. --minimum-of flow_rate_hat --along knudsen_number:
    /// the Knudsen-minimum diagram, Gupta 2017 Fig. 4.1)
    #[arg(long, requires = "along", value_name = "COLUMN")]
    pub minimum_of: Option<String>,
    /// the parameter the curves of `--minimum-of` run along (judged in log scale)
    #[arg(long, requires = "minimum_of", value_name = "PARAMETER")]
    pub along: Option<String>,
    #[command(flatten)]
    pub size: FigureSize,
}

/// Write `phase-<x>[-<y>].png` and `.svg` into `dir`; returns their paths.
pub fn write_plots(diagram: &PhaseDiagram, dir: &Path) -> anyhow::Result<(PathBuf, PathBuf)> {
    let stem = match &diagram.y {
        Some(y) => format!("phase-{}-{}", diagram.x, y),
        None => format!("phase-{}", diagram.x),
    };
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    diagram.write_png(&png)?;
    diagram.write_svg(&svg)?;
    Ok((png, svg))
}

pub fn run(args: PhaseDiagramArgs) -> anyhow::Result<()> {
    let (sweep, dirs) = args.source.open()?;
    let jobs = tables::collect(&sweep, &dirs);
    let (x, y) = choose_axes(
        &sweep,
        args.x.as_deref(),
        args.y.as_deref(),
        args.along.as_deref(),
    )
    .map_err(BadInput)?;
    let mut axes_shown: Vec<&str> = vec![x.as_str()];
    axes_shown.extend(y.as_deref());
    axes_shown.extend(args.along.as_deref());
    let frame = Frame {
        size: args.size.sizing()?,
        title: title(&sweep, &axes_shown),
    };
    let mut diagram = match (&args.minimum_of, &args.along) {
        (Some(column), Some(along)) => crate::sweep::curves::minimum_diagram(
            sweep.engine(),
            &jobs,
            along,
            column,
            &x,
            y.as_deref(),
            true,
        ),
        _ => PhaseDiagram::build(sweep.engine(), &jobs, &x, y.as_deref()),
    }
    .map_err(BadInput)?;
    diagram.frame = frame;
    let shown: Vec<&str> = std::iter::once(x.as_str())
        .chain(y.as_deref())
        .chain(args.along.as_deref())
        .collect();
    let others = crate::sweep::phase::varying_besides(&sweep, &shown);
    if !others.is_empty() {
        outln!(
            "note: {others:?} also vary; their jobs share cells (a cell whose jobs' labels differ \
             is marked {})",
            crate::sweep::phase::DISAGREE
        );
    }
    out!("{}", diagram.table());
    let (png, svg) = match &args.minimum_of {
        Some(column) => {
            let stem = format!("minimum-{column}-{}", diagram.x);
            let stem = match &diagram.y {
                Some(y) => format!("{stem}-{y}"),
                None => stem,
            };
            let (png, svg) = (
                dirs.tables.join(format!("{stem}.png")),
                dirs.tables.join(format!("{stem}.svg")),
            );
            diagram.write_png(&png)?;
            diagram.write_svg(&svg)?;
            (png, svg)
        }
        None => write_plots(&diagram, &dirs.tables)?,
    };
    outln!("plots: {} {}", png.display(), svg.display());
    Ok(())
}
