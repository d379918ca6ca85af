use rayon::prelude::*;

use super::CellList;
use crate::dynamics::Wall;
use crate::math::Vec2;

/// Pairs within reach plus a skin, valid until a grain moves more than half the skin.
#[derive(Clone, Debug, Default)]
pub struct VerletList {
    /// Positions at the last rebuild.
    reference: Vec<Vec2>,
    /// Pairs (i, j), i < j, sorted; at least one of the two is mobile.
    pub pairs: Vec<[u32; 2]>,
    /// (grain, wall) pairs, sorted.
    pub wall_pairs: Vec<[u32; 2]>,
    pub rebuilds: u64,
}

impl VerletList {
    pub fn memory_bytes(&self) -> usize {
        self.reference.capacity() * std::mem::size_of::<Vec2>()
            + (self.pairs.capacity() + self.wall_pairs.capacity()) * 8
    }

    /// True when some grain moved more than half the skin since the last rebuild (or has a
    /// non-finite position), so a pair could have come within reach unseen.
    pub fn is_stale(&self, positions: &[Vec2], skin: f64) -> bool {
        if self.reference.len() != positions.len() {
            return true;
        }
        let limit = (skin / 2.0).powi(2);
        positions.par_iter().zip(&self.reference).any(|(p, r)| {
            let d = (p - r).norm_squared();
            d > limit || d.is_nan()
        })
    }

    /// Rebuilds from scratch. `reach[i]` is grain i's bounding radius; `mobile[i]` is false for
    /// fixed grains (two fixed grains never interact).
    pub fn rebuild(
        &mut self,
        positions: &[Vec2],
        reach: &[f64],
        mobile: &[bool],
        walls: &[Wall],
        skin: f64,
    ) {
        let largest = reach.iter().copied().fold(0.0, f64::max);
        let cells = CellList::new(positions, 2.0 * largest + skin);
        let per_grain: Vec<Vec<u32>> = (0..positions.len())
            .into_par_iter()
            .map(|i| {
                let (p, r) = (positions[i], reach[i]);
                let mut near: Vec<u32> = cells
                    .around(p)
                    .filter(|&j| {
                        let j = j as usize;
                        j > i
                            && (mobile[i] || mobile[j])
                            && (positions[j] - p).norm_squared() < (r + reach[j] + skin).powi(2)
                    })
                    .collect();
                near.sort_unstable();
                near
            })
            .collect();
        self.pairs = per_grain
            .iter()
            .enumerate()
            .flat_map(|(i, near)| near.iter().map(move |&j| [i as u32, j]))
            .collect();
        self.wall_pairs = (0..positions.len())
            .filter(|&i| mobile[i])
            .flat_map(|i| {
                walls
                    .iter()
                    .enumerate()
                    .filter(move |(_, w)| w.distance(positions[i]) < reach[i] + skin)
                    .map(move |(k, _)| [i as u32, k as u32])
            })
            .collect();
        self.reference = positions.to_vec();
        self.rebuilds += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_same_pairs_as_brute_force() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 400;
        let positions: Vec<Vec2> = (0..n)
            .map(|_| Vec2::new(next() * 0.3, next() * 0.1 - 2.0))
            .collect();
        let reach: Vec<f64> = (0..n).map(|_| 0.002 + 0.003 * next()).collect();
        let mobile: Vec<bool> = (0..n).map(|i| i % 7 != 0).collect();
        let skin = 0.001;
        let mut list = VerletList::default();
        list.rebuild(&positions, &reach, &mobile, &[], skin);
        let mut brute = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let d = (positions[i] - positions[j]).norm();
                if (mobile[i] || mobile[j]) && d < reach[i] + reach[j] + skin {
                    brute.push([i as u32, j as u32]);
                }
            }
        }
        assert!(!brute.is_empty());
        assert_eq!(list.pairs, brute);
        assert!(!list.is_stale(&positions, skin));
        let mut moved = positions.clone();
        moved[3].x += 0.6 * skin;
        assert!(list.is_stale(&moved, skin));
        moved[3].x = f64::NAN;
        assert!(list.is_stale(&moved, skin));
    }
}
