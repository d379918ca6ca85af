//! Diagnostic: steps the engine benchmark's settled deposit on one thread, for counting
//! instructions with a tool that does not depend on the machine's load (this machine has no
//! hardware counters; `valgrind --tool=callgrind` counts them exactly):
//!
//! cargo build --profile ci --example engine_instructions
//! target/ci/examples/engine_instructions square:3000 WARMUP STEPS SETTLED.bin
//! valgrind --tool=callgrind --toggle-collect='*timed_steps*' \
//!     target/ci/examples/engine_instructions square:3000 WARMUP STEPS SETTLED.bin
//!
//! The first run settles the deposit (as `facets bench engine` does: 1.5 s at 2e-5 s, then
//! quenched if still moving) and saves the world to SETTLED.bin; later runs load it, so every
//! build steps the same world from the same state (a build that saves worlds differently
//! settles its own). WARMUP steps at the paper's 1e-6 s come before the STEPS that are counted
//! (only `timed_steps` is, with the toggle above).

use anyhow::Context;
use facets::bench::engine::{
    BOX_WIDTH, DepositSpec, grid_scene, kinetic_over_elastic, quench, settle,
};
use facets::grains::GrainKind;
use sim::World;

#[inline(never)]
fn timed_steps(world: &mut World, steps: u64) -> anyhow::Result<()> {
    world.run(steps)?;
    Ok(())
}

/// A fingerprint of every grain's position, angle and velocities, bit for bit.
fn state_hash(world: &World) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for i in 0..world.len() {
        let s = world.grain(i);
        for x in [
            s.position.x,
            s.position.y,
            s.angle,
            s.velocity.x,
            s.velocity.y,
            s.angular_velocity,
        ] {
            hash = (hash ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3);
        }
    }
    hash
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() == 5,
        "usage: engine_instructions KIND:COUNT WARMUP STEPS SETTLED.bin"
    );
    let (kind, count) = args[1]
        .split_once(':')
        .with_context(|| format!("`{}`: expected KIND:COUNT", args[1]))?;
    let kind: GrainKind = kind.parse().map_err(|e| anyhow::anyhow!("{e}"))?;
    let grains: usize = count
        .parse()
        .with_context(|| format!("`{count}`: a count"))?;
    let warmup: u64 = args[2]
        .parse()
        .with_context(|| format!("`{}`: warm-up steps", args[2]))?;
    let steps: u64 = args[3]
        .parse()
        .with_context(|| format!("`{}`: steps", args[3]))?;
    let path = std::path::Path::new(&args[4]);
    let spec = DepositSpec {
        kind,
        grains,
        seed: 1,
        width: BOX_WIDTH,
    };
    let mut world: World = if path.exists() {
        postcard::from_bytes(&std::fs::read(path)?).context("cannot read the settled world")?
    } else {
        let mut world = grid_scene(&spec, 2e-5)?;
        settle(&mut world, 1.5, |_| {})?;
        if kinetic_over_elastic(&world) >= 1e-4 {
            quench(&mut world)?;
        }
        std::fs::write(path, postcard::to_stdvec(&world)?)?;
        world
    };
    world.set_time_step(1e-6)?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| world.run(warmup))?;
    pool.install(|| timed_steps(&mut world, steps))?;
    let e = world.energies();
    println!(
        "{} grains, {} + {} steps: kinetic {:.6e} J, elastic {:.6e} J, {} sub-contacts, {} rebuilds, state hash {:016x}",
        world.len(),
        warmup,
        steps,
        e.kinetic,
        e.elastic,
        world.contacts().count(),
        world.verlet_rebuilds(),
        state_hash(&world)
    );
    Ok(())
}
