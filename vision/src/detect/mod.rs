//! TEMPORARY STAND-IN for the detector, written on branch `vision` so that the benchmark
//! compiles. The detector itself is written on branch `detect`; on merge its
//! `vision/src/detect/` replaces this file entirely. It finds nothing.

use image::DynamicImage;

use crate::GrainShape;

/// What the detector is told about the photograph.
#[derive(Clone, Debug)]
pub struct DetectParams {
    pub shape: GrainShape,
    /// Pixels per metre.
    pub scale: f64,
}

impl Default for DetectParams {
    fn default() -> Self {
        DetectParams {
            shape: GrainShape::nut(6.9e-3),
            scale: 1e4,
        }
    }
}

/// One grain found in a photograph.
#[derive(Clone, Debug)]
pub struct Detection {
    pub outline: crate::GrainOutline,
    pub confidence: f64,
    pub cut: bool,
}

#[derive(Debug, thiserror::Error)]
pub enum DetectError {
    #[error("the detector is not merged into this branch yet")]
    Unavailable,
}

/// Stand-in: returns no grains.
pub fn detect(
    _image: &DynamicImage,
    _params: &DetectParams,
) -> Result<Vec<Detection>, DetectError> {
    Ok(Vec::new())
}
