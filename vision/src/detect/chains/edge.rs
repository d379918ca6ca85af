//! Rods fitted turned across the photograph's edge. A rod lying along the edge, a little in
//! from it, with the stub of a rod the edge cuts beyond it, may be fitted turned by a right
//! angle and pushed out over the edge: the part of the outline outside the frame reads
//! nothing, so the turned fit covers the rod and the stub at once (lab rod53 at 6 px/mm, the
//! two rods turned by a right angle on seed 3, ordered packing; on seed 1 one of two). The
//! across-highlights repair can make one too, turning a rod fitted shifted onto the stubs.
//! Such a rod is fitted again along the edge, moved in from it, and up to two rods the edge
//! cuts are fitted in what that leaves between it and the edge; they are kept when they
//! explain the photograph better. The cut rods standing beside it may hold part of its place
//! (one fitted shifted into it): the trial is made again with them refitted too, and the
//! one that gains more is kept.

use super::{
    Context, Edge, Found, Local, SetTrials, Window, fit, fit_reads, in_order, nearest_edge, turn,
    unexplained_near, with_nearest,
};
use crate::detect::model::Pose;
use crate::detect::plane::Plane;

/// Least turn (degrees) from the edge's direction of a rod the repair refits. The rods
/// turned this way are turned by near a right angle (83-90 degrees on lab rod53 at
/// 6 px/mm); at 45, true rods of the disordered packing standing at 57 degrees across the
/// edge were refitted (lab rod53 at 10 px/mm, seed 1: a rod lost).
const ACROSS_DEG: f64 = 60.0;

/// Most turn (degrees) from the edge's direction of the rod refitted along it: refined
/// further, it is no longer the rod along the edge (lab rod3 at 6 px/mm, seed 3: a rod
/// refitted 29 degrees off, across a column of rods, left a false rod beside it).
const ALONG_DEG: f64 = 30.0;

/// Least unexplained dark area (parts of L x W) left between the refitted rod and the edge
/// that a rod is fitted in: 0.8 of the least part of a stub kept ([`STUB_SEEN`]), as it
/// was 0.2 of `min_visible` (a quarter) before stubs centred outside were kept. At 0.2, the
/// stub beyond a rod along the top edge, 0.23 seen, left 207 px unexplained where 294 were
/// asked, and the refit along the edge gained 0.0995 L x W without it (lab rod53 at
/// 10 px/mm, seed 8, at (68.2, 117.7) mm).
const LEAST_STUB: f64 = 0.8 * STUB_SEEN;

/// How much deeper (parts of W) than the turned rod reached the far face of the rod
/// refitted along the edge may lie: a pixel or two of a fit's play.
const SLACK: f64 = 0.1;

/// Most stubs fitted between the refitted rod and the edge: the rods of a row the edge cuts
/// lie a length apart, so a band a length long holds parts of two.
const MOST_STUBS: usize = 2;

/// Most rods beside the turned one, cut by the same edge, refitted with it when the rod
/// along the edge alone keeps nothing: one on either side.
const MOST_BESIDE: usize = 2;

/// Least part of a stub centred outside the photograph that must be seen (the acceptance
/// asks `min_visible`, a quarter, of every rod). Such a rod is never reported: it stands for
/// the strip the edge leaves of it, which the turned fit explained, so that the trial and
/// the turned fit are scored on the same dark area. Lab rod53 at 6 px/mm, seed 1: the stub
/// beside the rod turned at (249.1, 1.6) mm is 0.22 seen.
const STUB_SEEN: f64 = 0.15;

/// Whether two rod poses are one rod fitted twice: centres within a tenth of a width, axes
/// within [`SAME_DEG`].
fn same_rod(p: Pose, q: Pose, cx: &Context) -> bool {
    (p.x - q.x).hypot(p.y - q.y) < 0.1 * cx.width && turn(p.phi, q.phi) < SAME_DEG.to_radians()
}

/// Most turn (degrees) between two fits of one rod.
const SAME_DEG: f64 = 3.0;

/// How far the outline of rod pose `p` reaches from its centre across an edge of direction
/// `edge_phi`.
fn reach(p: Pose, edge_phi: f64, cx: &Context) -> f64 {
    let t = turn(p.phi, edge_phi);
    0.5 * cx.length * t.sin() + 0.5 * cx.width * t.cos()
}

/// A trial of [`AlongEdge::with`] kept: the rods taken off, their fits, and what the fits
/// score more than the old poses and the trial with a rod fitted afresh.
struct Refit {
    set: Vec<usize>,
    fits: Vec<fit::Fitted>,
    gain: f64,
}

