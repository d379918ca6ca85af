//! Tests 2 and 3: grains at rest on a floor carry exactly their weight.

use sim::{ContactLaw, Vec2};

use super::common::*;

const G: f64 = 10.0;

/// Height of a square's centre resting face down on a floor with the given overlap.
fn resting_height(overlap: f64) -> f64 {
    SIDE / 2.0 - overlap
}

#[test]
fn square_resting_face_down_for_one_second() {
    let law = ContactLaw::default();
    let mut w = world(law, Vec2::new(0.0, -G), None);
    let floor = add_floor(&mut w);
    let id = add_square(&mut w);
    w.add_grain(id, at(0.0, 0.0, 0.0)).unwrap();
    let m = mass(&w, 0);
    // Start at the equilibrium overlap of two sub-contacts.
    let y0 = resting_height(m * G / (2.0 * law.normal_stiffness));
    w.set_grain(0, at(0.01, y0, 0.0));
    let steps = (1.0 / w.time_step()).round() as u64;
    w.run(steps).unwrap();
    let s = w.grain(0);
    let drift = s.position - Vec2::new(0.01, y0);
    assert!(drift.norm() < 1e-6, "drift {drift:?} m");
    assert!(s.angle.abs() < 1e-6, "rotation {} rad", s.angle);
    let load = w.wall_load(floor);
    assert!(
        (load.y + m * G).abs() < 1e-6 * m * G && load.x.abs() < 1e-6 * m * G,
        "floor carries {load:?}, weight {}",
        m * G
    );
}

#[test]
fn column_of_twenty_squares_loads_the_floor_with_its_weight() {
    let law = ContactLaw::default();
    let n = 20;
    let mut w = world(law, Vec2::new(0.0, -G), None);
    let floor = add_floor(&mut w);
    let id = add_square(&mut w);
    let m = square().mass_properties(NUT_DENSITY).unwrap().0;
    stack_at_equilibrium(&mut w, id, n, G);
    w.run((0.2 / w.time_step()).round() as u64).unwrap();
    let weight = n as f64 * m * G;
    let load = -w.wall_load(floor).y;
    assert!(
        (load - weight).abs() < 1e-3 * weight,
        "floor carries {load} N, column weighs {weight} N"
    );
    // And every grain is still in its column.
    for i in 0..n {
        assert!(w.grain(i).position.x.abs() < 1e-6 && w.grain(i).angle.abs() < 1e-6);
    }
}
