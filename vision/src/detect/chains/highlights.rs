//! Short rods lying face to face fitted by one rod turned across them. Two rod53 rods side by
//! side make a block of 2D x L, nearly square, that a rod turned by a right angle (or by
//! less) fits almost as well; the rod left over is then fitted shifted onto what remains, or
//! missed, and every repair before this one sees little unexplained area. The highlights do
//! not agree: the rods' own run across the turned rod, inside it.
//!
//! In a row of rods end to end the rods beside the turned one are often fitted shifted into
//! its place, and the highlight, unbroken along the row, does not say where one rod ends:
//! the rods on its line are then refitted together as a row, whose phase the rods left in
//! place at its ends fix.

use super::{
    Context, Found, Local, Maps, SetTrials, Spot, Window, fit, fit_reads, in_order, nearest,
    nearest_edge, refit_together, turn,
};
use crate::detect::model::Pose;
use crate::detect::ridges::AxisSeed;

/// A highlight turned from a rod by more than this (degrees) is not its own.
const TURNED_DEG: f64 = 45.0;

/// The middle of a rod, as parts of its length and width, where the highlights of rods it
/// was fitted across lie: two rod53 rods face to face carry theirs a quarter of the block's
/// side, 0.31 L, from its centre; the highlights of neighbours reach into a rod's place only
/// at its ends and corners (0.47 L, the median on lab rod53 at 10 px/mm), where nothing is
/// wrong with it.
const MIDDLE: (f64, f64) = (0.8, 1.0);

/// Most rods near a turned rod that its trials take off with it, one at a time (and, near
/// the frame's edge, two at a time).
const NEAR_ROD: usize = 3;

/// Within this many lengths of the frame's edge, a turned rod's trials also take it off with
/// two of its nearest rods. Two short rods face to face beside a rod standing by the edge are
/// read as the same block turned by a right angle: a rod standing across the pair and two
/// lying face to face where the standing rod is. With one of those two off, the rod fitted at
/// a highlight of the pair lies across the other; with both off, the block comes back (unit
/// test `a_block_read_turned_by_the_edge_is_refitted_as_it_is`; lab rod53 at 10 px/mm, seed
/// 19 disordered, the top right corner). The 13 rods traced of the 14 turned at 10 px/mm on
/// seeds 1-21 and 50-59 all lay within 7 mm (1.4 rod53 lengths) of the edge. Pairs taken off
/// everywhere cost lab rod53 at 10 px/mm 1.3 s more a photograph (seed 19); by the edge,
/// 0.5-4.5 % more of the whole detection's tap sums.
const PAIRS_NEAR_EDGE: f64 = 1.5;

/// Only where two rods face to face make a nearly square block (its sides within this
/// ratio: rod53 6 x 4.9 mm, 1.22) can it be read turned by a right angle. rod3's pair (8.9 x
/// 6 mm, 1.48) gained nothing from the trials with pairs (lab, seeds 1-21 and 22-29, 40-49,
/// 80-89 at 6 px/mm: the same rods turned) and cost 5-6 % more tap sums.
const SQUARE_PAIR: f64 = 1.35;

/// How far along a highlight from where it was found (parts of a length) the rods lying on
/// its line are taken off together as a row: the rods end to end beside one fitted across
/// lie 0.6-0.85 L from it, and on lab rod53 at 6 px/mm a row shifted into its place began
/// 1.9 L from it.
const ON_LINE: f64 = 2.5;

/// Sweeps of the row's refinement, each rod refined once a sweep.
const ROW_SWEEPS: usize = 2;

/// Most turn (degrees) of a rod from a highlight for it to lie end to end along it.
const ROW_TURN_DEG: f64 = 15.0;

/// Phases along a highlight, a length apart in all, at which the rods on its line are
/// fitted as a row.
const ROW_PHASES: usize = 12;

/// Whether the rod at `p` lies on the line of the highlight at `spot`: its centre within
/// half a width of it and [`ON_LINE`] lengths along it.
fn on_line(p: Pose, spot: &Spot, cx: &Context) -> bool {
    let Some(phi) = spot.axis else { return false };
    let (s, c) = phi.sin_cos();
    let (dx, dy) = (p.x - spot.at.0, p.y - spot.at.1);
    turn(p.phi, phi) <= ROW_TURN_DEG.to_radians()
        && (dx * c - dy * s).abs() <= ON_LINE * cx.length
        && (dx * s + dy * c).abs() <= 0.5 * cx.width
}

