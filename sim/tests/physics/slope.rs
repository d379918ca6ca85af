//! Test 4: a rod on a slope (gravity tilted by alpha) sticks when tan(alpha) < mu and slides
//! with acceleration g (sin alpha - mu cos alpha) when tan(alpha) > mu.

use sim::{ContactLaw, Vec2};

use super::common::*;

const G: f64 = 10.0;

/// A rod lying on the floor under gravity tilted by `alpha` (down-slope is +x). Returns the
/// world after settling the rod at its normal equilibrium.
fn rod_on_slope(alpha: f64) -> sim::World {
    let law = ContactLaw::default();
    let gravity = Vec2::new(G * alpha.sin(), -G * alpha.cos());
    let mut w = world(law, gravity, None);
    add_floor(&mut w);
    let id = w.add_shape(rod(), ROD_DENSITY).unwrap();
    let m = rod().mass_properties(ROD_DENSITY).unwrap().0;
    let overlap = m * G * alpha.cos() / (2.0 * law.normal_stiffness);
    w.add_grain(id, at(0.0, ROD_WIDTH / 2.0 - overlap, 0.0))
        .unwrap();
    w
}

#[test]
fn sticks_below_the_friction_angle() {
    let alpha = 0.3f64.atan();
    let mut w = rod_on_slope(0.0);
    // Tilt the slope over 50 ms: a sudden tilt makes the tangential springs overshoot past the
    // Coulomb cap, a real (if tiny) slip that is not what this test is about.
    let ramp = (0.05 / w.time_step()).round() as u64;
    for k in 1..=ramp {
        let a = alpha * k as f64 / ramp as f64;
        w.set_gravity(Vec2::new(G * a.sin(), -G * a.cos()));
        w.step().unwrap();
    }
    let steps = (0.5 / w.time_step()).round() as u64;
    w.run(steps / 2).unwrap();
    let half_time = w.grain(0).position.x;
    w.run(steps - steps / 2).unwrap();
    let end = w.grain(0).position.x;
    // The tangential springs take up the load (m g sin(alpha) / (2 k_T) ~ 0.7 um), then hold.
    assert!(end.abs() < 1e-6, "moved {end} m in 0.5 s");
    assert!(
        (end - half_time).abs() < 1e-8,
        "creeps {} m",
        end - half_time
    );
}

#[test]
fn slides_with_the_coulomb_acceleration_above_it() {
    let alpha = 0.6f64.atan();
    let mu = ContactLaw::default().friction;
    let expected = G * (alpha.sin() - mu * alpha.cos());
    let mut w = rod_on_slope(alpha);
    let dt = w.time_step();
    w.run((0.1 / dt).round() as u64).unwrap();
    let (t1, v1) = (w.time(), w.grain(0).velocity.x);
    w.run((0.2 / dt).round() as u64).unwrap();
    let (t2, v2) = (w.time(), w.grain(0).velocity.x);
    let a = (v2 - v1) / (t2 - t1);
    assert!(
        (a - expected).abs() < 0.01 * expected,
        "acceleration {a} m/s^2, Coulomb {expected} m/s^2"
    );
}
