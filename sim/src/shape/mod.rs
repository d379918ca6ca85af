//! Grain outlines: convex spheropolygons and their exact mass properties.

mod mass_properties;
mod spheropolygon;

pub use mass_properties::RoundedMoments;
pub use spheropolygon::Spheropolygon;
