//! Test 7: undamped, frictionless grains bouncing in a box conserve energy.

use std::collections::HashSet;

use sim::{Body, ContactLaw, Vec2, Wall};

use super::common::*;

/// Grains alone in a box meet only walls, where each vertex has its own continuous potential:
/// what is left is the integrator's error.
#[test]
fn energy_is_conserved_over_a_hundred_wall_collisions() {
    for (grains, first_shape) in [(1, 0), (1, 1)] {
        let (drift, switching) = bouncing_box(None, grains, first_shape);
        assert_eq!(switching, 0.0);
        assert!(
            drift < 1e-4,
            "shape {first_shape}: energy drifted by {drift:e}"
        );
    }
}

/// Squares and rods colliding with each other, spinning, at up to 1.4 m/s. Sub-contacts
/// appear and vanish as corners slide past faces and face-on-face pairs turn corner-on-corner;
/// with the close-corner weights none does so at a finite overlap, and the weighted energy is
/// a potential, so the total energy (no energy set aside) is conserved within 1e-4.
#[test]
fn energy_is_conserved_in_grain_collisions() {
    for grains in [4, 12] {
        let (drift, switching) = bouncing_box(None, grains, 0);
        assert!(
            drift < 1e-4,
            "{grains} grains: energy drifted by {drift:e} (switched at finite overlap: {switching:e})"
        );
    }
}

#[test]
#[ignore = "measurement: energy drift against the time step"]
fn energy_drift_against_time_step() {
    for fraction in [50.0, 100.0, 200.0, 400.0] {
        let shape = rod();
        let m = shape.mass_properties(ROD_DENSITY).unwrap().0;
        let law = ContactLaw {
            normal_damping: 0.0,
            ..ContactLaw::default()
        };
        let tc = sim::collision_time(&law, m / 2.0);
        for grains in [1, 4, 12] {
            let (drift, switching) = bouncing_box(Some(tc / fraction), grains, 0);
            println!(
                "dt = t_c/{fraction}, {grains} grains: drift {drift:e}, switching {switching:e}"
            );
        }
    }
}

/// `grains` spinning grains (alternating squares and rods, starting with `first_shape`: 0
/// square, 1 rod) in a 60 mm box; returns (total energy drift, energy switched in or out at a
/// finite overlap), both relative to the initial energy, after 100 collisions.
fn bouncing_box(dt: Option<f64>, grains: usize, first_shape: usize) -> (f64, f64) {
    let law = ContactLaw {
        normal_damping: 0.0,
        tangential_damping: 0.0,
        friction: 0.0,
        ..ContactLaw::default()
    };
    let mut w = world(law, Vec2::zeros(), dt);
    let box_side = 0.06;
    for (p, n) in [
        (Vec2::zeros(), Vec2::new(0.0, 1.0)),
        (Vec2::zeros(), Vec2::new(1.0, 0.0)),
        (Vec2::new(box_side, box_side), Vec2::new(0.0, -1.0)),
        (Vec2::new(box_side, box_side), Vec2::new(-1.0, 0.0)),
    ] {
        w.add_wall(Wall::new(p, n)).unwrap();
    }
    let square = add_square(&mut w);
    let rod = w.add_shape(rod(), ROD_DENSITY).unwrap();
    let mut seed = 7u64;
    let mut random = || uniform(&mut seed) - 0.5;
    for k in 0..grains {
        let (row, col) = (k / 4, k % 4);
        let shape = if (k + first_shape) % 2 == 0 {
            square
        } else {
            rod
        };
        let x = 0.0075 + col as f64 * 0.015;
        let y = 0.01 + row as f64 * 0.02;
        let state = sim::GrainState {
            position: Vec2::new(x, y),
            angle: 6.0 * random(),
            velocity: Vec2::new(2.0 * random(), 2.0 * random()),
            angular_velocity: 100.0 * random(),
        };
        w.add_grain(shape, state).unwrap();
    }
    w.prime().unwrap();
    let e0 = w.energies().total();
    let mut touching: HashSet<(usize, Body)> = HashSet::new();
    let mut collisions = 0;
    while collisions < 100 {
        assert!(w.time() < 20.0, "only {collisions} collisions in 20 s");
        w.step().unwrap();
        let now: HashSet<(usize, Body)> = w.contacts().map(|c| (c.first, c.second)).collect();
        collisions += now.difference(&touching).count();
        touching = now;
    }
    // Let the last collisions finish.
    w.run(2000).unwrap();
    let e = w.energies();
    let switching = e.switching.abs() / e0;
    let drift = (e.total() - e0).abs() / e0;
    (drift, switching)
}
