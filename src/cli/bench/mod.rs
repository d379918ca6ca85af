//! `facets bench ...`: one file per benchmark.

mod vision;

use clap::Subcommand;

#[derive(Debug, Subcommand)]
pub enum Bench {
    /// Detector accuracy (recall, precision, centre and orientation RMS) and time per
    /// photograph on rendered dense packings of every shape, scale and style.
    Vision(vision::Args),
}

pub fn run(bench: Bench) -> anyhow::Result<()> {
    match bench {
        Bench::Vision(args) => vision::run(args),
    }
}
