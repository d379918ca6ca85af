use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};

use facets::bench::engine::{self, DepositSpec};
use facets::grains::GrainKind;
use facets::io::write_atomic;
use sim::World;

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

/// Longest settling of a deposit built from the grid (s); most reach kinetic / elastic < 1e-4
/// well before.
const SETTLE_MAX_S: f64 = 1.5;

/// The world saved under `key` in `cache` by this version of facets, or `build`'s, saved there.
fn cached(
    cache: Option<&Path>,
    key: &str,
    build: impl FnOnce() -> anyhow::Result<World>,
) -> anyhow::Result<World> {
    let Some(dir) = cache else {
        return build();
    };
    let path = dir.join(format!("{key}-facets-{}.bin", env!("CARGO_PKG_VERSION")));
    if path.exists() {
        let bytes =
            std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        eprintln!("{key}: settled deposit read from {}", path.display());
        return postcard::from_bytes(&bytes).with_context(|| {
            format!(
                "{}: not a settled world of this build of facets (delete it)",
                path.display()
            )
        });
    }
    let world = build()?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    write_atomic(&path, |w| {
        w.write_all(&postcard::to_stdvec(&world)?)?;
        Ok(())
    })?;
    Ok(world)
}

/// How the 30 000-square case is built from ten settled 3 000-square deposits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Layout {
    Wide,
    Stacked,
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
    if !args.scaling.is_empty() && !cases.contains(&(GrainKind::Square, 3000)) {
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
            width: engine::BOX_WIDTH,
        };
        let bar = ProgressBar::new_spinner().with_style(
            ProgressStyle::with_template("{spinner} settling {msg} [{elapsed}]").unwrap(),
        );
        // Settles by the scene rule (quenched if still moving), or reads what an earlier run
        // with the same key saved.
        let settled = |label: &str,
                       grains: usize,
                       max_time: f64,
                       build: &dyn Fn() -> anyhow::Result<World>| {
            let key = format!(
                "{label}-{grains}-seed{}-dt{:e}-{max_time}s",
                args.seed, args.settle_dt
            )
            .replace(' ', "-");
            let mut world = cached(args.settled_cache.as_deref(), &key, || {
                let mut world = build()?;
                let ratio = engine::settle(&mut world, max_time, |t| {
                    bar.set_message(format!("{label}: t = {t:.3} s"));
                    bar.tick();
                })?;
                eprintln!("{grains} {label}: settled to kinetic / elastic = {ratio:.1e}");
                Ok(world)
            })?;
            if engine::kinetic_over_elastic(&world) >= 1e-4 {
                bar.set_message(format!("{label}: quench"));
                let ratio = engine::quench(&mut world)?;
                eprintln!("{grains} {label}: quenched to kinetic / elastic = {ratio:.1e}");
            }
            Ok::<_, anyhow::Error>(world)
        };
        let base = settled(&kind.to_string(), n, SETTLE_MAX_S, &|| {
            engine::grid_scene(&spec, args.settle_dt)
        })?;
        let mut worlds = vec![(base, kind.to_string())];
        if kind == GrainKind::Square && n == 3000 {
            for &layout in &args.scaling {
                let label = format!("{kind} {layout:?}").to_lowercase();
                let big = match layout {
                    Layout::Wide => settled(&label, 10 * n, SETTLE_MAX_S, &|| {
                        engine::grid_scene(
                            &DepositSpec {
                                grains: 10 * n,
                                width: 10.0 * engine::BOX_WIDTH,
                                ..spec
                            },
                            args.settle_dt,
                        )
                    })?,
                    // Stacked touching: a gap would let each copy fall free and open its
                    // contacts. The column takes up ten times the weight and keeps compacting
                    // for seconds; 0.3 s is the rule the LAMMPS peer shares (benches/peers/).
                    Layout::Stacked => settled(&label, 10 * n, 0.3, &|| {
                        engine::stacked(&worlds[0].0, 10, 0.0)
                    })?,
                };
                worlds.push((big, label));
            }
        }
        bar.finish_and_clear();
        for (world, label) in &worlds {
            let n = world.len();
            let bytes_per_grain = world.memory_bytes() as f64 / n as f64;
            for &threads in &args.threads {
                let t = engine::measure(world, args.dt, args.steps, threads)?;
                println!(
                    "| {label} | {n} | {threads} | {} | {:.2} | {:.3e} | {:.2} | {:.3e} | {} | {} | {:.0} |",
                    t.steps,
                    t.seconds,
                    t.grain_steps_per_second,
                    t.cpu_seconds,
                    (n as f64 * t.steps as f64) / t.cpu_seconds,
                    t.contacts,
                    t.pairs,
                    bytes_per_grain
                );
                rows.push((label.clone(), n, t, bytes_per_grain));
            }
        }
    }
    if let Some(peak) = facets::bench::process::peak_memory() {
        println!(
            "peak resident memory of this run: {:.0} MB",
            peak as f64 / 1e6
        );
    }
    if let Some(path) = &args.csv {
        write_atomic(path, |w| {
            writeln!(
                w,
                "grains,n,threads,steps,wall_s,grain_steps_per_s,cpu_s,sub_contacts,world_bytes_per_grain"
            )?;
            for (label, n, t, b) in &rows {
                writeln!(
                    w,
                    "{label},{n},{},{},{:.4},{:.1},{:.4},{},{:.0}",
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
