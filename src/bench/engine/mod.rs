//! Engine throughput on settled dense deposits (issue: DEM core, "Speed").
//!
//! The scene is defined so that a peer code can build the same one (benches/peers/): a box of
//! width W = 256 mm (or a multiple of it) with a floor and two side walls; grains on a square
//! grid of pitch 1.1 x sqrt(L^2 + D^2), n_c = floor(W / pitch) columns, centres at
//! x = pitch/2 + k pitch and rows from y = pitch/2 up, filled row by row, random orientation
//! in [0, 2 pi), at rest; settled under gravity with a coarse step (and quenched if still
//! moving), then timed at the paper's 1e-6 s.

mod run;

use std::time::Instant;

use anyhow::Context;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::{ContactLaw, GrainState, ShapeId, Vec2, Wall, World, WorldSettings};

use crate::grains::{DEFAULT_ROUNDING, GrainKind};

pub use run::{EngineBench, EngineEvent, Layout, Row, parse_case, run, write_csv};

/// Width of the benchmark box (m).
pub const BOX_WIDTH: f64 = 0.256;

/// One deposit to settle.
#[derive(Clone, Copy, Debug)]
pub struct DepositSpec {
    pub kind: GrainKind,
    pub grains: usize,
    pub seed: u64,
    /// Width of the box (m): [`BOX_WIDTH`], or a multiple of it for a wider deposit of the
    /// same depth.
    pub width: f64,
}

/// An empty box of `width` (m): floor at y = 0, side walls at x = 0 and x = `width`, with the
/// paper's contact law and the grain kind's outline registered as shape 0.
fn empty_box(kind: GrainKind, width: f64, time_step: f64) -> anyhow::Result<(World, ShapeId)> {
    let mut world = World::new(WorldSettings {
        law: ContactLaw::default(),
        gravity: Vec2::new(0.0, -10.0),
        time_step: Some(time_step),
        ..WorldSettings::default()
    })?;
    world.add_wall(Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)))?;
    world.add_wall(Wall::new(Vec2::zeros(), Vec2::new(1.0, 0.0)))?;
    world.add_wall(Wall::new(Vec2::new(width, 0.0), Vec2::new(-1.0, 0.0)))?;
    let shape = world.add_shape(kind.outline(DEFAULT_ROUNDING)?, kind.areal_density())?;
    Ok((world, shape))
}

/// Builds the grid of grains in the box, at rest, with the paper's contact law.
pub fn grid_scene(spec: &DepositSpec, time_step: f64) -> anyhow::Result<World> {
    let kind = spec.kind;
    let (mut world, shape) = empty_box(kind, spec.width, time_step)?;
    let pitch = 1.1 * kind.length().hypot(kind.width());
    let columns = (spec.width / pitch).floor() as usize;
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    for k in 0..spec.grains {
        let (row, col) = (k / columns, k % columns);
        let position = Vec2::new(pitch * (col as f64 + 0.5), pitch * (row as f64 + 0.5));
        let angle = rng.random::<f64>() * std::f64::consts::TAU;
        world.add_grain(shape, GrainState::at_rest(position, angle))?;
    }
    Ok(world)
}

/// Lets the grid fall and settle until the kinetic energy is below `1e-4` of the elastic
/// energy (docs/model.md §2's relaxation criterion), checked every 1000 steps, or until `max_time`
/// (s): a throughput benchmark needs a dense deposit near rest. `progress` gets the simulated
/// time. Returns kinetic / elastic at the end.
pub fn settle(
    world: &mut World,
    max_time: f64,
    mut progress: impl FnMut(f64),
) -> anyhow::Result<f64> {
    // Nothing can be at rest before the top row has had time to land.
    let top = world
        .grains()
        .position
        .iter()
        .map(|p| p.y)
        .fold(0.0, f64::max);
    let fall_time = world.time() + (2.0 * top / 10.0).sqrt();
    let end = world.time() + max_time;
    loop {
        world
            .run(1000)
            .context("while settling the benchmark deposit")?;
        progress(world.time());
        let ratio = kinetic_over_elastic(world);
        if (world.time() > fall_time && ratio < 1e-4) || world.time() > end {
            return Ok(ratio);
        }
    }
}

