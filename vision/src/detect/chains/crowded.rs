//! Rods missed where a neighbour was fitted onto part of their place: fitted at the seed
//! that failed there, with the neighbour refined again.

use super::{
    ADDED_AGREEMENT, Context, Found, Guess, Local, Maps, Window, changed_by, fit, fit_reads,
    nearest, replay, speculate, unexplained_near, usable,
};
use crate::detect::model::Pose;

/// A rod fitted shifted across onto part of its neighbour's place leaves the neighbour's
/// remainder unexplained, too small for a rod of its own: its seed fails. At such a seed
/// with at least a third of a rod's area of unexplained dark area around it (in a square
/// of side L), each accepted rod within a length (nearest first) is taken off, a rod fitted
/// at the seed (all angles), and the rod taken off refined again (Newton from its pose); the
/// first pair that passes the acceptance's confidence and scores more than the rod alone is
/// kept. Each trial changes the maps in a window around the seed only. As in
/// [`repair_turned`](super::repair_turned), the trials are worked out ahead in parallel and
/// taken over in order where nothing they read has changed since.
pub fn repair_crowded(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    seeds: &[(f64, f64)],
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let mut local = Local::new(maps, cx);
    let trial = Crowded {
        reach: cx.trial_reach(),
        offsets,
        step,
        reads: fit_reads(cx, offsets, step),
    };
    let before: &[Found] = found;
    let untouched = vec![false; found.len()];
    let guesses = speculate(seeds, &local, |local, &seed| {
        let found = before;
        let mut guesses = Vec::new();
        if !trial.crowded(local, seed, cx) {
            return guesses;
        }
        for h in trial.near(found, &untouched, seed, cx) {
            let pose = found[h].pose;
            let kept = trial.run(local, found, seed, h, cx, true);
            let done = kept.is_some();
            guesses.push(Guess {
                rod: h,
                pose,
                reads: trial.reads(local, seed, pose),
                kept,
            });
            if done {
                break;
            }
        }
        guesses
    });
    let mut changed: Vec<Window> = Vec::new();
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for (i, &seed) in seeds.iter().enumerate() {
        if !trial.crowded(&local, seed, cx) {
            continue;
        }
        for h in trial.near(found, &touched, seed, cx) {
            let old = found[h].pose;
            let guess = guesses
                .as_ref()
                .and_then(|all| usable(&all[i], h, old, &changed));
            let fitted = match guess {
                Some(guess) => guess.kept.inspect(|fits| {
                    changed.push(replay(&mut local, found, &[h], fits, cx));
                }),
                None => trial
                    .run(&mut local, found, seed, h, cx, false)
                    .inspect(|fits| {
                        changed.push(changed_by(&local, old, fits, cx));
                    }),
            };
            let Some(fitted) = fitted else {
                continue;
            };
            let [added, moved] = fitted.map(|ft| cx.found(&ft));
            found[h] = moved;
            touched[h] = true;
            found.push(added);
            touched.push(true);
            repaired += 1;
            break;
        }
    }
    repaired
}

/// The settings of [`repair_crowded`]'s trials.
struct Crowded<'a> {
    /// Half side of the window a trial may change.
    reach: f64,
    offsets: &'a [(f64, f64)],
    step: f64,
    /// How far from the seed (and from the rod taken off) a trial's fits may read.
    reads: f64,
}

impl Crowded<'_> {
    fn crowded(&self, local: &Local, seed: (f64, f64), cx: &Context) -> bool {
        unexplained_near(&local.maps.free, seed.0, seed.1, cx.length).count
            >= cx.length * cx.width / 3.0
    }

    /// The rods tried at a seed: the three nearest within a length not yet touched.
    fn near(
        &self,
        found: &[Found],
        touched: &[bool],
        seed: (f64, f64),
        cx: &Context,
    ) -> Vec<usize> {
        nearest(found, touched, seed, cx.length, 3)
    }

    /// What a trial at `seed` taking off the rod at `old` reads: its fits at the seed and,
    /// afresh, at the rod's place, of either level.
    fn reads(&self, local: &Local, seed: (f64, f64), old: Pose) -> Window {
        let r = self.reads;
        let free = &local.maps.free;
        Window::around(seed.0, seed.1, r, r, free).union(Window::around(old.x, old.y, r, r, free))
    }

    /// The trial taking rod `h` off at `seed`: the fits (added, moved) when kept (the maps
    /// then changed, unless `undo`), otherwise nothing (the maps as they were).
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        seed: (f64, f64),
        h: usize,
        cx: &Context,
        undo: bool,
    ) -> Option<[fit::Fitted; 2]> {
        let window = Window::around(seed.0, seed.1, self.reach, self.reach, &local.maps.free);
        let saved = local.save(window);
        let old = found[h].pose;
        let old_total = local.take_off(found, h, cx);
        let mut fitted = Vec::with_capacity(2);
        let mut new_total = 0.0;
        // The rod at the seed, then the rod taken off: refined from its pose, or when
        // that fails (a rod fitted across two may need turning), fitted afresh there.
        for k in 0..3 {
            if k == 2 && fitted.len() != 1 {
                break;
            }
            let levels = local.levels(cx);
            let ft = match k {
                0 => fit::fit(&levels, seed, self.offsets, self.step, None),
                1 => fit::refine(&levels, old),
                _ => fit::fit(&levels, (old.x, old.y), self.offsets, self.step, None),
            };
            let b = local.box_of(ft.pose, cx.model);
            // The rod added where the acceptance found none must agree clearly: at the
            // acceptance's 0.5, rods added at the photograph's edge with agreements of
            // 0.69 and 0.79 were false (lab, rod3 at 10 px/mm: two false detections more).
            if !cx.passes(&ft, b, window) || (k == 0 && ft.score.agreement < ADDED_AGREEMENT) {
                if k == 0 {
                    break;
                }
                continue;
            }
            new_total += f64::from(ft.score.total);
            local.place(ft.pose, b, cx);
            fitted.push(ft);
        }
        let kept = !(fitted.len() < 2 || new_total <= old_total);
        if !kept || undo {
            local.restore(window, &saved);
        }
        kept.then(|| [fitted[0], fitted[1]])
    }
}