/// The settings of [`repair_along_edge`]'s trials.
struct AlongEdge<'a> {
    offsets: &'a [(f64, f64)],
    step: f64,
    /// Half side of the window a trial may change around the rod.
    reach: f64,
    /// How far from the rod's centre a trial may read.
    reads: f64,
}

/// Whether rod pose `p`, centred inside, is turned across its nearest edge and its outline
/// reaches over it: the rods this repair refits.
pub fn across_edge(p: Pose, plane: &Plane, cx: &Context) -> bool {
    let e = nearest_edge(p, plane);
    e.depth >= 0.0 && turn(p.phi, e.phi) > ACROSS_DEG.to_radians() && reach(p, e.phi, cx) > e.depth
}

impl AlongEdge<'_> {
    /// A rod the edge cuts, fitted in what is left unexplained about `mid`, between a rod
    /// refitted along the edge (centred `depth` in from it) and the edge: the best of the
    /// fits over every angle and along the edge that passes the acceptance (or, centred
    /// outside, is [`STUB_SEEN`] seen), is cut by the edge and lies nearer to it than the
    /// rod. None where less than [`LEAST_STUB`] of a rod is left unexplained there.
    fn stub(
        &self,
        local: &Local,
        mid: (f64, f64),
        depth: f64,
        window: Window,
        edge_phi: f64,
        cx: &Context,
    ) -> Option<fit::Fitted> {
        let plane = &local.maps.free;
        let left = unexplained_near(plane, mid.0, mid.1, cx.length);
        if left.count < LEAST_STUB * cx.length * cx.width {
            return None;
        }
        // A stub is most often a rod of the row along the edge: the fit over every angle
        // alone takes two such stubs for one rod standing across them, centred outside and
        // too little of it seen.
        [None, Some(edge_phi)]
            .into_iter()
            .map(|axis| {
                fit::fit(
                    &local.levels(cx),
                    left.middle,
                    self.offsets,
                    self.step,
                    axis,
                )
            })
            .filter(|ft| {
                self.seen_as_stub(local, ft, window, cx)
                    && nearest_edge(ft.pose, plane).depth < depth
            })
            .max_by(|a, b| a.score.total.total_cmp(&b.score.total))
    }

    /// Whether fit `ft` agrees as a rod the edge cuts must: cut, within `window`, passing
    /// the acceptance, or [`STUB_SEEN`] seen when centred outside.
    fn seen_as_stub(&self, local: &Local, ft: &fit::Fitted, window: Window, cx: &Context) -> bool {
        let at = nearest_edge(ft.pose, &local.maps.free).depth;
        let seen = f64::from(ft.score.visible);
        let least_seen = if at < 0.0 { STUB_SEEN } else { cx.min_visible };
        f64::from(ft.score.agreement) >= cx.min_confidence
            && seen >= least_seen
            && seen < 1.0
            && window.holds(local.box_of(ft.pose, cx.model))
    }
}

impl SetTrials for AlongEdge<'_> {
    type Item = usize;
    type Near = Vec<usize>;
    type Kept = Option<(Vec<usize>, Vec<fit::Fitted>)>;

    fn passed_over(&self, &g: &usize, touched: &[bool]) -> bool {
        touched[g]
    }

    /// Rod `g`, then the untouched rods the same edge cuts centred within a length of it,
    /// nearest first.
    fn near(&self, found: &[Found], touched: &[bool], &g: &usize, cx: &Context) -> Vec<usize> {
        let e = nearest_edge(found[g].pose, cx.dark);
        with_nearest(found, touched, g, cx.length, MOST_BESIDE, |h| {
            let q = found[h].pose;
            let f = nearest_edge(q, cx.dark);
            f.inward == e.inward && reach(q, f.phi, cx) > f.depth
        })
    }

    fn rods<'n>(&self, near: &'n Vec<usize>) -> &'n [usize] {
        near
    }

    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        _: &Vec<usize>,
        &g: &usize,
        _: &Context,
    ) -> Window {
        let p = found[g].pose;
        Window::around(p.x, p.y, self.reads, self.reads, &local.maps.free)
    }

    /// The trial: rod `g` taken off and fitted again along its edge, and again with the rods
    /// beside it that the edge cuts (`near`) taken off too and refitted after it
    /// ([`AlongEdge::with`]); the one that gains more is kept.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Vec<usize>,
        &g: &usize,
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let alone = self.with(local, found, &[g], cx);
        // A cut rod beside it may have been fitted shifted into the place of the rod along
        // the edge (lab rod53 at 6 px/mm, seed 3: by 0.9 mm), which the refit then cannot
        // take whole. Tried only when the rod alone kept nothing, it was left shifted once
        // the rod turned across the edge paid for its whole ring (`Model::ring_seen`) and
        // the rod alone gained enough to be kept.
        let beside = (near.len() > 1)
            .then(|| self.with(local, found, near, cx))
            .flatten();
        let kept = match (alone, beside) {
            (Some(a), Some(b)) => Some(if b.gain > a.gain { b } else { a }),
            (a, b) => a.or(b),
        };
        kept.map(|t| (t.set, t.fits))
    }
}

