//! The 8-connected regions of a mask, labelled in strips of rows in parallel and merged
//! across the strips' borders. imageproc's `connected_components` labels the whole image on
//! one core; a nut photograph at 10 px/mm spent a tenth of its detection time there.
//! The strip height is fixed, so the regions and their order do not depend on the thread
//! count.

use rayon::prelude::*;

/// One region: its pixel count, sums of pixel-centre coordinates, bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub count: f64,
    pub sum_x: f64,
    pub sum_y: f64,
    pub min_col: usize,
    pub max_col: usize,
    pub min_row: usize,
    pub max_row: usize,
    /// Raster index (row * width + column) of its first pixel: the regions' order.
    first: usize,
}

impl Region {
    fn at(c: usize, r: usize, width: usize) -> Self {
        Region {
            count: 1.0,
            sum_x: c as f64 + 0.5,
            sum_y: r as f64 + 0.5,
            min_col: c,
            max_col: c,
            min_row: r,
            max_row: r,
            first: r * width + c,
        }
    }

    /// Sums of integers and halves: exact in f64 whatever the order they are added in.
    fn absorb(&mut self, o: &Region) {
        self.count += o.count;
        self.sum_x += o.sum_x;
        self.sum_y += o.sum_y;
        self.min_col = self.min_col.min(o.min_col);
        self.max_col = self.max_col.max(o.max_col);
        self.min_row = self.min_row.min(o.min_row);
        self.max_row = self.max_row.max(o.max_row);
        self.first = self.first.min(o.first);
    }

    /// Whether it touches the border of a `width` x `height` image.
    pub fn touches_edge(&self, width: usize, height: usize) -> bool {
        self.min_col == 0
            || self.min_row == 0
            || self.max_col + 1 == width
            || self.max_row + 1 == height
    }
}

/// Rows per strip.
const STRIP_ROWS: usize = 64;

/// Union-find over region ids, with path halving.
struct Forest(Vec<u32>);

impl Forest {
    fn add(&mut self) -> u32 {
        let id = self.0.len() as u32;
        self.0.push(id);
        id
    }

    fn root(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let up = self.0[self.0[i as usize] as usize];
            self.0[i as usize] = up;
            i = up;
        }
        i
    }

    fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.root(a), self.root(b));
        if a != b {
            let (lo, hi) = (a.min(b), a.max(b));
            self.0[hi as usize] = lo;
        }
    }
}

/// A strip labelled on its own: its regions, and the region of each pixel of its first and
/// last rows (`u32::MAX` off the mask).
struct Strip {
    regions: Vec<Region>,
    top: Vec<u32>,
    bottom: Vec<u32>,
}

const NONE: u32 = u32::MAX;

fn label_strip(mask: &[bool], width: usize, rows: std::ops::Range<usize>) -> Strip {
    let mut forest = Forest(Vec::new());
    let mut labels = vec![NONE; rows.len() * width];
    let r0 = rows.start;
    for r in rows.clone() {
        let lr = r - r0;
        for c in 0..width {
            if !mask[r * width + c] {
                continue;
            }
            let mut label = NONE;
            let neighbours = [
                (c > 0).then(|| (lr, c - 1)),
                (lr > 0 && c > 0).then(|| (lr - 1, c - 1)),
                (lr > 0).then(|| (lr - 1, c)),
                (lr > 0 && c + 1 < width).then(|| (lr - 1, c + 1)),
            ];
            for (nr, nc) in neighbours.into_iter().flatten() {
                let n = labels[nr * width + nc];
                if n == NONE {
                    continue;
                }
                if label == NONE {
                    label = n;
                } else {
                    forest.union(label, n);
                }
            }
            if label == NONE {
                label = forest.add();
            }
            labels[lr * width + c] = label;
        }
    }
    // Compact the roots to 0..n, in raster order of first pixels (roots are the least id of
    // their tree, and ids are made in raster order).
    let mut index = vec![NONE; forest.0.len()];
    let mut regions: Vec<Region> = Vec::new();
    for (i, l) in labels.iter_mut().enumerate() {
        if *l == NONE {
            continue;
        }
        let root = forest.root(*l) as usize;
        let (lr, c) = (i / width, i % width);
        let pixel = Region::at(c, r0 + lr, width);
        if index[root] == NONE {
            index[root] = regions.len() as u32;
            regions.push(pixel);
        } else {
            regions[index[root] as usize].absorb(&pixel);
        }
        *l = index[root];
    }
    let last = rows.len().saturating_sub(1);
    Strip {
        regions,
        top: labels[..width].to_vec(),
        bottom: labels[last * width..(last + 1) * width].to_vec(),
    }
}

