//! Rods accepted with a low agreement: fitted afresh, alone, with the rods turned like them,
//! or with a rod turned across them.

use super::{
    Context, Found, Local, Maps, Parts, SetTrials, Window, centred_inside, fit, fit_reads,
    in_order, offsets, refit_together, turn, with_nearest,
};
use crate::detect::model::Pose;

/// Agreement below which [`repair_doubtful`] fits a rod afresh. Rods fitted at the right
/// pose agree at 0.85-0.95 (lab, rod53 at 10 px/mm); the ones fitted turned by 10-30 degrees
/// agreed at 0.55-0.60.
pub(super) const DOUBTFUL: f64 = 0.75;

/// A rod accepted with a low agreement was often fitted turned away from its true angle,
/// from a seed whose highlight lay along a gap, or before its neighbours took their places.
/// Each such rod, in the order found, is taken off and fitted afresh at its centre over every
/// angle against the maps as they are now, its neighbours painted; the new fit is kept when
/// it passes the acceptance and scores more than the old pose on the same maps.
///
/// With rods turned the same way within a length of it, and a rod turned otherwise within
/// 1.5 lengths (the rows around), the doubtful rod may be one of two fitted across the three
/// rods really there (lab, rod3 at 10 px/mm: two rods at 62 degrees, agreements 0.70 and
/// 0.94, over three lying face to face), the other holding it in place. They are first taken
/// off together and fitted afresh ([`refit_together`]), once at the rows' angle and once at
/// any, and the trial that scores more is kept; failing that, the same with only those of
/// them that can overlap it. The rod turned otherwise may instead be the wrong one, fitted
/// across the doubtful rod and its row: when it overlaps the doubtful rod, the two are next
/// refitted together at the doubtful rod's angle. With no rod turned like it, its
/// neighbours in the rows may have been fitted shifted into its place: it is refitted with
/// them at the rows' angle. Only when none of these is kept is the doubtful rod refitted
/// alone.
///
/// The trials are worked out ahead in parallel on copies of the maps (they took a seventh of
/// a rod photograph's time one after another: each fits three to six rods over every angle);
/// the rods are then looked at in order, each taking its trial's guess unless a repair kept
/// before it changed the rods it would refit or what the guess read, as in
/// [`repair_turned`](super::repair_turned).
pub fn repair_doubtful(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let mut local = Local::new(maps, cx);
    let trial = Doubtful {
        offsets,
        step,
        reach: cx.trial_reach(),
        reads: fit_reads(cx, offsets, step),
    };
    let doubtful: Vec<usize> = (0..found.len())
        .filter(|&g| found[g].confidence < DOUBTFUL)
        .collect();
    in_order(&trial, &doubtful, found, &mut local, cx)
}

/// What a doubtful rod's trial kept: the rods refitted together, the doubtful rod with the
/// rod turned otherwise over it, the doubtful rod alone, or nothing.
#[derive(Clone)]
enum Refit {
    Together(Vec<fit::Fitted>),
    Overlapping(Vec<fit::Fitted>),
    WithTurned(Vec<fit::Fitted>),
    WithRows(Vec<fit::Fitted>),
    Alone(fit::Fitted),
    None,
}

/// The rods a kept trial took off (of the rods picked, the doubtful one first; or the pair)
/// and the fits it painted.
impl Parts<Picked> for Refit {
    fn parts<'r>(&'r self, near: &'r Picked) -> (&'r [usize], &'r [fit::Fitted]) {
        let rods = &near.rods;
        match self {
            Refit::Together(fits) => (rods, fits),
            Refit::Overlapping(fits) => (&near.overlapping, fits),
            Refit::WithTurned(fits) => (&near.pair, fits),
            Refit::WithRows(fits) => (&near.rows, fits),
            Refit::Alone(ft) => (&rods[..1], std::slice::from_ref(ft)),
            Refit::None => (&[], &[]),
        }
    }
}

/// What picks a doubtful rod's trials.
#[derive(PartialEq)]
struct Picked {
    /// The rods refitted together, the doubtful one first.
    rods: Vec<usize>,
    /// Those of them near enough to overlap the doubtful one (centres within (L + W) / 2),
    /// when that leaves some out.
    overlapping: Vec<usize>,
    /// The angle of the rows around them, if any.
    around: Option<f64>,
    /// The doubtful rod and the rod turned otherwise over it, or none.
    pair: Vec<usize>,
    /// The doubtful rod and the untouched rods turned like the rows around within a length
    /// of it, nearest first, when no rod is turned like it and it is centred inside.
    rows: Vec<usize>,
}

/// The settings of [`repair_doubtful`]'s trials.
struct Doubtful<'a> {
    offsets: &'a [(f64, f64)],
    step: f64,
    /// Half side of the window a trial may change around each rod.
    reach: f64,
    /// How far from its seed a fit may read.
    reads: f64,
}

