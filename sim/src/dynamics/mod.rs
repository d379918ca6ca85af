//! What moves and what pushes: grain state, the contact law, walls.

mod contact_law;
mod grains;
mod wall;

pub use contact_law::{ContactLaw, SubContactForce};
pub use grains::Grains;
pub use wall::Wall;
