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

    /// Brings the list up to date by searching around the grains that moved, not the whole
    /// deposit: a grain is searched again when one of its vertices may have moved more than
    /// half the skin since its own last search (and when it is new); pairs of two grains that
    /// were not are kept as they were. A rain of grains falling through the skin in a few
    /// steps then costs a search around the falling grains, not around the deposit.
    ///
    /// Why it stays exact: a grain i searched now lists every j within reach + skin + m_j,
    /// where m_j is how far j's vertices may already have moved since j's own last search
    /// (under half the skin, or j would be searched too). Until the next search of either,
    /// i moves less than half the skin, and j less than half the skin from its reference,
    /// so less than half the skin + m_j from where it is now: a pair left out cannot touch.
    ///
    /// On an empty list (`default`, or after a new wall) every grain is new: a full build.
    /// `reach[i]` is grain i's bounding radius; `mobile[i]` is false for fixed grains (two
    /// fixed grains never interact). `near(i, j, margin)` is the exact test of a pair whose
    /// bounding disks come within the skin (plus `margin` for j): it keeps only pairs whose
    /// outlines do, so the narrow phase does not visit, every step, neighbours that cannot
    /// touch before the next rebuild.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        positions: &[Vec2],
        angles: &[f64],
        reach: &[f64],
        arm: &[f64],
        mobile: &[bool],
        walls: &[Wall],
        skin: f64,
        near: impl Fn(usize, usize, f64) -> bool + Sync,
    ) -> Replaced {
        let n = positions.len();
        // How far each grain's vertices may have moved since its last search; infinite for a
        // grain never searched (new) and for a non-finite position.
        let moved: Vec<f64> = (0..n)
            .into_par_iter()
            .map(
                |i| match (self.reference.get(i), self.reference_angles.get(i)) {
                    (Some(p0), Some(a0)) => {
                        let d = (positions[i] - p0).norm() + arm[i] * (angles[i] - a0).abs();
                        if d.is_nan() { f64::INFINITY } else { d }
                    }
                    _ => f64::INFINITY,
                },
            )
            .collect();
        let searched: Vec<bool> = moved.iter().map(|&d| d > skin / 2.0).collect();
        let (moved, searched) = (&moved, &searched);
        // Margin of a grain that is not searched now; a searched one starts afresh.
        let margin = |j: usize| if searched[j] { 0.0 } else { moved[j] };
        let largest = reach.iter().copied().fold(0.0, f64::max);
        // The widest pair test: two largest reaches, the skin, and a margin under half of it.
        let cells = CellList::new(positions, 2.0 * largest + 1.5 * skin);
        let moving: Vec<u32> = (0..n as u32).filter(|&i| searched[i as usize]).collect();
        let mut found: Vec<[u32; 2]> = moving
            .par_iter()
            .flat_map_iter(|&i| {
                let i = i as usize;
                let (p, r) = (positions[i], reach[i]);
                let cells = &cells;
                let near = &near;
                cells.around(p).filter_map(move |j| {
                    let j = j as usize;
                    // A pair of two searched grains is found once, from its first grain;
                    // two fixed grains never interact.
                    let new = j != i && (!searched[j] || j > i) && (mobile[i] || mobile[j]);
                    let m = margin(j);
                    (new && (positions[j] - p).norm_squared() < (r + reach[j] + skin + m).powi(2)
                        && near(i, j, m))
                    .then(|| [i.min(j) as u32, i.max(j) as u32])
                })
            })
            .collect();
        found.par_sort_unstable();
        let kept = |pair: &&[u32; 2]| !(searched[pair[0] as usize] || searched[pair[1] as usize]);
        let pairs = merge_sorted(self.pairs.iter().filter(kept).copied(), found);
        let pairs = std::mem::replace(&mut self.pairs, pairs);
        let wall_found: Vec<[u32; 2]> = moving
            .iter()
            .filter(|&&i| mobile[i as usize])
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
        let wall_pairs = merge_sorted(
            self.wall_pairs
                .iter()
                .filter(|p| !searched[p[0] as usize])
                .copied(),
            wall_found,
        );
        let wall_pairs = std::mem::replace(&mut self.wall_pairs, wall_pairs);
        self.reference.resize(n, Vec2::zeros());
        self.reference_angles.resize(n, 0.0);
        for &i in &moving {
            let i = i as usize;
            self.reference[i] = positions[i];
            self.reference_angles[i] = angles[i];
        }
        self.rebuilds += 1;
        Replaced { pairs, wall_pairs }
    }
}

/// The lists an update replaced (often equal to the new ones: a grain falling alone through
/// its skin finds the same neighbours, none).
pub struct Replaced {
    pub pairs: Vec<[u32; 2]>,
    pub wall_pairs: Vec<[u32; 2]>,
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
        let mut next = super::super::uniform(12345);
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
        list.update(
            &positions,
            &angles,
            &reach,
            &arm,
            &mobile,
            &[],
            skin,
            |_, _, _| true,
        );
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

    #[test]
    fn updates_around_moved_grains_miss_no_pair() {
        // Every grain trembles along a line, up to just under half the skin either side of
        // where it started, so it is never searched for its own motion and sweeps almost a
        // whole skin between the searches of its neighbours; a third of them also drift at
        // up to a tenth of the skin a step, and are searched as they go. A neighbour searched
        // while a trembling grain is at the far end of its swing must still list it.
        let mut next = super::super::uniform(777);
        let (n, skin) = (300, 0.001);
        let mut positions: Vec<Vec2> = (0..n)
            .map(|_| Vec2::new(next() * 0.12, next() * 0.06))
            .collect();
        let reach: Vec<f64> = (0..n).map(|_| 0.002 + 0.002 * next()).collect();
        let arm: Vec<f64> = reach.iter().map(|r| 0.8 * r).collect();
        let angles = vec![0.0; n];
        let drift: Vec<Vec2> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * next();
                let speed = if i % 3 == 0 { 0.1 * skin * next() } else { 0.0 };
                Vec2::new(a.cos(), a.sin()) * speed
            })
            .collect();
        let swing: Vec<(Vec2, f64, f64)> = (0..n)
            .map(|_| {
                let a = std::f64::consts::TAU * next();
                let amplitude = 0.49 * skin * next();
                (
                    Vec2::new(a.cos(), a.sin()) * amplitude,
                    0.1 + 0.5 * next(),
                    6.3 * next(),
                )
            })
            .collect();
        let start = positions.clone();
        let mobile = vec![true; n];
        let update = |list: &mut VerletList, positions: &[Vec2]| {
            list.update(
                positions,
                &angles,
                &reach,
                &arm,
                &mobile,
                &[],
                skin,
                |_, _, _| true,
            )
        };
        let mut list = VerletList::default();
        update(&mut list, &positions);
        let mut partial = 0;
        for t in 1..=300 {
            for i in 0..n {
                let (line, rate, phase) = swing[i];
                positions[i] =
                    start[i] + drift[i] * t as f64 + line * (rate * t as f64 + phase).sin();
            }
            if list.is_stale(&positions, &angles, &arm, skin) {
                let before = list.reference.clone();
                update(&mut list, &positions);
                partial += usize::from(list.reference.iter().zip(&before).any(|(a, b)| a == b));
            }
            for i in 0..n {
                for j in i + 1..n {
                    if (positions[i] - positions[j]).norm() < reach[i] + reach[j] {
                        assert!(
                            list.pairs.binary_search(&[i as u32, j as u32]).is_ok(),
                            "pair ({i}, {j}) touches but is not listed"
                        );
                    }
                }
            }
        }
        assert!(partial > 10, "only {partial} updates kept some references");
    }
}