impl SetTrials for Doubtful<'_> {
    /// A doubtful rod.
    type Item = usize;
    type Near = Picked;
    type Kept = Refit;

    fn passed_over(&self, &g: &usize, touched: &[bool]) -> bool {
        touched[g]
    }

    /// The rods refitted with the doubtful rod `g` (it first, then the untouched rods turned
    /// like it within a length), the angle of the nearest rod around them turned otherwise
    /// (the rows there), if one lies within 1.5 lengths, and `g` with that rod when it is
    /// untouched and near enough to overlap it (centres within (L + W) / 2).
    fn near(&self, found: &[Found], touched: &[bool], &g: &usize, cx: &Context) -> Picked {
        let old = found[g].pose;
        let rods: Vec<usize> = std::iter::once(g)
            .chain((0..found.len()).filter(|&h| {
                let p = found[h].pose;
                h != g
                    && !touched[h]
                    && (p.x - old.x).hypot(p.y - old.y) < cx.length
                    && turn(p.phi, old.phi) < PARALLEL_DEG.to_radians()
            }))
            .collect();
        let nearest_turned = (0..found.len())
            .filter(|&h| !rods.contains(&h))
            .map(|h| (found[h].pose, h))
            .filter(|(p, _)| turn(p.phi, old.phi) >= PARALLEL_DEG.to_radians())
            .map(|(p, h)| ((p.x - old.x).hypot(p.y - old.y), h))
            .filter(|&(d, _)| d < 1.5 * cx.length)
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let around = nearest_turned.map(|(_, h)| found[h].pose.phi);
        let pair = match nearest_turned {
            Some((d, h)) if d < 0.5 * (cx.length + cx.width) && !touched[h] => vec![g, h],
            _ => Vec::new(),
        };
        // A rod centred outside is too little seen to move the rods inside for it.
        let inside = centred_inside(old, cx.dark);
        let rows = if let (1, Some(rows_phi), true) = (rods.len(), around, inside) {
            with_nearest(found, touched, g, cx.length, MOST_ROWS, |h| {
                turn(found[h].pose.phi, rows_phi) < PARALLEL_DEG.to_radians()
            })
        } else {
            Vec::new()
        };
        let overlap = 0.5 * (cx.length + cx.width);
        let overlapping: Vec<usize> = rods
            .iter()
            .copied()
            .filter(|&h| {
                let p = found[h].pose;
                (p.x - old.x).hypot(p.y - old.y) < overlap
            })
            .collect();
        let overlapping = if overlapping.len() > 1 && overlapping.len() < rods.len() {
            overlapping
        } else {
            Vec::new()
        };
        Picked {
            rods,
            overlapping,
            around,
            pair,
            rows,
        }
    }

    fn rods<'n>(&self, near: &'n Picked) -> &'n [usize] {
        &near.rods
    }

    /// What a trial about the rods reads, of either level: fits at each rod's centre and at
    /// the middle of what they leave unexplained (within a length of their mean centre).
    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        Picked {
            rods, pair, rows, ..
        }: &Picked,
        _: &usize,
        cx: &Context,
    ) -> Window {
        let free = &local.maps.free;
        let r = self.reads;
        let n = rods.len() as f64;
        let (mx, my) = rods.iter().fold((0.0, 0.0), |(x, y), &k| {
            (x + found[k].pose.x / n, y + found[k].pose.y / n)
        });
        let far = cx.length + r;
        let pair_reads = pair.iter().chain(rows).map(|&k| {
            let p = found[k].pose;
            Window::around(p.x, p.y, far + cx.length, far + cx.length, free)
        });
        rods.iter()
            .map(|&k| Window::around(found[k].pose.x, found[k].pose.y, r, r, free))
            .chain(pair_reads)
            .fold(Window::around(mx, my, far, far, free), Window::union)
    }

    /// The trial: the rods taken off together and fitted afresh, once at the rows' angle and
    /// once at any, the trial that scores more kept ([`at_either_angle`]), then the same
    /// with the overlapping ones alone; when none is (or the rod has no parallel neighbour,
    /// or no rows around), the doubtful rod and the rod turned otherwise overlapping it
    /// refitted together at the doubtful rod's angle; then the doubtful rod with the rows'
    /// rods around it at the rows' angle; failing all, the doubtful rod alone fitted afresh
    /// at its centre over every angle, kept when it passes the acceptance and scores more
    /// than its old pose on the same maps. The maps are left as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        Picked {
            rods,
            overlapping,
            around,
            pair,
            rows,
        }: &Picked,
        _: &usize,
        cx: &Context,
    ) -> Refit {
        // At the rows' angle and at any: a block of rods face to face fits rods of either
        // angle, and the rows around may tell which. Rods turned like every rod around them
        // are a row, not rods fitted across one: not tried together.
        let search = (self.offsets, self.step, self.reach);
        if rods.len() > 1
            && let Some(fits) = at_either_angle(local, found, rods, cx, search, *around)
        {
            return Refit::Together(fits);
        }
        // The rods turned like it may take in a true rod beside the block it lies in (lab
        // rod3 at 10 px/mm, seed 7: three rods fitted at 57 degrees across three at 147,
        // and a fourth rightly at 57 a length away, which the rows' angle cannot fit): the
        // rods overlapping it alone, the same way.
        if !overlapping.is_empty()
            && let Some(fits) = at_either_angle(local, found, overlapping, cx, search, *around)
        {
            return Refit::Overlapping(fits);
        }
        // The rod turned otherwise may be the wrong one, fitted across the doubtful rod and
        // its row (lab rod53 at 10 px/mm, seed 4: a rod turned by 74 degrees, agreeing at
        // 0.95, across two rows whose rods it overlaps agree at 0.55). Refitted together at
        // the doubtful rod's angle, kept when it gains and leaves no rod doubtful (without
        // that, at the frame's edge, seed 3 at 6 px/mm: a false rod agreeing at 0.51).
        if !pair.is_empty() {
            let axis = Some(found[pair[0]].pose.phi);
            if let Some((fits, gain)) = refit_together(local, found, pair, cx, search, axis, &[])
                && gain > cx.least_gain()
                && fits
                    .iter()
                    .all(|f| f64::from(f.score.agreement) >= DOUBTFUL)
            {
                return Refit::WithTurned(fits);
            }
        }
        // A rod alone among rows turned otherwise: its neighbours may have been fitted
        // shifted into its place (lab rod53 at 10 px/mm, seed 4: at the right edge, the cut
        // rods of two rows shifted by 1.2 and 1.8 mm, the rod between fitted turned by 46
        // degrees, which refitted alone came back there, gaining 0.003 L x W). Refitted
        // together at the rows' angle, kept as the pair is, and when each rod of the rows
        // is refitted in its row (seed 3 at 6 px/mm: a rod refitted into the row below,
        // leaving its place unexplained).
        if rows.len() > 1
            && let Some((fits, gain)) = refit_together(local, found, rows, cx, search, *around, &[])
            && gain > cx.least_gain()
            && fits
                .iter()
                .all(|f| f64::from(f.score.agreement) >= DOUBTFUL)
            && rows[1..]
                .iter()
                .all(|&h| fits.iter().any(|f| in_its_row(found[h].pose, f.pose, cx)))
        {
            return Refit::WithRows(fits);
        }
        let g = rods[0];
        let old = found[g].pose;
        let window = Window::around(old.x, old.y, self.reach, self.reach, &local.maps.free);
        let saved = local.save(window);
        let old_total = local.take_off(found, g, cx);
        let ft = fit::fit(
            &local.levels(cx),
            (old.x, old.y),
            self.offsets,
            self.step,
            None,
        );
        let b = local.box_of(ft.pose, cx.model);
        let kept = cx.passes(&ft, b, window) && f64::from(ft.score.total) > old_total;
        local.restore(window, &saved);
        if kept { Refit::Alone(ft) } else { Refit::None }
    }
}

