//! The command-line front end: clap arguments and one module per command.

mod bench;
mod bench_dem;
mod bench_job;
mod bench_result;
mod completions;
mod engines;
mod figure_size;
mod gather;
mod lammps;
mod lammps_import;
mod out;
mod params;
mod phase_diagram;
mod plan;
mod plot;
mod report;
mod run;
mod signals;
mod sim;
mod slurm;
mod source;
mod status;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// granflow: granular channel flow simulations, analysis and sweeps.
#[derive(Debug, Parser)]
#[command(
    name = "granflow",
    version = concat!(env!("CARGO_PKG_VERSION"), " (", env!("GRANFLOW_COMMIT"), ")"),
    about,
    long_about = None
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a single simulation of any engine from flags or a RON file and print progress.
    Sim(sim::SimArgs),
    /// List the engines and their parameters (`--markdown`: the parameter tables of docs/parameters.md).
    Engines(engines::EnginesArgs),
    /// Measure engine speed on standard workloads (collisions/s, events/s, memory).
    Bench(bench::BenchArgs),
    /// Run the jobs of a sweep that are not done yet (resumable), then write the tables.
    Run(run::RunArgs),
    /// List the jobs of a sweep (id, parameters, N, estimated work, state) without running.
    Plan(plan::PlanArgs),
    /// Show a sweep's jobs by state, their progress and failures.
    Status(status::StatusArgs),
    /// Write the Parquet tables of a results directory.
    Gather(gather::GatherArgs),
    /// Print and plot (PNG, SVG) the structure labels over two swept parameters.
    PhaseDiagram(phase_diagram::PhaseDiagramArgs),
    /// Plot a column of the jobs table over a swept parameter, one curve per value of another.
    Plot(plot::PlotArgs),
    /// Write a DEM job of a sweep as LAMMPS input (data file + script) from its prepared state.
    Lammps(lammps::LammpsArgs),
    /// Read a LAMMPS dump of a DEM job's run into granflow's DEM tables and figures.
    LammpsImport(lammps_import::LammpsImportArgs),
    /// Write one self-contained HTML report of a sweep (diagram, jobs, figures); also while it
    /// runs.
    Report(report::ReportArgs),
    /// Run a sweep on a Slurm cluster as job arrays (submit), or show it in Slurm (status).
    Slurm(slurm::SlurmArgs),
    /// Print the shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(completions::CompletionsArgs),
}

/// Exit code for bad input (files, keys, values).
pub const EXIT_BAD_INPUT: u8 = 2;

/// Parse the command line, run the command, report errors with their cause chain.
pub fn main() -> ExitCode {
    return_big_buffers_to_the_system();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help and --version go to stdout through `out`, so that a full stdout is an error
        // (exit 75), not a silent success; usage errors go to stderr with exit 2
        Err(e) if !e.use_stderr() => {
            let text = if std::io::IsTerminal::is_terminal(&std::io::stdout()) {
                e.render().ansi().to_string()
            } else {
                e.render().to_string()
            };
            out::write(format_args!("{text}"));
            return ExitCode::SUCCESS;
        }
        Err(e) => e.exit(),
    };
    // A report piped into `head` ends quietly when the reader goes (the Unix default, which
    // Rust turns off). Not for `run` and `slurm`: a run must go on writing its results
    // whatever happens to its output, so it ignores a closed pipe instead.
    if !matches!(cli.command, Command::Run(_) | Command::Slurm(_)) {
        // SAFETY: restoring the default disposition of SIGPIPE before any thread starts
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        }
    }
    let result = match cli.command {
        Command::Sim(args) => sim::run(args),
        Command::Engines(args) => engines::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Run(args) => {
            signals::announce_stops(&std::env::args().collect::<Vec<_>>());
            run::run(args).and_then(|()| crate::sweep::stdout_failure())
        }
        Command::Plan(args) => plan::run(args),
        Command::Status(args) => status::run(args),
        Command::Gather(args) => gather::run(args),
        Command::PhaseDiagram(args) => phase_diagram::run(args),
        Command::Plot(args) => plot::run(args),
        Command::Report(args) => report::run(args),
        Command::Lammps(args) => lammps::run(args),
        Command::LammpsImport(args) => lammps_import::run(args),
        Command::Slurm(args) => slurm::run(args),
        Command::Completions(args) => completions::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err}");
            for cause in err.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            if err
                .downcast_ref::<crate::sweep::fs_error::ResourceStop>()
                .is_some()
            {
                ExitCode::from(crate::sweep::fs_error::EXIT_RESOURCE)
            } else if crate::sweep::fs_error::is_resource_error(&err) {
                // a full disk (or quota, read-only file system, failing device) anywhere
                eprintln!(
                    "  the file system refused the write ({}): free space, make the directory \
                     writable or fix the device, then run the same command again (exit code {})",
                    crate::sweep::fs_error::resource_kind(&err),
                    crate::sweep::fs_error::EXIT_RESOURCE
                );
                ExitCode::from(crate::sweep::fs_error::EXIT_RESOURCE)
            } else if err.downcast_ref::<crate::sweep::SpecError>().is_some()
                || err.downcast_ref::<crate::sweep::BadInput>().is_some()
            {
                ExitCode::from(EXIT_BAD_INPUT)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Buffers of 4 MiB and more (snapshots, checkpoints, neighbour lists of big systems) get
/// their own mappings, returned to the system when freed. glibc's default raises that
/// threshold to the size of the first such buffer freed (up to 32 MiB) and from then on keeps
/// freed buffers in its heap, so a job's resident memory kept every transient it ever had:
/// measured on the 322 289-sphere job of Fig. 5.26 (300 collisions per particle, one thread),
/// peak resident memory 193 MB with the default, 157 MB with this (docs/performance.md).
fn return_big_buffers_to_the_system() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; called before any thread starts
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 4 << 20);
    }
}
