//! Diagnostic: steps the engine benchmark's settled deposit on one thread, for counting
//! instructions with a tool that does not depend on the machine's load (this machine has no
//! hardware counters; `valgrind --tool=callgrind` counts them exactly):
//!
//! cargo run --release --example engine_instructions -- KIND:COUNT STEPS SETTLED.bin
//! valgrind --tool=callgrind target/release/examples/engine_instructions square:3000 200 SETTLED.bin
//!
//! The first run settles the deposit (as `facets bench engine` does) and saves it to
//! SETTLED.bin; later runs load it, so every build steps the same world from the same state.

use anyhow::Context;
use facets::bench::engine::{BOX_WIDTH, DepositSpec, grid_scene, settle};
use facets::grains::GrainKind;
use sim::World;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() == 4,
        "usage: engine_instructions KIND:COUNT STEPS SETTLED.bin"
    );
    let (kind, count) = args[1]
        .split_once(':')
        .with_context(|| format!("`{}`: expected KIND:COUNT", args[1]))?;
    let kind: GrainKind = kind.parse().map_err(|e| anyhow::anyhow!("{e}"))?;
    let grains: usize = count
        .parse()
        .with_context(|| format!("`{count}`: a count"))?;
    let steps: u64 = args[2]
        .parse()
        .with_context(|| format!("`{}`: steps", args[2]))?;
    let path = std::path::Path::new(&args[3]);
    let mut world: World = if path.exists() {
        postcard::from_bytes(&std::fs::read(path)?).context("cannot read the settled world")?
    } else {
        let spec = DepositSpec {
            kind,
            grains,
            seed: 1,
            width: BOX_WIDTH,
        };
        let mut world = grid_scene(&spec, 2e-5)?;
        settle(&mut world, 1.0, |_| {})?;
        std::fs::write(path, postcard::to_stdvec(&world)?)?;
        world
    };
    world.set_time_step(1e-6)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| world.run(steps))?;
    let e = world.energies();
    println!(
        "{} grains, {} steps: kinetic {:.6e} J, elastic {:.6e} J",
        world.len(),
        steps,
        e.kinetic,
        e.elastic
    );
    Ok(())
}
