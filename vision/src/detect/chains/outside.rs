//! Rods fitted centred outside the photograph across what the edge leaves of rods it cuts.
//! Where the edge cuts two columns of rods, one rod fitted centred outside the frame may
//! explain both stubs at once; the rods inside are then fitted shifted or turned about it,
//! and no other repair sees an error: the rod outside explains the stubs the row-shift repair
//! looks for, and leaves nothing unexplained beside the turned rods (lab rod53, disordered,
//! 6 px/mm, seed 1: a rod at (194.7, -1.1) mm over two columns, a rod above turned by a right
//! angle). The rod outside and the rods inside near it are taken off together and fitted
//! afresh, innermost first, the rod outside last in what they leave.

use super::{
    Context, Found, Local, Maps, SetTrials, Window, centred_inside, fit, fit_reads, in_order,
    nearest_edge, turn, unexplained_near, with_nearest,
};
use crate::detect::model::Pose;

/// The pose of a rod a kept trial took away: it paints nothing and lies near no rod, and
/// [`repair_outside`] drops it from the rods found at its end.
const GONE: Pose = Pose {
    x: -1e9,
    y: -1e9,
    phi: 0.0,
};

/// Rods inside within this many lengths of a rod centred outside are refitted with it.
const NEAR_OUTSIDE: f64 = 2.0;

/// Most rods inside refitted with a rod centred outside, the nearest first. Uncapped, a near
/// set of 13 rods refitted one of them wrong and added a false rod (lab rod3 at 10 px/mm,
/// seed 1: precision 99.72 -> 99.66 %). At 6, lab rod3 at 6 px/mm gained a rod on seed 2 and
/// a false one on seed 1 (by the unexplained spots it left for the last repair), and the
/// repair cost rod3 at 10 px/mm a quarter of its time; at 4, no lab figure worse on seeds 1-3
/// and the rod53 gains the same.
const NEAR_MOST: usize = 4;

/// Rods turned by less than this (degrees) from the rod outside, their centres within half
/// a width of its axis, are the column it lies in: tried alone first.
const ON_AXIS_DEG: f64 = 15.0;

/// The settings of [`repair_outside`]'s trials.
struct Outside<'a> {
    offsets: &'a [(f64, f64)],
    step: f64,
    /// Half side of the window a trial may change around each rod.
    reach: f64,
    /// How far from its seed a fit may read.
    reads: f64,
}

impl Outside<'_> {
    /// The trial with the rods inside `inside` and the rod outside `g`: all taken off; the
    /// rods inside fitted afresh at their centres over every angle, innermost first (the
    /// deepest are least in doubt, and each fit leaves less for the next); up to two rods
    /// added where at least a third of a rod is left unexplained (each agreeing as an added
    /// rod must); the rod outside fitted last in what is left, taken away when it fails.
    /// Kept when at least as many fits are centred inside as rods inside were taken off, and
    /// they score more, by [`Context::least_gain`], than the old poses did on the maps
    /// without them: returned as the rods taken off (those inside, then `g`) and a fit for
    /// each in that order ([`GONE`] for one that failed), then the added ones. The maps are
    /// left as they were.
    fn refit(
        &self,
        local: &mut Local,
        found: &[Found],
        inside: &[usize],
        g: usize,
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let mut rods = inside.to_vec();
        let plane = &local.maps.free;
        rods.sort_by(|&a, &b| {
            nearest_edge(found[b].pose, plane)
                .depth
                .total_cmp(&nearest_edge(found[a].pose, plane).depth)
                .then(a.cmp(&b))
        });
        rods.push(g);
        let window = rods
            .iter()
            .map(|&k| {
                let p = found[k].pose;
                Window::around(p.x, p.y, self.reach, self.reach, plane)
            })
            .reduce(Window::union)?;
        let saved = local.save(window);
        let old_total = local.take_off_set(found, &rods, cx);
        let mut new_total = 0.0;
        let mut fits = Vec::with_capacity(rods.len() + 2);
        let mut fit_at = |local: &mut Local, at: (f64, f64), least: f32| {
            let ft = fit::fit(&local.levels(cx), at, self.offsets, self.step, None);
            let b = local.box_of(ft.pose, cx.model);
            let passes = cx.passes(&ft, b, window) && ft.score.agreement >= least;
            if passes {
                new_total += f64::from(ft.score.total);
                local.place(ft.pose, b, cx);
            }
            passes.then_some(ft)
        };
        let gone = fit::Fitted {
            pose: GONE,
            score: Default::default(),
        };
        for &k in &rods[..inside.len()] {
            let p = found[k].pose;
            fits.push(fit_at(local, (p.x, p.y), 0.0).unwrap_or(gone));
        }
        let n = rods.len() as f64;
        let (mx, my) = rods.iter().fold((0.0, 0.0), |(x, y), &k| {
            (x + found[k].pose.x / n, y + found[k].pose.y / n)
        });
        let mut added = Vec::new();
        for _ in 0..2 {
            let left = unexplained_near(&local.maps.free, mx, my, 2.0 * cx.length);
            if left.count < cx.length * cx.width / 3.0 {
                break;
            }
            match fit_at(local, left.middle, super::ADDED_AGREEMENT) {
                Some(ft) => added.push(ft),
                None => break,
            }
        }
        let p = found[g].pose;
        fits.push(fit_at(local, (p.x, p.y), 0.0).unwrap_or(gone));
        fits.extend(added);
        local.restore(window, &saved);
        let free = &local.maps.free;
        let fitted_inside = fits
            .iter()
            .filter(|ft| centred_inside(ft.pose, free))
            .count();
        let gain = new_total - old_total;
        (fitted_inside >= inside.len() && gain > cx.least_gain()).then_some((rods, fits))
    }
}

