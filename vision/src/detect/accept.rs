//! Greedy acceptance with explained-pixel bookkeeping: the best fits are accepted first and
//! paint their outline into an "explained" map; a later fit that would cover explained pixels
//! loses agreement and is refined again in its place, refused, or refitted in the next round.
//! Each round seeds new fits in the dark area no accepted grain explains yet.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::DetectParams;
use super::chains;
use super::fit::{self, Levels};
use super::model::{Model, Pose};
use super::nearby::Nearby;
use super::phases::Laps;
use super::plane::{Bordered, Plane};
use super::ridges;
use super::seeds::{self, BrightBlob};
use super::settle::{self, Settling};
use crate::GrainShape;

/// An accepted grain (full-resolution pixels).
pub struct Found {
    pub pose: Pose,
    pub corners: [(f64, f64); 4],
    pub confidence: f64,
}

impl Found {
    /// The grain at `pose`, its outline's corners from `model`.
    pub fn at(pose: Pose, confidence: f64, model: &Model) -> Found {
        Found {
            pose,
            corners: model.corners(pose),
            confidence,
        }
    }
}

/// The maps the acceptance keeps: explained opacity and the darkness it leaves free.
#[derive(Clone)]
pub struct Maps {
    pub explained: Plane,
    pub free: Plane,
    pub free_bordered: Bordered,
}

/// A seed to fit: position, offsets to try, first refinement step, known axis angle.
type Task<'a> = ((f64, f64), &'a [(f64, f64)], f64, Option<f64>);

/// Coarse level resolution the pose search runs at (pixels per millimetre).
const COARSE_PX_PER_MM: f64 = 3.0;

/// Times a fit put off for a neighbour accepted before it is refined again in the same round
/// before it waits for the next round's fit.
const REFINED_AGAIN: u8 = 2;

/// A fit of seed `k` waiting to be taken: the best first, ties by position (top to bottom,
/// left to right) then by seed, so the order is the same whatever the thread count.
#[derive(Clone, Copy)]
struct Candidate {
    k: usize,
    fitted: fit::Fitted,
    refined_again: u8,
}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (&self.fitted, &other.fitted);
        a.score
            .total
            .total_cmp(&b.score.total)
            .then(b.pose.y.total_cmp(&a.pose.y))
            .then(b.pose.x.total_cmp(&a.pose.x))
            .then(other.k.cmp(&self.k))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Candidate {}

