//! Test 8: a 500-grain pour gives bit-identical states with 1 and 2 threads.

use sim::{ContactLaw, GrainState, Vec2, World};

use super::common::*;

fn pour() -> World {
    // dt = 1e-5 s, so the 10 000 steps cover 0.1 s of a lively pour.
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    let width = 0.12;
    add_box(&mut w, width);
    let square = add_square(&mut w);
    let rod = w.add_shape(rod(), ROD_DENSITY).unwrap();
    let mut seed = 99u64;
    let mut random = || uniform(&mut seed);
    let pitch = 0.0105;
    let columns = (width / pitch) as usize;
    for k in 0..500 {
        let (row, col) = (k / columns, k % columns);
        let shape = if random() < 0.5 { square } else { rod };
        let state = GrainState {
            position: Vec2::new(pitch * (col as f64 + 0.5), pitch * (row as f64 + 0.5)),
            angle: 6.3 * random(),
            velocity: Vec2::new(2.0 * (random() - 0.5), -2.0 * random()),
            angular_velocity: 0.0,
        };
        w.add_grain(shape, state).unwrap();
    }
    w.run(10_000).unwrap();
    w
}

fn fingerprint(w: &World) -> Vec<u64> {
    let g = w.grains();
    let mut bits = Vec::new();
    for i in 0..g.len() {
        bits.extend([
            g.position[i].x.to_bits(),
            g.position[i].y.to_bits(),
            g.angle[i].to_bits(),
            g.velocity[i].x.to_bits(),
            g.velocity[i].y.to_bits(),
            g.angular_velocity[i].to_bits(),
            g.force[i].x.to_bits(),
            g.torque[i].to_bits(),
        ]);
    }
    bits
}

#[test]
fn one_and_two_threads_give_identical_bits() {
    let (one, two) = (on_threads(1, pour), on_threads(2, pour));
    // The pour really moved and collided.
    assert!(
        one.contacts().count() > 200,
        "{} contacts",
        one.contacts().count()
    );
    assert!(one.verlet_rebuilds() > 1);
    assert_eq!(fingerprint(&one), fingerprint(&two));
}