/// The rods `rods` refitted together ([`refit_together`]) once at the rows' angle `around`
/// and once at any, the trial that gains more kept; nothing without rows around.
fn at_either_angle(
    local: &mut Local,
    found: &[Found],
    rods: &[usize],
    cx: &Context,
    search: (&[(f64, f64)], f64, f64),
    around: Option<f64>,
) -> Option<Vec<fit::Fitted>> {
    around?;
    let mut best: Option<(Vec<fit::Fitted>, f64)> = None;
    for axis in around.map(Some).into_iter().chain([None]) {
        let Some((fits, gain)) = refit_together(local, found, rods, cx, search, axis, &[]) else {
            continue;
        };
        if best.as_ref().is_none_or(|(_, b)| gain > *b) {
            best = Some((fits, gain));
        }
    }
    best.map(|(fits, _)| fits)
}

/// Rods turned by less than this (degrees) from a doubtful rod, and within a length of it,
/// are refitted together with it; a rod turned by more is one of the rows around.
const PARALLEL_DEG: f64 = 15.0;

/// Whether rod pose `new` lies in the row of rod pose `old`: less than half a width across
/// its axis, and half a length along it.
fn in_its_row(old: Pose, new: Pose, cx: &Context) -> bool {
    let (along, across) = offsets(old.x, old.y, old.phi, new.x, new.y);
    across.abs() < 0.5 * cx.width && along.abs() < 0.5 * cx.length
}

/// Most rods of the rows around refitted with a doubtful rod turned otherwise than all of
/// them: its neighbours along and across the rows.
const MOST_ROWS: usize = 3;
