//! Diagnostic: fills a scene up to a simulated time, then times the world stepping on alone
//! from that state (no feeder) and prints grain-steps per second, to compare with the engine
//! bench's settled deposit.
//!
//! cargo run --release --example fill_rate -- SCENE.toml STOP_TIME_S STEPS

use facets::fill::{Checkpoint, FillControl, FillOutcome, StopAt, fill_with};
use facets::scene::load_scene;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let scene = load_scene(std::path::Path::new(&args[1]))?;
    let stop: f64 = args[2].parse()?;
    let steps: u64 = args[3].parse()?;
    let out = std::env::temp_dir().join(format!("fill-rate-{}", std::process::id()));
    let control = FillControl {
        stop: StopAt::Time(stop),
        ..FillControl::default()
    };
    let t0 = std::time::Instant::now();
    let FillOutcome::Stopped { checkpoint, .. } =
        fill_with(&scene, scene.run.seed, &out, control, &mut |_| {})?
    else {
        anyhow::bail!("ended early")
    };
    let fill_wall = t0.elapsed().as_secs_f64();
    let mut world = Checkpoint::read(&checkpoint)?.world().clone();
    std::fs::remove_dir_all(&out).ok();
    let (pairs, walls) = world.neighbour_pairs();
    let subs = world.contacts().count();
    let rebuilds = world.verlet_rebuilds();
    let t = std::time::Instant::now();
    world.run(steps)?;
    let wall = t.elapsed().as_secs_f64();
    let n = world.len();
    println!(
        "fill to {stop} s: {fill_wall:.1} s wall; {n} grains, {subs} sub-contacts, {pairs}+{walls} pairs; {steps} steps {wall:.2} s = {:.3e} grain-steps/s, rebuilds {}",
        n as f64 * steps as f64 / wall,
        world.verlet_rebuilds() - rebuilds
    );
    Ok(())
}
