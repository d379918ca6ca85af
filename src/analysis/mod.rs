//! The analysis shared by photographs and simulations (docs/model.md §3). One module per measure, each
//! with the same shape: an input struct (parameters), `compute` (on an ensemble), a result
//! struct (serialisable, so `facets compare` can read what `facets analyse` wrote).

pub mod coarse_grain;
pub mod compare;
pub mod load_share;
pub mod orientation;
pub mod pressure;
pub mod rdf;
pub mod stats;
pub mod stress_grid;
pub mod summary;
pub mod tables;
