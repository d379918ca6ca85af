use clap::Args as ClapArgs;

use facets::analysis::coarse_grain::{CoarseGrainInput, DEFAULT_CUTOFF};
use facets::bench::analysis::{self, AnalysisBench};
use facets::bench::process::load_average;

#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Deposits in the g(r) ensemble.
    #[arg(long, default_value_t = 100)]
    pub deposits: usize,
    /// Grains per deposit.
    #[arg(long, default_value_t = 1000)]
    pub grains: usize,
    /// Repetitions of each timing; the best is reported (the machine is shared).
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    println!(
        "facets bench analysis ({} threads; best of {}; load average {})",
        rayon::current_num_threads(),
        args.repeat,
        load_average()
    );
    println!(
        "{:<58} {:>10} {:>8} {:>8} {:>6}",
        "measure", "wall (s)", "cpu (s)", "goal (s)", "ok"
    );
    let bench = AnalysisBench {
        deposits: args.deposits,
        grains: args.grains,
        repeat: args.repeat,
    };
    for t in analysis::run(&bench)? {
        println!(
            "{:<58} {:>10.3} {:>8.2} {:>8.1} {:>6}",
            t.what,
            t.wall_s,
            t.cpu_s,
            t.goal_s,
            if t.met() { "yes" } else { "NO" }
        );
    }
    println!(
        "(stress kernel cut off at {DEFAULT_CUTOFF} w: relative error <= {:.1e})",
        CoarseGrainInput::new(1.0).cutoff_error_bound()
    );
    Ok(())
}
