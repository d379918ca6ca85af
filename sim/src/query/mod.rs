//! Narrow phase: the sub-contacts between two placed cores, or a core and a wall (docs/model.md §2).

mod core_core;
mod core_wall;
mod placed_core;
mod separation;
mod sub_contact;

pub use core_core::{core_core_sub_contacts, feature_overlap};
pub use core_wall::{core_wall_sub_contacts, wall_feature_overlap};
pub use placed_core::PlacedCore;
pub use separation::core_core_separation;
pub use sub_contact::{Features, SubContact, WeightGradient};
