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
        let cells: Vec<(i64, i64)> = positions.iter().map(|p| cell_of(*p, cell_size)).collect();
        Self {
            cell_size,
            entries: sorted_by_cell(&cells),
        }
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

/// (row, column, grain) sorted. A broad phase rebuilt every few steps around a few moving
/// grains spends most of its time here, so while the occupied rows and columns span no more
/// cells than a few per grain (a silo, a box) the grains are counted into them in one pass
/// (grains within a cell stay in index order, as a sort would leave them); a scattered
/// scene is sorted.
fn sorted_by_cell(cells: &[(i64, i64)]) -> Vec<(i64, i64, u32)> {
    let Some(&(first_row, first_col)) = cells.first() else {
        return Vec::new();
    };
    let (mut rows, mut cols) = ((first_row, first_row), (first_col, first_col));
    for &(r, c) in cells {
        rows = (rows.0.min(r), rows.1.max(r));
        cols = (cols.0.min(c), cols.1.max(c));
    }
    let span = |(lo, hi): (i64, i64)| {
        hi.checked_sub(lo)
            .and_then(|d| usize::try_from(d).ok()?.checked_add(1))
    };
    let dense = span(rows)
        .zip(span(cols))
        .and_then(|(r, c)| r.checked_mul(c))
        .filter(|&count| count <= 4 * cells.len() + 64);
    let Some(count) = dense else {
        let mut entries: Vec<(i64, i64, u32)> = cells
            .iter()
            .enumerate()
            .map(|(i, &(r, c))| (r, c, i as u32))
            .collect();
        entries.sort_unstable();
        return entries;
    };
    let width = (cols.1 - cols.0 + 1) as usize;
    let slot = |(r, c): (i64, i64)| (r - rows.0) as usize * width + (c - cols.0) as usize;
    let mut start = vec![0usize; count + 1];
    for &cell in cells {
        start[slot(cell) + 1] += 1;
    }
    for k in 0..count {
        start[k + 1] += start[k];
    }
    let mut entries = vec![(0, 0, 0); cells.len()];
    for (i, &cell) in cells.iter().enumerate() {
        let k = &mut start[slot(cell)];
        entries[*k] = (cell.0, cell.1, i as u32);
        *k += 1;
    }
    entries
}

fn cell_of(p: Vec2, size: f64) -> (i64, i64) {
    // Saturating casts: a non-finite position lands in an extreme cell instead of panicking;
    // the caller reports divergence separately.
    ((p.y / size).floor() as i64, (p.x / size).floor() as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counting_and_sorting_give_the_same_order() {
        // A compact block of grains is counted into cells, a scattered one sorted: both must
        // give the entries in (row, column, grain) order.
        let mut next = super::super::uniform(99);
        let compact: Vec<Vec2> = (0..500)
            .map(|_| Vec2::new(next() * 0.2 - 0.1, next() * 0.3))
            .collect();
        let mut scattered = compact.clone();
        scattered.push(Vec2::new(1e6, -1e6));
        scattered.push(Vec2::new(f64::NAN, 0.0));
        for positions in [compact, scattered] {
            let cells: Vec<(i64, i64)> = positions.iter().map(|p| cell_of(*p, 0.01)).collect();
            let mut expected: Vec<(i64, i64, u32)> = cells
                .iter()
                .enumerate()
                .map(|(i, &(r, c))| (r, c, i as u32))
                .collect();
            expected.sort_unstable();
            assert_eq!(sorted_by_cell(&cells), expected);
        }
    }
}