/// The grains found, and the darkness they leave unexplained (`free`).
pub fn find_grains(
    dark: &Plane,
    blobs: &[BrightBlob],
    params: &DetectParams,
    laps: &mut Laps,
) -> (Vec<Found>, Plane) {
    let px_per_mm = params.scale * 1e-3;
    let factor = (px_per_mm / COARSE_PX_PER_MM).floor().max(1.0) as usize;
    let f = factor as f64;
    let coarse = dark.downsample(factor);
    let fine_model = Model::new(params.shape, params.scale);
    let coarse_model = Model::with_softness(params.shape, params.scale / f, 2.0);
    let length = params.shape.length() * params.scale;
    let width = params.shape.width() * params.scale;

    // Offsets (grain frame, full-res pixels) around seeds, and the refinement's first step.
    let (residual_offsets, min_depth, spacing): (Vec<(f64, f64)>, f64, f64) = match params.shape {
        GrainShape::Rod { .. } => {
            // A seed on a rod's axis may sit anywhere along it, a little off it across.
            let half = 0.5 * length;
            let along =
                [-1.0, -2.0 / 3.0, -1.0 / 3.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0].map(|k| k * half);
            let across = [-0.5, -0.25, 0.0, 0.25, 0.5].map(|k| k * width);
            let offs = along
                .iter()
                .flat_map(|&a| across.iter().map(move |&b| (a, b)))
                .collect();
            (offs, 0.3 * width, 0.8 * width)
        }
        GrainShape::Square {
            side,
            hole_diameter,
        } => {
            // A seed in the ring between hole and edge may be far from the centre.
            let steps = [-0.3, -0.15, 0.0, 0.15, 0.3].map(|k| k * width);
            let offs = steps
                .iter()
                .flat_map(|&a| steps.iter().map(move |&b| (a, b)))
                .collect();
            let ring = 0.5 * (side - hole_diameter) * params.scale;
            (offs, 0.25 * ring, 0.5 * width)
        }
    };
    // Nuts: the coarse level resolves a square's corners and hole, and a finalist that climbs
    // there to more than 2 % below the best seldom wins refined (bench, every style: the same
    // recall and precision, orientation RMS within 0.02 degrees). Rods: the coarse level
    // barely sees the highlight, and the same margin lost rods (lab rod3 at 10 px/mm
    // 99.49 -> 99.32 %, rod53 at 6 px/mm 4.7 -> 6.0 degrees): every finalist is refined.
    let finalist_margin = match params.shape {
        GrainShape::Square { .. } => 0.02,
        GrainShape::Rod { .. } => f64::INFINITY,
    };
    let hole_seeds = match params.shape {
        GrainShape::Square { hole_diameter, .. } => {
            seeds::hole_seeds(blobs, 0.5 * hole_diameter * params.scale)
        }
        GrainShape::Rod { .. } => Vec::new(),
    };
    let centre_only = [(0.0, 0.0)];
    // A point on a rod's highlight lies on its axis, anywhere along the straight part.
    // A thin gap between two rods may pass for a highlight: their axes lie half a width off.
    let along_axis: Vec<(f64, f64)> = (-3..=3)
        .flat_map(|k| {
            [-0.5, 0.0, 0.5].map(|b| (k as f64 / 6.0 * (length - width).max(0.0), b * width))
        })
        .collect();
    let axis_seeds = match params.shape {
        GrainShape::Rod { .. } => ridges::axis_seeds(dark, 0.1 * width, length, width),
        GrainShape::Square { .. } => Vec::new(),
    };

    // The typical highlight's darkness: the axis of a fit counts no lighter than this.
    let highlight_floor = {
        let mut depths: Vec<f32> = axis_seeds.iter().map(|a| a.depth).collect();
        if depths.is_empty() {
            0.0
        } else {
            let mid = depths.len() / 2;
            *depths.select_nth_unstable_by(mid, |a, b| a.total_cmp(b)).1
        }
    };
    laps.lap("axis seeds");
    let fine_model = fine_model.with_highlight_floor(highlight_floor);
    let coarse_model = coarse_model.with_highlight_floor(highlight_floor);
    let residual_step = (0.15 * width).max(f);
    let mut explained = Plane::new(dark.width, dark.height, 0.0);
    let mut free = dark.clone();
    let mut found: Vec<Found> = Vec::new();
    // Seeds to fit this round: position, offsets to try, first refinement step.
    let mut pending: Vec<Task> = hole_seeds
        .iter()
        .map(|&s| (s, &centre_only[..], 1.0, None))
        .chain(
            axis_seeds
                .iter()
                .map(|a| ((a.x, a.y), &along_axis[..], residual_step, Some(a.phi))),
        )
        .collect();
    // Seeds whose fit failed, retried only when a grain is accepted next to them.
    let mut failed: Vec<(f64, f64)> = Vec::new();
    // Two outlines closer than this may overlap: a fit made before its neighbour was
    // accepted is redone.
    let reach = length.hypot(width) + 2.0;
    // Nothing is explained yet: the coarse map of none, as downsampling would give it.
    let mut coarse_explained = Plane::new(coarse.width, coarse.height, 0.0);
    // What the tap sums read: the planes with a border repeating their edge.
    let dark_bordered = Bordered::new(dark);
    let coarse_bordered = Bordered::new(&coarse);
    let mut free_bordered = dark_bordered.clone();
    let mut coarse_free = coarse_bordered.clone();
    // Farther apart than this, a grain's paint (coverage within its ring) and another pose's
    // taps (with their bilinear neighbours) share no pixel.
    let unchanged_beyond = 2.0 * f64::from(fine_model.reach()) + 6.0;
    // The accepted grains' centres, for the duplicate test.
    let mut found_near = Nearby::new(reach);
    // What every fit reads: the darkness at both levels and the models; its free maps are
    // the unpainted darkness, each use putting in the free maps of the moment (the coarse
    // one each round refreshes).
    let reads = Levels {
        fine: &dark_bordered,
        fine_free: &dark_bordered,
        coarse: &coarse_bordered,
        coarse_free: &coarse_bordered,
        fine_model: &fine_model,
        coarse_model: &coarse_model,
        factor: f,
        period: params.shape.symmetry_period(),
        finalist_margin,
        finalists: params.finalists,
    };
    // The poses last fitted to the hole seeds put off to this round.
    let mut put_off: Vec<Pose> = Vec::new();
    for round in 0..params.max_rounds.max(1) {
        let avoid_points = pending
            .iter()
            .map(|t| t.0)
            .chain(failed.iter().copied())
            .chain(found.iter().map(|g| (g.pose.x, g.pose.y)));
        let mut avoid = Nearby::with_points(spacing, avoid_points);
        // Holes pin nuts exactly: fit those first, so that the residual seeds of later rounds
        // only go where a nut's hole was not seen.
        let residual = if round == 0 && !pending.is_empty() {
            Vec::new()
        } else {
            seeds::residual_seeds(&coarse, &coarse_explained, min_depth / f, spacing / f, f)
        };
        // A nut put off last round comes back with its hole, which pins its centre: the dark
        // area its outline held is that nut's, and a residual seed there would only find it
        // again (lab nuts at 10 px/mm, disordered: 245 of 372 such fits were duplicates). A
        // rod's seed pins neither its centre nor its angle, so a rod put off claims nothing.
        let claimed = |s: (f64, f64)| put_off.iter().any(|&p| fine_model.covers(p, s));
        for s in residual {
            if !avoid.any_within(s, 0.5 * spacing) && !claimed(s) {
                pending.push((s, &residual_offsets[..], residual_step, None));
                avoid.insert(s);
            }
        }
        if pending.is_empty() {
            break;
        }
        laps.lap("residual seeds");
        // What the round's fits read but the free darkness, which each grain accepted paints.
        let unpainted = Levels {
            coarse_free: &coarse_free,
            ..reads
        };
        let levels = Levels {
            fine_free: &free_bordered,
            ..unpainted
        };
        let mut fits: BinaryHeap<Candidate> = pending
            .par_iter()
            .enumerate()
            .map(|(k, &(seed, offsets, step, axis))| Candidate {
                k,
                fitted: fit::fit(&levels, seed, offsets, step, axis),
                refined_again: 0,
            })
            .collect::<Vec<_>>()
            .into();
        laps.lap("fits");
        let mut this_round = Nearby::new(reach);
        let mut accepted_this_round = 0;
        let mut deferred = Vec::new();
        let mut deferred_poses = Vec::new();
        // The fits put off this round for a neighbour accepted before them: each holds its
        // place until it is fitted again.
        let mut held: Vec<Pose> = Vec::new();
        let mut held_near = Nearby::new(reach);
        while let Some(Candidate {
            k,
            fitted: ft,
            refined_again,
        }) = fits.pop()
        {
            let seed = pending[k];
            if (ft.score.agreement as f64) < params.min_confidence
                || (ft.score.visible as f64) < params.min_visible
            {
                failed.push(seed.0);
                continue;
            }
            let centre = (ft.pose.x, ft.pose.y);
            if found_near.any_within(centre, 0.5 * width) {
                continue;
            }
            // A fit put off holds its place: a fit scoring less in the same place waits for
            // it. Else the fit put off (its neighbour's paint took a few per cent of its
            // score) loses its place to a worse one that does not touch that neighbour:
            // lab rod53 at 10 px/mm, seed 22, ordered, a rod lying 3.7 mm above the bottom
            // edge (1 300) was put off and one standing across it and the cut rod below
            // (1 196) accepted in its place.
            let holds = |h: &Pose| {
                (h.x - centre.0).hypot(h.y - centre.1) < reach && fine_model.same_place(*h, ft.pose)
            };
            if held_near.any_within(centre, reach) && held.iter().any(holds) {
                deferred.push(seed);
                if std::ptr::eq(seed.1, &centre_only[..]) {
                    deferred_poses.push(ft.pose);
                }
                continue;
            }
            // The fit was scored on the maps as the round began; unless a grain accepted
            // since painted where its taps read, it scores the same now, to the bit.
            let now = if this_round.any_within(centre, unchanged_beyond) {
                fine_model.score(ft.pose, &dark_bordered, &free_bordered)
            } else {
                ft.score
            };
            // Fitted without knowing a neighbour accepted this round: if that neighbour
            // takes part of this outline, fit again next round against the updated map.
            if (this_round.any_within(centre, reach) || this_round.any_within(seed.0, reach))
                && now.total < ft.score.total - 0.02 * ft.score.total.abs()
            {
                // Refined again from where it was, on the maps as they are now: when that wins
                // back what the neighbour took, the neighbour only nudged it, and it goes back
                // among the fits still to be taken, at what it scores now.
                if refined_again < REFINED_AGAIN {
                    let levels = Levels {
                        fine_free: &free_bordered,
                        ..unpainted
                    };
                    let again = fit::refine(&levels, ft.pose);
                    if again.score.total >= ft.score.total - 0.02 * ft.score.total.abs() {
                        fits.push(Candidate {
                            k,
                            fitted: again,
                            refined_again: refined_again + 1,
                        });
                        continue;
                    }
                }
                deferred.push(seed);
                if std::ptr::eq(seed.1, &centre_only[..]) {
                    deferred_poses.push(ft.pose);
                }
                held.push(ft.pose);
                held_near.insert(centre);
                continue;
            }
            if (now.agreement as f64) < params.min_confidence {
                failed.push(seed.0);
                continue;
            }
            fine_model.paint(ft.pose, dark, &mut explained, &mut free, &mut free_bordered);
            this_round.insert(centre);
            found_near.insert(centre);
            accepted_this_round += 1;
            found.push(Found::at(ft.pose, now.agreement as f64, &fine_model));
        }
        laps.lap("acceptance");
        if accepted_this_round == 0 {
            break;
        }
        // Failed seeds next to a new grain may now fit: the grain explains what misled them.
        failed.retain(|s| !this_round.any_within(*s, reach));
        pending = deferred;
        put_off = deferred_poses;
        let new = found[found.len() - accepted_this_round..]
            .iter()
            .map(|g| g.pose);
        refresh_coarse(
            &mut coarse_explained,
            &mut coarse_free,
            (&explained, &free),
            new,
            &fine_model,
            factor,
        );
        laps.lap("acceptance");
    }
    let mut maps = Maps {
        explained,
        free,
        free_bordered,
    };
    // What the repairs and the settling read: each refit reads the free darkness of the
    // moment instead of `fine_free`.
    let after = Levels {
        coarse_free: &coarse_free,
        ..reads
    };
    if let GrainShape::Rod { .. } = params.shape {
        let cx = chains::Context {
            dark,
            levels: after,
            model: &fine_model,
            min_confidence: params.min_confidence,
            min_visible: params.min_visible,
            length,
            width,
        };
        let first: Vec<Pose> = found.iter().map(|f| f.pose).collect();
        let all = 0..found.len();
        chains::repair(&mut found, &mut maps, &cx, all);
        // A row repaired may leave its neighbour row's stub at a rod it moved, or move a rod
        // of a row whose repair it blocked (each rod is repaired once a pass): rows near the
        // rods it moved are looked at once more.
        let again = near_moved(&found, &first, 2.0 * length);
        chains::repair(&mut found, &mut maps, &cx, again.into_iter());
        laps.lap("repair: rows");
        // The rows' repair takes 1 % of the time and holds a third of what the repairs
        // gain in recall (lab rod53 at 10 px/mm, seeds 1-4: 99.43 % without any repair,
        // 99.78 % with the rows' alone, 99.92 % with all): it stays when the rest are left out.
        if params.repairs {
            // After the rows, which a rod fitted centred outside the frame can hide from their
            // repair, and before the rest, which look for what it leaves: lab rod53 at 6 px/mm
            // 2.95 -> 2.51 degrees on seed 1 and 2.33 -> 1.74 on seed 2, rod3 at 10 px/mm
            // 99.49 -> 99.55 % recall on seed 1 (seed 3 unchanged).
            chains::repair_outside(&mut found, &mut maps, &cx, &residual_offsets, residual_step);
            laps.lap("repair: outside");
            let rows: Vec<Pose> = found.iter().map(|f| f.pose).collect();
            // The seeds that failed to the end mark the dark area no rod could explain. Before
            // the turned-rod repair, whose cases it mostly covers too: lab rod53 at 10 px/mm
            // 2.48 degrees instead of 2.99 after it.
            chains::repair_crowded(
                &mut found,
                &mut maps,
                &cx,
                &failed,
                &residual_offsets,
                residual_step,
            );
            laps.lap("repair: crowded");
            chains::repair_turned(&mut found, &mut maps, &cx, &along_axis, residual_step);
            laps.lap("repair: turned");
            chains::repair_doubtful(&mut found, &mut maps, &cx, &residual_offsets, residual_step);
            laps.lap("repair: doubtful");
            let across = |found: &mut Vec<Found>, maps: &mut Maps, tried: Vec<usize>| {
                chains::repair_across_highlights(
                    found,
                    maps,
                    &cx,
                    tried.into_iter(),
                    &axis_seeds,
                    &residual_offsets,
                    &along_axis,
                    residual_step,
                )
            };
            let every = (0..found.len()).collect();
            across(&mut found, &mut maps, every);
            laps.lap("repair: across highlights");
            // Last: what every other repair left unexplained marks the rods still missed (lab
            // rod53 at 10 px/mm: 8 misses -> 3, 4 rods turned -> 2).
            let before: Vec<Pose> = found.iter().map(|f| f.pose).collect();
            chains::repair_unexplained(
                &mut found,
                &mut maps,
                &cx,
                &residual_offsets,
                residual_step,
            );
            laps.lap("repair: unexplained");
            // A rod added at an unexplained spot may be turned across rods face to face as the
            // first fits were: those it added or refitted are looked at again.
            let changed = moved_since(&found, &before).collect();
            across(&mut found, &mut maps, changed);
            laps.lap("repair: across highlights");
            // After the across-highlights repair, which can turn a rod fitted onto the stubs
            // the edge leaves: lab rod53 at 6 px/mm 2.51 -> 2.03 degrees on seed 1 and
            // 2.96 -> 2.08 on seed 3 (run before the crowded repair instead, seed 1 2.51 -> 2.92).
            chains::repair_along_edge(&mut found, &mut maps, &cx, &residual_offsets, residual_step);
            laps.lap("repair: along edge");
            // A rod moved by a later repair may uncover the stub of a row shifted along itself
            // that the row repairs before could not see: rows near a moved rod are looked at again.
            let again = near_moved(&found, &rows, 2.0 * length);
            chains::repair(&mut found, &mut maps, &cx, again.into_iter());
            laps.lap("repair: rows");
        }
    }
    // Last, once no repair moves a rod any more: every grain refined against its neighbours
    // where they ended up.
    let settling = Settling {
        dark,
        levels: after,
        min_confidence: params.min_confidence,
        min_visible: params.min_visible,
    };
    settle::settle(&mut found, &mut maps, &settling, params.settle_sweeps);
    laps.lap("settle");
    (found, maps.free)
}

