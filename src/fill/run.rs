use std::collections::VecDeque;
use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use sim::{Body, GrainState, Vec2, World};

use super::outline::Placed;
use super::output::write_outputs;
use super::record::{EnergiesRecord, RunRecord};
use super::silo::{FLOOR, LEFT_WALL, RIGHT_WALL, Silo};
use super::vtk::write_vtk;
use crate::scene::{Insertion, Scene};

/// Where a run stands, for a progress bar.
#[derive(Clone, Copy, Debug)]
pub struct FillProgress {
    /// Simulated time (s).
    pub time: f64,
    pub inserted: usize,
    pub total: usize,
    /// Guess of the simulated time at the end: the filling time plus a relaxation allowance.
    pub expected_end: f64,
    pub relaxing: bool,
    /// Mean kinetic over mean elastic energy at the last relaxation check (NaN while filling).
    pub energy_ratio: f64,
    /// |load on floor and walls - weight| / weight at the last check (NaN while filling).
    pub load_imbalance: f64,
    /// Grains asleep (not integrated) now.
    pub asleep: usize,
}

/// A grain slower than this fraction of the inflow speed and touching something has landed.
const SETTLED_SPEED_FRACTION: f64 = 0.25;
/// Relaxation allowance for the progress estimate (s); relaxation takes tenths of a second.
const RELAXATION_GUESS: f64 = 0.3;

