//! `facets bench engine`: the cases, settled (or read from a cache of settled deposits), then
//! timed on each thread count; the table's rows and their CSV.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;
use sim::World;

use super::{BOX_WIDTH, DepositSpec, Throughput, grid_scene, kinetic_over_elastic, measure};
use super::{quench, settle, stacked};
use crate::grains::GrainKind;
use crate::io::write_atomic;

/// Longest settling of a deposit built from the grid (s); most reach kinetic / elastic < 1e-4
/// well before.
const SETTLE_MAX_S: f64 = 1.5;

/// How the 30 000-square case is built from ten settled 3 000-square deposits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Layout {
    /// The 3 000 case's rule in a box ten times as wide.
    Wide,
    /// Ten copies of the settled 3 000 on each other, settled again.
    Stacked,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct EngineBench {
    /// (kind, grain count) of each case.
    pub cases: Vec<(GrainKind, usize)>,
    /// The 30 000-square cases to add (with the 3 000-square case they are built from).
    pub scaling: Vec<Layout>,
    /// Folder of settled deposits saved by earlier runs and read back.
    pub settled_cache: Option<PathBuf>,
    /// Timed steps per run.
    pub steps: u64,
    /// Time step of the timed runs (s).
    pub time_step: f64,
    /// Time step of the settling (s).
    pub settle_time_step: f64,
    pub threads: Vec<usize>,
    /// Seed of the grain orientations.
    pub seed: u64,
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct Row {
    pub label: String,
    pub grains: usize,
    pub throughput: Throughput,
    pub world_bytes_per_grain: f64,
}

/// What the bench reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum EngineEvent<'a> {
    /// Settling `label`, at simulated time `time` (s).
    Settling { label: &'a str, time: f64 },
    /// A settled deposit read from the cache.
    Read { label: &'a str, path: &'a Path },
    /// `grains` of `label` settled (`quenched`: by the quench) to kinetic / elastic `ratio`.
    Settled {
        label: &'a str,
        grains: usize,
        ratio: f64,
        quenched: bool,
    },
    /// A row of the table.
    Row(&'a Row),
}

/// A case written KIND:COUNT (e.g. square:3000).
pub fn parse_case(text: &str) -> anyhow::Result<(GrainKind, usize)> {
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

/// Settles and times every case; the rows in order.
pub fn run(bench: &EngineBench, progress: &dyn Fn(EngineEvent)) -> anyhow::Result<Vec<Row>> {
    let mut cases = bench.cases.clone();
    if !bench.scaling.is_empty() && !cases.contains(&(GrainKind::Square, 3000)) {
        cases.push((GrainKind::Square, 3000));
    }
    let mut rows = Vec::new();
    for (kind, n) in cases {
        let spec = DepositSpec {
            kind,
            grains: n,
            seed: bench.seed,
            width: BOX_WIDTH,
        };
        let base = settled(bench, &kind.to_string(), n, SETTLE_MAX_S, progress, &|| {
            grid_scene(&spec, bench.settle_time_step)
        })?;
        let mut worlds = vec![(base, kind.to_string())];
        if kind == GrainKind::Square && n == 3000 {
            for &layout in &bench.scaling {
                let label = format!("{kind} {layout:?}").to_lowercase();
                let big = match layout {
                    Layout::Wide => {
                        settled(bench, &label, 10 * n, SETTLE_MAX_S, progress, &|| {
                            grid_scene(
                                &DepositSpec {
                                    grains: 10 * n,
                                    width: 10.0 * BOX_WIDTH,
                                    ..spec
                                },
                                bench.settle_time_step,
                            )
                        })?
                    }
                    // Stacked touching: a gap would let each copy fall free and open its
                    // contacts. The column takes up ten times the weight and keeps compacting
                    // for seconds; 0.3 s is the rule the LAMMPS peer shares (benches/peers/).
                    Layout::Stacked => settled(bench, &label, 10 * n, 0.3, progress, &|| {
                        stacked(&worlds[0].0, 10, 0.0)
                    })?,
                };
                worlds.push((big, label));
            }
        }
        for (world, label) in &worlds {
            let grains = world.len();
            let world_bytes_per_grain = world.memory_bytes() as f64 / grains as f64;
            for &threads in &bench.threads {
                let row = Row {
                    label: label.clone(),
                    grains,
                    throughput: measure(world, bench.time_step, bench.steps, threads)?,
                    world_bytes_per_grain,
                };
                progress(EngineEvent::Row(&row));
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// A deposit settled by the scene rule (quenched if still moving), or read from what an
/// earlier run with the same key saved in the cache.
fn settled(
    bench: &EngineBench,
    label: &str,
    grains: usize,
    max_time: f64,
    progress: &dyn Fn(EngineEvent),
    build: &dyn Fn() -> anyhow::Result<World>,
) -> anyhow::Result<World> {
    let key = format!(
        "{label}-{grains}-seed{}-dt{:e}-{max_time}s",
        bench.seed, bench.settle_time_step
    )
    .replace(' ', "-");
    let mut world = cached(bench.settled_cache.as_deref(), &key, progress, || {
        let mut world = build()?;
        let ratio = settle(&mut world, max_time, |time| {
            progress(EngineEvent::Settling { label, time })
        })?;
        progress(EngineEvent::Settled {
            label,
            grains,
            ratio,
            quenched: false,
        });
        Ok(world)
    })?;
    if kinetic_over_elastic(&world) >= 1e-4 {
        let ratio = quench(&mut world)?;
        progress(EngineEvent::Settled {
            label,
            grains,
            ratio,
            quenched: true,
        });
    }
    Ok(world)
}

/// The world saved under `key` in `cache` by this version of facets, or `build`'s, saved there.
fn cached(
    cache: Option<&Path>,
    key: &str,
    progress: &dyn Fn(EngineEvent),
    build: impl FnOnce() -> anyhow::Result<World>,
) -> anyhow::Result<World> {
    let Some(dir) = cache else {
        return build();
    };
    let path = dir.join(format!("{key}-facets-{}.bin", env!("CARGO_PKG_VERSION")));
    if path.exists() {
        let bytes =
            std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        progress(EngineEvent::Read {
            label: key,
            path: &path,
        });
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

/// Writes the rows as CSV.
pub fn write_csv(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        writeln!(
            w,
            "grains,n,threads,steps,wall_s,grain_steps_per_s,cpu_s,sub_contacts,world_bytes_per_grain"
        )?;
        for r in rows {
            let t = &r.throughput;
            writeln!(
                w,
                "{},{},{},{},{:.4},{:.1},{:.4},{},{:.0}",
                r.label,
                r.grains,
                t.threads,
                t.steps,
                t.seconds,
                t.grain_steps_per_second,
                t.cpu_seconds,
                t.contacts,
                r.world_bytes_per_grain
            )?;
        }
        Ok(())
    })
}
