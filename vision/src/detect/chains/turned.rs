//! Rods fitted at a right angle across rods lying face to face: refitted as those rods.

use super::edge::across_edge;
use super::{
    ADDED_AGREEMENT, Context, Found, Guess, Local, Maps, Window, changed_by, fit, fit_reads,
    replay, speculate, usable,
};
use crate::detect::model::Pose;

/// Least part of a rod seen for it to count as whole in the photograph: 1 but for the
/// rounding of the sums.
const WHOLE: f64 = 0.99;

/// A rod fitted across the ends of n = L/D (rounded) rods lying face to face at right angles
/// to it leaves their remainder unexplained beside it. Such a rod, with at least a third of a
/// rod's area of unexplained dark area in the block the n rods would fill, is refitted as n
/// rods turned by a right angle, kept when they explain the photograph better and each agrees
/// with it as well as a rod any repair adds ([`ADDED_AGREEMENT`]). Lying across
/// the middle of one rod and the ends of two, it leaves that area in a block moved across
/// it: it is refitted as n - 1 rods, whole in the photograph, kept when they explain it
/// better by a tenth of a rod and leave no such block. Each trial changes the maps in a
/// window around the rod only, and is undone there when not kept.
/// The trials are worked out ahead in parallel on copies of the maps; the rods are then
/// looked at in order, each taking its trial's guess unless a repair kept before it changed
/// what the guess read: the outcome is the sequential one whatever the thread count.
pub fn repair_turned(
    found: &mut Vec<Found>,
    maps: &mut Maps,
    cx: &Context,
    offsets: &[(f64, f64)],
    step: f64,
) -> usize {
    let (length, width) = (cx.length, cx.width);
    let n = (length / width).round().max(2.0) as usize;
    let mut local = Local::new(maps, cx);
    let (half_u, half_v) = (0.5 * (n as f64 * width).max(length), 0.5 * length);
    // The rods turned to the rod may lie across it anywhere along their length.
    let shift = 0.5 * (length - width);
    let trial = Turned {
        n,
        half_u,
        half_v,
        shift,
        least: length * width / 3.0,
        reach: cx.trial_reach(),
        offsets,
        step,
        // The n seeds lie along the rod, at most (n - 1) / 2 widths from its centre; the
        // trial then counts what is left unexplained in the blocks.
        reads: (0.5 * (n as f64 - 1.0) * width + fit_reads(cx, offsets, step))
            .max(half_u.hypot(half_v + shift) + 1.0),
    };
    let rods: Vec<usize> = (0..found.len()).collect();
    let before: &[Found] = found;
    let guesses = speculate(&rods, &local, |local, &g| {
        let found = before;
        let pose = found[g].pose;
        let block = trial.block(local, pose);
        (block != Block::Explained).then(|| Guess {
            rod: g,
            pose,
            reads: trial.reads(local, pose),
            kept: trial.run(local, found, g, block, cx, true),
        })
    });
    let mut changed: Vec<Window> = Vec::new();
    let mut touched = vec![false; found.len()];
    let mut repaired = 0;
    for g in rods {
        if touched[g] {
            continue;
        }
        let p = found[g].pose;
        let block = trial.block(&local, p);
        if block == Block::Explained {
            continue;
        }
        let guess = guesses
            .as_ref()
            .and_then(|all| all[g].as_ref())
            .and_then(|guess| usable(std::slice::from_ref(guess), g, p, &changed));
        let fitted = match guess {
            Some(guess) => guess.kept.clone().inspect(|fits| {
                changed.push(replay(&mut local, found, &[g], fits, cx));
            }),
            None => trial
                .run(&mut local, found, g, block, cx, false)
                .inspect(|fits| {
                    changed.push(changed_by(&local, p, fits, cx));
                }),
        };
        let Some(fitted) = fitted else {
            continue;
        };
        for (k, ft) in fitted.iter().enumerate() {
            let r = cx.found(ft);
            if k == 0 {
                found[g] = r;
                touched[g] = true;
            } else {
                found.push(r);
                touched.push(true);
            }
        }
        repaired += 1;
    }
    repaired
}

/// What the unexplained dark area about a rod calls for.
#[derive(Clone, Copy, PartialEq)]
enum Block {
    /// Too little of it: no trial.
    Explained,
    /// In the block centred on the rod: n rods, or n - 1.
    Centred,
    /// Only in a block moved across the rod: n - 1 rods (n of them would lie centred).
    Aside,
}

/// The settings of [`repair_turned`]'s trials.
struct Turned<'a> {
    n: usize,
    /// Half sides of the block the n rods would fill, along and across the rod.
    half_u: f64,
    half_v: f64,
    /// Farthest the block's middle may lie across the rod, either side.
    shift: f64,
    /// Unexplained dark area (pixels) in the block that calls for a trial.
    least: f64,
    /// Half side of the window a trial may change.
    reach: f64,
    offsets: &'a [(f64, f64)],
    step: f64,
    /// How far from the rod's centre a trial's fits may read.
    reads: f64,
}

