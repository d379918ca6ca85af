//! Test 5: a square dropped corner-first at 5 m/s overlaps deeper than r_i + r_j, yet the
//! contact stays repulsive, finite, and the grains separate with no energy gained.

use std::f64::consts::FRAC_PI_4;

use sim::{Body, ContactLaw, Vec2};

use super::common::*;

const G: f64 = 10.0;

struct Outcome {
    deepest: f64,
    energy_before: f64,
    energy_after: f64,
}

fn drop_corner_first(onto_square: bool, tilt: f64) -> Outcome {
    let law = ContactLaw::default();
    let mut w = world(law, Vec2::new(0.0, -G), None);
    add_floor(&mut w);
    let id = add_square(&mut w);
    let m = square().mass_properties(NUT_DENSITY).unwrap().0;
    let mut target_top = 0.0;
    if onto_square {
        let overlap = m * G / (2.0 * law.normal_stiffness);
        w.add_grain(id, at(0.0, SIDE / 2.0 - overlap, 0.0)).unwrap();
        target_top = SIDE - overlap;
    }
    let core_half = SIDE / 2.0 - SQUARE_RADIUS;
    // Lowest core vertex 0.2 mm above the target's rounded surface.
    let angle = FRAC_PI_4 + tilt;
    let lowest = (0..4)
        .map(|k| {
            let a = angle + FRAC_PI_4 + k as f64 * std::f64::consts::FRAC_PI_2;
            core_half * 2f64.sqrt() * a.sin()
        })
        .fold(f64::INFINITY, f64::min);
    let y = target_top + 0.2e-3 + SQUARE_RADIUS - lowest;
    let dropped = w.add_grain(id, moving(0.0, y, angle, 0.0, -5.0)).unwrap().0;
    w.prime().unwrap();
    let energy_before = w.energies().total();
    let reach = if onto_square {
        2.0 * SQUARE_RADIUS
    } else {
        SQUARE_RADIUS
    };
    let mut deepest = 0.0f64;
    let mut touched = false;
    for _ in 0..(0.1 / w.time_step()) as u64 {
        w.step().unwrap();
        let mut touching = false;
        for c in w.contacts() {
            assert!(c.force.x.is_finite() && c.force.y.is_finite() && c.overlap.is_finite());
            assert!(c.force.dot(&c.normal) >= 0.0, "attractive contact {c:?}");
            if c.first == dropped || c.second == Body::Grain(dropped) {
                touching = true;
                deepest = deepest.max(c.overlap);
            }
        }
        let s = w.grain(dropped);
        assert!(s.position.x.is_finite() && s.position.y.is_finite());
        if onto_square {
            // No tunnelling: the dropped grain stays above the one it hit.
            assert!(s.position.y > w.grain(0).position.y);
        }
        touched |= touching;
        if touched && !touching && s.velocity.y > 0.0 {
            return Outcome {
                deepest: deepest / reach,
                energy_before,
                energy_after: w.energies().total(),
            };
        }
    }
    panic!("the dropped square never left the target (deepest overlap {deepest} m)");
}

#[test]
fn corner_first_onto_floor_and_onto_a_resting_square() {
    for onto_square in [false, true] {
        for tilt in [0.0, 0.2] {
            let o = drop_corner_first(onto_square, tilt);
            let case = format!("onto square {onto_square}, tilt {tilt}");
            assert!(
                o.deepest > 1.0,
                "{case}: deepest overlap only {} x (r_i + r_j)",
                o.deepest
            );
            assert!(
                o.energy_after <= o.energy_before,
                "{case}: energy grew from {} J to {} J",
                o.energy_before,
                o.energy_after
            );
        }
    }
}

/// Two long rods meeting end-on along their common axis, collinear or nearly so: at 2.5 m/s
/// each (5 m/s relative, the top of a fill's impact speeds), and at 5 m/s each exactly on the
/// side lines, the case that locked in deposits. (At 5 m/s each with a corner 0.05 mm off the
/// side line, or turned by 0.01 rad, the corner past the end is genuinely nearest the side and
/// the rods still lock: a limit of vertex-edge sub-contacts at three rounding radii deep.) The
/// corners of each end lie on (or next to) the other rod's long sides, so once a corner has gone
/// deeper than r_i + r_j it is nearer a long side than the end it came through. It must still be
/// pushed back through that end: pushed sideways, the two corners of an end are squeezed from
/// both sides, the forces cancel and the rods slide into each other and lock (seen in a
/// paper-scale deposit of rods: collinear pairs half a rod deep, pressed at 3 N).
#[test]
fn rods_meeting_end_on_bounce_back_along_their_axis() {
    let cases = [
        (2.5, 0.0, 0.0),
        (2.5, 1e-9, 0.0),
        (2.5, 0.05e-3, 0.0),
        (2.5, 0.0, 0.01),
        (2.5, 0.4e-3, -0.02),
        (5.0, 0.0, 0.0),
        (5.0, -1e-9, 0.0),
        (5.0, 1e-9, 0.0),
    ];
    for (speed, offset, turn) in cases {
        let law = ContactLaw::default();
        let mut w = world(law, Vec2::zeros(), None);
        let id = w.add_shape(rod(), ROD_DENSITY).unwrap();
        let gap = 0.1e-3;
        w.add_grain(id, moving(0.0, 0.0, 0.0, speed, 0.0)).unwrap();
        w.add_grain(id, moving(ROD_LENGTH + gap, offset, turn, -speed, 0.0))
            .unwrap();
        w.prime().unwrap();
        // The cores' ends touch at a centre distance of L - 2 r.
        let mut closest = f64::INFINITY;
        for _ in 0..(5e-3 / w.time_step()) as u64 {
            w.step().unwrap();
            closest = closest.min((w.grain(1).position - w.grain(0).position).norm());
        }
        let case = format!("{speed} m/s each, offset {offset} m, turn {turn} rad");
        assert!(
            closest < ROD_LENGTH - 2.0 * ROD_RADIUS,
            "{case}: the cores never went deeper than r_i + r_j into each other"
        );
        let (a, b) = (w.grain(0), w.grain(1));
        assert_eq!(
            w.contacts().count(),
            0,
            "{case}: still touching, {a:?} {b:?}"
        );
        // Bounced back along the axis (restitution about 0.9), not sideways.
        assert!(
            a.velocity.x < -0.8 * speed && b.velocity.x > 0.8 * speed,
            "{case}: {:?} {:?}",
            a.velocity,
            b.velocity
        );
        assert!(
            (b.position - a.position).x > ROD_LENGTH,
            "{case}: the rods overlap along their axis"
        );
    }
}