/// Longest duration (s) and rate (1/s) of [`quench`]; the rate is the LAMMPS peer's
/// (benches/peers/).
pub const QUENCH: (f64, f64) = (0.25, 100.0);

/// Brings a deposit that [`settle`] left moving to rest: its touching grains lose their
/// velocity at [`QUENCH`]'s rate until kinetic / elastic < 1e-4, checked every 1000 steps, or
/// for at most its duration. Some deposits keep flowing for seconds (30 000 squares in a
/// 2.56 m box: kinetic / elastic 4e-2 after 1.5 s, in slow avalanches), and a throughput
/// measured on a flowing deposit is not one on a settled one. Returns kinetic / elastic.
pub fn quench(world: &mut World) -> anyhow::Result<f64> {
    let (duration, rate) = QUENCH;
    let end = world.time() + duration;
    world.set_drag(rate)?;
    let ratio = loop {
        world
            .run(1000)
            .context("while quenching the benchmark deposit")?;
        let ratio = kinetic_over_elastic(world);
        if ratio < 1e-4 || world.time() >= end {
            break ratio;
        }
    };
    world.set_drag(0.0)?;
    Ok(ratio)
}

/// The relaxation measure of docs/model.md §2.
pub fn kinetic_over_elastic(world: &World) -> f64 {
    let e = world.energies();
    e.kinetic / e.elastic
}

/// `copies` copies of a settled deposit stacked with `gap` between them (the 30 000-grain
/// case: a grid 14 m tall would take hours to settle; the peer benchmark does the same).
pub fn stacked(settled: &World, copies: usize, gap: f64) -> anyhow::Result<World> {
    let mut world = settled.clone();
    let g = settled.grains();
    let height = g.position.iter().map(|p| p.y).fold(0.0, f64::max)
        + settled.shape(settled.shape_of(0)).bounding_radius();
    for copy in 1..copies {
        let lift = Vec2::new(0.0, copy as f64 * (height + gap));
        for i in 0..settled.len() {
            let state = GrainState::at_rest(g.position[i] + lift, g.angle[i]);
            world.add_grain(settled.shape_of(i), state)?;
        }
    }
    Ok(world)
}

/// Throughput of one timed run.
#[derive(Clone, Copy, Debug)]
pub struct Throughput {
    pub threads: usize,
    pub steps: u64,
    pub seconds: f64,
    pub grain_steps_per_second: f64,
    /// Processor time used by the run, all threads (s). On a loaded machine the wall time
    /// measures the other processes too; grain-steps per CPU second do not.
    pub cpu_seconds: f64,
    /// Sub-contacts at the end of the run (a check that the deposit is dense).
    pub contacts: usize,
    /// Grain pairs in the Verlet list at the end of the run.
    pub pairs: usize,
}

/// Runs `steps` steps of a copy of `world` at `time_step` on `threads` threads.
pub fn measure(
    world: &World,
    time_step: f64,
    steps: u64,
    threads: usize,
) -> anyhow::Result<Throughput> {
    let mut w = world.clone();
    w.set_time_step(time_step)?;
    w.prime()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the thread pool")?;
    let (start, cpu_start) = (Instant::now(), super::process::cpu_time());
    pool.install(|| w.run(steps))?;
    let seconds = start.elapsed().as_secs_f64();
    let cpu_seconds = super::process::cpu_time() - cpu_start;
    Ok(Throughput {
        threads,
        steps,
        seconds,
        grain_steps_per_second: (w.len() as f64 * steps as f64) / seconds,
        cpu_seconds,
        contacts: w.contacts().count(),
        pairs: w.neighbour_pairs().0,
    })
}
