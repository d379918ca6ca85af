//! Resources of a task: CPU time, memory and a time limit, from the plan's sizes (grains, feed
//! rate, time step, relaxation allowance, photograph pixels) and the engine's measured rate.
//!
//! A filling's work is counted in grain-steps: the steps of its filling time with on average
//! half its grains (plus any wall grains) in the silo, then the steps of the last grains' fall
//! and of the whole relaxation allowance with all of them. Grains asleep cost less, so this
//! is an upper bound of the engine's work. A photograph's detection is counted per pixel.

use std::path::Path;

use anyhow::Context;

use crate::fill::Silo;
use crate::reproduce::plan::Plan;
use crate::reproduce::shard::Unit;
use crate::reproduce::simulate::{Filling, Side};
use crate::scene::FrameChoice;

/// Detector processor time per megapixel of photograph (s), on lab-style photographs of the
/// three shapes (docs/results/cluster-estimates.md).
pub const DETECT_CPU_SECONDS_PER_MEGAPIXEL: f64 = 6.0;
/// Peak memory of a detection per pixel of photograph (bytes; same source).
pub const DETECT_BYTES_PER_PIXEL: f64 = 100.0;
/// Memory of a filling per grain (bytes): the world, its contacts and neighbour lists, the
/// deposit and contact tables; generous.
pub const FILLING_BYTES_PER_GRAIN: f64 = 20_000.0;
/// Memory of the process before any work (MB).
pub const BASE_MEMORY_MB: f64 = 256.0;
/// The time limit is this many times the estimate, plus [`TIME_MARGIN_S`]: a shared node runs
/// slower than the measurement, and a task that hits its limit has to run again.
pub const TIME_SAFETY: f64 = 2.0;
pub const TIME_MARGIN_S: f64 = 600.0;
/// Packing fraction assumed for a deposit's height when the photograph shows the whole
/// deposit: lower than any measured one, so the height is an upper bound.
const LOOSE_PACKING: f64 = 0.5;
/// Height of region E (mm), the frame of paper-scale photographs.
const REGION_E_HEIGHT_MM: f64 = 120.0;

/// The estimated cost of one unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitCost {
    /// Processor time at one thread (s).
    pub cpu_seconds: f64,
    pub memory_mb: f64,
}

/// What one array task asks of Slurm, with the numbers it comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resources {
    pub cpus: usize,
    pub memory_mb: u64,
    pub time_limit_s: u64,
    /// Units of the largest task, its processor time (s), its longest unit's (s) and the
    /// wall time estimated for it (s).
    pub units_per_task: usize,
    pub task_cpu_seconds: f64,
    pub longest_unit_cpu_seconds: f64,
    pub task_wall_seconds: f64,
    /// The engine's rate the estimate used (grain-steps per second on one thread).
    pub grain_steps_per_second: f64,
}

/// Grain-steps of a filling (see the module's doc).
pub fn filling_grain_steps(plan: &Plan, f: &Filling) -> anyhow::Result<f64> {
    let silo = Silo::new(&f.scene, f.seed)?;
    let dt = silo.world.time_step();
    let walls = silo.world.len() as f64;
    let grains = silo.feeder.total as f64;
    let fill_time = grains / silo.feeder.rate();
    let fall_time = silo.height / silo.feeder.speed;
    let after = fall_time + plan.max_relaxation_time_s;
    Ok(fill_time / dt * (walls + 0.5 * grains) + after / dt * (walls + grains))
}

/// Pixels of the photograph of a photographed filling.
fn rendered_pixels(plan: &Plan, f: &Filling) -> f64 {
    let width_mm = f.scene.silo.width_mm;
    let height_mm = match plan.frame {
        FrameChoice::RegionE => REGION_E_HEIGHT_MM,
        _ => {
            let kind = f.kind;
            let area_mm2 = kind.length() * kind.width() * 1e6;
            let grains = plan
                .shapes
                .iter()
                .find(|s| s.kind == f.kind)
                .map_or(0, |s| s.grains) as f64;
            grains * area_mm2 / (LOOSE_PACKING * width_mm) + kind.length() * 1e3
        }
    };
    width_mm * height_mm * plan.photo_px_per_mm.powi(2)
}

