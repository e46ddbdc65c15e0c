//! `granflow plot results/<sweep> --x P --y COLUMN [--by Q] [--log-x] [--log-y]`: a summary
//! column over a swept parameter, one curve per value of another, with error bars; printed as
//! a table with each curve's minimum and written as PNG and SVG into the results directory.

use super::figure_size::FigureSize;
use super::out::{out, outln};
use super::source::SweepSource;
use crate::sweep::curves::CurvePlot;
use crate::sweep::phase::swept_in;
use crate::sweep::{BadInput, tables};
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow plot results/dsmc-knudsen-minimum --x knudsen_number --y flow_rate \\
      --by restitution --log-x")]
pub struct PlotArgs {
    #[command(flatten)]
    pub source: SweepSource,
    /// parameter along x (a number, e.g. knudsen_number)
    #[arg(long)]
    pub x: String,
    /// a numeric column of jobs.parquet (its `<column>_error` gives the error bars)
    #[arg(long)]
    pub y: String,
    /// one curve per value of this parameter (default: the other swept one, if exactly one)
    #[arg(long)]
    pub by: Option<String>,
    /// logarithmic x axis (and minima refined in log x)
    #[arg(long)]
    pub log_x: bool,
    /// logarithmic y axis
    #[arg(long)]
    pub log_y: bool,
    #[command(flatten)]
    pub size: FigureSize,
}

pub fn run(args: PlotArgs) -> anyhow::Result<()> {
    let sizing = args.size.sizing()?;
    let (sweep, dirs) = args.source.open()?;
    let jobs = tables::collect(&sweep, &dirs);
    let swept = swept_in(&sweep);
    let by = args.by.clone().or_else(|| {
        let others: Vec<&&str> = swept.iter().filter(|s| **s != args.x).collect();
        (others.len() == 1).then(|| others[0].to_string())
    });
    let mut plot = CurvePlot::build(sweep.engine(), &jobs, &args.x, &args.y, by.as_deref())
        .map_err(BadInput)?;
    plot.log_x = args.log_x;
    plot.log_y = args.log_y;
    let shown: Vec<&str> = std::iter::once(args.x.as_str())
        .chain(by.as_deref())
        .collect();
    let others = crate::sweep::phase::varying_besides(&sweep, &shown);
    if !others.is_empty() {
        outln!(
            "note: {others:?} also vary; their jobs are averaged into the same points (a point \
             whose jobs' labels differ is marked {})",
            crate::sweep::phase::DISAGREE
        );
    }
    out!("{}", plot.table());
    let png = dirs.tables.join(format!("{}.png", plot.stem()));
    let svg = dirs.tables.join(format!("{}.svg", plot.stem()));
    plot.write_png(&png, &sizing)?;
    plot.write_svg(&svg, &sizing)?;
    outln!("plots: {} {}", png.display(), svg.display());
    Ok(())
}
