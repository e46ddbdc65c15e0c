//! `granflow sim`: run one simulation from flags and print progress.

use clap::Args;

#[derive(Debug, Args)]
pub struct SimArgs {}

pub fn run(_args: SimArgs) -> anyhow::Result<()> {
    anyhow::bail!("not yet implemented")
}
