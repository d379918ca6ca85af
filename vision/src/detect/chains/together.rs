//! Rods taken off together and fitted afresh in what they leave, and the rods near a place
//! that such a trial takes off.

use super::{Context, Found, Local, Window, fit, unexplained_near};
use crate::detect::model::Pose;

/// The trial of [`repair_doubtful`](super::repair_doubtful) for a doubtful rod and the rods
/// turned like it near it (`rods`, the doubtful one first): all are taken off; a rod is
/// fitted afresh at each of their centres, at the angle `axis` or over every angle, and up to
/// two more at the middle of what they leave unexplained while that is at least a third of a
/// rod (each agreeing as clearly as [`repair_crowded`](super::repair_crowded) asks of an
/// added rod). Kept when at least as many rods pass the acceptance and they score more than
/// the old poses did on the maps without them: returned with what they score more (their
/// gain), the refits first. Either way the maps are left as they were
/// ([`replay`](super::replay) paints a kept trial's fits). `search` is the fits' offsets and
/// first step, and the half side of the window the trial may change around each rod.
///
/// At `spots`, rods are fitted before the others: with its neighbours taken off, a rod their
/// fits had eaten into is found whole, where fitted after them it is not. A needed spot
/// ([`repair_unexplained`](super::repair_unexplained)) fails the trial unless its rod agrees
/// as clearly as an added rod; another
/// ([`repair_across_highlights`](super::repair_across_highlights)) is passed over if it is
/// already explained or its rod does not agree so, and the trial fails if every spot is
/// passed over.
pub(super) fn refit_together(
    local: &mut Local,
    found: &[Found],
    rods: &[usize],
    cx: &Context,
    search: (&[(f64, f64)], f64, f64),
    axis: Option<f64>,
    spots: &[Spot],
) -> Option<(Vec<fit::Fitted>, f64)> {
    let (offsets, step, reach) = search;
    let free = &local.maps.free;
    let window = rods
        .iter()
        .map(|&k| {
            let p = found[k].pose;
            Window::around(p.x, p.y, reach, reach, free)
        })
        .reduce(Window::union)?;
    let saved = local.save(window);
    let old_total = local.take_off_set(found, rods, cx);
    let mut fitted = Vec::with_capacity(rods.len() + 2);
    let mut new_total = 0.0;
    for spot in spots {
        let (sx, sy) = (spot.at.0 as usize, spot.at.1 as usize);
        let explained = sx >= local.maps.free.width
            || sy >= local.maps.free.height
            || local.maps.free.at(sx, sy) <= 0.5;
        if explained && !spot.needed {
            continue;
        }
        let ft = match (spot.fixed, spot.axis.or(axis)) {
            (true, Some(phi)) => {
                let (x, y) = spot.at;
                let pose = Pose { x, y, phi };
                let score = cx
                    .model
                    .score(pose, cx.levels.fine, &local.maps.free_bordered);
                fit::Fitted { pose, score }
            }
            (_, axis) => fit::fit(
                &local.levels(cx),
                spot.at,
                spot.offsets.unwrap_or(offsets),
                step,
                axis,
            ),
        };
        let b = local.box_of(ft.pose, cx.model);
        if !(cx.passes(&ft, b, window) && ft.score.agreement >= ADDED_AGREEMENT) {
            if spot.needed {
                local.restore(window, &saved);
                return None;
            }
            continue;
        }
        new_total += f64::from(ft.score.total);
        local.place(ft.pose, b, cx);
        fitted.push(ft);
    }
    let at_spots = fitted.len();
    if at_spots == 0 && !spots.is_empty() {
        // Without a rod at a spot, the trial is a refit the caller did not ask for.
        local.restore(window, &saved);
        return None;
    }
    for &k in rods {
        let p = found[k].pose;
        let ft = fit::fit(&local.levels(cx), (p.x, p.y), offsets, step, axis);
        let b = local.box_of(ft.pose, cx.model);
        if cx.passes(&ft, b, window) {
            new_total += f64::from(ft.score.total);
            local.place(ft.pose, b, cx);
            fitted.push(ft);
        }
    }
    let n = rods.len() as f64;
    let (mx, my) = rods.iter().fold((0.0, 0.0), |(x, y), &k| {
        (x + found[k].pose.x / n, y + found[k].pose.y / n)
    });
    // Rods more where their place is left unexplained: n rods fitted across n + 1 leave one,
    // a seed that failed above another.
    for _ in 0..2 {
        let left = unexplained_near(&local.maps.free, mx, my, 2.0 * cx.length);
        if left.count < cx.length * cx.width / 3.0 {
            break;
        }
        let ft = fit::fit(&local.levels(cx), left.middle, offsets, step, axis);
        let b = local.box_of(ft.pose, cx.model);
        if !(cx.passes(&ft, b, window) && ft.score.agreement >= ADDED_AGREEMENT) {
            break;
        }
        new_total += f64::from(ft.score.total);
        local.place(ft.pose, b, cx);
        fitted.push(ft);
    }
    let kept = fitted.len() >= rods.len() && new_total > old_total;
    local.restore(window, &saved);
    // The rods at the spots are added ones: after the refits.
    fitted.rotate_left(at_spots);
    kept.then_some((fitted, new_total - old_total))
}

/// A rod fitted by [`refit_together`] before the refits: where, at what angle (else the
/// trial's), and from which offsets (else the trial's).
#[derive(Clone, Copy)]
pub(super) struct Spot<'a> {
    pub(super) at: (f64, f64),
    pub(super) axis: Option<f64>,
    pub(super) offsets: Option<&'a [(f64, f64)]>,
    /// Whether the trial fails without a rod here; else a spot already explained, or whose
    /// fit does not agree as an added rod must, is passed over.
    pub(super) needed: bool,
    /// Whether the rod is placed at `at` and its angle as it is, not fitted: where rods
    /// refined together as a row end to end put it.
    pub(super) fixed: bool,
}

/// The `most` rods not yet touched nearest to `at` within `within` (nearest first, ties in
/// the order found).
pub(super) fn nearest(
    found: &[Found],
    touched: &[bool],
    at: (f64, f64),
    within: f64,
    most: usize,
) -> Vec<usize> {
    nearest_where(found, touched, at, within, most, |_| true)
}

/// [`nearest`], of the rods that `keep` keeps.
fn nearest_where(
    found: &[Found],
    touched: &[bool],
    at: (f64, f64),
    within: f64,
    most: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let mut near: Vec<(f64, usize)> = (0..found.len())
        .filter(|&k| !touched[k] && keep(k))
        .map(|k| {
            let p = found[k].pose;
            ((p.x - at.0).hypot(p.y - at.1), k)
        })
        .filter(|&(d, _)| d < within)
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    near.into_iter().take(most).map(|(_, k)| k).collect()
}

/// Rod `g`, then the `most` other rods not yet touched nearest to it within `within` that
/// `keep` keeps: the rods a set trial about `g` takes off.
pub(super) fn with_nearest(
    found: &[Found],
    touched: &[bool],
    g: usize,
    within: f64,
    most: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let p = found[g].pose;
    let near = nearest_where(found, touched, (p.x, p.y), within, most, |k| {
        k != g && keep(k)
    });
    std::iter::once(g).chain(near).collect()
}

/// Least agreement of a rod a repair adds or fits in place of others (the crowded, outside
/// and turned repairs, and rods refitted together).
pub(super) const ADDED_AGREEMENT: f32 = 0.8;
