//! The command-line front end: clap arguments and one module per command.

mod bench;
mod sim;
mod slurm;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// granflow: granular channel flow simulations, analysis and sweeps.
#[derive(Debug, Parser)]
#[command(name = "granflow", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a single simulation from flags or a small RON file and print progress.
    Sim(sim::SimArgs),
    /// Measure engine speed on standard workloads (collisions/s, events/s, memory).
    Bench(bench::BenchArgs),
    /// Run a sweep on a Slurm cluster as job arrays (submit), or show it in Slurm (status).
    Slurm(slurm::SlurmArgs),
}

/// Exit code for bad input (files, keys, values).
pub const EXIT_BAD_INPUT: u8 = 2;

/// Parse the command line, run the command, report errors with their cause chain.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Sim(args) => sim::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Slurm(args) => slurm::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err}");
            for cause in err.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
}
