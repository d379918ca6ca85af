use thiserror::Error;

/// A grain outline that cannot be built. Each message names the offending field and value.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ShapeError {
    #[error("field `{field}` is {value}; expected a finite number")]
    NotFinite { field: &'static str, value: f64 },
    #[error("field `radius` (rounding radius r) is {0} m; it must be positive")]
    NonPositiveRadius(f64),
    #[error("field `vertices` has {0} vertices; a core polygon needs at least 3")]
    TooFewVertices(usize),
    #[error("field `vertices` has {0} vertices; at most 64 are supported")]
    TooManyVertices(usize),
    #[error(
        "field `vertices` is not a convex counter-clockwise polygon: the turn at vertex {vertex} is {turn:e} (must be > 0)"
    )]
    NotConvex { vertex: usize, turn: f64 },
    #[error(
        "field `length` ({length} m) is smaller than field `width` ({width} m); the length is the long side"
    )]
    LengthBelowWidth { length: f64, width: f64 },
    #[error(
        "field `width` ({width} m) must exceed twice the rounding radius `radius` ({radius} m), or the core vanishes"
    )]
    WidthNotAboveRounding { width: f64, radius: f64 },
    #[error("field `areal_density` is {0} kg/m^2; it must be positive")]
    NonPositiveDensity(f64),
}

/// An engine setting or state that cannot be simulated.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    Shape(#[from] ShapeError),
    #[error("field `{field}` is {value}; {expected}")]
    BadParameter {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
    #[error(
        "time step dt = {dt:e} s is above the stability bound {critical:e} s (stiffest contact against the lightest grain); use dt <= {critical:e} s"
    )]
    TimeStepTooLarge { dt: f64, critical: f64 },
    #[error(
        "grain {grain} has a non-finite position or velocity at t = {time} s: the run diverged"
    )]
    Diverged { grain: usize, time: f64 },
    #[error("unknown shape id {0}")]
    UnknownShape(usize),
    #[error("cannot start a worker thread: {0}")]
    ThreadPool(String),
}
