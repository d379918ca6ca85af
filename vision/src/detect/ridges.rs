//! Seeds for rods from the faint line of front light reflected along each rod's axis.
//!
//! Rods touching face to face leave no light between them, so the dark area alone cannot tell
//! one wide rod from two parallel ones; the highlight can: each rod carries its own bright
//! line, D apart from its neighbour's. Across the line the darkness has a minimum, so the
//! Hessian of the smoothed darkness has one large positive eigenvalue whose eigenvector points
//! across the rod: the line gives both a point on the axis and the axis direction.

use rayon::prelude::*;

use super::plane::Plane;

/// A point on a rod's axis (full-resolution pixels) and the axis' frame angle `phi` (the axis
/// points along (cos phi, -sin phi), as in [`super::model::Pose`]).
#[derive(Clone, Copy, Debug)]
pub struct AxisSeed {
    pub x: f64,
    pub y: f64,
    pub phi: f64,
    /// Darkness of the smoothed photograph there: how light the highlight is.
    pub depth: f32,
}

/// Minimum darkness on a highlight: it lies inside a grain.
const MIN_DARKNESS: f32 = 0.55;
/// Minimum darkness at a highlight's centre, lightly smoothed: the highlights of the styles
/// take off 10-25 % of a grain's darkness, a gap between grains much more.
const MIN_SHARP_DARKNESS: f32 = 0.6;
/// A line, not a spot: the eigenvalue along it must be this much smaller than across.
const ELONGATION: f32 = 0.5;
/// Lines weaker than this fraction of the typical strong line are noise.
const RELATIVE_THRESHOLD: f32 = 0.25;

/// Axis seeds from the highlights. `sigma`: the highlight's width (pixels); `length`, `width`:
/// the rod's size (pixels). Points on one line closer than about half a rod along it and half
/// a width across it give one seed; strongest first.
pub fn axis_seeds(dark: &Plane, sigma: f64, length: f64, width: f64) -> Vec<AxisSeed> {
    let smooth = dark.blurred(sigma.max(0.8) as f32);
    // A thin bright gap between two grains also looks like a line once smoothed, but its
    // centre is far brighter than a highlight's: checked on the lightly smoothed darkness.
    let sharp = dark.blurred(1.0);
    let (w, h) = (smooth.width, smooth.height);
    if w < 3 || h < 3 {
        return Vec::new();
    }
    // Per pixel: strength (largest eigenvalue) and the across direction, or nothing.
    let lines: Vec<Vec<(f32, usize, f32, f32)>> = (1..h - 1)
        .into_par_iter()
        .map(|r| {
            let mut row = Vec::new();
            for c in 1..w - 1 {
                let i = r * w + c;
                let d = smooth.data[i];
                if d < MIN_DARKNESS {
                    continue;
                }
                let dxx = smooth.data[i - 1] - 2.0 * d + smooth.data[i + 1];
                let dyy = smooth.data[i - w] - 2.0 * d + smooth.data[i + w];
                let dxy = 0.25
                    * (smooth.data[i + w + 1] - smooth.data[i + w - 1] - smooth.data[i - w + 1]
                        + smooth.data[i - w - 1]);
                let mean = 0.5 * (dxx + dyy);
                let spread = (0.25 * (dxx - dyy).powi(2) + dxy * dxy).sqrt();
                let (big, small) = (mean + spread, mean - spread);
                if big <= 0.0 || small.abs() > ELONGATION * big {
                    continue;
                }
                let across = 0.5 * (2.0 * dxy).atan2(dxx - dyy);
                // Thin the line: a minimum of the darkness across it.
                let (s, c_) = across.sin_cos();
                let (oc, or) = (c_.round() as isize, s.round() as isize);
                let at = |dc: isize, dr: isize| {
                    smooth.data[(r as isize + dr) as usize * w + (c as isize + dc) as usize]
                };
                if d > at(oc, or) || d > at(-oc, -or) || sharp.data[i] < MIN_SHARP_DARKNESS {
                    continue;
                }
                row.push((big, c, across, d));
            }
            row
        })
        .collect();
    let mut points: Vec<(f32, usize, usize, f32, f32)> = lines
        .into_iter()
        .enumerate()
        .flat_map(|(k, row)| row.into_iter().map(move |(s, c, a, d)| (s, c, k + 1, a, d)))
        .collect();
    if points.is_empty() {
        return Vec::new();
    }
    // The typical strong line: highlights are many, so a high quantile is one of them.
    let mut strengths: Vec<f32> = points.iter().map(|p| p.0).collect();
    let q = (strengths.len() * 9) / 10;
    let (_, typical, _) = strengths.select_nth_unstable_by(q, |a, b| a.total_cmp(b));
    let threshold = RELATIVE_THRESHOLD * *typical;
    points.retain(|p| p.0 >= threshold);
    points.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.2, a.1).cmp(&(b.2, b.1))));

    let (along_gap, across_gap) = (0.45 * length, 0.5 * width);
    let mut seeds: Vec<AxisSeed> = Vec::new();
    // Kept seeds per coarse cell, so the spacing test looks at neighbours only.
    let cell = along_gap.max(1.0);
    let cols = (w as f64 / cell).ceil() as usize + 1;
    let rows = (h as f64 / cell).ceil() as usize + 1;
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); cols * rows];
    for (_, c, r, across, depth) in points {
        let (x, y) = (c as f64 + 0.5, r as f64 + 0.5);
        let (gc, gr) = ((x / cell) as usize, (y / cell) as usize);
        let mut near = false;
        'look: for nr in gr.saturating_sub(1)..=(gr + 1).min(rows - 1) {
            for nc in gc.saturating_sub(1)..=(gc + 1).min(cols - 1) {
                for &k in &grid[nr * cols + nc] {
                    let s: &AxisSeed = &seeds[k];
                    let (dx, dy) = (x - s.x, y - s.y);
                    // Along and across the kept seed's axis (cos phi, -sin phi).
                    let (sp, cp) = s.phi.sin_cos();
                    let along = dx * cp - dy * sp;
                    let off = dx * sp + dy * cp;
                    if along.abs() < along_gap && off.abs() < across_gap {
                        near = true;
                        break 'look;
                    }
                }
            }
        }
        if near {
            continue;
        }
        let phi = (-(across as f64) - std::f64::consts::FRAC_PI_2).rem_euclid(std::f64::consts::PI);
        grid[gr * cols + gc].push(seeds.len());
        seeds.push(AxisSeed { x, y, phi, depth });
    }
    seeds
}
