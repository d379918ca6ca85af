use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::Context;
use serde::{Deserialize, Serialize};
use sim::{Body, GrainState, Vec2, World};

use super::checkpoint::{CHECKPOINT_FILE, Checkpoint, write_checkpoint};
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

/// When a fill stops before its end, leaving a checkpoint in its folder.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum StopAt {
    #[default]
    Never,
    /// Once this many steps are done in all (counted from the start of the run).
    Steps(u64),
    /// At the first step boundary at or after this simulated time (s).
    Time(f64),
}

/// How a fill starts and when it stops early.
#[derive(Debug, Default)]
pub struct FillControl<'a> {
    /// Continue this checkpoint; it must be of the same scene and seed.
    pub resume: Option<Checkpoint>,
    pub stop: StopAt,
    /// When this becomes true (a Ctrl-C handler sets it), the run stops at the next step
    /// boundary it checks (at most [`STEPS_BETWEEN_STOP_CHECKS`] steps later) and writes a
    /// checkpoint.
    pub interrupt: Option<&'a AtomicBool>,
}

/// How a fill ended.
#[derive(Debug)]
pub enum FillOutcome {
    /// Filled and relaxed (or out of relaxation time); the run's files are written.
    Finished(Box<RunRecord>),
    /// Stopped early; `checkpoint` continues it.
    Stopped {
        checkpoint: PathBuf,
        time: f64,
        steps: u64,
        /// Grains poured so far.
        grains: usize,
    },
}

/// Steps run without looking at [`FillControl::interrupt`].
pub const STEPS_BETWEEN_STOP_CHECKS: u64 = 1000;

/// The fill loop's own state, beside the world and the feeder: what a checkpoint needs to
/// continue the loop exactly where it stood.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct FillState {
    /// (time, grains in) after each full band, for the measured feed rate.
    events: Vec<(f64, usize)>,
    /// Simulated time of the next insertion band (s).
    next_band: f64,
    last_insertion: f64,
    stalled_bands: usize,
    energy_ratio: f64,
    imbalance: f64,
    /// (time, kinetic, elastic) at the checks of the last `relaxation_hold_s`.
    window: VecDeque<(f64, f64, f64)>,
    /// Step at which the stretch of steps under way ends and the loop next decides what to do;
    /// a run stopped inside a stretch finishes it before deciding anything.
    stretch_end: u64,
    /// Simulated time of the next periodic checkpoint (s).
    next_checkpoint: f64,
    /// Wall time spent by the sessions before this one (s).
    wall_time_before: f64,
}

impl FillState {
    fn new(scene: &Scene) -> Self {
        Self {
            events: Vec::new(),
            next_band: 0.0,
            last_insertion: 0.0,
            stalled_bands: 0,
            energy_ratio: f64::NAN,
            imbalance: f64::NAN,
            window: VecDeque::new(),
            stretch_end: 0,
            next_checkpoint: scene.output.checkpoint_every_s.unwrap_or(f64::INFINITY),
            wall_time_before: 0.0,
        }
    }
}

/// Fills the silo of `scene` with the grains of seed `seed`, relaxes the deposit and writes the
/// run's files into `out` (created if missing; checked writable before simulating). The run is
/// deterministic given scene and seed.
pub fn fill(
    scene: &Scene,
    seed: u64,
    out: &Path,
    progress: &mut dyn FnMut(FillProgress),
) -> anyhow::Result<RunRecord> {
    match fill_with(scene, seed, out, FillControl::default(), progress)? {
        FillOutcome::Finished(record) => Ok(*record),
        FillOutcome::Stopped { .. } => unreachable!("a fill without a stop runs to its end"),
    }
}