impl Turned<'_> {
    /// Whether a block beside the rod at `p` holds at least a third of a rod's area of
    /// unexplained dark area: the block centred on it, or only one moved across it by
    /// [`Turned::shift`].
    fn block(&self, local: &Local, p: Pose) -> Block {
        let crowded = |shift| self.unexplained(local, p, shift) >= self.least;
        if crowded(0.0) {
            Block::Centred
        } else if crowded(self.shift) || crowded(-self.shift) {
            Block::Aside
        } else {
            Block::Explained
        }
    }

    /// Unexplained dark pixels in the block beside the rod at `p`, its middle moved `shift`
    /// across the rod.
    fn unexplained(&self, local: &Local, p: Pose, shift: f64) -> f64 {
        let (s, c) = p.phi.sin_cos();
        let free = &local.maps.free;
        let mut unexplained = 0.0;
        let mut u = -self.half_u;
        while u <= self.half_u {
            let mut v = shift - self.half_v;
            while v <= shift + self.half_v {
                let (x, y) = (p.x + u * c + v * s, p.y - u * s + v * c);
                if x >= 0.0
                    && y >= 0.0
                    && x < free.width as f64
                    && y < free.height as f64
                    && free.at(x as usize, y as usize) > 0.5
                {
                    unexplained += 1.0;
                }
                v += 1.0;
            }
            u += 1.0;
        }
        unexplained
    }

    /// What a trial at the rod at `p` reads, of either level.
    fn reads(&self, local: &Local, p: Pose) -> Window {
        Window::around(p.x, p.y, self.reads, self.reads, &local.maps.free)
    }

    /// The trial at rod `g`, whose block is `block` ([`Turned::block`]): the fits when kept
    /// (the maps then changed, unless `undo`), otherwise nothing (the maps as they were).
    fn run(
        &self,
        local: &mut Local,
        found: &[Found],
        g: usize,
        block: Block,
        cx: &Context,
        undo: bool,
    ) -> Option<Vec<fit::Fitted>> {
        let p = found[g].pose;
        let (s, c) = p.phi.sin_cos();
        let window = Window::around(p.x, p.y, self.reach, self.reach, &local.maps.free);
        let saved = local.save(window);
        let old_total = local.take_off(found, g, cx);
        let mut new_total = 0.0;
        let mut failed = 0;
        let mut fitted = Vec::with_capacity(self.n);
        let turned = p.phi + std::f64::consts::FRAC_PI_2;
        for k in 0..self.n {
            let a = (k as f64 - 0.5 * (self.n as f64 - 1.0)) * cx.width;
            let seed = (p.x + a * c, p.y - a * s);
            let ft = fit::fit(
                &local.levels(cx),
                seed,
                self.offsets,
                self.step,
                Some(turned),
            );
            let b = local.box_of(ft.pose, cx.model);
            // Right rods refitted as two turned ones, the second agreeing at 0.52-0.54, were
            // the trials kept wrongly that were traced (lab rod53, seed 32 at 10 px/mm, seed
            // 48 at 6 px/mm); other repairs ask this of every rod they add.
            if !cx.passes(&ft, b, window) || ft.score.agreement < ADDED_AGREEMENT {
                failed += 1;
                if failed > 1 {
                    break;
                }
                continue;
            }
            new_total += f64::from(ft.score.total);
            local.place(ft.pose, b, cx);
            fitted.push(ft);
        }
        let gain = new_total - old_total;
        let kept = if fitted.len() == self.n {
            block == Block::Centred && gain > 0.0
        } else {
            // One rod fewer: the turned rod lay across the middle of one rod and the ends of
            // the two beside it, which are fitted already (lab rod53 at 6 px/mm, seed 1: a
            // rod fitted along the left edge over a column of rods lying across it). What
            // called for the trial must then be gone: where a rod of the n was dropped, its
            // place is left unexplained in a block. The rod must be whole in the photograph:
            // where the edge cuts it, a fit sliding out over the edge reads as one that
            // explains more (seed 2: a rod at 14 degrees cut by the right edge refitted at
            // 92). And not standing across the edge, which the edge repair would refit
            // along it: a rod along the edge with the stub of a cut rod beyond it reads the
            // same dark area turned (seed 3).
            fitted.len() + 1 == self.n
                && gain > cx.least_gain()
                && fitted.iter().all(|ft| {
                    f64::from(ft.score.visible) >= WHOLE
                        && !across_edge(ft.pose, &local.maps.free, cx)
                })
                && self.block(local, p) == Block::Explained
        };
        if !kept || undo {
            local.restore(window, &saved);
        }
        kept.then_some(fitted)
    }
}
