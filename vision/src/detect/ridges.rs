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
/// Lines weaker than this fraction of the typical strong line are noise...
const RELATIVE_THRESHOLD: f32 = 0.25;
/// ...unless they are this strong against the typical highlight.
const HIGHLIGHT_SHARE: f32 = 0.7;

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
    // A high quantile is a strong line. At low resolution that is a thin gap between grains,
    // far stronger there than a faint highlight: a quarter of it cut every highlight of clean
    // rod53 at 6 px/mm (0.21 of the 90 % quantile; lab 0.27, 10 px/mm 0.35-0.98), leaving
    // the gaps to seed rods across two. Most line points lie on highlights, each running its
    // rod's length, so the median is a highlight's strength (within 10 % of the highlights'
    // own median in every rod photograph of the bench, seed 1), and lines 0.7 of it are kept:
    // the threshold only ever falls, so no line the quarter kept is lost.
    let mut strengths: Vec<f32> = points.iter().map(|p| p.0).collect();
    let (strong_at, middle) = ((strengths.len() * 9) / 10, strengths.len() / 2);
    let mut quantile = |k: usize| *strengths.select_nth_unstable_by(k, f32::total_cmp).1;
    let (strong, highlight) = (quantile(strong_at), quantile(middle));
    let threshold = (RELATIVE_THRESHOLD * strong).min(HIGHLIGHT_SHARE * highlight);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows of rods 30 x 18 px lying end to end and face to face, each with a highlight that
    /// takes off 10 % of its darkness (sigma 2.2 px: the clean style at 6 px/mm), every end on
    /// a bright gap 1 px wide, a line about five times stronger, and a quarter of the lines'
    /// points: every rod still gets a seed on its axis, pointing along it.
    #[test]
    fn faint_highlights_beside_sharp_gaps_seed_every_rod() {
        let (length, width, columns, rows) = (30, 18, 8, 6);
        let mut plane = Plane::new(columns * length, rows * width, 0.0);
        for r in 0..plane.height {
            for c in 0..plane.width {
                let across = (r % width) as f32 + 0.5 - 0.5 * width as f32;
                plane.data[r * plane.width + c] = if c % length == 0 {
                    0.3
                } else {
                    0.95 * (1.0 - 0.1 * (-0.5 * (across / 2.2).powi(2)).exp())
                };
            }
        }
        let seeds = axis_seeds(&plane, 0.1 * width as f64, length as f64, width as f64);
        for row in 0..rows {
            for column in 0..columns {
                let (x, y) = (
                    (column as f64 + 0.5) * length as f64,
                    (row as f64 + 0.5) * width as f64,
                );
                assert!(
                    seeds.iter().any(|s| (s.y - y).abs() < 1.5
                        && (s.x - x).abs() < 0.5 * length as f64
                        && s.phi.sin().abs() < 0.1),
                    "no seed on the axis of the rod at ({x}, {y})"
                );
            }
        }
    }
}
