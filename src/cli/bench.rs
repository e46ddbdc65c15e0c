//! `granflow bench`: engine speed on standard workloads.

use clap::Args;

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// print a JSON array instead of a table
    #[arg(long)]
    pub json: bool,
}

pub fn run(_args: BenchArgs) -> anyhow::Result<()> {
    anyhow::bail!("not yet implemented")
}