fn detection(pixels: f64) -> UnitCost {
    UnitCost {
        cpu_seconds: pixels * 1e-6 * DETECT_CPU_SECONDS_PER_MEGAPIXEL,
        memory_mb: pixels * DETECT_BYTES_PER_PIXEL / 1e6,
    }
}

/// The cost of one unit at `rate` grain-steps per second.
pub fn unit_cost(plan: &Plan, unit: &Unit, rate: f64) -> anyhow::Result<UnitCost> {
    match unit {
        Unit::Filling(f) => {
            let grains = (f.scene.grains.count) as f64;
            let filling = UnitCost {
                cpu_seconds: filling_grain_steps(plan, f)? / rate,
                memory_mb: grains * FILLING_BYTES_PER_GRAIN / 1e6,
            };
            if f.side == Side::Simulation {
                return Ok(filling);
            }
            let d = detection(rendered_pixels(plan, f));
            Ok(UnitCost {
                cpu_seconds: filling.cpu_seconds + d.cpu_seconds,
                memory_mb: filling.memory_mb.max(d.memory_mb),
            })
        }
        Unit::Photo(p) => {
            let (w, h) = image::image_dimensions(&p.path)
                .map_err(|e| anyhow::anyhow!("{}: {e}", p.path.display()))?;
            Ok(detection(w as f64 * h as f64))
        }
    }
}

/// The resources of the largest of `tasks` tasks sharing `costs` round-robin, each on `cpus`
/// processors (default: as many as its units, at most 4). A task runs its units `cpus` at a
/// time; one unit is not assumed to run faster on several processors.
pub fn resources(costs: &[UnitCost], tasks: usize, cpus: Option<usize>, rate: f64) -> Resources {
    let per_task: Vec<Vec<UnitCost>> = (0..tasks)
        .map(|t| costs.iter().skip(t).step_by(tasks).copied().collect())
        .collect();
    let units_per_task = per_task.iter().map(Vec::len).max().unwrap_or(0);
    let cpus = cpus.unwrap_or(units_per_task.clamp(1, 4));
    let cpu = |c: &[UnitCost]| c.iter().map(|u| u.cpu_seconds).sum::<f64>();
    let longest = costs.iter().map(|u| u.cpu_seconds).fold(0.0, f64::max);
    let wall = per_task
        .iter()
        .map(|c| (cpu(c) / cpus as f64).max(c.iter().map(|u| u.cpu_seconds).fold(0.0, f64::max)))
        .fold(0.0, f64::max);
    let task_cpu = per_task.iter().map(|c| cpu(c)).fold(0.0, f64::max);
    let largest_unit_mb = costs.iter().map(|u| u.memory_mb).fold(0.0, f64::max);
    let memory = BASE_MEMORY_MB + cpus.min(units_per_task.max(1)) as f64 * largest_unit_mb;
    Resources {
        cpus,
        // Whole quarter-gigabytes.
        memory_mb: ((memory / 256.0).ceil() * 256.0) as u64,
        // Whole minutes.
        time_limit_s: (((wall * TIME_SAFETY + TIME_MARGIN_S) / 60.0).ceil() * 60.0) as u64,
        units_per_task,
        task_cpu_seconds: task_cpu,
        longest_unit_cpu_seconds: longest,
        task_wall_seconds: wall,
        grain_steps_per_second: rate,
    }
}

/// Where the engine's rate came from.
#[derive(Clone, Debug, PartialEq)]
pub enum RateSource {
    Given,
    /// Fillings already done in the output folder (their run.json: grain-steps / wall time).
    Finished(usize),
    /// Timed now on a small filling of the plan's first shape, one thread.
    Measured,
}

