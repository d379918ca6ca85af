//! Test 9: each bad input gives an error that names the field.

use sim::{
    ContactLaw, GrainState, SimError, Spheropolygon, Vec2, World, WorldSettings, critical_time_step,
};

use super::common::*;

fn message<T: std::fmt::Debug>(r: Result<T, SimError>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn bad_settings_name_the_field() {
    let bad_law = ContactLaw {
        tangential_damping: -1.0,
        ..ContactLaw::default()
    };
    let settings = |f: fn(&mut WorldSettings)| {
        let mut s = WorldSettings::default();
        f(&mut s);
        World::new(s)
    };
    assert!(
        message(World::new(WorldSettings {
            law: bad_law,
            ..Default::default()
        }))
        .contains("`tangential_damping`")
    );
    assert!(message(settings(|s| s.gravity.y = f64::NAN)).contains("`gravity`"));
    assert!(message(settings(|s| s.time_step = Some(-1e-6))).contains("`time_step`"));
    assert!(message(settings(|s| s.skin_fraction = 0.0)).contains("`skin_fraction`"));
}

#[test]
fn a_time_step_above_the_bound_is_refused_with_both_numbers() {
    let shape = square();
    let (m, inertia) = shape.mass_properties(NUT_DENSITY).unwrap();
    let critical = critical_time_step(&ContactLaw::default(), m, inertia, shape.bounding_radius());
    assert!(critical > 1e-5 && critical < 1e-3, "{critical}");
    let dt = 2.0 * critical;
    let mut w = World::new(WorldSettings {
        time_step: Some(dt),
        ..Default::default()
    })
    .unwrap();
    let err = message(w.add_shape(shape.clone(), NUT_DENSITY));
    assert!(
        err.contains(&format!("{dt:e}")) && err.contains(&format!("{critical:e}")),
        "{err}"
    );
    // Just below the bound is accepted.
    let mut w = World::new(WorldSettings {
        time_step: Some(0.99 * critical),
        ..Default::default()
    })
    .unwrap();
    assert!(w.add_shape(shape, NUT_DENSITY).is_ok());
}

#[test]
fn bad_grains_and_shapes_name_the_field() {
    let mut w = World::new(WorldSettings::default()).unwrap();
    assert!(message(w.step()).contains("time_step"));
    assert!(message(w.add_shape(square(), -2.0)).contains("`areal_density`"));
    let id = add_square(&mut w);
    let nan = GrainState::at_rest(Vec2::new(f64::NAN, 0.0), 0.0);
    assert!(message(w.add_grain(id, nan)).contains("`position`"));
    let spinning = GrainState {
        angular_velocity: f64::INFINITY,
        ..GrainState::at_rest(Vec2::zeros(), 0.0)
    };
    assert!(message(w.add_grain(id, spinning)).contains("`angular_velocity`"));
    assert!(
        message(w.add_grain(sim::ShapeId(7), GrainState::at_rest(Vec2::zeros(), 0.0)))
            .contains("7")
    );
    let r = Spheropolygon::rounded_rectangle(3e-3, 8.9e-3, 0.15e-3);
    assert!(r.unwrap_err().to_string().contains("`length`"));
}
