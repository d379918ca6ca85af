//! Rods in a dense disordered packing, rendered in the lab style: nearly every rod found once, at
//! its own angle. Before the detector scored each rod's axis highlight against the lines flanking
//! it, short rods in such clusters were fitted across two neighbours or turned by 90 degrees.

use vision::evaluate::bench::{FRAME_HEIGHT, FRAME_WIDTH, shapes, truth_in_frame};
use vision::evaluate::{Tally, score};
use vision::packing::{PackedFrame, Packing, generate};
use vision::render::{Style, render};
use vision::{
    DetectError, DetectParams, Frame, GrainOutline, GrainShape, Shortcuts, detect, detect_report,
};

/// The benchmark's short rod (L/D = 5/3).
fn rod53() -> GrainShape {
    shapes()
        .into_iter()
        .find(|(n, _)| *n == "rod53")
        .expect("rod53 is a benchmark shape")
        .1
}

/// The benchmark's 258 x 120 mm frame at 10 px/mm.
fn bench_frame() -> Frame {
    Frame {
        width: FRAME_WIDTH,
        height: FRAME_HEIGHT,
        scale: 1e4,
    }
}

/// A packing of rod53 filling `frame`, packed and rendered with `seed`, detected and scored.
fn packing_tally(packing: Packing, style: &Style, frame: &Frame, seed: u64) -> Tally {
    let shape = rod53();
    let packed = generate(shape, packing, frame, seed);
    let photo = render(&packed.grains, frame, style, seed).to_image(16);
    let found = detect(&photo, &DetectParams::new(shape, frame.scale)).expect("detects");
    score(&truth_in_frame(&packed, frame), &found)
}

#[test]
fn short_rods_in_a_disordered_packing() {
    let frame = Frame {
        width: 0.045,
        height: 0.035,
        scale: 1e4,
    };
    let tally = packing_tally(Packing::Disordered, &Style::lab(), &frame, 3);
    // About 70 whole rods. The benchmark's rod53 lab 10 px/mm figures were 91.7 % recall and
    // 16 degrees before the highlight contrast, 98 % and 5 degrees after: the bounds sit
    // between (the 99.5 % and 1 degree are not reached yet). Rods turned across
    // their neighbours are counted: over 70 rods one such rod alone makes 10 degrees of RMS.
    // Since session 30 (a fit put off holds its place) one is, at the top edge: two rods
    // standing across it over a rod lying along it and the cut rods beyond, the edge's
    // usual case.
    assert!(tally.truth_uncut > 50, "{tally:?}");
    assert!(tally.recall() >= 0.95, "{tally:?}");
    assert!(tally.precision() >= 0.95, "{tally:?}");
    assert!(tally.centre_rms_mm() <= 0.2, "{tally:?}");
    assert!(tally.turned <= 2, "{tally:?}");
    assert!(tally.unturned_orientation_rms_deg() <= 2.0, "{tally:?}");
}

/// Short rods side by side in the clean style at 6 px/mm, where a highlight is a fainter line
/// than the thin gaps between grains: while the axis seeds kept only lines a quarter as strong
/// as the strongest, the gaps alone seeded rods, and they were fitted across two neighbours
/// (95 of 110 whole rods found in this 60 x 40 mm packing; 108 since).
#[test]
fn short_rods_with_faint_highlights_at_low_resolution() {
    let frame = Frame {
        width: 0.060,
        height: 0.040,
        scale: 6e3,
    };
    let tally = packing_tally(Packing::Ordered, &Style::clean(), &frame, 1);
    assert!(tally.truth_uncut > 100, "{tally:?}");
    assert!(tally.recall() >= 0.95, "{tally:?}");
    assert!(tally.precision() >= 0.95, "{tally:?}");
    assert!(tally.orientation_rms_deg() <= 5.0, "{tally:?}");
}

/// A `side` x `side` crop of a benchmark packing of rod53 (258 x 120 mm, `seed`), centred at
/// The shortcuts give up accuracy, not the rods: the packing above detected with one finalist
/// a fit, no repairs and no settling still meets the bounds the full detector is held to
/// there but the centres' (the bench's lab rod53 at 10 px/mm with these shortcuts, seeds 1-4:
/// 99.72 % recall, 0.094 mm, 0.67 degrees for the rods not turned), and no repair runs but
/// the rows'. A fit
/// refining no finalist is refused, naming the parameter.
#[test]
fn the_shortcuts_still_find_the_rods() {
    let frame = Frame {
        width: 0.045,
        height: 0.035,
        scale: 1e4,
    };
    let shape = rod53();
    let packed = generate(shape, Packing::Disordered, &frame, 3);
    let photo = render(&packed.grains, &frame, &Style::lab(), 3).to_image(16);
    let shortcuts = Shortcuts {
        finalists: Some(1),
        settle_sweeps: Some(0),
        no_repairs: true,
        no_relax: false,
    };
    let params = shortcuts.apply(DetectParams::new(shape, frame.scale));
    let report = detect_report(&photo, &params).expect("detects");
    let repairs: Vec<&str> = report
        .phases
        .iter()
        .map(|(name, _)| name)
        .filter(|name| name.starts_with("repair"))
        .collect();
    assert_eq!(repairs, ["repair: rows"]);
    let tally = score(&truth_in_frame(&packed, &frame), &report.grains);
    assert!(tally.truth_uncut > 50, "{tally:?}");
    assert!(tally.recall() >= 0.95, "{tally:?}");
    assert!(tally.precision() >= 0.95, "{tally:?}");
    // Without settling the centres are three times as far off on the bench (0.030 ->
    // 0.094 mm), and over 70 rods one rod off by a millimetre adds 0.12 mm.
    assert!(tally.centre_rms_mm() <= 0.3, "{tally:?}");
    assert!(tally.turned <= 2, "{tally:?}");
    assert!(tally.unturned_orientation_rms_deg() <= 2.0, "{tally:?}");

    let none = DetectParams {
        finalists: 0,
        ..params
    };
    match detect_report(&photo, &none) {
        Err(e @ DetectError::InvalidParams(_)) => {
            assert!(e.to_string().contains("finalists"), "{e}")
        }
        other => panic!("expected the finalists refused, got {other:?}"),
    }
}

