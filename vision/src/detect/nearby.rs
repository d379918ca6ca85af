//! Points binned on a square grid, so that "is any point within d of this one" looks at the
//! few cells around it instead of every point (acceptance asks it once or twice per fit, of
//! lists that grow to thousands of grains).

use std::collections::HashMap;

pub struct Nearby {
    cell: f64,
    bins: HashMap<(i64, i64), Vec<(f64, f64)>>,
}

impl Nearby {
    /// `cell`: the bin side, best about the largest distance asked for.
    pub fn new(cell: f64) -> Self {
        assert!(cell > 0.0 && cell.is_finite(), "bin side {cell}");
        Nearby {
            cell,
            bins: HashMap::new(),
        }
    }

    pub fn with_points(cell: f64, points: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let mut nearby = Nearby::new(cell);
        for p in points {
            nearby.insert(p);
        }
        nearby
    }

    fn bin(&self, p: (f64, f64)) -> (i64, i64) {
        (
            (p.0 / self.cell).floor() as i64,
            (p.1 / self.cell).floor() as i64,
        )
    }

    pub fn insert(&mut self, p: (f64, f64)) {
        let bin = self.bin(p);
        self.bins.entry(bin).or_default().push(p);
    }

    /// Whether a point lies closer than `d` to `p` (the distance as `f64::hypot` gives it, so
    /// the answer is the plain scan's).
    pub fn any_within(&self, p: (f64, f64), d: f64) -> bool {
        let (c, r) = self.bin(p);
        // One bin more than the distance needs: rounding at a bin's edge cannot hide a point.
        let k = (d / self.cell).ceil() as i64 + 1;
        (r - k..=r + k).any(|rr| {
            (c - k..=c + k).any(|cc| {
                self.bins
                    .get(&(cc, rr))
                    .is_some_and(|points| points.iter().any(|q| (q.0 - p.0).hypot(q.1 - p.1) < d))
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::testing::Lcg;

    /// The grid answers as a scan of every point does, for distances below, at and above
    /// the bin side, and for points on bin edges and at negative coordinates.
    #[test]
    fn answers_as_a_scan_does() {
        let mut rng = Lcg(0x51_7cc1_b727_220a);
        let mut next = || rng.unit_f64();
        let points: Vec<(f64, f64)> = (0..300)
            .map(|k| {
                if k % 10 == 0 {
                    ((k / 10) as f64 * 10.0, 20.0)
                } else {
                    (300.0 * next() - 50.0, 200.0 * next() - 50.0)
                }
            })
            .collect();
        let grid = Nearby::with_points(10.0, points.iter().copied());
        let (mut near, mut far) = (0, 0);
        for _ in 0..2000 {
            let p = (320.0 * next() - 60.0, 220.0 * next() - 60.0);
            for d in [3.0, 10.0, 25.0] {
                let scan = points.iter().any(|q| (q.0 - p.0).hypot(q.1 - p.1) < d);
                assert_eq!(grid.any_within(p, d), scan, "{p:?} {d}");
                if scan { near += 1 } else { far += 1 }
            }
        }
        assert!(near > 500 && far > 500, "{near} near, {far} far");
    }
}
