//! Synthetic backlit photographs of grain deposits, and a detector that finds every grain.
//!
//! The crate knows photographs and grain outlines, nothing of how a deposit was made.
//! Coordinates are SI (metres) in the frame: origin at the bottom-left corner of the
//! photograph, y upward; image row 0 is the top (y = (rows - row - 0.5) / scale).
//!
//! - [`packing`]: dense packings of touching grains that stand in for deposits;
//! - [`render`]: synthetic backlit photographs of grain outlines, in styles;
//! - [`detect`](mod@detect): finds the grains of a photograph;
//! - [`evaluate`]: matches detections to the truth and scores them; the benchmark.

pub mod detect;
pub mod evaluate;
mod grain;
mod outline;
pub mod overlay;
pub mod packing;
pub mod render;

pub use detect::{
    DetectError, DetectParams, Detection, Phases, Report, ScaleCheck, Shortcuts, WELL_EXPLAINED,
    detect, detect_report,
};
pub use grain::{Frame, GrainOutline, GrainShape};
pub use outline::ROUNDING_FRACTION;