/// (`x`, `y`) (metres): the grains centred in it, moved with it, and its photograph in the lab
/// style at 10 px/mm (render seed 1).
fn bench_crop_photo(
    packing: Packing,
    seed: u64,
    x: f64,
    y: f64,
    side: f64,
) -> (PackedFrame, Frame, image::DynamicImage) {
    let shape = rod53();
    let packed = generate(shape, packing, &bench_frame(), seed);
    let (x0, y0) = (x - 0.5 * side, y - 0.5 * side);
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
    (crop, frame, photo)
}

/// [`bench_crop_photo`], detected and scored.
fn bench_crop(packing: Packing, seed: u64, x: f64, y: f64, side: f64) -> Tally {
    let (crop, frame, photo) = bench_crop_photo(packing, seed, x, y, side);
    let found = detect(&photo, &DetectParams::new(rod53(), frame.scale)).expect("detects");
    score(&truth_in_frame(&crop, &frame), &found)
}

/// The repairs work their trials out ahead on several threads and take them over in order
/// only where no repair kept before changed what they read: one thread and several give the
/// same detections to the bit (a 40 mm crop holding the crowded rod of the test below).
#[test]
fn repairs_do_not_depend_on_the_thread_count() {
    let (_, frame, photo) = bench_crop_photo(Packing::Ordered, 1, 0.0789, 0.100, 0.040);
    let params = DetectParams::new(rod53(), frame.scale);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| detect(&photo, &params).expect("detects"))
    };
    let one = on(1);
    assert!(one.len() > 50, "{} rods", one.len());
    for threads in [2, 3] {
        assert!(on(threads) == one, "{threads} threads differ from one");
    }
}

/// A short rod standing across its neighbours' direction (ordered packing, seed 1, at
/// (78.9, 113.1) mm): its neighbour was fitted shifted a millimetre onto it, and its
/// remainder was too small for a rod of its own, so it was missed (12 of 13 whole rods found
/// in this 20 mm crop) until the neighbour is refitted with a rod at the failed seed beside
/// it (`detect::chains::repair_crowded`).
#[test]
fn a_rod_crowded_by_its_neighbour() {
    let tally = bench_crop(Packing::Ordered, 1, 0.0789, 0.110, 0.020);
    assert!(tally.truth_uncut >= 12, "{tally:?}");
    assert_eq!(tally.recall(), 1.0, "{tally:?}");
    assert_eq!(tally.precision(), 1.0, "{tally:?}");
}

/// Two short rods face to face fitted as one rod across both, turned by 90 degrees, with the
/// second rod's remainder beside it unexplained (disordered packing, seed 1, at (136.5, 68.5)
/// mm): the crowded-rod repair takes the turned rod off, fits the missed one at its failed
/// seed, then fits the rod taken off afresh at all angles, since refining it from its turned
/// pose fails (without that fresh fit: 22 of 23 whole rods found in this 25 mm crop, 18.6
/// degrees of orientation RMS).
#[test]
fn a_rod_across_two_is_turned_by_the_crowded_repair() {
    let tally = bench_crop(Packing::Disordered, 1, 0.1355, 0.070, 0.025);
    assert!(tally.truth_uncut >= 20, "{tally:?}");
    assert_eq!(tally.recall(), 1.0, "{tally:?}");
    assert_eq!(tally.precision(), 1.0, "{tally:?}");
    assert!(tally.orientation_rms_deg() < 5.0, "{tally:?}");
}

/// The acceptance puts off a fit whose score a neighbour accepted before it lowered (by its
/// paint) and fits it again next round; meanwhile the fit holds its place. The benchmark's
/// photograph of lab rod53 at 10 px/mm, seed 22, ordered packing: a rod lying 3.7 mm above
/// the bottom edge, between a rod above it and the cut rod below, was put off for its
/// neighbour along the row, and a rod standing across it and the cut rod, scoring less but
/// touching no rod accepted yet, was accepted in its place; it stayed turned by 88 degrees
/// (a second rod of the photograph by 21). No crop of the packing shows it: the fits that
/// compete depend on the whole photograph's rounds.
#[test]
fn a_fit_put_off_holds_its_place() {
    let tally = packing_tally(Packing::Ordered, &Style::lab(), &bench_frame(), 22);
    assert!(tally.truth_uncut > 1500, "{tally:?}");
    assert_eq!(tally.turned, 0, "{tally:?}");
    // The targets at 10 px/mm, on this photograph.
    assert!(tally.recall() >= 0.995, "{tally:?}");
    assert!(tally.precision() >= 0.995, "{tally:?}");
    assert!(tally.orientation_rms_deg() <= 1.0, "{tally:?}");
}
