//! Grain outlines: convex spheropolygons and their exact mass properties.

mod mass_properties;
mod spheropolygon;

pub use mass_properties::RoundedMoments;
pub use spheropolygon::Spheropolygon;

/// Most core vertices a shape may have (contact features are indexed by a byte).
pub const MAX_VERTICES: usize = 64;
