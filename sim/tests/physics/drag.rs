//! Relaxation drag: it brings a ringing column to rest, leaves a grain in free flight alone, and
//! does not move where a deposit rests.

use sim::{ContactLaw, Vec2, World};

use super::common::*;

fn run_for(w: &mut World, seconds: f64) {
    w.run((seconds / w.time_step()).ceil() as u64).unwrap();
}

#[test]
fn drag_stills_a_ringing_column_the_contact_law_leaves_ringing() {
    let n = 10;
    let ratio = |drag: f64| {
        let (mut w, _) = ringing_column(n, 20e-6);
        w.set_drag(drag).unwrap();
        run_for(&mut w, 0.1);
        let e = w.energies();
        e.kinetic / e.elastic
    };
    let (free, dragged) = (ratio(0.0), ratio(200.0));
    // exp(-200 s^-1 x 0.1 s) = 2e-9 of the energy left, were every mode at the drag's rate.
    assert!(
        dragged < 1e-6,
        "kinetic / elastic after 0.1 s with drag: {dragged:e}"
    );
    assert!(
        free > 1e3 * dragged,
        "without drag the column should still ring: {free:e} against {dragged:e}"
    );
}

#[test]
fn drag_leaves_the_static_balance_where_it_was() {
    let n = 10;
    let (mut w, floor) = ringing_column(n, 20e-6);
    w.set_drag(200.0).unwrap();
    run_for(&mut w, 0.2);
    let weight: f64 = (0..n).map(|i| mass(&w, i) * 10.0).sum();
    let floor_load = -w.wall_load(floor).y;
    // At rest the drag vanishes: the floor carries the weight as in test 3 (0.1 %).
    assert!(
        (floor_load - weight).abs() < 1e-3 * weight,
        "floor {floor_load} N, weight {weight} N"
    );
}

#[test]
fn drag_does_not_slow_a_grain_in_free_flight() {
    let fall = |drag: f64| {
        let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
        let square = add_square(&mut w);
        w.add_grain(square, moving(0.0, 1.0, 0.3, 0.5, -3.5))
            .unwrap();
        w.set_drag(drag).unwrap();
        run_for(&mut w, 0.05);
        w.grain(0)
    };
    let (free, dragged) = (fall(0.0), fall(200.0));
    assert_eq!(free.position, dragged.position);
    assert_eq!(free.velocity, dragged.velocity);
}

#[test]
fn a_negative_or_nan_drag_is_refused_by_name() {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), None);
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let err = w.set_drag(bad).unwrap_err().to_string();
        assert!(err.contains("drag"), "{err}");
    }
}