/// Whether the highlight `a` lies inside the middle of the rod at `p`: `part` of its length
/// and of its width.
fn inside(p: Pose, a: &AxisSeed, cx: &Context, part: (f64, f64)) -> bool {
    let (s, c) = p.phi.sin_cos();
    let (dx, dy) = (a.x - p.x, a.y - p.y);
    (dx * c - dy * s).abs() <= 0.5 * part.0 * cx.length
        && (dx * s + dy * c).abs() <= 0.5 * part.1 * cx.width
}

/// The settings of [`repair_across_highlights`]'s trials.
struct Across<'a> {
    offsets: &'a [(f64, f64)],
    /// Offsets of the fits at a highlight: along its axis (the seed may lie anywhere on it).
    along_axis: &'a [(f64, f64)],
    step: f64,
    /// Half side of the window a trial may change around each rod.
    reach: f64,
    /// How far from its seed a fit may read.
    reads: f64,
}

impl Across<'_> {
    /// The highlights inside the rod at `p` turned from it.
    fn turned_inside(&self, p: Pose, seeds: &[AxisSeed], cx: &Context) -> Vec<Spot<'_>> {
        seeds
            .iter()
            .filter(|a| inside(p, a, cx, MIDDLE) && turn(a.phi, p.phi) > TURNED_DEG.to_radians())
            .map(|a| Spot {
                at: (a.x, a.y),
                axis: Some(a.phi),
                offsets: Some(self.along_axis),
                needed: false,
                fixed: false,
            })
            .collect()
    }
}

/// Rods on the line of a highlight inside a turned rod, to be refitted as a row end to end:
/// a highlight along rods end to end does not say where one ends, the rods still in place
/// at the row's ends do.
struct Row<'s> {
    highlight: Spot<'s>,
    /// The turned rod first.
    rods: Vec<usize>,
    /// Mean position of the rods along the highlight from it (pixels).
    mean: f64,
}

impl<'s> Row<'s> {
    /// The rods of `near` (the turned rod first) on the line of `highlight`, if three or
    /// more.
    fn of(found: &[Found], near: &[usize], highlight: Spot<'s>, cx: &Context) -> Option<Self> {
        let phi = highlight.axis?;
        let rods: Vec<usize> = std::iter::once(near[0])
            .chain(
                near[1..]
                    .iter()
                    .copied()
                    .filter(|&k| on_line(found[k].pose, &highlight, cx)),
            )
            .collect();
        if rods.len() < 3 {
            return None;
        }
        let (sn, cs) = phi.sin_cos();
        let along = |k: usize| {
            let p = found[k].pose;
            (p.x - highlight.at.0) * cs - (p.y - highlight.at.1) * sn
        };
        let mean = rods.iter().map(|&k| along(k)).sum::<f64>() / rods.len() as f64;
        Some(Row {
            highlight,
            rods,
            mean,
        })
    }

