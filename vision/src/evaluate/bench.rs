//! The vision benchmark's photograph: grains in a frame, drawn in a look, stored as its file
//! stores it, detected, and scored against the truth.

use std::time::Instant;

use crate::detect::{DetectParams, Phases, Report, Shortcuts, detect_report};
use crate::packing::PackedFrame;
use crate::render::Look;
use crate::{Frame, GrainOutline, GrainShape};

use super::{Tally, Truth, memory, score_with_errors};

/// Frame of the packings' photographs in the detector's tests: the full silo width by the
/// 120 mm analysed band.
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
pub struct Photo<'a> {
    /// The grains that show in the frame (frame coordinates).
    pub grains: &'a [GrainOutline],
    /// The frame and its scale.
    pub frame: Frame,
    /// The grain the detector is told to look for.
    pub shape: GrainShape,
    pub look: &'a Look,
    /// Seed of the noise, dust and light.
    pub seed: u64,
    /// What the detector leaves out (none by default).
    pub shortcuts: Shortcuts,
}

/// Result of one photograph.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub tally: Tally,
    /// Orientation error of every matched uncut grain (degrees, signed).
    pub orientation_errors_deg: Vec<f64>,
    /// Wall time of the detector alone (seconds).
    pub detect_seconds: f64,
    /// The detector's time step by step.
    pub phases: Phases,
    /// Wall time of rendering and storing the photograph (seconds).
    pub render_seconds: f64,
    /// The process's peak resident memory during the detection (bytes; [`memory`] says what
    /// it counts), where the system tells it.
    pub peak_memory_bytes: Option<u64>,
    /// Why the detector refused the photograph, if it did (then it found nothing).
    pub refused: Option<String>,
}

/// Why a photograph of the benchmark gave no outcome: it could not be stored as its look
/// asks. (A photograph the detector refuses is an outcome: nothing found.)
#[derive(Debug, thiserror::Error)]
#[error("storing the photograph as its look asks: {0}")]
pub struct StoreError(#[from] image::ImageError);

/// The true grains of a packing as a photograph of `frame` shows them.
pub fn truth_in_frame(packed: &PackedFrame, frame: &Frame) -> Vec<Truth> {
    truth_of(&packed.grains, frame)
}

/// The true grains among `grains` that a photograph of `frame` shows.
pub fn truth_of(grains: &[GrainOutline], frame: &Frame) -> Vec<Truth> {
    grains
        .iter()
        .filter(|g| g.overlaps_frame(frame))
        .map(|g| Truth {
            outline: *g,
            cut: g.is_cut_by(frame),
        })
        .collect()
}

/// Renders and stores the photograph, detects, and scores.
pub fn run_photo(photo: &Photo) -> Result<Outcome, StoreError> {
    let start = Instant::now();
    let image = photo
        .look
        .photograph(photo.grains, &photo.frame, photo.seed)?;
    let render_seconds = start.elapsed().as_secs_f64();
    // The defaults of this shape (not `Default`'s, which are the nuts').
    let params = photo
        .shortcuts
        .apply(DetectParams::new(photo.shape, photo.frame.scale));
    let measured = memory::reset_peak();
    let start = Instant::now();
    let detected = detect_report(&image, &params);
    let detect_seconds = start.elapsed().as_secs_f64();
    let peak_memory_bytes = memory::peak_bytes().filter(|_| measured);
    let (report, refused) = match detected {
        Ok(report) => (report, None),
        Err(e) => (Report::default(), Some(e.to_string())),
    };
    let (tally, orientation_errors_deg) =
        score_with_errors(&truth_of(photo.grains, &photo.frame), &report.grains);
    Ok(Outcome {
        tally,
        orientation_errors_deg,
        detect_seconds,
        phases: report.phases,
        render_seconds,
        peak_memory_bytes,
        refused,
    })
}
