//! Diagnostic: where a fill's wall time goes along the run. Prints, for every stretch of
//! simulated time, the wall time it took, the grains in the silo and the throughput in
//! grain-steps per wall second, so a fill can be set against the engine benchmark's rate.
//!
//! cargo run --release --example fill_timeline -- SCENE.toml DT_S [SEED] [STRETCH_S]
//! (DT_S: the run's time step, as its run.json gives it)

use anyhow::Context;
use facets::fill::{FillControl, FillOutcome, fill_with};
use facets::scene::load_scene;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() >= 3,
        "usage: fill_timeline SCENE.toml DT_S [SEED] [STRETCH_S]"
    );
    let dt: f64 = args[2]
        .parse()
        .with_context(|| format!("`{}`: expected a time step in s", args[2]))?;
    let scene = load_scene(std::path::Path::new(&args[1]))?;
    let seed = match args.get(3) {
        Some(s) => s
            .parse()
            .with_context(|| format!("`{s}`: expected a seed"))?,
        None => scene.run.seed,
    };
    let stretch: f64 = match args.get(4) {
        Some(s) => s.parse().with_context(|| format!("`{s}`: expected s"))?,
        None => 1.0,
    };
    let out = std::env::temp_dir().join(format!("fill-timeline-{}", std::process::id()));
    let started = std::time::Instant::now();
    let (mut last_time, mut last_wall, mut grain_time) = (0.0, 0.0, 0.0);
    let (mut last_report, mut last_inserted) = (0.0, 0usize);
    println!(
        "sim_s\twall_s\tgrains\tgrain_steps_per_s\tasleep\tkinetic_over_elastic\tload_imbalance"
    );
    let outcome = fill_with(&scene, seed, &out, FillControl::default(), &mut |p| {
        // Grain-seconds simulated (grains in x simulated time), by the trapezoid rule.
        grain_time += 0.5 * (p.inserted + last_inserted) as f64 * (p.time - last_report);
        last_report = p.time;
        last_inserted = p.inserted;
        if p.time - last_time >= stretch {
            let wall = started.elapsed().as_secs_f64();
            println!(
                "{:.3}\t{:.2}\t{}\t{:.3e}\t{}\t{:.2e}\t{:.2e}",
                p.time,
                wall - last_wall,
                p.inserted,
                grain_time / dt / (wall - last_wall),
                p.asleep,
                p.energy_ratio,
                p.load_imbalance
            );
            (last_time, last_wall, grain_time) = (p.time, wall, 0.0);
        }
    })?;
    if let FillOutcome::Finished(record) = outcome {
        println!(
            "total\t{:.2}\t{}\tsteps {}",
            record.wall_time_s, record.grains, record.steps
        );
    }
    std::fs::remove_dir_all(&out).ok();
    Ok(())
}
