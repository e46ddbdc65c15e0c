//! `granflow report results/<sweep>`: one self-contained HTML file of a sweep (the phase
//! diagram, a sortable table of the jobs, and per job its parameters, provenance, figures and
//! structure evolution), written into the results directory; works while the sweep runs.

use super::figure_size::FigureSize;
use super::out::outln;
use super::source::SweepSource;
use clap::Args;

#[derive(Debug, Args)]
#[command(after_help = "Examples:
  granflow run sweeps/quick.ron && granflow report results/quick
      writes results/quick/report.html: open it in any browser (file -> open, or
      `xdg-open results/quick/report.html`); it loads nothing from the network
  granflow report results/quick --where restitution=0.7 --x length_over_width
      only the jobs at e = 0.7, the diagram as a strip over L/W")]
pub struct ReportArgs {
    #[command(flatten)]
    pub source: SweepSource,
    /// parameter along x of the phase diagram (default: the first swept one)
    #[arg(long)]
    pub x: Option<String>,
    /// parameter along y of the phase diagram (default: the second swept one; none gives a
    /// strip)
    #[arg(long)]
    pub y: Option<String>,
    /// size and resolution of every figure in the report (the figure files of done jobs are
    /// written at their own size and 96 dpi where missing)
    #[command(flatten)]
    pub size: FigureSize,
}

pub fn run(args: ReportArgs) -> anyhow::Result<()> {
    let sizing = args.size.sizing()?;
    let (sweep, dirs) = args.source.open()?;
    let path =
        crate::report::write_report(&sweep, &dirs, args.x.as_deref(), args.y.as_deref(), &sizing)?;
    outln!("report: {}", path.display());
    outln!(
        "open it in a browser (e.g. xdg-open {}); it is one file with every figure inside",
        path.display()
    );
    Ok(())
}
