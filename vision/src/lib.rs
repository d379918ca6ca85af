//! Synthetic backlit photographs of grain deposits, and a detector that finds every grain.
//!
//! The crate knows photographs and grain outlines, nothing of how a deposit was made.
//! Coordinates are SI (metres) in the frame: origin at the bottom-left corner of the
//! photograph, y upward; image row 0 is the top (y = (rows - row - 0.5) / scale).

pub mod detect;
pub mod evaluate;
mod grain;
mod outline;
pub mod overlay;
pub mod packing;
pub mod render;

pub use detect::{DetectError, DetectParams, Detection, detect};
pub use grain::{Frame, GrainOutline, GrainShape};
pub use outline::ROUNDING_FRACTION;
