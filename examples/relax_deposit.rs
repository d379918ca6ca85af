//! Diagnostic: rebuilds a deposit table of squares at rest in a flat-walled silo and prints,
//! every 50 ms of simulated time, how far it is from rest (kinetic / elastic energy), the
//! energy switched in by the sub-contact rules, and the grains faster than 2 mm/s. A deposit
//! that keeps rattling shows a switching energy that grows steadily.
//!
//! cargo run --release --example relax_deposit -- DEPOSIT.csv SILO_WIDTH_MM [STEPS_PER_COLLISION]

use anyhow::Context;
use facets::deposit::read_deposit_csv;
use facets::grains::GrainKind;
use sim::{ContactLaw, GrainState, Spheropolygon, Vec2, Wall, World, WorldSettings};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() >= 3,
        "usage: relax_deposit DEPOSIT.csv SILO_WIDTH_MM [STEPS_PER_COLLISION]"
    );
    let deposit = read_deposit_csv(std::path::Path::new(&args[1]))?;
    let width = args[2]
        .parse::<f64>()
        .with_context(|| format!("silo width `{}`: expected millimetres", args[2]))?
        * 1e-3;
    let steps_per_collision = match args.get(3) {
        Some(n) => n
            .parse::<f64>()
            .with_context(|| format!("`{n}`: expected steps per collision"))?,
        None => 50.0,
    };
    let first = deposit.grains.first().context("the deposit is empty")?;
    let law = ContactLaw::default();
    let mut world = World::new(WorldSettings {
        law,
        ..WorldSettings::default()
    })?;
    world.add_wall(Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)))?;
    world.add_wall(Wall::new(Vec2::zeros(), Vec2::new(1.0, 0.0)))?;
    world.add_wall(Wall::new(Vec2::new(width, 0.0), Vec2::new(-1.0, 0.0)))?;
    let density = GrainKind::Square.areal_density();
    let outline = Spheropolygon::rounded_rectangle(first.length, first.width, 0.05 * first.width)?;
    let (mass, _) = outline.mass_properties(density)?;
    let shape = world.add_shape(outline, density)?;
    world.set_time_step(sim::collision_time(&law, mass / 2.0) / steps_per_collision)?;
    for g in &deposit.grains {
        world.add_grain(shape, GrainState::at_rest(Vec2::new(g.x, g.y), g.theta))?;
    }
    let every = (0.05 / world.time_step()).round() as u64;
    for _ in 0..40 {
        world.run(every)?;
        let e = world.energies();
        let g = world.grains();
        let fast = (0..world.len())
            .filter(|&i| g.velocity[i].norm() > 2e-3)
            .count();
        println!(
            "t {:.2} s  kinetic/elastic {:.2e}  switched {:.3e} J  elastic {:.3e} J  {fast} grains above 2 mm/s",
            world.time(),
            e.kinetic / e.elastic,
            e.switching,
            e.elastic
        );
    }
    Ok(())
}
