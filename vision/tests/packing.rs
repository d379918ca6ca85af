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
        // Touching, not scattered: nearly every grain presses on a neighbour (gap < 1 % of D);
        // only a few rattlers sit loose in their cages.
        assert!(
            p.touching_fraction > 0.9,
            "{packing:?}: {}",
            p.touching_fraction
        );
        // Grains cut by the frame edges are part of the packing.
        assert!(p.grains.iter().any(|g| g.is_cut_by(&frame())));
    }
}

/// Fraction of grains within 10 degrees of lying flat (a face on the floor).
fn flat_fraction(shape: GrainShape, packing: Packing) -> f64 {
    let grains = generate(shape, packing, &frame(), 3).grains;
    let period = shape.symmetry_period();
    let near = grains
        .iter()
        .filter(|g| {
            let t = g.theta.rem_euclid(period);
            // Folded by symmetry, flat is 0 or one period (a square lies flat on any face).
            t.min(period - t) < 10f64.to_radians()
        })
        .count();
    near as f64 / grains.len() as f64
}

#[test]
fn ordered_grains_lie_flat_and_disordered_do_not() {
    // Uniform angles put 20/90 = 22 % of squares and 20/180 = 11 % of rods within 10 degrees
    // of flat; a slow filling lays most of them flat (more than half, whatever the seed).
    let rod = GrainShape::Rod {
        length: 8.9e-3,
        width: 3e-3,
    };
    for (shape, uniform) in [(GrainShape::nut(6.9e-3), 0.22), (rod, 0.11)] {
        let ordered = flat_fraction(shape, Packing::Ordered);
        let disordered = flat_fraction(shape, Packing::Disordered);
        assert!(ordered > 0.5, "{shape:?} ordered: {ordered}");
        assert!(
            disordered < 2.0 * uniform,
            "{shape:?} disordered: {disordered}"
        );
    }
}

#[test]
fn same_seed_same_packing() {
    let shape = GrainShape::nut(6.9e-3);
    let a = generate(shape, Packing::Disordered, &frame(), 11);
    let b = generate(shape, Packing::Disordered, &frame(), 11);
    assert_eq!(a.grains, b.grains);
}
