//! Rods in a dense disordered packing, rendered in the lab style: nearly every rod found once, at
//! its own angle. Before the detector scored each rod's axis highlight against the lines flanking
//! it, short rods in such clusters were fitted across two neighbours or turned by 90 degrees.

use vision::evaluate::bench::{shapes, truth_in_frame};
use vision::evaluate::score;
use vision::packing::{PackedFrame, Packing, generate};
use vision::render::{Style, render};
use vision::{DetectParams, Frame, GrainOutline, detect};

#[test]
fn short_rods_in_a_disordered_packing() {
    let shape = shapes()
        .into_iter()
        .find(|(n, _)| *n == "rod53")
        .expect("rod53 is a benchmark shape")
        .1;
    let frame = Frame {
        width: 0.045,
        height: 0.035,
        scale: 1e4,
    };
    let packed = generate(shape, Packing::Disordered, &frame, 3);
    let photo = render(&packed.grains, &frame, &Style::lab(), 3).to_image(16);
    let found = detect(&photo, &DetectParams::new(shape, frame.scale)).expect("detects");
    let tally = score(&truth_in_frame(&packed, &frame), &found);
    // About 70 whole rods. The benchmark's rod53 lab 10 px/mm figures were 91.7 % recall and
    // 16 degrees before the highlight contrast, 98 % and 5 degrees after: the bounds sit
    // between (the 99.5 % and 1 degree are not reached yet).
    assert!(tally.truth_uncut > 50, "{tally:?}");
    assert!(tally.recall() >= 0.95, "{tally:?}");
    assert!(tally.precision() >= 0.95, "{tally:?}");
    assert!(tally.centre_rms_mm() <= 0.2, "{tally:?}");
    assert!(tally.orientation_rms_deg() <= 8.0, "{tally:?}");
}

/// A short rod standing across its neighbours' direction (rod53, ordered packing of the
/// benchmark, lab, 10 px/mm, at (78.9, 113.1) mm): its neighbour was fitted shifted a
/// millimetre onto it, and its remainder was too small for a rod of its own, so it was
/// missed (12 of 13 whole rods found in this 20 mm crop) until the neighbour is refitted with
/// a rod at the failed seed beside it (`detect::chains::repair_crowded`).
#[test]
fn a_rod_crowded_by_its_neighbour() {
    let shape = shapes()
        .into_iter()
        .find(|(n, _)| *n == "rod53")
        .expect("rod53 is a benchmark shape")
        .1;
    let bench = Frame {
        width: 0.258,
        height: 0.120,
        scale: 1e4,
    };
    let packed = generate(shape, Packing::Ordered, &bench, 1);
    // A 20 mm crop of the benchmark's photograph: the grains centred in it, moved with it.
    let (x0, y0, side) = (0.0689, 0.100, 0.020);
    let frame = Frame {
        width: side,
        height: side,
        scale: 1e4,
    };
    let grains = packed
        .grains
        .iter()
        .filter(|g| g.x >= x0 && g.y >= y0 && g.x < x0 + side && g.y < y0 + side)
        .map(|g| GrainOutline {
            x: g.x - x0,
            y: g.y - y0,
            ..*g
        })
        .collect();
    let crop = PackedFrame { grains, ..packed };
    let photo = render(&crop.grains, &frame, &Style::lab(), 1).to_image(16);
    let found = detect(&photo, &DetectParams::new(shape, frame.scale)).expect("detects");
    let tally = score(&truth_in_frame(&crop, &frame), &found);
    assert!(tally.truth_uncut >= 12, "{tally:?}");
    assert_eq!(tally.recall(), 1.0, "{tally:?}");
    assert_eq!(tally.precision(), 1.0, "{tally:?}");
}