    /// The rows tried: as many rods as were taken off or one fewer, end to end along the
    /// highlight, at [`ROW_PHASES`] phases a length apart in all.
    fn candidates(&self, cx: &Context) -> impl Iterator<Item = Vec<Pose>> + '_ {
        let phi = self.highlight.axis.unwrap_or_default();
        let (sn, cs) = phi.sin_cos();
        let (x0, y0) = self.highlight.at;
        let n = self.rods.len();
        let length = cx.length;
        [n - 1, n].into_iter().flat_map(move |k| {
            (0..ROW_PHASES).map(move |j| {
                let mid = self.mean + length * (j as f64 / ROW_PHASES as f64 - 0.5);
                (0..k)
                    .map(|i| {
                        let t = mid + length * (i as f64 - 0.5 * (k - 1) as f64);
                        Pose {
                            x: x0 + t * cs,
                            y: y0 - t * sn,
                            phi,
                        }
                    })
                    .collect()
            })
        })
    }

    /// The best of the [`candidates`](Row::candidates), scored with the row's rods taken off,
    /// then refined together: each in turn with the others in place, from both sides, so
    /// that none is pushed along by the one placed before it. Returned as spots where rods
    /// are placed as they are; empty when the row does not fit in the trial's window. The
    /// maps are left as they were.
    fn best(&self, local: &mut Local, found: &[Found], reach: f64, cx: &Context) -> Vec<Spot<'s>> {
        let around = |k: usize| {
            let p = found[k].pose;
            Window::around(p.x, p.y, reach, reach, &local.maps.free)
        };
        let Some(window) = self.rods.iter().map(|&k| around(k)).reduce(Window::union) else {
            return Vec::new();
        };
        let saved = local.save(window);
        for &k in &self.rods {
            local.unpaint(found, k, &self.rods, cx);
        }
        let score = |local: &Local, poses: &[Pose]| -> f64 {
            let free = &local.maps.free_bordered;
            poses
                .iter()
                .map(|&p| f64::from(cx.model.score(p, cx.levels.fine, free).total))
                .sum()
        };
        let mut best: (f64, Vec<Pose>) = (f64::NEG_INFINITY, Vec::new());
        for poses in self.candidates(cx) {
            let total = score(local, &poses);
            if total > best.0 {
                best = (total, poses);
            }
        }
        let mut poses = best.1;
        let held = |local: &Local, p: Pose| window.holds(local.box_of(p, cx.model));
        let without = local.save(window);
        for _ in 0..ROW_SWEEPS {
            for i in 0..poses.len() {
                if !poses.iter().all(|&p| held(local, p)) {
                    local.restore(window, &saved);
                    return Vec::new();
                }
                local.restore(window, &without);
                for (j, &q) in poses.iter().enumerate() {
                    if j != i {
                        let b = local.box_of(q, cx.model);
                        local.place(q, b, cx);
                    }
                }
                poses[i] = fit::refine(&local.levels(cx), poses[i]).pose;
            }
        }
        local.restore(window, &saved);
        poses
            .into_iter()
            .map(|p| Spot {
                at: (p.x, p.y),
                axis: Some(p.phi),
                offsets: None,
                needed: false,
                fixed: true,
            })
            .collect()
    }
}

impl<'a> SetTrials for Across<'a> {
    /// A rod, and the highlights inside it turned from it.
    type Item = (usize, Vec<Spot<'a>>);
    /// The rods a trial may take off, and how many of them after the first are its nearest.
    type Near = (Vec<usize>, usize);
    type Kept = Option<(Vec<usize>, Vec<fit::Fitted>)>;

    fn passed_over(&self, &(g, _): &Self::Item, touched: &[bool]) -> bool {
        touched[g]
    }

    /// The rods a trial about rod `g` takes off: it, then the nearest [`NEAR_ROD`] within a
    /// length not yet touched, then the others on the line of a highlight inside it.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        (g, spots): &Self::Item,
        cx: &Context,
    ) -> (Vec<usize>, usize) {
        let g = *g;
        let p = found[g].pose;
        let mut near: Vec<usize> = std::iter::once(g)
            .chain(
                nearest(found, touched, (p.x, p.y), cx.length, NEAR_ROD + 1)
                    .into_iter()
                    .filter(|&k| k != g)
                    .take(NEAR_ROD),
            )
            .collect();
        let nearest_count = near.len() - 1;
        let reach = (ON_LINE + 0.5) * cx.length;
        for k in nearest(found, touched, (p.x, p.y), reach, usize::MAX) {
            if !near.contains(&k) && spots.iter().any(|s| on_line(found[k].pose, s, cx)) {
                near.push(k);
            }
        }
        (near, nearest_count)
    }