/// The rate of fillings already done under `out`, if any: their grain-steps over their wall
/// time (fillings that ran side by side each had a share of the processors, so this errs low).
pub fn rate_of_finished(fillings: &[Filling]) -> Option<(f64, usize)> {
    #[derive(serde::Deserialize)]
    struct Timing {
        grain_steps: u64,
        wall_time_s: f64,
    }
    let (mut steps, mut seconds, mut n) = (0.0, 0.0, 0);
    for f in fillings {
        if crate::reproduce::simulate::done(f).is_none() {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(f.dir.join("run.json")) else {
            continue;
        };
        if let Ok(t) = serde_json::from_str::<Timing>(&text) {
            if t.wall_time_s > 0.0 {
                steps += t.grain_steps as f64;
                seconds += t.wall_time_s;
                n += 1;
            }
        }
    }
    (n > 0 && steps > 0.0).then(|| (steps / seconds, n))
}

/// Grains of the calibration filling: seconds on one processor.
const CALIBRATION_GRAINS: usize = 40;

/// Times a small filling of the plan's first shape and phi0 (its silo, [`CALIBRATION_GRAINS`]
/// grains, a fifth of a second of relaxation) on one thread: its grain-steps per second.
/// A small world pays the per-step costs over few grains, so the rate errs low.
pub fn measure_rate(plan: &Plan) -> anyhow::Result<f64> {
    let mut small = plan.clone();
    small.max_relaxation_time_s = small.max_relaxation_time_s.min(0.2);
    let mut shape = plan.shapes[0].clone();
    shape.grains = CALIBRATION_GRAINS;
    let phi0 = shape.phi0s[0];
    let scene = small.scene(&shape, phi0)?;
    let dir = tempfile::tempdir().context("cannot create a folder for the calibration filling")?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("cannot start the thread pool")?;
    let record = pool.install(|| crate::fill::fill(&scene, 1, dir.path(), &mut |_| {}))?;
    anyhow::ensure!(
        record.wall_time_s > 0.0 && record.grain_steps > 0,
        "the calibration filling recorded no work"
    );
    Ok(record.grain_steps as f64 / record.wall_time_s)
}

/// The rate to use: `given`, else that of fillings done under the output folder, else measured.
pub fn engine_rate(
    plan: &Plan,
    given: Option<f64>,
    fillings: &[Filling],
) -> anyhow::Result<(f64, RateSource)> {
    if let Some(r) = given {
        anyhow::ensure!(
            r.is_finite() && r > 0.0,
            "--grain-steps-per-second {r}: expected a positive rate"
        );
        return Ok((r, RateSource::Given));
    }
    if let Some((r, n)) = rate_of_finished(fillings) {
        return Ok((r, RateSource::Finished(n)));
    }
    Ok((measure_rate(plan)?, RateSource::Measured))
}

/// Whether a path can stand in an `#SBATCH` line (Slurm does not unquote them).
pub fn plain(path: &Path) -> bool {
    !path.to_string_lossy().chars().any(char::is_whitespace)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(cpu: f64, mb: f64) -> UnitCost {
        UnitCost {
            cpu_seconds: cpu,
            memory_mb: mb,
        }
    }

    #[test]
    fn a_task_is_as_long_as_its_share_or_its_longest_unit() {
        // Units 0, 2 in task 0 (100 + 300 s), 1, 3 in task 1 (200 + 50 s).
        let costs = [
            unit(100.0, 10.0),
            unit(200.0, 10.0),
            unit(300.0, 10.0),
            unit(50.0, 400.0),
        ];
        let r = resources(&costs, 2, Some(2), 1e6);
        assert_eq!(r.units_per_task, 2);
        assert_eq!(r.task_cpu_seconds, 400.0);
        // Task 0 on two processors: its 300 s unit is the limit, not 400 / 2.
        assert_eq!(r.task_wall_seconds, 300.0);
        assert_eq!(r.time_limit_s, (300.0 * TIME_SAFETY + TIME_MARGIN_S) as u64);
        // Two units at a time, each up to the largest's 400 MB, on the base.
        assert!(r.memory_mb as f64 >= BASE_MEMORY_MB + 800.0 && r.memory_mb % 256 == 0);
        // One task of four on one processor: the sum.
        let r = resources(&costs, 1, Some(1), 1e6);
        assert_eq!(r.task_wall_seconds, 650.0);
    }
}