/// The rods moved or added since `old` (the poses then, in order).
fn moved_since<'a>(found: &'a [Found], old: &'a [Pose]) -> impl Iterator<Item = usize> + 'a {
    (0..found.len()).filter(|&g| old.get(g) != Some(&found[g].pose))
}

/// The rods within `reach` of a rod moved or added since `old` (the poses then, in order).
fn near_moved(found: &[Found], old: &[Pose], reach: f64) -> Vec<usize> {
    let moved: Vec<Pose> = moved_since(found, old).map(|g| found[g].pose).collect();
    (0..found.len())
        .filter(|&g| {
            let p = found[g].pose;
            moved.iter().any(|m| (m.x - p.x).hypot(m.y - p.y) < reach)
        })
        .collect()
}

/// Brings the coarse maps (`explained`, and `free` with its border) up to date after the grains
/// at `poses` were painted on the full-resolution ones (`fine`). Only the blocks under their
/// paint changed: when those are few (later rounds: tens of grains) they alone are
/// downsampled again, else the whole maps are (in parallel). Either way the maps are those
/// downsampling gives, to the bit.
fn refresh_coarse(
    explained: &mut Plane,
    free: &mut Bordered,
    fine: (&Plane, &Plane),
    poses: impl Iterator<Item = Pose>,
    model: &Model,
    factor: usize,
) {
    let (fine_explained, fine_free) = fine;
    let (w, h) = (fine_explained.width, fine_explained.height);
    let block = factor.max(1);
    let boxes: Vec<(usize, usize, usize, usize)> = poses
        .map(|pose| model.painted_box(pose, w, h))
        .filter(|&(c0, c1, r0, r1)| c0 <= c1 && r0 <= r1)
        .map(|(c0, c1, r0, r1)| {
            let (c0, c1) = (c0 as usize / block, c1 as usize / block);
            (c0, c1, r0 as usize / block, r1 as usize / block)
        })
        .collect();
    let changed: usize = boxes
        .iter()
        .map(|&(c0, c1, r0, r1)| (c1 - c0 + 1) * (r1 - r0 + 1))
        .sum();
    // Block by block on one thread against the whole maps on two: the whole maps past a
    // tenth of their blocks (lab nuts at 10 px/mm: the whole maps 9 ms, round 1's 43 nuts
    // 1.3 ms, round 0's 455-520 the same 9 ms).
    if 10 * changed > explained.data.len() {
        *explained = fine_explained.downsample(factor);
        *free = Bordered::new(&fine_free.downsample(factor));
        return;
    }
    for (c0, c1, r0, r1) in boxes {
        for row in r0..=r1 {
            for col in c0..=c1 {
                explained.data[row * explained.width + col] =
                    fine_explained.block_mean(factor, col, row);
                free.set(col, row, fine_free.block_mean(factor, col, row));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::model::Score;
    use crate::detect::testing::Lcg;

    /// After grains are painted (across the edges too), the refreshed coarse maps are, bit for
    /// bit, the downsampled full-resolution maps, whether a few grains were painted or many.
    #[test]
    fn refreshed_coarse_maps_are_the_downsampled_ones() {
        let mut rng = Lcg(11);
        let (w, h) = (400, 300);
        let dark = Plane {
            width: w,
            height: h,
            data: (0..w * h).map(|_| rng.unit_f32()).collect(),
        };
        for (shape, factor) in [
            (GrainShape::nut(6.9e-3), 3),
            (GrainShape::nut(6.9e-3), 1),
            (
                GrainShape::Rod {
                    length: 8.9e-3,
                    width: 3e-3,
                },
                2,
            ),
        ] {
            let model = Model::new(shape, 3.3e3);
            let mut explained = Plane::new(w, h, 0.0);
            let mut free = dark.clone();
            let mut free_bordered = Bordered::new(&dark);
            let mut coarse_explained = explained.downsample(factor);
            let mut coarse_free = Bordered::new(&free.downsample(factor));
            for round in 0..3 {
                // A few grains refresh block by block, many the whole maps.
                let n = if round == 2 { 80 } else { 5 };
                let poses: Vec<Pose> = (0..n)
                    .map(|k| Pose {
                        x: -6.0 + rng.unit_f64() * (w as f64 + 12.0),
                        y: -6.0 + rng.unit_f64() * (h as f64 + 12.0),
                        phi: (round * 5 + k) as f64 * 0.37,
                    })
                    .collect();
                for &p in &poses {
                    model.paint(p, &dark, &mut explained, &mut free, &mut free_bordered);
                }
                refresh_coarse(
                    &mut coarse_explained,
                    &mut coarse_free,
                    (&explained, &free),
                    poses.into_iter(),
                    &model,
                    factor,
                );
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&coarse_explained.data),
                    bits(&explained.downsample(factor).data)
                );
                let want = Bordered::new(&free.downsample(factor));
                assert_eq!(bits(&coarse_free.data), bits(&want.data), "factor {factor}");
            }
            assert!(explained.data.iter().any(|&e| e > 0.0));
        }
    }

    /// The rods looked at again after a repair pass are those near a rod it moved or added,
    /// the moved and added ones among them, and no others.
    #[test]
    fn rods_near_those_moved_or_added_are_looked_at_again() {
        let rod = |x: f64| Found {
            pose: Pose {
                x,
                y: 50.0,
                phi: 0.0,
            },
            corners: [(0.0, 0.0); 4],
            confidence: 0.9,
        };
        let old: Vec<Pose> = [0.0, 40.0, 80.0, 200.0, 240.0, 400.0]
            .map(|x| rod(x).pose)
            .to_vec();
        let mut found: Vec<Found> = old.iter().map(|p| rod(p.x)).collect();
        assert!(near_moved(&found, &old, 50.0).is_empty(), "nothing moved");
        found[1] = rod(45.0);
        found.push(rod(420.0));
        assert_eq!(near_moved(&found, &old, 50.0), [0, 1, 2, 5, 6]);
    }

    /// Fits are taken best first, equal scores top to bottom, then left to right, then by
    /// seed: the order the fits were made in (which depends on the threads) plays no part,
    /// and a fit refined again and put back is taken at its new score.
    #[test]
    fn fits_are_taken_best_first_in_a_fixed_order() {
        let candidate = |k: usize, total: f32, x: f64, y: f64| Candidate {
            k,
            fitted: fit::Fitted {
                pose: Pose { x, y, phi: 0.0 },
                score: Score {
                    total,
                    agreement: 0.9,
                    visible: 1.0,
                },
            },
            refined_again: 0,
        };
        let all = [
            candidate(0, 5.0, 10.0, 20.0),
            candidate(1, 9.0, 30.0, 40.0),
            candidate(2, 5.0, 10.0, 10.0),
            candidate(3, 5.0, 5.0, 10.0),
            candidate(4, 7.0, 0.0, 0.0),
            candidate(5, 5.0, 5.0, 10.0),
        ];
        let taken = |heap: &mut BinaryHeap<Candidate>| {
            std::iter::from_fn(|| heap.pop().map(|c| c.k)).collect::<Vec<_>>()
        };
        let want = [1, 4, 3, 5, 2, 0];
        let mut forward: BinaryHeap<Candidate> = all.iter().copied().collect();
        assert_eq!(taken(&mut forward), want);
        let mut backward: BinaryHeap<Candidate> = all.iter().rev().copied().collect();
        assert_eq!(taken(&mut backward), want);
        // Fit 1 is taken first; put back at a lower score, it comes after fit 4.
        let mut heap: BinaryHeap<Candidate> = all.into_iter().collect();
        let first = heap.pop().expect("six fits");
        assert_eq!(first.k, 1);
        heap.push(candidate(1, 6.0, 30.0, 40.0));
        assert_eq!(taken(&mut heap), [4, 1, 3, 5, 2, 0]);
    }
}