/// Fills the silo of `scene` with the grains of seed `seed`, relaxes the deposit and writes the
/// run's files into `out` (created if missing; checked writable before simulating). The run is
/// deterministic given scene and seed.
pub fn fill(
    scene: &Scene,
    seed: u64,
    out: &Path,
    progress: &mut dyn FnMut(FillProgress),
) -> anyhow::Result<RunRecord> {
    let start = Instant::now();
    super::output::check_writable(out)?;
    let mut silo = Silo::new(scene, seed)?;
    let dt = silo.world.time_step();
    let period = silo.feeder.period();
    let check_steps = ((scene.run.check_interval_s / dt).round() as u64).max(1);
    let snapshot_every = scene.output.snapshot_every_steps;
    if snapshot_every.is_some() {
        let dir = out.join("snapshots");
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let fill_time = silo.feeder.total as f64 / silo.feeder.rate();
    let mut events: Vec<(f64, usize)> = Vec::new();
    let mut next_band = 0.0;
    let mut last_insertion = 0.0;
    let mut stalled_bands = 0usize;
    let (mut energy_ratio, mut imbalance) = (f64::NAN, f64::NAN);
    // (time, kinetic, elastic) at the checks of the last `relaxation_hold_s`.
    let mut window: VecDeque<(f64, f64, f64)> = VecDeque::new();
    let relaxed = loop {
        let world = &silo.world;
        if !silo.feeder.done() && world.time() >= next_band - 0.5 * dt {
            let placed = insert_band(&mut silo)?;
            next_band += period;
            if placed > 0 {
                last_insertion = silo.world.time();
                stalled_bands = 0;
                // The last band is cut short by the grain count: it says nothing of the rate.
                let t = silo.world.time();
                if silo.feeder.rate() * (t + period) <= silo.feeder.total as f64 {
                    events.push((t, silo.feeder.inserted));
                }
            } else if silo.feeder.due(silo.world.time()) > silo.feeder.inserted {
                stalled_bands += 1;
                anyhow::ensure!(
                    stalled_bands < 1000,
                    "the feeder found no room for a grain in 1000 bands in a row (t = {:.3} s, {} grains in): the insertion band is blocked",
                    silo.world.time(),
                    silo.feeder.inserted
                );
            }
        }
        let world = &silo.world;
        // Steps to the next thing to do: a band, a relaxation check, a snapshot.
        let mut steps = check_steps - world.steps() % check_steps;
        if !silo.feeder.done() {
            let to_band = ((next_band - world.time()) / dt).ceil().max(1.0) as u64;
            steps = steps.min(to_band);
        }
        if let Some(k) = snapshot_every {
            steps = steps.min(k - world.steps() % k);
        }
        silo.world
            .run(steps)
            .with_context(|| format!("seed {seed}: the simulation failed"))?;
        let world = &silo.world;
        if let Some(k) = snapshot_every {
            if world.steps() % k == 0 {
                let path = out.join(format!("snapshots/step-{:09}.vtk", world.steps()));
                write_vtk(&path, world)?;
            }
        }
        if world.steps() % check_steps == 0 {
            progress(FillProgress {
                time: world.time(),
                inserted: silo.feeder.inserted,
                total: silo.feeder.total,
                expected_end: fill_time.max(last_insertion) + RELAXATION_GUESS,
                relaxing: silo.feeder.done(),
                energy_ratio,
                load_imbalance: imbalance,
                asleep: world.sleeping(),
            });
            if silo.feeder.done() {
                if scene.model.wake_to_relax && world.sleep_settings().is_some() {
                    silo.world.set_sleep(None)?;
                }
                let world = &silo.world;
                let e = world.energies();
                window.push_back((world.time(), e.kinetic, e.elastic));
                // Keep the newest stretch that spans the hold time, and no more.
                while window.len() > 1 && world.time() - window[1].0 >= scene.run.relaxation_hold_s
                {
                    window.pop_front();
                }
                let n = window.len() as f64;
                let kinetic = window.iter().map(|w| w.1).sum::<f64>() / n;
                let elastic = window.iter().map(|w| w.2).sum::<f64>() / n;
                energy_ratio = kinetic / elastic;
                let full = world.time() - window[0].0 >= scene.run.relaxation_hold_s;
                imbalance = load_imbalance(world);
                if full
                    && kinetic < scene.run.relaxation_ratio * elastic
                    && imbalance < scene.run.load_balance
                {
                    break true;
                }
                if world.time() - last_insertion > scene.run.max_relaxation_time_s {
                    break false;
                }
            }
        }
    };
    let world = &silo.world;
    let e = world.energies();
    let mut record = RunRecord {
        facets_version: env!("CARGO_PKG_VERSION").to_string(),
        scene: scene.clone(),
        seed,
        insertion: scene.feed.insertion,
        grains: world.len(),
        time_step_s: dt,
        steps: world.steps(),
        simulated_time_s: world.time(),
        fill_time_s: last_insertion,
        relaxed,
        wall_time_s: 0.0,
        energies: EnergiesRecord {
            kinetic_j: e.kinetic,
            elastic_j: e.elastic,
            potential_j: e.potential,
            switching_j: e.switching,
        },
        feed_rate_target_per_s: silo.feeder.rate(),
        feed_rate_measured_per_s: slope(&events),
        band_height_mm: silo.feeder.band_height * 1e3,
        insertion_events: events.len(),
        packing_fraction: f64::NAN,
        frame_mm: None,
        deposit_height_mm: 0.0,
        overflow: false,
        weight_n: (0..world.len())
            .map(|i| world.grains().mass[i] * scene.contact.gravity_m_s2)
            .sum(),
        floor_load_n: load(world, FLOOR),
        left_wall_load_n: load(world, LEFT_WALL),
        right_wall_load_n: load(world, RIGHT_WALL),
        deepest_overlap_mm: world.contacts().map(|c| c.overlap).fold(0.0, f64::max) * 1e3,
    };
    record.wall_time_s = start.elapsed().as_secs_f64();
    write_outputs(out, &silo, &mut record)?;
    Ok(record)
}

/// Inserts the grains due, in the band above the free surface (or at its fixed height).
fn insert_band(silo: &mut Silo) -> anyhow::Result<usize> {
    let world = &silo.world;
    let bottom = match silo.insertion {
        Insertion::Fixed => silo.fixed_bottom,
        Insertion::Surface => free_surface(world, silo.feeder.speed, silo.reach) + silo.gap,
    };
    let half = silo.feeder.half;
    let existing: Vec<Placed> = (0..world.len())
        .map(|i| {
            let g = world.grain(i);
            Placed {
                centre: g.position,
                angle: g.angle,
                half,
            }
        })
        .collect();
    let time = world.time();
    let new = silo.feeder.band(time, bottom, &existing);
    let velocity = Vec2::new(0.0, -silo.feeder.speed);
    for &(position, angle) in &new {
        silo.world.add_grain(
            silo.shape,
            GrainState {
                position,
                angle,
                velocity,
                angular_velocity: 0.0,
            },
        )?;
    }
    Ok(new.len())
}

/// Top of the highest grain that has landed (touches something and moves slower than a
/// quarter of the inflow speed); the floor when none has. A grain at the top of a bounce is
/// slow but touches nothing, so it does not lift the surface.
pub(crate) fn free_surface(world: &World, speed: f64, reach: f64) -> f64 {
    let mut touching = vec![false; world.len()];
    for c in world.contacts() {
        touching[c.first] = true;
        if let Body::Grain(j) = c.second {
            touching[j] = true;
        }
    }
    (0..world.len())
        .filter(|&i| touching[i])
        .map(|i| world.grain(i))
        .filter(|g| g.velocity.norm() < SETTLED_SPEED_FRACTION * speed)
        .map(|g| g.position.y + reach)
        .fold(0.0, f64::max)
}

/// |grains' load on floor and walls - their weight| / weight: zero for a deposit at rest.
fn load_imbalance(world: &World) -> f64 {
    let gravity = world.settings().gravity;
    let mass: f64 = world.grains().mass.iter().sum();
    let load: Vec2 = (0..world.walls().len()).map(|k| world.wall_load(k)).sum();
    (load - gravity * mass).norm() / (mass * gravity.norm())
}

fn load(world: &World, wall: usize) -> [f64; 2] {
    let f = world.wall_load(wall);
    [f.x, f.y]
}

/// Least-squares slope of the cumulative count against time (grains per second).
fn slope(events: &[(f64, usize)]) -> f64 {
    if events.len() < 2 {
        return f64::NAN;
    }
    let n = events.len() as f64;
    let mt = events.iter().map(|e| e.0).sum::<f64>() / n;
    let mc = events.iter().map(|e| e.1 as f64).sum::<f64>() / n;
    let (mut num, mut den) = (0.0, 0.0);
    for &(t, c) in events {
        num += (t - mt) * (c as f64 - mc);
        den += (t - mt) * (t - mt);
    }
    num / den
}
