//! The vision benchmark: dense packings of each shape, photographed at several scales and in
//! several styles, detected, and scored against the truth.

use std::time::Instant;

use crate::detect::{DetectError, DetectParams, Phases, Shortcuts, detect_report};
use crate::packing::{PackedFrame, Packing};
use crate::render::{Style, render};
use crate::{Frame, GrainShape};

use super::{Tally, Truth, score};

/// Frame of the benchmark photographs: the full silo width by the 120 mm analysed band.
pub const FRAME_WIDTH: f64 = 0.258;
pub const FRAME_HEIGHT: f64 = 0.120;

/// The three grains of the experiment (docs/model.md §1), by the names the command line uses.
pub fn shapes() -> [(&'static str, GrainShape); 3] {
    [
        ("square", GrainShape::nut(6.9e-3)),
        (
            "rod53",
            GrainShape::Rod {
                length: 4.9e-3,
                width: 3e-3,
            },
        ),
        (
            "rod3",
            GrainShape::Rod {
                length: 8.9e-3,
                width: 3e-3,
            },
        ),
    ]
}

/// One photograph of the benchmark.
#[derive(Clone, Debug)]
pub struct Case {
    pub shape_name: &'static str,
    pub shape: GrainShape,
    pub packing: Packing,
    pub px_per_mm: f64,
    pub style_name: &'static str,
    pub seed: u64,
    /// What the detector leaves out (none by default).
    pub shortcuts: Shortcuts,
}

/// Result of one photograph.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub tally: Tally,
    /// Wall time of the detector alone (seconds).
    pub detect_seconds: f64,
    /// The detector's time step by step.
    pub phases: Phases,
    /// Wall time of rendering the photograph (seconds).
    pub render_seconds: f64,
}

/// The true grains of a packing as a photograph of `frame` shows them.
pub fn truth_in_frame(packed: &PackedFrame, frame: &Frame) -> Vec<Truth> {
    packed
        .grains
        .iter()
        .filter(|g| g.overlaps_frame(frame))
        .map(|g| Truth {
            outline: *g,
            cut: g.is_cut_by(frame),
        })
        .collect()
}

/// Renders the case's photograph of `packed`, detects, and scores.
pub fn run_case(case: &Case, packed: &PackedFrame) -> Result<Outcome, DetectError> {
    let frame = Frame {
        width: FRAME_WIDTH,
        height: FRAME_HEIGHT,
        scale: case.px_per_mm * 1e3,
    };
    let style = Style::named(case.style_name).unwrap_or_else(Style::lab);
    let start = Instant::now();
    let photo = render(&packed.grains, &frame, &style, case.seed).to_image(16);
    let render_seconds = start.elapsed().as_secs_f64();
    // The defaults of this shape (not `Default`'s, which are the nuts').
    let params = case
        .shortcuts
        .apply(DetectParams::new(case.shape, frame.scale));
    let start = Instant::now();
    let report = detect_report(&photo, &params)?;
    let detect_seconds = start.elapsed().as_secs_f64();
    Ok(Outcome {
        tally: score(&truth_in_frame(packed, &frame), &report.grains),
        detect_seconds,
        phases: report.phases,
        render_seconds,
    })
}
