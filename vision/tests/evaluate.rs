//! Scores of constructed detections: known recall, precision and errors.

use vision::detect::Detection;
use vision::evaluate::{Truth, score};
use vision::{GrainOutline, GrainShape};

fn rods() -> Vec<Truth> {
    // A 10 x 10 lattice of rods 8.9 x 3 mm, none cut.
    (0..100)
        .map(|i| Truth {
            outline: GrainOutline {
                x: 0.01 * (i % 10) as f64,
                y: 0.004 * (i / 10) as f64,
                theta: 0.05 * i as f64 % std::f64::consts::PI,
                shape: GrainShape::Rod {
                    length: 8.9e-3,
                    width: 3e-3,
                },
            },
            cut: false,
        })
        .collect()
}

fn detected(t: &Truth, dx: f64, dtheta: f64) -> Detection {
    let mut outline = t.outline;
    outline.x += dx;
    outline.theta += dtheta;
    Detection {
        outline,
        confidence: 0.9,
        cut: false,
    }
}

#[test]
fn shifted_and_turned_detections_give_their_errors() {
    let truth = rods();
    // Every detection 0.1 mm off and 1 degree turned, the angle wrapped past pi for some.
    let detections: Vec<Detection> = truth
        .iter()
        .map(|t| detected(t, 1e-4, 1f64.to_radians() + std::f64::consts::PI))
        .collect();
    let tally = score(&truth, &detections);
    assert_eq!(tally.recall(), 1.0);
    assert_eq!(tally.precision(), 1.0);
    assert!((tally.centre_rms_mm() - 0.1).abs() < 1e-9);
    assert!((tally.orientation_rms_deg() - 1.0).abs() < 1e-9);
}

#[test]
fn turned_grains_are_told_from_imprecise_angles() {
    let truth = rods();
    // 97 rods 1 degree off, 3 fitted across their neighbours (80 degrees off): the RMS of
    // all is theirs, that of the rest is the 1 degree.
    let detections: Vec<Detection> = truth
        .iter()
        .enumerate()
        .map(|(i, t)| detected(t, 0.0, if i < 3 { 80f64 } else { 1.0 }.to_radians()))
        .collect();
    let tally = score(&truth, &detections);
    assert_eq!(tally.turned, 3);
    let all = ((3.0 * 80f64.powi(2) + 97.0) / 100.0).sqrt();
    assert!((tally.orientation_rms_deg() - all).abs() < 1e-9);
    assert!((tally.unturned_orientation_rms_deg() - 1.0).abs() < 1e-9);
}

#[test]
fn missed_and_false_detections_count() {
    let truth = rods();
    let mut detections: Vec<Detection> =
        truth[..90].iter().map(|t| detected(t, 0.0, 0.0)).collect();
    // Five detections far from any grain, and one beyond the gate (D/2 = 1.5 mm) of its grain.
    for t in &truth[..5] {
        detections.push(detected(t, 0.005, 0.0));
    }
    detections.push(detected(&truth[95], 1.6e-3, 0.0));
    // A second detection of a found grain is a false one.
    detections.push(detected(&truth[0], 2e-4, 0.0));
    let tally = score(&truth, &detections);
    assert!((tally.recall() - 0.90).abs() < 1e-12);
    assert!((tally.precision() - 90.0 / 97.0).abs() < 1e-12);
    assert_eq!(tally.centre_rms_mm(), 0.0);
}

#[test]
fn cut_grains_neither_missed_nor_false() {
    let mut truth = rods();
    truth[3].cut = true;
    let mut detections: Vec<Detection> = truth.iter().map(|t| detected(t, 0.0, 0.0)).collect();
    // The cut grain's centre is badly estimated: its error must not enter the RMS.
    detections[3].outline.x += 1e-3;
    detections[3].cut = true;
    // Missing the cut grain would not lower recall either.
    let tally = score(&truth, &detections);
    assert_eq!(tally.truth_uncut, 99);
    assert_eq!(tally.recall(), 1.0);
    assert_eq!(tally.precision(), 1.0);
    assert_eq!(tally.centre_rms_mm(), 0.0);
    assert_eq!((tally.detections_cut, tally.detections_cut_matched), (1, 1));
    let without: Vec<Detection> = detections
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != 3)
        .map(|(_, d)| *d)
        .collect();
    assert_eq!(score(&truth, &without).recall(), 1.0);
}
