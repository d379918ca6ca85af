//! One file per subcommand; each holds its clap arguments and a `run` that calls the library.

mod analyse;
mod bench;
mod compare;
mod detect;
mod drop;
mod progress;
mod render;
mod reproduce;
mod shortcuts;
mod sim;
mod validate;

use clap::{Parser, Subcommand};

/// facets: granular deposits of faceted grains (square nuts, short and long rods) in a 2D silo.
///
/// Simulates silo fillings (DEM of spheropolygons), finds grains in photographs of deposits,
/// and measures both with the same analysis.
#[derive(Debug, Parser)]
#[command(name = "facets", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Drop one grain onto a floor or a resting grain and report the collision.
    Drop(drop::Args),
    // Analyse and Compare take their help (with the list of outputs) from their Args' docs.
    Analyse(analyse::Args),
    Compare(compare::Args),
    /// Find every grain in backlit photographs of deposits; write a deposit table per photo.
    Detect(detect::Args),
    Sim(sim::Args),
    /// Render a synthetic backlit photograph of a deposit table (or of a generated dense
    /// packing), with its ground-truth table beside it.
    Render(render::Args),
    Reproduce(reproduce::Args),
    Validate(validate::Args),
    /// Benchmarks: engine throughput and the other measured speed goals.
    #[command(subcommand)]
    Bench(bench::Bench),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Drop(args) => drop::run(args),
        Command::Analyse(args) => analyse::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Detect(args) => detect::run(args),
        Command::Sim(args) => sim::run(args),
        Command::Render(args) => render::run(args),
        Command::Reproduce(args) => reproduce::run(args),
        Command::Validate(args) => validate::run(args),
        Command::Bench(bench) => bench::run(bench),
    }
}
