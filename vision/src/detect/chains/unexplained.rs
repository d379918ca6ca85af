//! Rods missed where their neighbours' fits ate into their place. What is left of such a
//! rod is too small for a fit of its own, and its seeds were spent finding the neighbours
//! again, so no failed seed marks it for [`repair_crowded`](super::repair_crowded): the
//! spots are found on the maps instead, where dark area is left unexplained.

use super::{
    Context, Found, Local, Maps, SetTrials, Spot, Window, fit, in_order, nearest, refit_together,
    unexplained_near,
};
use crate::detect::plane::Plane;

/// Spots where at least a third of a rod's area is left unexplained within a square of side
/// L (the test [`repair_crowded`](super::repair_crowded) makes at a failed seed), at least
/// a length apart, the most unexplained first: the middles of what is left there. The
/// squares are counted on a grid of a quarter width, each in four reads of a summed-area
/// table (13-20 ms for a 258 x 120 mm frame at 10 px/mm).
pub(super) fn unexplained_spots(free: &Plane, cx: &Context) -> Vec<(f64, f64)> {
    let (w, h) = (free.width, free.height);
    let stride = w + 1;
    let mut sum = vec![0u32; stride * (h + 1)];
    for r in 0..h {
        let mut run = 0u32;
        for c in 0..w {
            run += u32::from(free.at(c, r) > 0.5);
            sum[(r + 1) * stride + c + 1] = sum[r * stride + c + 1] + run;
        }
    }
    let count = |c0: usize, r0: usize, c1: usize, r1: usize| {
        sum[r1 * stride + c1] + sum[r0 * stride + c0]
            - sum[r0 * stride + c1]
            - sum[r1 * stride + c0]
    };
    let half = (0.5 * cx.length) as usize;
    let step = ((0.25 * cx.width) as usize).max(1);
    let least = least_unexplained(cx);
    let mut candidates = Vec::new();
    for r in (0..h).step_by(step) {
        let (r0, r1) = (r.saturating_sub(half), (r + half).min(h));
        for c in (0..w).step_by(step) {
            let (c0, c1) = (c.saturating_sub(half), (c + half).min(w));
            let n = count(c0, r0, c1, r1);
            if f64::from(n) >= least {
                candidates.push((n, r, c));
            }
        }
    }
    candidates.sort_by(|a, b| b.0.cmp(&a.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut centres: Vec<(f64, f64)> = Vec::new();
    let mut spots = Vec::new();
    for (_, r, c) in candidates {
        let p = (c as f64 + 0.5, r as f64 + 0.5);
        if centres
            .iter()
            .any(|q| (q.0 - p.0).hypot(q.1 - p.1) < cx.length)
        {
            continue;
        }
        centres.push(p);
        spots.push(unexplained_near(free, p.0, p.1, cx.length).middle);
    }
    spots
}

/// Unexplained dark area (pixels) within a square of side L that calls for a trial.
fn least_unexplained(cx: &Context) -> f64 {
    cx.length * cx.width / 3.0
}

/// The settings of [`repair_unexplained`]'s trials.
struct Spots<'a> {
    offsets: &'a [(f64, f64)],
    step: f64,
    /// Half side of the window a trial may change around each rod.
    reach: f64,
    /// How far from its seed a fit may read.
    reads: f64,
}

/// Most spots tried per rod found, the most unexplained first. A photograph the rounds read
/// well leaves fewer (lab, 10 and 6 px/mm: 18-50 for 900-1 700 rods); one they read badly
/// leaves hundreds, most of which no trial mends (grains cut by the frame, rods the fits
/// cannot tell apart), and trying them all made it two to three times slower.
const SPOTS_PER_ROD: f64 = 0.04;

/// Spots tried whatever the number of rods: a small photograph's few are all tried.
const FEWEST_SPOTS: usize = 10;

/// Most rods near a spot that its trials take off, one or two at a time.
const NEAR_SPOT: usize = 4;

impl Spots<'_> {
    fn unexplained(&self, local: &Local, spot: (f64, f64), cx: &Context) -> bool {
        unexplained_near(&local.maps.free, spot.0, spot.1, cx.length).count >= least_unexplained(cx)
    }
}