    /// What a trial about `near` reads, of either level: fits at the rods' centres, at the
    /// highlights (inside the first rod), and at the middle of what is left unexplained
    /// within a length of a set's mean centre (within a length of the first rod).
    fn rods<'n>(&self, near: &'n (Vec<usize>, usize)) -> &'n [usize] {
        &near.0
    }

    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        (near, _): &(Vec<usize>, usize),
        (_, spots): &Self::Item,
        cx: &Context,
    ) -> Window {
        let free = &local.maps.free;
        let r = self.reads;
        let p = found[near[0]].pose;
        let far = 2.0 * cx.length + r;
        let rows = spots.iter().filter_map(|&a| Row::of(found, near, a, cx));
        let row_poses: Vec<Pose> = rows
            .flat_map(|row| row.candidates(cx).flatten().collect::<Vec<_>>())
            .collect();
        near.iter()
            .map(|&k| found[k].pose)
            .chain(row_poses)
            .map(|q| Window::around(q.x, q.y, r, r, free))
            .fold(Window::around(p.x, p.y, far, far, free), Window::union)
    }

    /// The trials about a rod with highlights turned from it inside: the rod taken off alone,
    /// then with each rod near it, then (short rods by the frame's edge) with each two of
    /// them; rods fitted at the highlights first, then the rods afresh at their centres and
    /// rods added where their place is left unexplained; the first that keeps as many rods
    /// as it took off and scores more. Then the rods on the line of a highlight taken off
    /// with it, refitted as a [`Row`]: kept instead when it gains more. Returned: the rods
    /// taken off and their fits. The maps are left as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        &(ref near, nearest): &(Vec<usize>, usize),
        (_, spots): &Self::Item,
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let g = near[0];
        let search = (self.offsets, self.step, self.reach);
        let close = &near[1..=nearest];
        let pair_block = (2.0 * cx.width).max(cx.length) / (2.0 * cx.width).min(cx.length);
        let by_edge = pair_block < SQUARE_PAIR
            && nearest_edge(found[g].pose, &local.maps.free).depth < PAIRS_NEAR_EDGE * cx.length;
        let pairs = (0..close.len())
            .filter(|_| by_edge)
            .flat_map(|i| (i + 1..close.len()).map(move |j| vec![g, close[i], close[j]]));
        let sets = std::iter::once(vec![g])
            .chain(close.iter().map(|&k| vec![g, k]))
            .chain(pairs);
        let first = sets.into_iter().find_map(|set| {
            refit_together(local, found, &set, cx, search, None, spots).map(|t| (set, t))
        });
        // Rods end to end along a highlight, fitted shifted into the place of the rod fitted
        // across it, come off with it, refitted as a row; kept instead when it gains more.
        let row = spots.iter().find_map(|&a| {
            let row = Row::of(found, near, a, cx)?;
            let spots = row.best(local, found, self.reach, cx);
            if spots.is_empty() {
                return None;
            }
            refit_together(local, found, &row.rods, cx, search, None, &spots).map(|t| (row.rods, t))
        });
        let best = match (first, row) {
            (Some(f), Some(r)) => Some(if r.1.1 > f.1.1 { r } else { f }),
            (f, r) => f.or(r),
        };
        best.map(|(set, (fits, _))| (set, fits))
    }
}

/// Rods fitted across short rods lying face to face, found by the highlights inside them
/// turned from them ([`AxisSeed`]s): each such rod is taken off, alone, with a rod near it
/// or (by the frame's edge) with two, rods are fitted at the highlights first, then the rods
/// taken off afresh, with rods added where their place is left unexplained; kept when it
/// keeps as many rods and scores more, or, gaining more, the rods end to end along a
/// highlight refitted as a row with it. As in [`repair_doubtful`](super::repair_doubtful),
/// the trials are worked out ahead in parallel and taken over in order where the rods near,
/// their poses and what the trials read are unchanged since, so the outcome is the
/// sequential one whatever the thread count.
/// Only the rods `tried` are looked at. Returns the number of rods repaired.
#[allow(clippy::too_many_arguments)]
pub fn repair_across_highlights(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    tried: impl Iterator<Item = usize>,
    seeds: &[AxisSeed],
    offsets: &[(f64, f64)],
    along_axis: &[(f64, f64)],
    step: f64,
) -> usize {
    let mut local = Local::new(maps, cx);
    let trial = Across {
        offsets,
        along_axis,
        step,
        reach: cx.trial_reach(),
        reads: fit_reads(cx, offsets, step).max(fit_reads(cx, along_axis, step)),
    };
    let rods: Vec<(usize, Vec<Spot>)> = tried
        .map(|g| (g, trial.turned_inside(found[g].pose, seeds, cx)))
        .filter(|(_, spots)| !spots.is_empty())
        .collect();
    in_order(&trial, &rods, found, &mut local, cx)
}
