//! The work a run did, counted in the engine benchmark's unit.

use sim::{ContactLaw, Vec2};

use super::common::*;

#[test]
fn grain_steps_sum_the_grains_in_the_world_over_the_steps() {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    add_floor(&mut w);
    let square = add_square(&mut w);
    w.add_grain(square, at(0.0, 0.01, 0.0)).unwrap();
    w.run(30).unwrap();
    assert_eq!(w.grain_steps(), 30);
    // Grains poured in mid-run count from the step after they arrive.
    w.add_grain(square, at(0.02, 0.01, 0.0)).unwrap();
    w.add_grain(square, at(0.04, 0.01, 0.0)).unwrap();
    w.run(20).unwrap();
    assert_eq!(w.grain_steps(), 30 + 3 * 20);
    assert_eq!(w.steps(), 50);
}
