//! Pairs found apart are not looked at again until their grains have travelled the gap: the
//! contact must still start on the very step the outlines first overlap.

use sim::{ContactLaw, Spheropolygon, Vec2, World};

use crate::common::*;

/// Distance between the two grains' rounded outlines, from their poses alone: the distance
/// between the core polygons (a vertex of one against an edge of the other) less 2 r.
fn outline_gap(w: &World, shape: &Spheropolygon) -> f64 {
    let core = |i: usize| -> Vec<Vec2> {
        let g = w.grain(i);
        let (sin, cos) = g.angle.sin_cos();
        shape
            .vertices()
            .iter()
            .map(|v| g.position + Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y))
            .collect()
    };
    let to_segment = |p: Vec2, s: Vec2, t: Vec2| {
        let d = t - s;
        let u = ((p - s).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        (p - (s + d * u)).norm()
    };
    let one_way = |a: &[Vec2], b: &[Vec2]| {
        a.iter()
            .flat_map(|p| (0..b.len()).map(move |e| to_segment(*p, b[e], b[(e + 1) % b.len()])))
            .fold(f64::INFINITY, f64::min)
    };
    let (a, b) = (core(0), core(1));
    one_way(&a, &b).min(one_way(&b, &a)) - 2.0 * shape.radius()
}

#[test]
fn a_pair_found_apart_touches_on_the_step_its_outlines_meet() {
    // A square turning as it slides towards another at rest, starting 0.7 mm apart (inside
    // the Verlet skin, so the pair is listed and found apart at once): 0.3 m/s and 20 rad/s
    // close the gap in a few thousand steps of 1 us, through both terms of the travel bound.
    let mut w = world(ContactLaw::default(), Vec2::zeros(), Some(1e-6));
    let shape = square();
    let nut = add_square(&mut w);
    w.add_grain(nut, at(0.0, 0.0, 0.0)).unwrap();
    let start = {
        let mut g = moving(SIDE + 1.5e-3, 0.5e-3, 0.3, -0.3, 0.0);
        g.angular_velocity = 20.0;
        g
    };
    w.add_grain(nut, start).unwrap();
    w.prime().unwrap();
    assert!(
        outline_gap(&w, &shape) > 0.5e-3,
        "{}",
        outline_gap(&w, &shape)
    );
    let mut first_touch = None;
    for step in 1..=5_000 {
        w.step().unwrap();
        let touching = outline_gap(&w, &shape) < 0.0;
        let in_contact = w.contacts().any(|c| c.second == sim::Body::Grain(1));
        assert_eq!(
            touching,
            in_contact,
            "step {step}: outlines {} apart, contact listed: {in_contact}",
            outline_gap(&w, &shape)
        );
        if touching {
            first_touch = Some(step);
            break;
        }
    }
    let step = first_touch.expect("the squares never met");
    assert!(
        step > 500,
        "met after {step} steps: the pair was never skipped"
    );
}
