//! Greedy acceptance with explained-pixel bookkeeping: the best fits are accepted first and
//! paint their outline into an "explained" map; a later fit that would cover explained pixels
//! loses agreement and is refused or refitted in the next round. Each round seeds new fits
//! in the dark area no accepted grain explains yet.

use rayon::prelude::*;

use super::DetectParams;
use super::fit::{self, Levels};
use super::model::{Model, Pose};
use super::plane::Plane;
use super::seeds::{self, BrightBlob};
use crate::GrainShape;

/// An accepted grain (full-resolution pixels).
pub struct Found {
    pub pose: Pose,
    pub corners: [(f64, f64); 4],
    pub confidence: f64,
}

/// Coarse level resolution the pose search runs at (pixels per millimetre).
const COARSE_PX_PER_MM: f64 = 3.0;

pub fn find_grains(dark: &Plane, blobs: &[BrightBlob], params: &DetectParams) -> Vec<Found> {
    let px_per_mm = params.scale * 1e-3;
    let factor = (px_per_mm / COARSE_PX_PER_MM).floor().max(1.0) as usize;
    let f = factor as f64;
    let coarse = dark.downsample(factor);
    let fine_model = Model::new(params.shape, params.scale);
    let coarse_model = Model::new(params.shape, params.scale / f);
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
    let hole_seeds = match params.shape {
        GrainShape::Square { hole_diameter, .. } => {
            seeds::hole_seeds(blobs, 0.5 * hole_diameter * params.scale)
        }
        GrainShape::Rod { .. } => Vec::new(),
    };
    let centre_only = [(0.0, 0.0)];

    let mut explained = Plane::new(dark.width, dark.height, 0.0);
    let mut found: Vec<Found> = Vec::new();
    for round in 0..params.max_rounds.max(1) {
        let coarse_explained = explained.downsample(factor);
        let levels = Levels {
            fine: dark,
            fine_explained: &explained,
            coarse: &coarse,
            coarse_explained: &coarse_explained,
            fine_model,
            coarse_model,
            factor: f,
            period: params.shape.symmetry_period(),
        };
        let mut tasks: Vec<((f64, f64), &[(f64, f64)], f64)> = Vec::new();
        if round == 0 {
            tasks.extend(hole_seeds.iter().map(|&s| (s, &centre_only[..], 1.0)));
        }
        let residual =
            seeds::residual_seeds(&coarse, &coarse_explained, min_depth / f, spacing / f, f);
        let near_found = |s: (f64, f64)| {
            found
                .iter()
                .any(|g| (g.pose.x - s.0).hypot(g.pose.y - s.1) < 0.3 * width)
        };
        tasks.extend(
            residual
                .into_iter()
                .filter(|&s| !near_found(s))
                .map(|s| (s, &residual_offsets[..], (0.15 * width).max(f))),
        );
        if tasks.is_empty() {
            break;
        }
        let mut fits: Vec<fit::Fitted> = tasks
            .par_iter()
            .map(|&(seed, offsets, step)| fit::fit(&levels, seed, offsets, step))
            .filter(|ft| {
                ft.score.agreement as f64 >= params.min_confidence
                    && ft.score.visible as f64 >= params.min_visible
            })
            .collect();
        fits.sort_by(|a, b| {
            b.score
                .total
                .total_cmp(&a.score.total)
                .then(a.pose.y.total_cmp(&b.pose.y))
                .then(a.pose.x.total_cmp(&b.pose.x))
        });
        let mut accepted = 0;
        let mut this_round: Vec<Pose> = Vec::new();
        for ft in fits {
            // A fit next to a grain accepted in this round was made without knowing it: its
            // seed comes back in the next round, fitted against the updated explained map.
            let reach = 2.0 * fine_model.half_length as f64 + 2.0;
            if this_round
                .iter()
                .any(|p| (p.x - ft.pose.x).hypot(p.y - ft.pose.y) < reach)
            {
                continue;
            }
            let duplicate = found
                .iter()
                .any(|g| (g.pose.x - ft.pose.x).hypot(g.pose.y - ft.pose.y) < 0.5 * width);
            if duplicate {
                continue;
            }
            // Grains accepted earlier in this round may now explain part of this outline.
            let now = fine_model.score(ft.pose, dark, Some(&explained));
            if (now.agreement as f64) < params.min_confidence
                || now.agreement < ft.score.agreement - 0.1
            {
                continue;
            }
            fine_model.paint(ft.pose, &mut explained);
            this_round.push(ft.pose);
            found.push(Found {
                pose: ft.pose,
                corners: fine_model.corners(ft.pose),
                confidence: now.agreement as f64,
            });
            accepted += 1;
        }
        if accepted == 0 {
            break;
        }
    }
    found
}
