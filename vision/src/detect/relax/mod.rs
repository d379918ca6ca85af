//! Joint relaxation of every grain's pose: one objective for the whole frame, the image
//! misfit of all grains rendered together plus a cost for every pixel two outlines claim
//! (`objective`, `overlap`), lowered by moves that are each taken only when it falls. The
//! acceptance fits grains one at a time and knows nothing of their not overlapping; here a
//! grain turned in place, or slipped across its neighbour's seam, pays for it.
//!
//! Rounds of, in order:
//! 1. a sweep over the grains centred in the frame: nudges of each along x, y and the angle
//!    (`moves`); for those near a change of the round before (all of them at first), its
//!    jumps and, for rods, the quarter turn together with a neighbour;
//! 2. deaths: of those near a change, grains whose removal lowers the objective
//!    (`birth_death`);
//! 3. births: grains fitted into the patches of dark area no outline covers;
//!
//! until a round changes nothing or [`ROUNDS`] are done. One thread, in a fixed order: the
//! result does not depend on the thread count.

mod birth_death;
mod moves;
mod objective;
mod overlap;

use super::accept::Found;
use super::model::{Model, Pose};
use super::plane::{Bordered, Plane};
use crate::GrainShape;

use moves::Geometry;
use objective::Canvas;

/// A grain nudged farther than this (pixels) has its neighbours looked at again.
const MOVED_PX: f64 = 0.5;

/// Most rounds of sweep, deaths and births: a bound on the cost, each round nudging every
/// grain; the step starts finer each round (`Geometry::sweep_step`), so later rounds settle
/// the grains their neighbours' moves left off their best pose.
pub const ROUNDS: usize = 3;

/// The grains relaxed together on `dark` (full-resolution pixels), and the darkness they
/// leave unexplained; a grain is born only where it passes the acceptance's test
/// (`min_confidence`, `min_visible`).
pub fn relax(
    dark: &Plane,
    found: Vec<Found>,
    shape: GrainShape,
    scale: f64,
    min_confidence: f64,
    min_visible: f64,
) -> (Vec<Found>, Plane) {
    // Nothing accepted, nothing to relax: the darkness of a bare field, stretched by the
    // normalisation, has dark patches a grain born there would lower the misfit on.
    if found.is_empty() {
        return (found, dark.clone());
    }
    let model = Model::new(shape, scale);
    let geometry = Geometry {
        shape,
        length: shape.length() * scale,
        width: shape.width() * scale,
    };
    let mut poses: Vec<Pose> = found.iter().map(|f| f.pose).collect();
    let mut confidence: Vec<f64> = found.iter().map(|f| f.confidence).collect();
    let mut alive = vec![true; poses.len()];
    let mut canvas = Canvas::new(dark, &model, poses.iter().copied());
    let dark_bordered = Bordered::new(dark);
    let mut active: Vec<usize> = (0..poses.len()).collect();
    for round in 0..ROUNDS {
        let step = Geometry::sweep_step(round);
        let mut changed: Vec<Pose> = Vec::new();
        let mut is_active = vec![false; poses.len()];
        for &g in &active {
            is_active[g] = true;
        }
        // Every grain is nudged every round, its neighbours having moved; only those near a
        // change try their jumps again.
        for g in 0..poses.len() {
            // A grain centred outside the frame is not reported, and the frame shows too little
            // of it to move it by: held, its rendering still counting (moved, one fitted over
            // the edge of a bare photograph slid into its darkened corner).
            let p = poses[g];
            let inside =
                (0.0..dark.width as f64).contains(&p.x) && (0.0..dark.height as f64).contains(&p.y);
            if !alive[g] || !inside {
                continue;
            }
            let (mut q, e) = geometry.polish(&mut canvas, p, step);
            let mut far = e < 0.0 && (q.x - p.x).hypot(q.y - p.y) > MOVED_PX;
            if !is_active[g] {
                poses[g] = q;
                continue;
            }
            if let Some((jumped, _)) = geometry.best_jump(&mut canvas, q) {
                q = jumped;
                far = true;
            }
            poses[g] = q;
            if far {
                changed.extend([p, q]);
            }
            if let Some((h, turned, e)) = best_pair_turn(&mut canvas, &geometry, &poses, &alive, g)
                && e < 0.0
            {
                canvas.apply(&[poses[g], poses[h]], &turned);
                changed.extend([poses[g], poses[h]]);
                poses[g] = turned[0];
                poses[h] = turned[1];
            }
        }
        for g in birth_death::deaths(&mut canvas, &poses, &mut alive, &is_active) {
            changed.push(poses[g]);
        }
        let accepted = |q: Pose, free: &Bordered| {
            let s = model.score(q, &dark_bordered, free);
            (f64::from(s.agreement) >= min_confidence && f64::from(s.visible) >= min_visible)
                .then_some(f64::from(s.agreement))
        };
        for (q, agreement) in birth_death::births(&mut canvas, &geometry, accepted) {
            poses.push(q);
            confidence.push(agreement);
            alive.push(true);
            changed.push(q);
        }
        if changed.is_empty() {
            break;
        }
        let reach = 1.5 * geometry.length;
        active = (0..poses.len())
            .filter(|&g| {
                alive[g]
                    && changed
                        .iter()
                        .any(|c| (c.x - poses[g].x).hypot(c.y - poses[g].y) < reach)
            })
            .collect();
    }
    let free = canvas.free();
    let relaxed = (0..poses.len())
        .filter(|&g| alive[g])
        .map(|g| Found::at(poses[g], confidence[g], &model))
        .collect();
    (relaxed, free)
}

/// Of the rods near rod `g`, the one whose quarter turn together with it (`pair_turns`)
/// lowers the objective most: its index, the pair's poses turned and polished, and the change.
fn best_pair_turn(
    canvas: &mut Canvas,
    geometry: &Geometry,
    poses: &[Pose],
    alive: &[bool],
    g: usize,
) -> Option<(usize, [Pose; 2], f64)> {
    let a = poses[g];
    let near = geometry.length;
    let mut best: Option<(usize, [Pose; 2], f64)> = None;
    for (h, &b) in poses.iter().enumerate() {
        if h == g || !alive[h] || (b.x - a.x).hypot(b.y - a.y) > near {
            continue;
        }
        for [ta, tb] in geometry.pair_turns(a, b) {
            let raw = canvas.change(&[a, b], &[ta, tb]);
            if raw > 8.0 * geometry.jump_slack() {
                continue;
            }
            // The pair turned and polished in the canvas, then put back.
            canvas.apply(&[a, b], &[ta, tb]);
            let (ta2, ea) = geometry.polish(canvas, ta, 2.0);
            let (tb2, eb) = geometry.polish(canvas, tb, 2.0);
            let (ta3, ea2) = geometry.polish(canvas, ta2, 0.5);
            canvas.apply(&[ta3, tb2], &[a, b]);
            let e = raw + ea + eb + ea2;
            if best.as_ref().is_none_or(|x| e < x.2) {
                best = Some((h, [ta3, tb2], e));
            }
        }
    }
    best
}