/// The 8-connected regions of the `true` pixels of a row-major `width` x `height` mask, in
/// raster order of their first pixels (the order imageproc's labels give).
pub fn regions(mask: &[bool], width: usize, height: usize) -> Vec<Region> {
    assert_eq!(mask.len(), width * height, "mask of {width} x {height}");
    if width == 0 || height == 0 {
        return Vec::new();
    }
    let strips: Vec<Strip> = (0..height.div_ceil(STRIP_ROWS))
        .into_par_iter()
        .map(|k| {
            label_strip(
                mask,
                width,
                k * STRIP_ROWS..((k + 1) * STRIP_ROWS).min(height),
            )
        })
        .collect();
    let offsets: Vec<u32> = strips
        .iter()
        .scan(0u32, |acc, s| {
            let at = *acc;
            *acc += s.regions.len() as u32;
            Some(at)
        })
        .collect();
    let total = strips.iter().map(|s| s.regions.len()).sum::<usize>();
    let mut forest = Forest((0..total as u32).collect());
    for k in 1..strips.len() {
        let (above, below) = (&strips[k - 1], &strips[k]);
        for c in 0..width {
            let b = below.top[c];
            if b == NONE {
                continue;
            }
            for nc in c.saturating_sub(1)..=(c + 1).min(width - 1) {
                let a = above.bottom[nc];
                if a != NONE {
                    forest.union(offsets[k - 1] + a, offsets[k] + b);
                }
            }
        }
    }
    let mut merged: Vec<Option<Region>> = vec![None; total];
    for (k, strip) in strips.iter().enumerate() {
        for (i, region) in strip.regions.iter().enumerate() {
            let root = forest.root(offsets[k] + i as u32) as usize;
            match &mut merged[root] {
                Some(m) => m.absorb(region),
                slot => *slot = Some(*region),
            }
        }
    }
    let mut out: Vec<Region> = merged.into_iter().flatten().collect();
    out.sort_by_key(|r| r.first);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::plane::NEIGHBOURS;
    use crate::detect::testing::Lcg;

    /// Regions by flood fill from each unvisited pixel in raster order: slow and plain.
    /// (imageproc's `connected_components`, the other reference to hand, panics on a
    /// 1 x 1 image.)
    fn reference(mask: &[bool], width: usize, height: usize) -> Vec<Region> {
        let mut seen = vec![false; mask.len()];
        let mut out = Vec::new();
        for start in 0..mask.len() {
            if !mask[start] || seen[start] {
                continue;
            }
            seen[start] = true;
            let mut region = Region::at(start % width, start / width, width);
            let mut stack = vec![start];
            while let Some(i) = stack.pop() {
                let (c, r) = ((i % width) as isize, (i / width) as isize);
                if i != start {
                    region.absorb(&Region::at(c as usize, r as usize, width));
                }
                for (dc, dr) in NEIGHBOURS {
                    let (nc, nr) = (c + dc, r + dr);
                    if nc < 0 || nr < 0 || nc >= width as isize || nr >= height as isize {
                        continue;
                    }
                    let j = nr as usize * width + nc as usize;
                    if mask[j] && !seen[j] {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
            out.push(region);
        }
        out
    }

    /// A deterministic pseudo-random mask of density `p`.
    fn mask(width: usize, height: usize, p: f64, seed: u64) -> Vec<bool> {
        let mut rng = Lcg(seed);
        rng.next_u64();
        (0..width * height).map(|_| rng.unit_f64() < p).collect()
    }

    #[test]
    fn regions_are_a_flood_fills_across_strip_borders_and_densities() {
        // Heights that end mid-strip and on a strip border; densities either side of the
        // percolation threshold, where regions wind across many strips.
        for &(w, h) in &[(150, 64), (97, 203), (300, 129), (1, 1), (7, 1), (1, 200)] {
            for (k, &p) in [0.2, 0.45, 0.6, 0.9].iter().enumerate() {
                let m = mask(w, h, p, (w * 1000 + h * 10 + k) as u64);
                assert_eq!(
                    regions(&m, w, h),
                    reference(&m, w, h),
                    "{w} x {h}, density {p}"
                );
            }
        }
    }

    #[test]
    fn a_region_winding_through_every_strip_is_one() {
        // A serpentine one pixel wide: down column 0, across, down, back across ...
        let (w, h) = (9, 5 * STRIP_ROWS + 3);
        let mut m = vec![false; w * h];
        for r in 0..h {
            m[r * w + if (r / 4) % 2 == 0 { 0 } else { w - 1 }] = true;
            if r % 4 == 3 {
                (0..w).for_each(|c| m[r * w + c] = true);
            }
        }
        let found = regions(&m, w, h);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].count as usize, m.iter().filter(|&&b| b).count());
    }
}
