//! Test 1: binary collisions at the paper's parameters; the restitution coefficient against
//! the exact solution of the linear spring-dashpot.

use std::f64::consts::{FRAC_PI_4, PI};

use sim::{ContactLaw, Spheropolygon, Vec2};

use super::common::*;

/// Restitution of m_r x'' = -k x - c x' (x the overlap) with the force clamped at zero: the
/// collision ends when k x + c x' = 0, before x returns to zero. With omega0^2 = k / m_r and
/// beta = c / (2 m_r), x = (v0 / w) exp(-beta t) sin(w t), and the force vanishes at
/// w t = pi - atan2(2 beta w, omega0^2 - 2 beta^2).
fn exact_restitution(omega0_sq: f64, beta: f64) -> f64 {
    let w = (omega0_sq - beta * beta).sqrt();
    let phase = PI - (2.0 * beta * w).atan2(omega0_sq - 2.0 * beta * beta);
    -(-beta * phase / w).exp() * (phase.cos() - beta / w * phase.sin())
}

/// Grain 1 approaches grain 0 at `speed` along -y; returns (restitution, collision steps).
fn collide(
    shape: Spheropolygon,
    density: f64,
    top_angle: f64,
    gap_y: f64,
    dt: Option<f64>,
) -> (f64, u64) {
    let mut w = world(ContactLaw::default(), Vec2::zeros(), dt);
    let id = w.add_shape(shape, density).unwrap();
    w.add_grain(id, at(0.0, 0.0, 0.0)).unwrap();
    let speed = 0.5;
    w.add_grain(id, moving(0.0, gap_y, top_angle, 0.0, -speed))
        .unwrap();
    let (mut touched, mut steps_in_contact) = (false, 0);
    for _ in 0..200_000 {
        w.step().unwrap();
        let touching = w.contacts().count() > 0;
        if touching {
            touched = true;
            steps_in_contact += 1;
        } else if touched {
            break;
        }
    }
    assert!(touched, "the grains never met");
    let relative = w.grain(1).velocity - w.grain(0).velocity;
    // Symmetric set-ups: no sideways motion, no spin.
    assert!(relative.x.abs() < 1e-9 * speed, "sideways {relative:?}");
    assert!(w.grain(1).angular_velocity.abs() < 1e-6);
    (relative.y / speed, steps_in_contact)
}

fn check(name: &str, measured: f64, expected: f64) {
    let error = (measured - expected).abs() / expected;
    assert!(
        error < 0.01,
        "{name}: restitution {measured:.5}, exact {expected:.5} ({:.2} % off)",
        100.0 * error
    );
}

#[test]
fn face_on_face_squares() {
    let law = ContactLaw::default();
    let m = square().mass_properties(NUT_DENSITY).unwrap().0;
    let reduced = m / 2.0;
    // Two sub-contacts in parallel: stiffness 2 k_N, damping 2 gamma_N m_r.
    let expected = exact_restitution(2.0 * law.normal_stiffness / reduced, law.normal_damping);
    assert!(expected > 0.8 && expected < 0.95, "{expected}");
    let gap = SIDE + 0.1e-3;
    for dt in [Some(1e-6), None] {
        let (e, steps) = collide(square(), NUT_DENSITY, 0.0, gap, dt);
        check(
            &format!("squares face on face, dt {dt:?}, {steps} steps"),
            e,
            expected,
        );
    }
}

#[test]
fn face_on_face_long_rods() {
    let law = ContactLaw::default();
    let m = rod().mass_properties(ROD_DENSITY).unwrap().0;
    let expected = exact_restitution(2.0 * law.normal_stiffness / (m / 2.0), law.normal_damping);
    for dt in [Some(1e-6), None] {
        let (e, steps) = collide(rod(), ROD_DENSITY, 0.0, ROD_WIDTH + 0.1e-3, dt);
        check(
            &format!("rods face on face, dt {dt:?}, {steps} steps"),
            e,
            expected,
        );
    }
}

#[test]
fn corner_on_face_squares() {
    let law = ContactLaw::default();
    let m = square().mass_properties(NUT_DENSITY).unwrap().0;
    let reduced = m / 2.0;
    // One sub-contact through both centres: no torque.
    let expected = exact_restitution(law.normal_stiffness / reduced, law.normal_damping / 2.0);
    let core_half = SIDE / 2.0 - SQUARE_RADIUS;
    let gap = core_half + core_half * 2f64.sqrt() + 2.0 * SQUARE_RADIUS + 0.1e-3;
    for dt in [Some(1e-6), None] {
        let (e, steps) = collide(square(), NUT_DENSITY, FRAC_PI_4, gap, dt);
        // The paper's grains are bouncy: 0.9 to 0.95 (docs/model.md §2).
        assert!(e > 0.88 && e < 0.96, "{e}");
        check(
            &format!("square corner on face, dt {dt:?}, {steps} steps"),
            e,
            expected,
        );
    }
}

/// Test 6: a corner against a corner is counted once and pushes like two disks of radius r.
#[test]
fn corner_on_corner_acts_like_two_disks() {
    let law = ContactLaw::default();
    let core_half_diagonal = (SIDE / 2.0 - SQUARE_RADIUS) * 2f64.sqrt();
    for skew in [0.0f64, 0.15, -0.3] {
        let mut w = world(law, Vec2::zeros(), Some(1e-6));
        let id = add_square(&mut w);
        let overlap = 0.2e-3;
        // Tips on the x axis: left tip at angle `skew` from its diagonal, right likewise.
        w.add_grain(id, at(0.0, 0.0, FRAC_PI_4 + skew)).unwrap();
        let tip = Vec2::new(skew.cos(), skew.sin()) * core_half_diagonal;
        let heel = Vec2::new(-skew.cos(), skew.sin()) * core_half_diagonal;
        let centre = tip + Vec2::new(2.0 * SQUARE_RADIUS - overlap, 0.0) - heel;
        w.add_grain(id, at(centre.x, centre.y, FRAC_PI_4 - skew))
            .unwrap();
        w.prime().unwrap();
        let contacts: Vec<_> = w.contacts().collect();
        assert_eq!(contacts.len(), 1, "skew {skew}: {contacts:?}");
        let c = contacts[0];
        // Two disks of radius r whose centres are the two tips, at this overlap.
        let disk_force = Vec2::new(law.normal_stiffness * overlap, 0.0);
        let on_right = if c.first == 1 { c.force } else { -c.force };
        assert!(
            (on_right - disk_force).norm() < 1e-9 * disk_force.norm(),
            "skew {skew}: {on_right:?} vs {disk_force:?}"
        );
    }
}
