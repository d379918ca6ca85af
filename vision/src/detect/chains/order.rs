//! Trials worked out ahead in parallel on copies of the maps and taken over in order, so that
//! a repair's outcome is the sequential one whatever the thread count.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use super::{Context, Found, Local, Window, fit};
use crate::detect::model::Pose;

/// How far (pixels, along x or y) from a fit's seed the taps of any pose it scores may read,
/// on either level: the farthest offset tried, the fit's drift, the model's reach, and the
/// bilinear neighbours (a coarse pixel stands for `factor` full-resolution ones).
pub(super) fn fit_reads(cx: &Context, offsets: &[(f64, f64)], step: f64) -> f64 {
    let f = cx.levels.factor;
    let farthest = offsets.iter().map(|o| o.0.hypot(o.1)).fold(0.0, f64::max);
    let taps = (f64::from(cx.levels.fine_model.reach()) + 1.5)
        .max(f64::from(cx.levels.coarse_model.reach()) * f + 1.5 * f);
    farthest + fit::fit_drift(step, f) + taps + 2.0
}

/// A trial's outcome worked out ahead on a copy of the maps, and the pixels it read (of
/// either level, in full-resolution pixels): the sequential pass takes it over when no
/// repair kept before it changed any of them.
pub(super) struct Guess<T> {
    /// The rod the trial took off, and its pose then.
    pub(super) rod: usize,
    pub(super) pose: Pose,
    pub(super) reads: Window,
    pub(super) kept: Option<T>,
}

/// Most copies of the maps worked on at once: each is about 12 bytes a pixel (40 MB for a
/// 258 x 120 mm frame at 10 px/mm, 200 MB for a tile of `TILE_PIXELS`).
const MOST_COPIES: usize = 4;

/// Worked out on copies of the maps as they are before the pass (one per worker, at most
/// [`MOST_COPIES`]), in parallel, `trial` for each item, in the items' order; nothing when
/// one thread works, since the sequential pass would then only redo what is guessed.
pub(super) fn speculate<I: Sync, R: Send>(
    items: &[I],
    local: &Local,
    trial: impl Fn(&mut Local, &I) -> R + Sync,
) -> Option<Vec<R>> {
    let workers = rayon::current_num_threads()
        .min(MOST_COPIES)
        .min(items.len());
    if workers < 2 {
        return None;
    }
    // Each worker takes the next item not yet taken, so uneven trials share out evenly.
    let next = AtomicUsize::new(0);
    let results: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let factor = local.factor;
    (0..workers).into_par_iter().for_each(|_| {
        let mut maps = local.maps.clone();
        let mut copy = Local {
            maps: &mut maps,
            coarse: local.coarse.clone(),
            factor,
        };
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(k) else {
                break;
            };
            let result = trial(&mut copy, item);
            *results[k].lock().unwrap_or_else(|e| e.into_inner()) = Some(result);
        }
    });
    Some(
        results
            .into_iter()
            .map(|r| {
                r.into_inner()
                    .unwrap_or_else(|e| e.into_inner())
                    .expect("every item is worked out")
            })
            .collect(),
    )
}

/// The guess for rod `rod` at `pose`, if there is one and no window in `changed` meets
/// what it read.
pub(super) fn usable<'g, T>(
    guesses: &'g [Guess<T>],
    rod: usize,
    pose: Pose,
    changed: &[Window],
) -> Option<&'g Guess<T>> {
    guesses
        .iter()
        .find(|g| g.rod == rod && g.pose == pose)
        .filter(|g| !changed.iter().any(|c| c.meets(g.reads)))
}

/// What a kept trial did to the maps, done again: the rods `rods` taken off (together: none
/// is painted back under another), `fits` painted. Returns the pixels it changed (of either
/// level).
pub(super) fn replay(
    local: &mut Local,
    found: &[Found],
    rods: &[usize],
    fits: &[fit::Fitted],
    cx: &Context,
) -> Window {
    let mut changed = rods
        .iter()
        .map(|&k| local.box_of(found[k].pose, cx.model))
        .reduce(Window::union)
        .expect("a kept trial takes a rod off");
    for &k in rods {
        local.unpaint(found, k, rods, cx);
    }
    for ft in fits {
        let b = local.box_of(ft.pose, cx.model);
        local.place(ft.pose, b, cx);
        changed = changed.union(b);
    }
    changed.grown(cx.levels.factor as isize + 1)
}

/// A kept trial taken over: the rods `rods` taken off and `fits` painted ([`replay`]), the
/// fits written over those rods in order and the rest added, all of them touched. Returns
/// the pixels it changed.
fn take_over(
    local: &mut Local,
    found: &mut Vec<Found>,
    touched: &mut Vec<bool>,
    rods: &[usize],
    fits: &[fit::Fitted],
    cx: &Context,
) -> Window {
    let changed = replay(local, found, rods, fits, cx);
    for (k, ft) in fits.iter().enumerate() {
        match rods.get(k) {
            Some(&h) => {
                found[h] = cx.found(ft);
                touched[h] = true;
            }
            None => {
                found.push(cx.found(ft));
                touched.push(true);
            }
        }
    }
    changed
}

