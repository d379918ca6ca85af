//! Broad phase: which pairs of grains, and which grains and walls, may touch before the next
//! rebuild. A cell list finds them in O(N); a Verlet list with a skin keeps them until some
//! grain has moved more than half the skin.

mod cell_list;
mod verlet_list;

pub use cell_list::CellList;
pub use verlet_list::{Replaced, VerletList, moved_past_half_skin};
