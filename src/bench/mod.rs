//! Benchmarks behind `facets bench ...`: the work and its measurement; the CLI only prints.

pub mod analysis;
pub mod engine;
pub mod fill;
pub mod process;
pub mod vision;
