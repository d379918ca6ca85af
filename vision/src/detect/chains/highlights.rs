//! Short rods lying face to face fitted by one rod turned across them. Two rod53 rods side by
//! side make a block of 2D x L, nearly square, that a rod turned by a right angle (or by
//! less) fits almost as well; the rod left over is then fitted shifted onto what remains, or
//! missed, and every repair before this one sees little unexplained area. The highlights do
//! not agree: the rods' own run across the turned rod, inside it.

use super::{
    Context, Found, Local, Maps, Spot, Window, fit, fit_reads, nearest, refit_together, speculate,
    take_over, turn,
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

/// A rod's trial worked out ahead: the rods near it (it first) and their poses then, what it
/// read, and what it kept (the rods taken off and the fits painted).
struct AcrossGuess {
    near: Vec<usize>,
    poses: Vec<Pose>,
    reads: Window,
    kept: Option<(Vec<usize>, Vec<fit::Fitted>)>,
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
            })
            .collect()
    }

    /// The rods a trial about rod `g` takes off: it, then the nearest [`NEAR_ROD`] within a
    /// length not yet touched.
    fn near(&self, found: &[Found], touched: &[bool], g: usize, cx: &Context) -> Vec<usize> {
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
    fn reads(&self, local: &Local, found: &[Found], near: &[usize], cx: &Context) -> Window {
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
        near: &[usize],
        seeds: &[AxisSeed],
        cx: &Context,
    ) -> Option<(Vec<usize>, Vec<fit::Fitted>)> {
        let g = near[0];
        let spots = self.turned_inside(found[g].pose, seeds, cx);
        if spots.is_empty() {
            return None;
        }
        let search = (self.offsets, self.step, self.reach);
        let sets = std::iter::once(vec![g]).chain(near[1..].iter().map(|&k| vec![g, k]));
        for set in sets {
            if let Some((fits, _)) = refit_together(local, found, &set, cx, search, None, &spots) {
                return Some((set, fits));
            }
        }
        None
    }
}

/// Rods fitted across short rods lying face to face, found by the highlights inside them
/// turned from them ([`AxisSeed`]s): each such rod is taken off, alone or with a rod near it,
/// rods are fitted at the highlights first, then the rods taken off afresh, with rods added
/// where their place is left unexplained; kept when it keeps as many rods and scores more.
/// As in [`repair_doubtful`](super::repair_doubtful), the trials are worked out ahead in
/// parallel and taken over in order where the rods near, their poses and what the trials
/// read are unchanged since, so the outcome is the sequential one whatever the thread count.
/// Returns the number of rods repaired.
pub fn repair_across_highlights(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
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
    let before: &[Found] = found;
    let rods: Vec<usize> = (0..found.len())
        .filter(|&g| !trial.turned_inside(before[g].pose, seeds, cx).is_empty())
        .collect();
    let untouched = vec![false; found.len()];
    let guesses = speculate(&rods, &local, |local, &g| {
        let near = trial.near(before, &untouched, g, cx);
        AcrossGuess {
            poses: near.iter().map(|&k| before[k].pose).collect(),
            reads: trial.reads(local, before, &near, cx),
            kept: trial.run(local, before, &near, seeds, cx),
            near,
        }
    });
    let mut changed: Vec<Window> = Vec::new();
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for (i, &g) in rods.iter().enumerate() {
        if touched[g] {
            continue;
        }
        let near = trial.near(found, &touched, g, cx);
        let guess = guesses.as_ref().map(|all| &all[i]).filter(|guess| {
            guess.near == near
                && near
                    .iter()
                    .zip(&guess.poses)
                    .all(|(&k, &p)| found[k].pose == p)
                && !changed.iter().any(|c| c.meets(guess.reads))
        });
        let kept = match guess {
            Some(guess) => guess.kept.clone(),
            None => trial.run(&mut local, found, &near, seeds, cx),
        };
        let Some((set, fits)) = kept else {
            continue;
        };
        changed.push(take_over(&mut local, found, &mut touched, &set, &fits, cx));
        repaired += 1;
    }
    repaired
}
