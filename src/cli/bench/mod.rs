//! `facets bench ...`: one file per benchmark.

mod engine;

use clap::Subcommand;

#[derive(Debug, Subcommand)]
pub enum Bench {
    /// DEM engine throughput (grain-steps per second) on settled dense deposits.
    Engine(engine::Args),
}

pub fn run(bench: Bench) -> anyhow::Result<()> {
    match bench {
        Bench::Engine(args) => engine::run(args),
    }
}
