//! Broad phase: which pairs of grains, and which grains and walls, may touch before the next
//! rebuild. A cell list finds them in O(N); a Verlet list with a skin keeps them until some
//! grain has moved more than half the skin.

mod cell_list;
mod verlet_list;

pub use cell_list::CellList;
pub use verlet_list::{Replaced, VerletList, moved_past_half_skin};

/// Uniform numbers in [0, 1) from a seed, for the tests' scattered grains.
#[cfg(test)]
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}
