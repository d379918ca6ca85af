//! The simulation loop: a [`World`] of grains and walls, advanced by [`World::step`].

mod contacts;
mod energy;
mod sleep;
mod step;
mod time_step;
mod world;

pub use contacts::{Body, ContactRecord, PairContact, SubContactState};
pub use energy::Energies;
pub use sleep::SleepSettings;
pub use time_step::{collision_time, critical_time_step};
pub use world::{GrainId, GrainState, ShapeId, World, WorldSettings};
