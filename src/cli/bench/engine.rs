use std::path::PathBuf;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};

use facets::bench::engine::{self, DepositSpec};
use facets::grains::GrainKind;
use facets::io::write_atomic;

/// Engine throughput on settled dense deposits in a 256 mm box: grain-steps per second on
/// 1 and 2 threads, memory per grain. The default cases are the issue's: 3 000 rounded squares
/// (6.9 mm, r = 0.35 mm) and 5 000 rods 8.9 x 3 mm; `--scaling` adds 30 000 squares to compare
/// the per-grain cost. The same scene for LAMMPS is in benches/peers/.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Cases as KIND:COUNT, comma-separated (kinds: square, rod53, rod3).
    #[arg(long, value_delimiter = ',', default_values = ["square:3000", "rod3:5000"])]
    cases: Vec<String>,
    /// Also run 30 000 squares: ten copies of the settled 3 000-square deposit stacked on each
    /// other and settled again (at most 0.3 s), to compare the per-grain cost with the 3 000
    /// case.
    #[arg(long)]
    scaling: bool,
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

fn parse_case(text: &str) -> anyhow::Result<(GrainKind, usize)> {
    let (kind, count) = text
        .split_once(':')
        .ok_or_else(|| anyhow::anyhow!("case `{text}`: expected KIND:COUNT, e.g. square:3000"))?;
    let kind = kind
        .parse()
        .map_err(|e: String| anyhow::anyhow!("case `{text}`: {e}"))?;
    let count = count
        .parse()
        .map_err(|_| anyhow::anyhow!("case `{text}`: `{count}` is not a grain count"))?;
    Ok((kind, count))
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut cases = args
        .cases
        .iter()
        .map(|c| parse_case(c))
        .collect::<anyhow::Result<Vec<_>>>()?;
    if args.scaling && !cases.contains(&(GrainKind::Square, 3000)) {
        cases.push((GrainKind::Square, 3000));
    }
    let mut rows = Vec::new();
    println!(
        "| grains | N | threads | steps | wall s | grain-steps/s | CPU s | grain-steps per CPU s | sub-contacts | Verlet pairs | world bytes/grain |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for (kind, n) in cases {
        let spec = DepositSpec {
            kind,
            grains: n,
            seed: args.seed,
        };
        let mut world = engine::grid_scene(&spec, args.settle_dt)?;
        let bar = ProgressBar::new_spinner().with_style(
            ProgressStyle::with_template("{spinner} settling {msg} [{elapsed}]").unwrap(),
        );
        let ratio = engine::settle(&mut world, 1.5, |t| {
            bar.set_message(format!("{n} {kind}: t = {t:.3} s"));
            bar.tick();
        })?;
        eprintln!("{n} {kind}: settled to kinetic / elastic = {ratio:.1e}");
        let mut worlds = vec![world];
        if args.scaling && kind == GrainKind::Square && n == 3000 {
            // Stacked touching: a gap would let each copy fall free and open its contacts.
            let mut big = engine::stacked(&worlds[0], 10, 0.0)?;
            // The copies are settled already; 0.3 s lets the column take up the extra weight.
            let ratio = engine::settle(&mut big, 0.3, |t| {
                bar.set_message(format!("30000 square: t = {t:.3} s"));
                bar.tick();
            })?;
            eprintln!("30000 square: settled to kinetic / elastic = {ratio:.1e}");
            worlds.push(big);
        }
        bar.finish_and_clear();
        for world in &worlds {
            let n = world.len();
            let bytes_per_grain = world.memory_bytes() as f64 / n as f64;
            for &threads in &args.threads {
                let t = engine::measure(world, args.dt, args.steps, threads)?;
                println!(
                    "| {kind} | {n} | {threads} | {} | {:.2} | {:.3e} | {:.2} | {:.3e} | {} | {} | {:.0} |",
                    t.steps,
                    t.seconds,
                    t.grain_steps_per_second,
                    t.cpu_seconds,
                    (n as f64 * t.steps as f64) / t.cpu_seconds,
                    t.contacts,
                    t.pairs,
                    bytes_per_grain
                );
                rows.push((kind, n, t, bytes_per_grain));
            }
        }
    }
    if let Some(peak) = engine::peak_memory() {
        println!(
            "peak resident memory of this run: {:.0} MB",
            peak as f64 / 1e6
        );
    }
    if let Some(path) = &args.csv {
        write_atomic(path, |w| {
            use std::io::Write;
            writeln!(
                w,
                "grains,n,threads,steps,wall_s,grain_steps_per_s,cpu_s,sub_contacts,world_bytes_per_grain"
            )?;
            for (kind, n, t, b) in &rows {
                writeln!(
                    w,
                    "{kind},{n},{},{},{:.4},{:.1},{:.4},{},{:.0}",
                    t.threads,
                    t.steps,
                    t.seconds,
                    t.grain_steps_per_second,
                    t.cpu_seconds,
                    t.contacts,
                    b
                )?;
            }
            Ok(())
        })?;
    }
    Ok(())
}
