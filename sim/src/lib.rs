//! A two-dimensional discrete-element engine for spheropolygons.
//!
//! A grain is a convex core polygon swept by a disk of radius r. Grains interact through
//! vertex-edge sub-contacts with a linear spring-dashpot normal law and a tangential spring
//! capped by Coulomb friction (docs/model.md §2). The pipeline of one step reads top to bottom in
//! [`pipeline::World::step`]: integrate the first half kick and drift, broad phase (cell list
//! and Verlet list), narrow phase (sub-contacts), contact forces, second half kick.
//!
//! Units are SI throughout. The engine knows grains, walls and forces, nothing of silos.

pub mod broad_phase;
pub mod dynamics;
mod error;
pub mod math;
pub mod pipeline;
pub mod query;
pub mod shape;

pub use dynamics::{ContactLaw, PlateFriction, Wall};
pub use error::{ShapeError, SimError};
pub use math::Vec2;
pub use pipeline::{
    Body, ContactRecord, Energies, GrainId, GrainState, ShapeId, SleepSettings, World,
    WorldSettings, collision_time, critical_time_step,
};
pub use shape::Spheropolygon;
