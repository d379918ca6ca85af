//! Short rods lying face to face fitted by one rod turned across them. Two rod53 rods side by
//! side make a block of 2D x L, nearly square, that a rod turned by a right angle (or by
//! less) fits almost as well; the rod left over is then fitted shifted onto what remains, or
//! missed, and every repair before this one sees little unexplained area. The highlights do
//! not agree: the rods' own run across the turned rod, inside it.

use super::{
    Context, Found, Local, Maps, SetTrials, Spot, Window, fit, fit_reads, in_order, nearest,
    refit_together, set_and_fits, turn,
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

/// Most rods near a turned rod that its trials take off with it, one at a time.
const NEAR_ROD: usize = 3;

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
            })
            .collect()
    }
}

impl<'a> SetTrials for Across<'a> {
    /// A rod, and the highlights inside it turned from it.
    type Item = (usize, Vec<Spot<'a>>);
    type Near = Vec<usize>;
    type Kept = Option<(Vec<usize>, Vec<fit::Fitted>)>;

    fn passed_over(&self, &(g, _): &Self::Item, touched: &[bool]) -> bool {
        touched[g]
    }

    /// The rods a trial about rod `g` takes off: it, then the nearest [`NEAR_ROD`] within a
    /// length not yet touched.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        &(g, _): &Self::Item,
        cx: &Context,
    ) -> Vec<usize> {
        let p = found[g].pose;
        std::iter::once(g)
            .chain(
                nearest(found, touched, (p.x, p.y), cx.length, NEAR_ROD + 1)
                    .into_iter()
                    .filter(|&k| k != g)
                    .take(NEAR_ROD),
            )
            .collect()
    }

    /// What a trial about `near` reads, of either level: fits at the rods' centres, at the
    /// highlights (inside the first rod), and at the middle of what is left unexplained
    /// within a length of a set's mean centre (within a length of the first rod).
    fn rods<'n>(&self, near: &'n Vec<usize>) -> &'n [usize] {
        near
    }

    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        near: &Vec<usize>,
        _: &Self::Item,
        cx: &Context,
    ) -> Window {
        let free = &local.maps.free;
        let r = self.reads;
        let p = found[near[0]].pose;
        let far = 2.0 * cx.length + r;
        near.iter()
            .map(|&k| Window::around(found[k].pose.x, found[k].pose.y, r, r, free))
            .fold(Window::around(p.x, p.y, far, far, free), Window::union)
    }

    /// The trials about a rod with highlights turned from it inside: the rod taken off alone,
    /// then with each rod near it, rods fitted at the highlights first, then the rods
    /// afresh at their centres and rods added where their place is left unexplained. The
    /// first trial that keeps as many rods as it took off and scores more is kept: the rods
    /// it took off and its fits. The maps are left as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Vec<usize>,
        (_, spots): &Self::Item,
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let g = near[0];
        let search = (self.offsets, self.step, self.reach);
        let sets = std::iter::once(vec![g]).chain(near[1..].iter().map(|&k| vec![g, k]));
        for set in sets {
            if let Some((fits, _)) = refit_together(local, found, &set, cx, search, None, spots) {
                return Some((set, fits));
            }
        }
        None
    }

    fn parts<'k>(
        &self,
        kept: &'k Self::Kept,
        _: &'k Vec<usize>,
    ) -> (&'k [usize], &'k [fit::Fitted]) {
        set_and_fits(kept)
    }
}

/// Rods fitted across short rods lying face to face, found by the highlights inside them
/// turned from them ([`AxisSeed`]s): each such rod is taken off, alone or with a rod near it,
/// rods are fitted at the highlights first, then the rods taken off afresh, with rods added
/// where their place is left unexplained; kept when it keeps as many rods and scores more.
/// As in [`repair_doubtful`](super::repair_doubtful), the trials are worked out ahead in
/// parallel and taken over in order where the rods near, their poses and what the trials
/// read are unchanged since, so the outcome is the sequential one whatever the thread count.
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
    let factor = cx.levels.factor as usize;
    let mut local = Local::new(maps, factor);
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
