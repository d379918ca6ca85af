//! `facets bench ...`: one file per benchmark.

use clap::Subcommand;

#[derive(Debug, Subcommand)]
pub enum Bench {}

pub fn run(bench: Bench) -> anyhow::Result<()> {
    match bench {}
}