impl AlongEdge<'_> {
    /// The trial with the rods `set` taken off, the turned rod first: it is fitted again
    /// along its edge, seeded at least three quarters of a width in from it; the others are
    /// refitted from their poses, each agreeing as a stub must; then up to [`MOST_STUBS`]
    /// stubs between the rod and the edge ([`AlongEdge::stub`]). Kept when the rod along
    /// the edge passes the acceptance and the fits score more, by [`Context::least_gain`],
    /// than the old poses did on the maps without them and than the same trial with a rod fitted
    /// afresh in the turned rod's place over every angle, unless that rod is the one along
    /// the edge ([`same_rod`]: lab rod53 at 10 px/mm, seed 9, a refit that gained 0.105
    /// L x W was refused against itself). Returned with that gain. The maps are left as they
    /// were.
    fn with(
        &self,
        local: &mut Local,
        found: &[Found],
        set: &[usize],
        cx: &Context,
    ) -> Option<Refit> {
        let p = found[set[0]].pose;
        let e = nearest_edge(p, &local.maps.free);
        let window = Window::around(p.x, p.y, self.reach, self.reach, &local.maps.free);
        let saved = local.save(window);
        let old_total = local.take_off_set(found, set, cx);
        let off = local.save(window);
        // The rod along the edge is fitted with the rods beside it where they were: with
        // them taken off, it slides along the dark row they leave.
        for &h in &set[1..] {
            let q = found[h].pose;
            let b = local.box_of(q, cx.model);
            local.place(q, b, cx);
        }
        let inward = (0.75 * cx.width - e.depth).max(0.0);
        let seed = (p.x + inward * e.inward.0, p.y + inward * e.inward.1);
        let along = fit::fit(
            &local.levels(cx),
            seed,
            self.offsets,
            self.step,
            Some(e.phi),
        );
        let depth = nearest_edge(along.pose, &local.maps.free).depth;
        // The turned rod covered the rod along the edge: that lies within its reach. Clean
        // rod53 at 6 px/mm, seed 1: a rod standing across the edge fitted shifted, in a
        // column of such rods, was refitted along the edge over two of them, its far
        // face 0.26 W deeper than the turned rod reached; on lab, 0.02 W at most.
        let covered = depth + 0.5 * cx.width <= e.depth + reach(p, e.phi, cx) + SLACK * cx.width;
        let b = local.box_of(along.pose, cx.model);
        let fits = if cx.passes(&along, b, window)
            && turn(along.pose.phi, e.phi) < ALONG_DEG.to_radians()
            && covered
        {
            local.restore(window, &off);
            self.fit_around(local, found, set, along, (e, true), (window, &off), cx)
        } else {
            None
        };
        local.restore(window, &saved);
        let (fits, new_total) = fits?;
        let least = cx.least_gain();
        if new_total - old_total <= least {
            return None;
        }
        // The old pose may be a rod standing across the edge fitted shifted (clean rod53 at
        // 6 px/mm, seed 1: in a column of rods stacked against the edge, one fitted shifted
        // by half a width was refitted along the edge over two of them): the rods along
        // the edge must also beat the same trial with a rod fitted afresh in its place.
        local.take_off(found, set[0], cx);
        let afresh = fit::fit(&local.levels(cx), (p.x, p.y), self.offsets, self.step, None);
        let b = local.box_of(afresh.pose, cx.model);
        // A rod fitted afresh onto the rod along the edge is that rod, not another trial.
        let afresh_total = if same_rod(afresh.pose, fits[0].pose, cx) {
            None
        } else if cx.passes(&afresh, b, window) {
            local.restore(window, &off);
            self.fit_around(local, found, set, afresh, (e, false), (window, &off), cx)
                .map(|(_, total)| total)
        } else {
            None
        };
        local.restore(window, &saved);
        let bar = afresh_total.map_or(old_total, |t| t.max(old_total));
        let gain = new_total - bar;
        (gain > least).then(|| Refit {
            set: set.to_vec(),
            fits,
            gain,
        })
    }

    /// On the maps with the rods of `set` taken off (`off`, saved over `window`): `first`
    /// placed, the rods of `set` after the first refitted from their poses (each cut by the
    /// edge and agreeing as a stub must, or the trial fails) and, when there are any,
    /// `first` refitted from its pose among them; then, when `(e, stubs)` asks, the stubs
    /// between `first` and the edge `e`: the fits and their total. The maps keep them.
    #[allow(clippy::too_many_arguments)]
    fn fit_around(
        &self,
        local: &mut Local,
        found: &[Found],
        set: &[usize],
        mut first: fit::Fitted,
        (e, stubs): (Edge, bool),
        (window, off): (Window, &[(f32, f32)]),
        cx: &Context,
    ) -> Option<(Vec<fit::Fitted>, f64)> {
        let mut fits = Vec::with_capacity(set.len() + MOST_STUBS);
        let b = local.box_of(first.pose, cx.model);
        local.place(first.pose, b, cx);
        for &h in &set[1..] {
            let q = found[h].pose;
            let ft = fit::fit(
                &local.levels(cx),
                (q.x, q.y),
                self.offsets,
                self.step,
                Some(q.phi),
            );
            if !self.seen_as_stub(local, &ft, window, cx) {
                return None;
            }
            let b = local.box_of(ft.pose, cx.model);
            local.place(ft.pose, b, cx);
            fits.push(ft);
        }
        if !fits.is_empty() {
            // The first fit was made with the others where they were before: once more
            // among their refits.
            local.restore(window, off);
            for ft in &fits {
                let b = local.box_of(ft.pose, cx.model);
                local.place(ft.pose, b, cx);
            }
            let q = first.pose;
            first = fit::fit(
                &local.levels(cx),
                (q.x, q.y),
                self.offsets,
                self.step,
                Some(q.phi),
            );
            let b = local.box_of(first.pose, cx.model);
            if !cx.passes(&first, b, window) {
                return None;
            }
            local.place(first.pose, b, cx);
        }
        fits.insert(0, first);
        let mut total: f64 = fits.iter().map(|ft| f64::from(ft.score.total)).sum();
        if fits.len() > 1 {
            // Scored again as placed one after another in their final poses: the others
            // were scored against the first fit's earlier pose (lab rod53 at 6 px/mm, seed
            // 3: 744 against 821 for the same three rods, the old poses 749). Each must
            // still agree as it did.
            local.restore(window, off);
            total = 0.0;
            for (k, ft) in fits.iter_mut().enumerate() {
                ft.score = cx
                    .model
                    .score(ft.pose, cx.levels.fine, &local.maps.free_bordered);
                let b = local.box_of(ft.pose, cx.model);
                let agrees = if k == 0 {
                    cx.passes(ft, b, window)
                } else {
                    self.seen_as_stub(local, ft, window, cx)
                };
                if !agrees {
                    return None;
                }
                total += f64::from(ft.score.total);
                local.place(ft.pose, b, cx);
            }
        }
        if !stubs {
            return Some((fits, total));
        }
        // The middle of the band between the rod and the edge.
        let q = first.pose;
        let depth = nearest_edge(q, &local.maps.free).depth;
        let to_mid = 0.5 * (depth + 0.5 * cx.width);
        let mid = (q.x - to_mid * e.inward.0, q.y - to_mid * e.inward.1);
        for _ in 0..MOST_STUBS {
            let Some(stub) = self.stub(local, mid, depth, window, e.phi, cx) else {
                break;
            };
            total += f64::from(stub.score.total);
            let b = local.box_of(stub.pose, cx.model);
            local.place(stub.pose, b, cx);
            fits.push(stub);
        }
        Some((fits, total))
    }
}

/// Rods fitted turned across the photograph's edge (see the module's text), each refitted
/// along it: the trials worked out ahead in parallel and taken over in order where nothing
/// they read has changed since ([`in_order`]). Returns the number of trials kept.
pub fn repair_along_edge(
    found: &mut Vec<Found>,
    maps: &mut super::Maps,
    cx: &Context,
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let across: Vec<usize> = (0..found.len())
        .filter(|&g| across_edge(found[g].pose, cx.dark, cx))
        .collect();
    if across.is_empty() {
        return 0;
    }
    let mut local = Local::new(maps, cx);
    let trial = AlongEdge {
        offsets,
        step,
        reach: cx.trial_reach(),
        // The refit's seed lies up to 0.75 W in, the stubs' square (side L) up to the edge
        // beyond it, and a fit reads about its seed in that square.
        reads: 1.25 * cx.length + 2.5 * cx.width + 2.0 * fit_reads(cx, offsets, step),
    };
    in_order(&trial, &across, found, &mut local, cx)
}
