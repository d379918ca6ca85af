use std::cell::RefCell;
use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};

use facets::bench::engine::{self, EngineBench, EngineEvent, Layout};

/// Engine throughput on settled dense deposits in a 256 mm box: grain-steps per second on
/// 1 and 2 threads, memory per grain. The default cases are the issue's: 3 000 rounded squares
/// (6.9 mm, r = 0.35 mm) and 5 000 rods 8.9 x 3 mm; `--scaling` adds 30 000 squares to compare
/// the per-grain cost. The same scene for LAMMPS is in benches/peers/.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Cases as KIND:COUNT, comma-separated (kinds: square, rod53, rod3).
    #[arg(long, value_delimiter = ',', default_values = ["square:3000", "rod3:5000"])]
    cases: Vec<String>,
    /// Also run 30 000 squares, to compare the per-grain cost with the 3 000 case: `wide`,
    /// the 3 000 case's rule in a box ten times as wide (2 560 mm: the same depth, load and
    /// contacts per grain, so it measures the engine's cost against N), or `stacked`, ten
    /// copies of the settled 3 000 on each other in the 256 mm box, settled again for 0.3 s
    /// (ten times the load at the bottom: more contacts per grain). Bare `--scaling` runs both.
    #[arg(long, value_enum, value_delimiter = ',', num_args = 0..=1,
          default_missing_value = "wide,stacked")]
    scaling: Vec<Layout>,
    /// Folder where each settled deposit is saved, and read back by later runs with the same
    /// case, seed and settling step instead of settling again (the 30 000-grain deposits take
    /// minutes). Files are tied to the facets version; delete them after changing the engine.
    #[arg(long)]
    settled_cache: Option<PathBuf>,
    /// Timed steps per run.
    #[arg(long, default_value_t = 2000)]
    steps: u64,
    /// Time step of the timed runs (s); the paper's.
    #[arg(long, default_value_t = 1e-6)]
    dt: f64,
    /// Time step used to let the grid fall and settle (s).
    #[arg(long, default_value_t = 2e-5)]
    settle_dt: f64,
    /// Thread counts to time, comma-separated (e.g. 1,2).
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 2])]
    threads: Vec<usize>,
    /// Seed of the grain orientations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Also write the table as CSV here.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let bench = EngineBench {
        cases: args
            .cases
            .iter()
            .map(|c| engine::parse_case(c))
            .collect::<anyhow::Result<Vec<_>>>()?,
        scaling: args.scaling,
        settled_cache: args.settled_cache,
        steps: args.steps,
        time_step: args.dt,
        settle_time_step: args.settle_dt,
        threads: args.threads,
        seed: args.seed,
    };
    println!(
        "| grains | N | threads | steps | wall s | grain-steps/s | CPU s | grain-steps per CPU s | sub-contacts | Verlet pairs | world bytes/grain |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    // A spinner while a case settles, gone once its rows are timed.
    let spinner: RefCell<Option<ProgressBar>> = RefCell::new(None);
    let spin = || {
        spinner
            .borrow_mut()
            .get_or_insert_with(|| {
                ProgressBar::new_spinner().with_style(
                    ProgressStyle::with_template("{spinner} settling {msg} [{elapsed}]")
                        .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                )
            })
            .clone()
    };
    let stop = || {
        if let Some(bar) = spinner.borrow_mut().take() {
            bar.finish_and_clear();
        }
    };
    let rows = engine::run(&bench, &|event| match event {
        EngineEvent::Settling { label, time } => {
            let bar = spin();
            bar.set_message(format!("{label}: t = {time:.3} s"));
            bar.tick();
        }
        EngineEvent::Read { label, path } => {
            spin().suspend(|| eprintln!("{label}: settled deposit read from {}", path.display()))
        }
        EngineEvent::Settled {
            label,
            grains,
            ratio,
            quenched,
        } => {
            let how = if quenched { "quenched" } else { "settled" };
            spin().suspend(|| {
                eprintln!("{grains} {label}: {how} to kinetic / elastic = {ratio:.1e}")
            });
        }
        EngineEvent::Row(r) => {
            stop();
            let t = &r.throughput;
            println!(
                "| {} | {} | {} | {} | {:.2} | {:.3e} | {:.2} | {:.3e} | {} | {} | {:.0} |",
                r.label,
                r.grains,
                t.threads,
                t.steps,
                t.seconds,
                t.grain_steps_per_second,
                t.cpu_seconds,
                (r.grains as f64 * t.steps as f64) / t.cpu_seconds,
                t.contacts,
                t.pairs,
                r.world_bytes_per_grain
            );
        }
    })?;
    stop();
    if let Some(peak) = facets::bench::process::peak_memory() {
        println!(
            "peak resident memory of this run: {:.0} MB",
            peak as f64 / 1e6
        );
    }
    if let Some(path) = &args.csv {
        engine::write_csv(path, &rows)?;
    }
    Ok(())
}
