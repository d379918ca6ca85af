//! The contact table (normals and points found again from the placed cores) accounts for the
//! whole force on every grain: summed with gravity it gives the force the step integrated.

use sim::{Body, ContactLaw, Vec2};

use super::common::*;

#[test]
fn contact_records_add_up_to_each_grains_force() {
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    add_box(&mut w, 10.0 * SIDE);
    let square = add_square(&mut w);
    let rod = w.add_shape(rod(), ROD_DENSITY).unwrap();
    for k in 0..120 {
        let (row, col) = (k / 6, k % 6);
        let shape = if k % 3 == 0 { rod } else { square };
        let x = (col as f64 + 0.8) * 1.5 * SIDE + 2e-4 * row as f64;
        w.add_grain(
            shape,
            moving(
                x,
                SIDE + row as f64 * 1.4 * SIDE,
                0.37 * k as f64,
                0.0,
                -1.0,
            ),
        )
        .unwrap();
    }
    w.run(20_000).unwrap();
    let n = w.len();
    let mut force = vec![Vec2::zeros(); n];
    let mut torque = vec![0.0; n];
    let mut records = 0;
    for c in w.contacts() {
        records += 1;
        let g = w.grains();
        force[c.first] += c.force;
        torque[c.first] += sim::math::cross(c.point - g.position[c.first], c.force);
        if let Body::Grain(j) = c.second {
            force[j] -= c.force;
            torque[j] -= sim::math::cross(c.point - g.position[j], c.force);
        }
    }
    assert!(
        records > 150,
        "{records} sub-contacts: the pile is not dense"
    );
    let g = w.grains();
    for i in 0..n {
        let weight = g.mass[i] * 10.0;
        let expected = g.force[i] - Vec2::new(0.0, -weight);
        assert!(
            (force[i] - expected).norm() < 1e-9 * weight.max(expected.norm()),
            "grain {i}: table {:?}, step {:?}",
            force[i],
            expected
        );
        assert!(
            (torque[i] - g.torque[i]).abs() < 1e-9 * weight * SIDE,
            "grain {i}: table torque {}, step {}",
            torque[i],
            g.torque[i]
        );
    }
}

#[test]
fn contact_records_against_fixed_grains_add_up_to_each_grains_force() {
    // A floor of fixed squares at scattered orientations, as a rough wall: the table must give
    // the force each grain felt from the wall grains as from the others.
    let mut w = world(ContactLaw::default(), Vec2::new(0.0, -10.0), Some(1e-5));
    add_box(&mut w, 10.0 * SIDE);
    let square = add_square(&mut w);
    let mut seed = 11;
    let mut fixed = 0;
    let mut x = 0.3 * SIDE;
    while x < 10.0 * SIDE {
        let angle = uniform(&mut seed) * std::f64::consts::PI;
        w.add_fixed_grain(square, Vec2::new(x, 0.2 * SIDE), angle)
            .unwrap();
        fixed += 1;
        x += 0.5 * SIDE;
    }
    for k in 0..60 {
        let (row, col) = (k / 6, k % 6);
        let x = (col as f64 + 0.8) * 1.5 * SIDE + 2e-4 * row as f64;
        let state = moving(
            x,
            2.0 * SIDE + row as f64 * 1.4 * SIDE,
            0.37 * k as f64,
            0.0,
            -1.0,
        );
        w.add_grain(square, state).unwrap();
    }
    w.run(20_000).unwrap();
    let n = w.len();
    let mut force = vec![Vec2::zeros(); n];
    let mut records = 0;
    for c in w.contacts() {
        force[c.first] += c.force;
        if let Body::Grain(j) = c.second {
            force[j] -= c.force;
        }
        records += 1;
    }
    assert!(
        records > 40,
        "{records} sub-contacts: the pile is not dense"
    );
    let g = w.grains();
    for (i, table) in force.iter().enumerate().skip(fixed) {
        let weight = g.mass[i] * 10.0;
        let expected = g.force[i] - Vec2::new(0.0, -weight);
        assert!(
            (table - expected).norm() < 1e-9 * weight.max(expected.norm()),
            "grain {i}: table {table:?}, step {expected:?}"
        );
    }
}
