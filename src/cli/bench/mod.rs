//! `facets bench ...`: one file per benchmark.

mod analysis;
mod engine;
mod fill;
mod vision;

use clap::Subcommand;

#[derive(Debug, Subcommand)]
pub enum Bench {
    /// Analysis speed: g(r) of 100 deposits of 1 000 grains (goal < 1 s on 2 cores) and the
    /// coarse-grained stress on a 200 x 600 grid from 20 000 contacts (goal < 2 s).
    Analysis(analysis::Args),
    /// DEM engine throughput (grain-steps per second) on settled dense deposits.
    Engine(engine::Args),
    // Takes its help (with the list of scenes, settings and outputs) from its Args' docs.
    Fill(fill::Args),
    /// Detector accuracy (recall, precision, centre and orientation RMS), time and memory per
    /// photograph on rendered simulated deposits and dense packings, in looks drawn at random
    /// from seeds of a tuning or a held-out split.
    Vision(vision::Args),
}

pub fn run(bench: Bench) -> anyhow::Result<()> {
    match bench {
        Bench::Analysis(args) => analysis::run(args),
        Bench::Engine(args) => engine::run(args),
        Bench::Fill(args) => fill::run(args),
        Bench::Vision(args) => vision::run(args),
    }
}