impl SetTrials for Spots<'_> {
    /// A spot of unexplained dark area.
    type Item = (f64, f64);
    type Near = Vec<usize>;
    type Kept = Option<(Vec<usize>, Vec<fit::Fitted>)>;

    fn passed_over(&self, _: &(f64, f64), _: &[bool]) -> bool {
        false
    }

    /// The rods a spot's trials take off: the nearest [`NEAR_SPOT`] within a length not yet
    /// touched.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        &spot: &(f64, f64),
        cx: &Context,
    ) -> Vec<usize> {
        nearest(found, touched, spot, cx.length, NEAR_SPOT)
    }

    fn rods<'n>(&self, near: &'n Vec<usize>) -> &'n [usize] {
        near
    }

    /// What a spot's trials read, of either level: fits at the rods' centres, at the spot,
    /// and at the middle of what is left unexplained within a length of the rods' mean
    /// centre (which lies within a length of the spot).
    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        near: &Vec<usize>,
        &spot: &(f64, f64),
        cx: &Context,
    ) -> Window {
        let free = &local.maps.free;
        let r = self.reads;
        let far = 2.0 * cx.length + r;
        near.iter()
            .map(|&k| Window::around(found[k].pose.x, found[k].pose.y, r, r, free))
            .fold(
                Window::around(spot.0, spot.1, far, far, free),
                Window::union,
            )
    }

    /// The trials at a spot: each rod near it taken off alone, then each pair, the rods
    /// fitted afresh at their centres and rods added where their place is left unexplained,
    /// or (when that adds none) a rod fitted at the spot first. The first trial that ends
    /// with more rods than it took off and scores more is kept: the rods it took off and
    /// its fits. The maps are left as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Vec<usize>,
        &spot: &(f64, f64),
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        if !self.unexplained(local, spot, cx) {
            return None;
        }
        let singles = near.iter().map(|&k| vec![k]);
        let pairs =
            (0..near.len()).flat_map(|i| (i + 1..near.len()).map(move |j| vec![near[i], near[j]]));
        let search = (self.offsets, self.step, self.reach);
        for set in singles.chain(pairs) {
            let adds = |kept: &(Vec<fit::Fitted>, f64)| kept.0.len() > set.len();
            let kept = refit_together(local, found, &set, cx, search, None, &[])
                .filter(adds)
                .or_else(|| {
                    refit_together(
                        local,
                        found,
                        &set,
                        cx,
                        search,
                        None,
                        &[Spot {
                            at: spot,
                            axis: None,
                            offsets: None,
                            needed: true,
                            fixed: false,
                        }],
                    )
                    .filter(adds)
                });
            if let Some((fits, _)) = kept {
                return Some((set, fits));
            }
        }
        None
    }
}

/// Rods missed where their neighbours' fits ate into their place, found at the spots of
/// unexplained dark area ([`unexplained_spots`]): at each, the rods near it are taken off
/// one or two at a time and fitted afresh, with a rod added where their place is left
/// unexplained (or fitted at the spot before them); a trial is kept when it adds a rod and
/// scores more. As in [`repair_doubtful`](super::repair_doubtful), the trials are worked
/// out ahead in parallel and taken over in order where the rods near the spot, their poses
/// and what the trials read are unchanged since, so the outcome is the sequential one
/// whatever the thread count. Returns the number of spots repaired.
pub fn repair_unexplained(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let mut spots = unexplained_spots(&maps.free, cx);
    spots.truncate(((SPOTS_PER_ROD * found.len() as f64).ceil() as usize).max(FEWEST_SPOTS));
    let mut local = Local::new(maps, cx);
    let trial = Spots {
        offsets,
        step,
        reach: cx.trial_reach(),
        reads: super::fit_reads(cx, offsets, step),
    };
    in_order(&trial, &spots, found, &mut local, cx)
}
