use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::CellList;
use crate::dynamics::Wall;
use crate::math::Vec2;

/// Pairs within reach plus a skin, valid until a grain moves more than half the skin.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct VerletList {
    /// Positions and angles at the last rebuild.
    reference: Vec<Vec2>,
    reference_angles: Vec<f64>,
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

    /// Positions and angles at the last rebuild.
    pub fn reference(&self) -> (&[Vec2], &[f64]) {
        (&self.reference, &self.reference_angles)
    }

    /// True when some vertex may have moved more than half the skin since the last rebuild
    /// (or a grain has a non-finite position), so a pair could have come within reach unseen.
    pub fn is_stale(&self, positions: &[Vec2], angles: &[f64], arm: &[f64], skin: f64) -> bool {
        if self.reference.len() != positions.len() {
            return true;
        }
        (positions, angles, arm)
            .into_par_iter()
            .zip((&self.reference, &self.reference_angles))
            .any(|((p, a, arm), (p0, a0))| moved_past_half_skin(*p - p0, a - a0, *arm, skin))
    }

    /// Rebuilds from scratch. `reach[i]` is grain i's bounding radius; `mobile[i]` is false for
    /// fixed grains (two fixed grains never interact). `near(i, j)` is the exact test of a pair
    /// whose bounding disks come within the skin: it keeps only pairs whose outlines do, so
    /// the narrow phase does not visit, every step, neighbours that cannot touch before the
    /// next rebuild.
    #[allow(clippy::too_many_arguments)]
    pub fn rebuild(
        &mut self,
        positions: &[Vec2],
        angles: &[f64],
        reach: &[f64],
        mobile: &[bool],
        walls: &[Wall],
        skin: f64,
        near: impl Fn(usize, usize) -> bool + Sync,
    ) {
        // Every mobile grain searched, nothing kept: the search around moving grains is the
        // whole rebuild.
        self.rebuild_around_awake(
            &[],
            &[],
            positions,
            angles,
            reach,
            mobile,
            walls,
            skin,
            near,
        );
    }
}

impl VerletList {
    /// Rebuilds around the awake grains only: pairs between two grains that do not move
    /// (fixed or sleeping) are kept from `old_pairs` as they were, and only the awake grains
    /// (`awake[i]`: mobile and not asleep) are searched. Equal to [`Self::rebuild`] as long as every grain that stopped moving did
    /// so with the list fresh around it, which holds because a grain that wakes forces a
    /// rebuild before it moves by more than a step.
    #[allow(clippy::too_many_arguments)]
    pub fn rebuild_around_awake(
        &mut self,
        old_pairs: &[[u32; 2]],
        old_wall_pairs: &[[u32; 2]],
        positions: &[Vec2],
        angles: &[f64],
        reach: &[f64],
        awake: &[bool],
        walls: &[Wall],
        skin: f64,
        near: impl Fn(usize, usize) -> bool + Sync,
    ) {
        let largest = reach.iter().copied().fold(0.0, f64::max);
        let cells = CellList::new(positions, 2.0 * largest + skin);
        let moving: Vec<u32> = (0..positions.len() as u32)
            .filter(|&i| awake[i as usize])
            .collect();
        let mut found: Vec<[u32; 2]> = moving
            .par_iter()
            .flat_map_iter(|&i| {
                let i = i as usize;
                let (p, r) = (positions[i], reach[i]);
                let cells = &cells;
                let near = &near;
                cells.around(p).filter_map(move |j| {
                    let j = j as usize;
                    // A pair of two awake grains is found once, from its first grain.
                    let new = j != i && (!awake[j] || j > i);
                    (new && (positions[j] - p).norm_squared() < (r + reach[j] + skin).powi(2)
                        && near(i, j))
                    .then(|| [i.min(j) as u32, i.max(j) as u32])
                })
            })
            .collect();
        found.par_sort_unstable();
        let resting = |pair: &&[u32; 2]| !(awake[pair[0] as usize] || awake[pair[1] as usize]);
        self.pairs = merge_sorted(old_pairs.iter().filter(resting).copied(), found);
        let wall_found: Vec<[u32; 2]> = moving
            .iter()
            .flat_map(|&i| {
                walls
                    .iter()
                    .enumerate()
                    .filter(move |(_, w)| {
                        w.distance(positions[i as usize]) < reach[i as usize] + skin
                    })
                    .map(move |(k, _)| [i, k as u32])
            })
            .collect();
        self.wall_pairs = merge_sorted(
            old_wall_pairs
                .iter()
                .filter(|p| !awake[p[0] as usize])
                .copied(),
            wall_found,
        );
        self.reference = positions.to_vec();
        self.reference_angles = angles.to_vec();
        self.rebuilds += 1;
    }
}

/// The union of two sorted lists without common elements, sorted.
fn merge_sorted(a: impl Iterator<Item = [u32; 2]>, b: Vec<[u32; 2]>) -> Vec<[u32; 2]> {
    let mut out = Vec::with_capacity(b.len());
    let mut b = b.into_iter().peekable();
    for x in a {
        while let Some(y) = b.next_if(|y| *y < x) {
            out.push(y);
        }
        out.push(x);
    }
    out.extend(b);
    out
}

/// Whether a grain displaced by `shift` and turned by `turn` may have a vertex (at most `arm`
/// from its centre) more than half the skin from where it was: a vertex moves at most
/// |shift| + arm |turn|. A non-finite displacement counts as moved.
#[inline]
pub fn moved_past_half_skin(shift: Vec2, turn: f64, arm: f64, skin: f64) -> bool {
    let moved = shift.norm() + arm * turn.abs();
    moved > skin / 2.0 || moved.is_nan()
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
        let angles = vec![0.0; n];
        let arm = vec![0.0; n];
        let mut list = VerletList::default();
        list.rebuild(&positions, &angles, &reach, &mobile, &[], skin, |_, _| true);
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
        assert!(!list.is_stale(&positions, &angles, &arm, skin));
        let mut moved = positions.clone();
        moved[3].x += 0.6 * skin;
        assert!(list.is_stale(&moved, &angles, &arm, skin));
        moved[3].x = f64::NAN;
        assert!(list.is_stale(&moved, &angles, &arm, skin));
        // A turn moves the vertices too.
        let arm = vec![0.004; n];
        let mut turned = angles.clone();
        turned[5] = 0.6 * skin / 0.004;
        assert!(list.is_stale(&positions, &turned, &arm, skin));
    }
}
