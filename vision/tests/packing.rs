//! Generated packings are dense, touching, and free of overlaps beyond the tolerance.

use vision::packing::{Packing, generate};
use vision::{Frame, GrainShape};

fn frame() -> Frame {
    Frame {
        width: 0.06,
        height: 0.04,
        scale: 1e4,
    }
}

#[test]
fn rods_pack_densely_without_overlaps() {
    let shape = GrainShape::Rod {
        length: 4.9e-3,
        width: 3e-3,
    };
    for packing in [Packing::Ordered, Packing::Disordered] {
        let p = generate(shape, packing, &frame(), 7);
        // Random packings of frictionless rectangles jam at about 0.65-0.8; a packing with
        // gaps between grains (or a dilute one) would be far below 0.6.
        assert!(
            p.packing_fraction > 0.6,
            "{packing:?}: {}",
            p.packing_fraction
        );
        // Relaxation aims at 0.3 % of D; its last sweep may leave a little more, but an
        // overlap of 1 % of D (0.03 mm, a third of a pixel at 10 px/mm) is the most a
        // photograph of touching grains may hide.
        assert!(p.max_overlap < 0.01, "{packing:?}: {}", p.max_overlap);
        // Grains cut by the frame edges are part of the packing.
        assert!(p.grains.iter().any(|g| g.is_cut_by(&frame())));
    }
}

#[test]
fn ordered_squares_lie_flat_and_disordered_do_not() {
    let shape = GrainShape::nut(6.9e-3);
    let flat = |p: Packing| {
        let grains = generate(shape, p, &frame(), 3).grains;
        let near = grains
            .iter()
            .filter(|g| {
                let t = g.theta.rem_euclid(std::f64::consts::FRAC_PI_2);
                t.min(std::f64::consts::FRAC_PI_2 - t) < 10f64.to_radians()
            })
            .count();
        near as f64 / grains.len() as f64
    };
    // Uniform angles put 2 x 10 / 90 = 22 % within 10 degrees of flat.
    let (ordered, disordered) = (flat(Packing::Ordered), flat(Packing::Disordered));
    assert!(ordered > 0.7, "ordered: {ordered}");
    assert!(disordered < 0.4, "disordered: {disordered}");
}

#[test]
fn same_seed_same_packing() {
    let shape = GrainShape::nut(6.9e-3);
    let a = generate(shape, Packing::Disordered, &frame(), 11);
    let b = generate(shape, Packing::Disordered, &frame(), 11);
    assert_eq!(a.grains, b.grains);
}
