//! What moves and what pushes: grain state, the contact law, walls, the plates of a quasi-2D
//! cell.

mod contact_law;
mod grains;
mod plate_friction;
mod wall;

pub use contact_law::{ContactLaw, SubContactForce};
pub use grains::Grains;
pub use plate_friction::PlateFriction;
pub use wall::Wall;
