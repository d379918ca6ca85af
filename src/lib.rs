//! facets: granular deposits of faceted grains in a two-dimensional silo.
//!
//! The library ties the DEM engine (`sim`) and the photograph tools (`vision`) to one deposit
//! model and one analysis, so that experiment and simulation are measured by the same code.
//! The binary in `main.rs` only parses arguments and dispatches here.

pub mod analysis;
pub mod bench;
pub mod deposit;
pub mod detection;
pub mod fill;
pub mod grains;
pub mod impact;
pub mod io;
pub mod photo;
pub mod plot;
pub mod reproduce;
pub mod scene;
pub mod validate;
