use rayon::prelude::*;

use crate::math::Vec2;

/// Grains binned into square cells at least as wide as the largest interaction reach.
///
/// Cells are kept as a sorted list of (row, column, grain) rather than a dense grid, so the
/// cost does not depend on the extent of the scene (a stray grain far away costs nothing).
pub struct CellList {
    cell_size: f64,
    /// (row, column, grain), sorted.
    entries: Vec<(i64, i64, u32)>,
}

impl CellList {
    pub fn new(positions: &[Vec2], cell_size: f64) -> Self {
        let mut entries: Vec<(i64, i64, u32)> = positions
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let (row, col) = cell_of(*p, cell_size);
                (row, col, i as u32)
            })
            .collect();
        entries.par_sort_unstable();
        Self { cell_size, entries }
    }

    /// Grains in the 3 x 3 cells around `p`, in increasing (row, column, index) order.
    pub fn around(&self, p: Vec2) -> impl Iterator<Item = u32> + '_ {
        let (row, col) = cell_of(p, self.cell_size);
        (-1..=1).flat_map(move |dr| {
            let lo = self
                .entries
                .partition_point(|e| (e.0, e.1) < (row + dr, col - 1));
            let hi = self
                .entries
                .partition_point(|e| (e.0, e.1) <= (row + dr, col + 1));
            self.entries[lo..hi].iter().map(|e| e.2)
        })
    }
}

fn cell_of(p: Vec2, size: f64) -> (i64, i64) {
    // Saturating casts: a non-finite position lands in an extreme cell instead of panicking;
    // the caller reports divergence separately.
    ((p.y / size).floor() as i64, (p.x / size).floor() as i64)
}
