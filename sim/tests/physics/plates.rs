//! Friction of a quasi-2D cell's plates and of the walls: a grain falling or sliding decelerates
//! as each law says, and dry plates hold a grain at rest.

use sim::{ContactLaw, PlateFriction, Vec2, World, WorldSettings};

use super::common::*;

fn world_with(plates: Option<PlateFriction>, wall_friction: Option<f64>) -> World {
    World::new(WorldSettings {
        gravity: Vec2::new(0.0, -10.0),
        wall_friction,
        plate_friction: plates,
        ..WorldSettings::default()
    })
    .unwrap()
}

fn run_for(w: &mut World, seconds: f64) {
    w.run((seconds / w.time_step()).round() as u64).unwrap();
}

#[test]
fn dry_plates_slow_a_falling_grain_by_their_friction() {
    // Sliding, the plates push up with mu_p x (load fraction) x m g: the grain falls at
    // g (1 - 0.3 x 0.5) = 8.5 m/s^2. Before it slides the plates' spring stretches by
    // mu_p x load x m g / k_T, a micron: it delays the fall by well under a millisecond.
    let plates = PlateFriction::Coulomb {
        coefficient: 0.3,
        load_fraction: 0.5,
    };
    let mut w = world_with(Some(plates), None);
    let square = add_square(&mut w);
    w.add_grain(square, at(0.0, 1.0, 0.2)).unwrap();
    run_for(&mut w, 0.1);
    let v = w.grain(0).velocity;
    assert!(
        (v.y + 0.85).abs() < 0.005 * 0.85,
        "after 0.1 s: {} m/s, the law says -0.85",
        v.y
    );
    assert!(v.x.abs() < 1e-12);
    // The plates carry what the grain does not accelerate by.
    let held = -w.plate_load().y;
    let expected = 0.15 * mass(&w, 0) * 10.0;
    assert!((held - expected).abs() < 1e-3 * expected, "{held} N");
}

#[test]
fn dry_plates_hold_a_grain_their_friction_can_bear() {
    // mu_p x load = 1.2 > 1: the plates bear the whole weight, and the grain stays put.
    let plates = PlateFriction::Coulomb {
        coefficient: 1.2,
        load_fraction: 1.0,
    };
    let mut w = world_with(Some(plates), None);
    let square = add_square(&mut w);
    w.add_grain(square, at(0.0, 1.0, 0.0)).unwrap();
    run_for(&mut w, 0.2);
    let held = w.grain(0);
    run_for(&mut w, 0.2);
    let g = w.grain(0);
    // Let go from rest, the spring overshoots past the cap once and slips a little; then it
    // holds: the grain hangs within a few k_T-stretches (10 microns each) of where it began,
    // and stays there.
    let stretch = mass(&w, 0) * 10.0 / ContactLaw::default().tangential_stiffness;
    let sank = 1.0 - g.position.y;
    assert!(sank > 0.0 && sank < 5.0 * stretch, "sank by {sank} m");
    assert!(
        (g.position - held.position).norm() < 1e-3 * stretch,
        "still moving: {:?} then {:?}",
        held.position,
        g.position
    );
    assert!(g.velocity.norm() < 1e-6, "{:?}", g.velocity);
    let weight = mass(&w, 0) * 10.0;
    assert!((-w.plate_load().y - weight).abs() < 1e-3 * weight);
}

#[test]
fn viscous_plates_give_the_exponential_approach_to_terminal_speed() {
    let rate = 20.0;
    let mut w = world_with(Some(PlateFriction::Viscous { rate }), None);
    let square = add_square(&mut w);
    w.add_grain(square, at(0.0, 1.0, 0.0)).unwrap();
    let t = 0.1;
    run_for(&mut w, t);
    let exact = -(10.0 / rate) * (1.0 - (-rate * t).exp());
    let v = w.grain(0).velocity.y;
    assert!(
        (v - exact).abs() < 1e-3 * exact.abs(),
        "{v} against {exact}"
    );
}

#[test]
fn a_grain_slides_on_a_floor_with_the_walls_friction() {
    // Grains' mu 0.4, walls' 0.1: a square sliding on the floor decelerates at 0.1 g.
    let mut w = world_with(None, Some(0.1));
    add_floor(&mut w);
    let square = add_square(&mut w);
    stack_at_equilibrium(&mut w, square, 1, 10.0);
    let mut g = w.grain(0);
    g.velocity.x = 1.0;
    w.set_grain(0, g);
    run_for(&mut w, 0.2);
    let v = w.grain(0).velocity.x;
    assert!(
        (v - 0.8).abs() < 0.01,
        "after 0.2 s: {v} m/s, the law says 0.8"
    );
}

#[test]
fn a_grain_slides_on_a_fixed_grain_with_the_walls_friction() {
    // A fixed grain is part of a wall: a square sliding on a fixed square decelerates at the
    // walls' 0.1 g, not the grains' 0.4 g.
    let mut w = world_with(None, Some(0.1));
    let square = add_square(&mut w);
    w.add_fixed_grain(square, Vec2::new(0.0, -SIDE / 2.0), 0.0)
        .unwrap();
    let m = mass_of_square();
    let k = ContactLaw::default().normal_stiffness;
    let sink = m * 10.0 / (2.0 * k);
    w.add_grain(square, moving(0.0, SIDE / 2.0 - sink, 0.0, 1.0, 0.0))
        .unwrap();
    // 0.2 s at 1 m/s is 0.2 m: a long fixed bed of grains edge to edge under it.
    for k in 1..40 {
        w.add_fixed_grain(square, Vec2::new(k as f64 * SIDE, -SIDE / 2.0), 0.0)
            .unwrap();
    }
    run_for(&mut w, 0.2);
    let v = w.grain(1).velocity.x;
    assert!(
        (v - 0.8).abs() < 0.01,
        "after 0.2 s: {v} m/s, the law says 0.8"
    );
}