impl SetTrials for Outside<'_> {
    /// A rod centred outside the photograph.
    type Item = usize;
    /// The rod outside first, then the untouched rods inside near it, nearest first.
    type Near = Vec<usize>;
    type Kept = Option<(Vec<usize>, Vec<fit::Fitted>)>;

    fn passed_over(&self, &g: &usize, touched: &[bool]) -> bool {
        touched[g]
    }

    /// The rod `g`, and the [`NEAR_MOST`] untouched rods centred inside nearest to it within
    /// [`NEAR_OUTSIDE`] lengths.
    fn near(&self, found: &[Found], touched: &[bool], &g: &usize, cx: &Context) -> Vec<usize> {
        let within = NEAR_OUTSIDE * cx.length;
        with_nearest(found, touched, g, within, NEAR_MOST, |k| {
            centred_inside(found[k].pose, cx.dark)
        })
    }

    fn rods<'n>(&self, near: &'n Vec<usize>) -> &'n [usize] {
        near
    }

    /// What a trial reads, of either level: fits at each rod's centre and at the middle of
    /// what they leave unexplained (within a length of their mean centre).
    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        near: &Vec<usize>,
        _: &usize,
        cx: &Context,
    ) -> Window {
        let free = &local.maps.free;
        let r = self.reads;
        let far = cx.length + r;
        // The mean centre of any subset lies in the rods' bounding box.
        let (x0, x1, y0, y1) = near.iter().fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |(x0, x1, y0, y1), &k| {
                let p = found[k].pose;
                (x0.min(p.x), x1.max(p.x), y0.min(p.y), y1.max(p.y))
            },
        );
        let middle = Window::around(
            0.5 * (x0 + x1),
            0.5 * (y0 + y1),
            0.5 * (x1 - x0) + far,
            0.5 * (y1 - y0) + far,
            free,
        );
        near.iter()
            .map(|&k| Window::around(found[k].pose.x, found[k].pose.y, r, r, free))
            .fold(middle, Window::union)
    }

    /// The trial: the rods inside on the axis of the rod outside (its column) first, then,
    /// if that is not kept, every rod inside near it ([`Outside::refit`]). The maps are left
    /// as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Vec<usize>,
        _: &usize,
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let (g, inside) = (near[0], &near[1..]);
        let p = found[g].pose;
        let (s, c) = p.phi.sin_cos();
        let on_axis: Vec<usize> = inside
            .iter()
            .copied()
            .filter(|&k| {
                let q = found[k].pose;
                // Across the axis: (sin phi, cos phi).
                let across = (q.x - p.x) * s + (q.y - p.y) * c;
                turn(q.phi, p.phi) < ON_AXIS_DEG.to_radians() && across.abs() < 0.5 * cx.width
            })
            .collect();
        // Without rods on its axis, the rod outside alone would be refitted: a trial that
        // can only take it away, leaving the rods it misled where they are.
        let column = (!on_axis.is_empty())
            .then(|| self.refit(local, found, &on_axis, g, cx))
            .flatten();
        column.or_else(|| {
            (on_axis.len() < inside.len())
                .then(|| self.refit(local, found, inside, g, cx))
                .flatten()
        })
    }
}

/// Rods fitted centred outside the photograph, each refitted with the rods inside near it
/// (see the module's text): the trials are worked out ahead in parallel and taken over in
/// order where the rods near the rod outside, their poses and what the trials read are
/// unchanged since, so the outcome is the sequential one whatever the thread count. Rods a
/// kept trial took away are dropped from `found`. Returns the number of trials kept.
pub fn repair_outside(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let outside: Vec<usize> = (0..found.len())
        .filter(|&g| !centred_inside(found[g].pose, cx.dark))
        .collect();
    if outside.is_empty() {
        return 0;
    }
    let mut local = Local::new(maps, cx);
    let trial = Outside {
        offsets,
        step,
        reach: cx.trial_reach(),
        reads: fit_reads(cx, offsets, step),
    };
    let repaired = in_order(&trial, &outside, found, &mut local, cx);
    found.retain(|g| g.pose != GONE);
    repaired
}