/// The trials of a repair that, about each item (a rod or a spot), takes a set of rods off
/// and fits them afresh: worked out ahead and taken over in order by [`in_order`].
pub(super) trait SetTrials: Sync {
    type Item: Sync;
    /// What picks a trial's rods besides the maps: the rods (see [`SetTrials::rods`]) and
    /// whatever else the trial depends on.
    type Near: PartialEq + Send;
    /// What a trial kept, of which [`Parts::parts`] tells the rods and the fits.
    type Kept: Clone + Send + Parts<Self::Near>;
    /// Whether `item` is passed over, the rods `touched` being repaired already.
    fn passed_over(&self, item: &Self::Item, touched: &[bool]) -> bool;
    /// What picks the trial about `item`, the rods `touched` left out.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        item: &Self::Item,
        cx: &Context,
    ) -> Self::Near;
    /// The rods a trial takes off, of those that `near` picks.
    fn rods<'n>(&self, near: &'n Self::Near) -> &'n [usize];
    /// What the trial reads, of either level.
    fn reads(
        &self,
        local: &Local,
        found: &[Found],
        near: &Self::Near,
        item: &Self::Item,
        cx: &Context,
    ) -> Window;
    /// The trial, leaving the maps as they were.
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        near: &Self::Near,
        item: &Self::Item,
        cx: &Context,
    ) -> Self::Kept;
}

/// What a [`SetTrials`] trial kept, read as the rods it took off and the fits it painted;
/// none of either when it kept nothing. `near` is what picked the trial's rods.
pub(super) trait Parts<N> {
    fn parts<'k>(&'k self, near: &'k N) -> (&'k [usize], &'k [fit::Fitted]);
}

/// The rods taken off and the fits of a trial that keeps them as they are.
impl<N> Parts<N> for Option<(Vec<usize>, Vec<fit::Fitted>)> {
    fn parts<'k>(&'k self, _: &'k N) -> (&'k [usize], &'k [fit::Fitted]) {
        self.as_ref()
            .map_or((&[], &[]), |(set, fits)| (set.as_slice(), fits.as_slice()))
    }
}

/// A [`SetTrials`] trial worked out ahead: what picked its rods and their poses then, what
/// it read, and what it kept.
struct SetGuess<N, K> {
    near: N,
    poses: Vec<Pose>,
    reads: Window,
    kept: K,
}

/// `trial` about each of `items` in order, each kept one taken over ([`take_over`]). The
/// trials are worked out ahead in parallel on copies of the maps ([`speculate`]); a guess
/// holds when the same rods are picked the same way, at the same poses, and no trial kept
/// since changed what it read; else the trial is done again. The outcome is the sequential
/// one whatever the thread count. Returns the number of trials kept.
pub(super) fn in_order<T: SetTrials>(
    trial: &T,
    items: &[T::Item],
    found: &mut Vec<Found>,
    local: &mut Local,
    cx: &Context,
) -> usize {
    let before: &[Found] = found;
    let untouched = vec![false; found.len()];
    let guesses = speculate(items, local, |local, item| {
        let near = trial.near(before, &untouched, item, cx);
        SetGuess {
            poses: trial.rods(&near).iter().map(|&k| before[k].pose).collect(),
            reads: trial.reads(local, before, &near, item, cx),
            kept: trial.run(local, before, &near, item, cx),
            near,
        }
    });
    let mut changed: Vec<Window> = Vec::new();
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for (i, item) in items.iter().enumerate() {
        if trial.passed_over(item, &touched) {
            continue;
        }
        let near = trial.near(found, &touched, item, cx);
        let guess = guesses.as_ref().map(|all| &all[i]).filter(|guess| {
            guess.near == near
                && trial
                    .rods(&near)
                    .iter()
                    .zip(&guess.poses)
                    .all(|(&k, &p)| found[k].pose == p)
                && !changed.iter().any(|c| c.meets(guess.reads))
        });
        let kept = match guess {
            Some(guess) => guess.kept.clone(),
            None => trial.run(local, found, &near, item, cx),
        };
        let (off, fits) = kept.parts(&near);
        if fits.is_empty() {
            continue;
        }
        changed.push(take_over(local, found, &mut touched, off, fits, cx));
        repaired += 1;
    }
    repaired
}

/// Pixels changed by a kept trial (of either level): the box of the rod taken off and those
/// of the fits painted.
pub(super) fn changed_by(local: &Local, old: Pose, fits: &[fit::Fitted], cx: &Context) -> Window {
    fits.iter()
        .fold(local.box_of(old, cx.model), |w, ft| {
            w.union(local.box_of(ft.pose, cx.model))
        })
        .grown(cx.levels.factor as isize + 1)
}