/// [`fill`], started from a checkpoint or stopped early as `control` says. A run stopped and
/// resumed, however many times, writes the same files as one run through (run.json's wall time
/// aside); with `[output] checkpoint_every_s` the run also leaves checkpoints on its way.
pub fn fill_with(
    scene: &Scene,
    seed: u64,
    out: &Path,
    control: FillControl,
    progress: &mut dyn FnMut(FillProgress),
) -> anyhow::Result<FillOutcome> {
    let start = Instant::now();
    super::output::check_writable(out)?;
    let mut silo = Silo::new(scene, seed)?;
    let mut st = match control.resume {
        Some(checkpoint) => {
            checkpoint.check_matches(scene, seed)?;
            checkpoint.restore(&mut silo)
        }
        None => FillState::new(scene),
    };
    let checkpoint_path = out.join(CHECKPOINT_FILE);
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
    let relaxed = loop {
        if silo.world.steps() == st.stretch_end {
            if !silo.feeder.done() && silo.world.time() >= st.next_band - 0.5 * dt {
                let placed = insert_band(&mut silo)?;
                st.next_band += period;
                if placed > 0 {
                    st.last_insertion = silo.world.time();
                    st.stalled_bands = 0;
                    // The last band is cut short by the grain count: it says nothing of the rate.
                    let t = silo.world.time();
                    if silo.feeder.rate() * (t + period) <= silo.feeder.total as f64 {
                        st.events.push((t, silo.feeder.inserted));
                    }
                } else if silo.feeder.due(silo.world.time()) > silo.feeder.inserted {
                    st.stalled_bands += 1;
                    anyhow::ensure!(
                        st.stalled_bands < 1000,
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
                let to_band = ((st.next_band - world.time()) / dt).ceil().max(1.0) as u64;
                steps = steps.min(to_band);
            }
            if let Some(k) = snapshot_every {
                steps = steps.min(k - world.steps() % k);
            }
            st.stretch_end = world.steps() + steps;
        }
        let world = &silo.world;
        let mut target = st
            .stretch_end
            .min(world.steps() + STEPS_BETWEEN_STOP_CHECKS);
        if let Some(stop) = stop_step(control.stop, world) {
            target = target.min(stop);
        }
        silo.world
            .run(target - silo.world.steps())
            .with_context(|| format!("seed {seed}: the simulation failed"))?;
        let world = &silo.world;
        if world.steps() == st.stretch_end {
            if let Some(k) = snapshot_every {
                if world.steps() % k == 0 {
                    let path = out.join(format!("snapshots/step-{:09}.vtu", world.steps()));
                    write_vtk(&path, &silo, scene.grains.length(), scene.grains.width())?;
                }
            }
            if world.steps() % check_steps == 0 {
                progress(FillProgress {
                    time: world.time(),
                    inserted: silo.feeder.inserted,
                    total: silo.feeder.total,
                    expected_end: fill_time.max(st.last_insertion) + RELAXATION_GUESS,
                    relaxing: silo.feeder.done(),
                    energy_ratio: st.energy_ratio,
                    load_imbalance: st.imbalance,
                    asleep: world.sleeping(),
                });
                if silo.feeder.done() {
                    if scene.model.wake_to_relax && world.sleep_settings().is_some() {
                        silo.world.set_sleep(None)?;
                    }
                    let drag = scene.model.relaxation_drag_per_s;
                    let from_the_last_grain = scene.model.relaxation_drag_below == f64::INFINITY;
                    if from_the_last_grain && silo.world.drag() != drag {
                        silo.world.set_drag(drag)?;
                    }
                    let world = &silo.world;
                    let e = world.energies();
                    let window = &mut st.window;
                    window.push_back((world.time(), e.kinetic, e.elastic));
                    // Keep the newest stretch that spans the hold time, and no more.
                    while window.len() > 1
                        && world.time() - window[1].0 >= scene.run.relaxation_hold_s
                    {
                        window.pop_front();
                    }
                    let n = window.len() as f64;
                    let kinetic = window.iter().map(|w| w.1).sum::<f64>() / n;
                    let elastic = window.iter().map(|w| w.2).sum::<f64>() / n;
                    st.energy_ratio = kinetic / elastic;
                    let full = world.time() - window[0].0 >= scene.run.relaxation_hold_s;
                    st.imbalance = load_imbalance(&silo);
                    if full
                        && kinetic < scene.run.relaxation_ratio * elastic
                        && st.imbalance < scene.run.load_balance
                    {
                        break true;
                    }
                    if world.time() - st.last_insertion > scene.run.max_relaxation_time_s {
                        break false;
                    }
                    // A late drag starts from the next step (a relaxed deposit has stopped above).
                    if st.energy_ratio < scene.model.relaxation_drag_below
                        && silo.world.drag() != drag
                    {
                        silo.world.set_drag(drag)?;
                    }
                }
            }
            let world = &silo.world;
            if world.time() >= st.next_checkpoint {
                let every = scene.output.checkpoint_every_s.unwrap_or(f64::INFINITY);
                while st.next_checkpoint <= world.time() {
                    st.next_checkpoint += every;
                }
                save(&checkpoint_path, scene, seed, &silo, &mut st, start)?;
            }
        }
        let world = &silo.world;
        let interrupted = control
            .interrupt
            .is_some_and(|flag| flag.load(Ordering::Relaxed));
        if interrupted || stop_step(control.stop, world) == Some(world.steps()) {
            save(&checkpoint_path, scene, seed, &silo, &mut st, start)?;
            return Ok(FillOutcome::Stopped {
                checkpoint: checkpoint_path,
                time: world.time(),
                steps: world.steps(),
                grains: silo.feeder.inserted,
            });
        }
    };
    let world = &silo.world;
    let e = world.energies();
    let loads = silo.wall_loads();
    let mut record = RunRecord {
        facets_version: env!("CARGO_PKG_VERSION").to_string(),
        scene: scene.clone(),
        seed,
        insertion: scene.feed.insertion,
        grains: silo.deposit_grains().len(),
        wall_grains: silo.wall_of.len(),
        time_step_s: dt,
        steps: world.steps(),
        grain_steps: world.grain_steps(),
        simulated_time_s: world.time(),
        fill_time_s: st.last_insertion,
        relaxed,
        wall_time_s: 0.0,
        energies: EnergiesRecord {
            kinetic_j: e.kinetic,
            elastic_j: e.elastic,
            potential_j: e.potential,
            switching_j: e.switching,
        },
        feed_rate_target_per_s: silo.feeder.rate(),
        feed_rate_measured_per_s: slope(&st.events),
        band_height_mm: silo.feeder.band_height * 1e3,
        insertion_events: st.events.len(),
        packing_fraction: f64::NAN,
        frame_mm: None,
        deposit_height_mm: 0.0,
        overflow: false,
        weight_n: silo
            .deposit_grains()
            .map(|i| world.grains().mass[i] * scene.contact.gravity_m_s2)
            .sum(),
        floor_load_n: [loads[FLOOR].x, loads[FLOOR].y],
        left_wall_load_n: [loads[LEFT_WALL].x, loads[LEFT_WALL].y],
        right_wall_load_n: [loads[RIGHT_WALL].x, loads[RIGHT_WALL].y],
        plate_load_n: {
            let p = world.plate_load();
            [p.x, p.y]
        },
        deepest_overlap_mm: world.contacts().map(|c| c.overlap).fold(0.0, f64::max) * 1e3,
    };
    record.wall_time_s = st.wall_time_before + start.elapsed().as_secs_f64();
    write_outputs(out, &silo, &mut record)?;
    Ok(FillOutcome::Finished(Box::new(record)))
}

/// The step at which `stop` asks the run to stop (never before the current one).
fn stop_step(stop: StopAt, world: &World) -> Option<u64> {
    match stop {
        StopAt::Never => None,
        StopAt::Steps(n) => Some(n.max(world.steps())),
        StopAt::Time(t) => {
            let dt = world.time_step();
            let left = ((t - world.time()) / dt - 0.5).ceil().max(0.0);
            Some(world.steps() + left as u64)
        }
    }
}

/// Writes a checkpoint with the wall time spent so far.
fn save(
    path: &Path,
    scene: &Scene,
    seed: u64,
    silo: &Silo,
    st: &mut FillState,
    start: Instant,
) -> anyhow::Result<()> {
    let before = st.wall_time_before;
    st.wall_time_before += start.elapsed().as_secs_f64();
    let written = write_checkpoint(path, scene, seed, silo, st);
    st.wall_time_before = before;
    written
}

/// Inserts the grains due, in the band above the free surface (or at its fixed height).
fn insert_band(silo: &mut Silo) -> anyhow::Result<usize> {
    let world = &silo.world;
    let bottom = match silo.insertion {
        Insertion::Fixed => silo.fixed_bottom,
        Insertion::Surface => free_surface(silo) + silo.gap,
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
    let first = silo.feeder.inserted;
    let new = silo.feeder.band(time, bottom, &existing);
    for (k, &(position, angle)) in new.iter().enumerate() {
        let (velocity, angular_velocity) = silo.feeder.launch(first + k);
        silo.world.add_grain(
            silo.shape,
            GrainState {
                position,
                angle,
                velocity,
                angular_velocity,
            },
        )?;
    }
    Ok(new.len())
}

/// Top of the highest grain that has landed (touches something and moves slower than a
/// quarter of the inflow speed); the floor when none has. A grain at the top of a bounce is
/// slow but touches nothing, so it does not lift the surface. Fixed wall grains are not part
/// of the deposit: a grain brushing a side wall does not lift it.
pub(crate) fn free_surface(silo: &Silo) -> f64 {
    let world = &silo.world;
    let first = silo.deposit_grains().start;
    let mut touching = vec![false; world.len() - first];
    for c in world.contacts() {
        let (i, other, _) = silo.deposit_side(&c);
        touching[i] = true;
        if let Body::Grain(j) = other {
            touching[j] = true;
        }
    }
    let speed = silo.feeder.speed;
    (0..touching.len())
        .filter(|&i| touching[i])
        .map(|i| world.grain(first + i))
        .filter(|g| g.velocity.norm() < SETTLED_SPEED_FRACTION * speed)
        .map(|g| g.position.y + silo.reach)
        .fold(0.0, f64::max)
}

/// |deposit's load on floor and walls - its weight| / weight: zero for a deposit at rest.
fn load_imbalance(silo: &Silo) -> f64 {
    let gravity = silo.world.settings().gravity;
    let mass = silo.deposit_mass();
    let load: Vec2 = silo.wall_loads().iter().sum::<Vec2>() + silo.world.plate_load();
    (load - gravity * mass).norm() / (mass * gravity.norm())
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
