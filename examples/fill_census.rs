//! Diagnostic: fills a scene up to a simulated time, stops, and prints a census of the deposit
//! by depth below the free surface: how many grains, how fast they move (median and 90th
//! percentile of centre plus corner speed) and how far from balance they are (net force over
//! weight). It shows which part of a growing deposit still moves, i.e. what sleeping grains or a
//! frozen base could leave out.
//!
//! With a window, the run goes on for that long and the census adds how far each grain's
//! centre and corners moved over it (rearranging, or only trembling in place).
//!
//! cargo run --release --example fill_census -- SCENE.toml STOP_TIME_S [DEPTH_BAND_MM] [WINDOW_S]

use anyhow::Context;
use facets::fill::{Checkpoint, FillControl, FillOutcome, StopAt, fill_with};
use facets::scene::load_scene;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() >= 3,
        "usage: fill_census SCENE.toml STOP_TIME_S [DEPTH_BAND_MM]"
    );
    let scene = load_scene(std::path::Path::new(&args[1]))?;
    let stop: f64 = args[2]
        .parse()
        .with_context(|| format!("`{}`: expected a time in s", args[2]))?;
    let band = match args.get(3) {
        Some(b) => {
            b.parse::<f64>()
                .with_context(|| format!("`{b}`: expected mm"))?
                * 1e-3
        }
        None => 0.02,
    };
    let window = match args.get(4) {
        Some(w) => w
            .parse::<f64>()
            .with_context(|| format!("`{w}`: expected s"))?,
        None => 0.0,
    };
    let out = std::env::temp_dir().join(format!("fill-census-{}", std::process::id()));
    let started = std::time::Instant::now();
    let run_to = |time: f64, resume: Option<Checkpoint>| -> anyhow::Result<Checkpoint> {
        let control = FillControl {
            stop: StopAt::Time(time),
            resume,
            ..FillControl::default()
        };
        match fill_with(&scene, scene.run.seed, &out, control, &mut |_| {})? {
            FillOutcome::Stopped { checkpoint, .. } => Checkpoint::read(&checkpoint),
            FillOutcome::Finished(_) => anyhow::bail!("the fill ended before {time} s"),
        }
    };
    let before = run_to(stop, None)?;
    let world = before.world().clone();
    let after = if window > 0.0 {
        Some(run_to(stop + window, Some(before))?.world().clone())
    } else {
        None
    };
    let cpu = started.elapsed().as_secs_f64();
    std::fs::remove_dir_all(&out).ok();
    // Horizontal, vertical and turning (corner arc) displacement over the window: a column
    // ringing in its lowest mode moves its grains up and down together; rearranging grains
    // also move sideways and turn.
    let moved = |i: usize| -> [f64; 3] {
        after.as_ref().map_or([f64::NAN; 3], |a| {
            let reach = world.shape(world.shape_of(i)).bounding_radius();
            let (ga, g0) = (a.grains(), world.grains());
            let d = ga.position[i] - g0.position[i];
            [
                d.x.abs(),
                d.y.abs(),
                reach * (ga.angle[i] - g0.angle[i]).abs(),
            ]
        })
    };
    let g = world.grains();
    let gravity = world.settings().gravity.norm();
    let mobile: Vec<usize> = (0..world.len()).filter(|&i| !g.is_fixed(i)).collect();
    let speed = |i: usize| {
        let reach = world.shape(world.shape_of(i)).bounding_radius();
        g.velocity[i].norm() + reach * g.angular_velocity[i].abs()
    };
    // The free surface: the highest grain slower than 1 m/s (the rain above it is faster).
    let surface = mobile
        .iter()
        .filter(|&&i| speed(i) < 1.0)
        .map(|&i| g.position[i].y)
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "t = {:.3} s, {} grains, surface at {:.1} mm, {:.1} s wall to get here, {} steps",
        world.time(),
        mobile.len(),
        surface * 1e3,
        cpu,
        world.steps()
    );
    println!(
        "depth mm    grains asleep  speed median  speed p90   |F|/W median  |F|/W p90  slower than 2 mm/s / 1 cm/s   moved in {:.0} ms (um), median/p90: sideways  up-down  turning",
        window * 1e3
    );
    let mut top = 0.0;
    while top < surface + band {
        let members: Vec<usize> = mobile
            .iter()
            .copied()
            .filter(|&i| {
                let depth = surface - g.position[i].y;
                depth >= top && depth < top + band
            })
            .collect();
        if !members.is_empty() {
            let mut speeds: Vec<f64> = members.iter().map(|&i| speed(i)).collect();
            let mut loads: Vec<f64> = members
                .iter()
                .map(|&i| g.force[i].norm() / (g.mass[i] * gravity))
                .collect();
            speeds.sort_by(f64::total_cmp);
            loads.sort_by(f64::total_cmp);
            let q = |v: &[f64], p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
            let slow = |limit: f64| speeds.iter().filter(|&&s| s < limit).count();
            let quantiles = |k: usize| {
                let mut m: Vec<f64> = members.iter().map(|&i| moved(i)[k] * 1e6).collect();
                m.sort_by(f64::total_cmp);
                format!("{:7.1}/{:<7.1}", q(&m, 0.5), q(&m, 0.9))
            };
            println!(
                "{:4.0}-{:<4.0}  {:6} {:6}  {:10.2e}  {:10.2e}  {:10.2}  {:10.2}  {:5} / {:5}   {} {} {}",
                top * 1e3,
                (top + band) * 1e3,
                members.len(),
                members.iter().filter(|&&i| world.is_asleep(i)).count(),
                q(&speeds, 0.5),
                q(&speeds, 0.9),
                q(&loads, 0.5),
                q(&loads, 0.9),
                slow(2e-3),
                slow(1e-2),
                quantiles(0),
                quantiles(1),
                quantiles(2)
            );
        }
        top += band;
    }
    Ok(())
}
