//! Narrow phase: the sub-contacts between two placed cores, or a core and a wall (docs/model.md §2).

mod core_core;
mod core_wall;
mod near_vertices;
mod placed_core;
mod separation;
mod sub_contact;

pub use core_core::{
    core_core_sub_contacts, core_core_sub_contacts_and_near, feature_overlap,
    near_vertex_sub_contacts,
};
pub use core_wall::{core_wall_sub_contacts, wall_feature_overlap};
pub use near_vertices::NearVertices;
pub use placed_core::PlacedCore;
pub use separation::core_core_separation;
pub use sub_contact::{Features, SubContact, WeightGradient};
