//! Pose fit of one candidate: a coarse search over angle and position on the downsampled
//! darkness, then sub-pixel, sub-degree refinement on the full-resolution darkness by
//! successive parabolic steps along x, y and the angle.

use super::model::{Model, Pose, Score};
use super::plane::Plane;

/// The two resolution levels a fit works on.
pub struct Levels<'a> {
    pub fine: &'a Plane,
    pub fine_explained: &'a Plane,
    pub coarse: &'a Plane,
    pub coarse_explained: &'a Plane,
    pub fine_model: Model,
    pub coarse_model: Model,
    /// Downsampling factor between the levels.
    pub factor: f64,
    /// Rotation after which the outline looks the same (radians).
    pub period: f64,
}

/// Positions tried around a seed, in the grain's own frame (along, across the long axis;
/// full-resolution pixels): a seed on a rod's axis may sit anywhere along it.
pub type Offsets = [(f64, f64)];

pub struct Fitted {
    pub pose: Pose,
    pub score: Score,
}

/// Coarse angle step (radians): fine enough that the refinement starts inside the basin.
const COARSE_ANGLE_STEP: f64 = 6.0 * std::f64::consts::PI / 180.0;

/// Coarse poses refined at full resolution: the coarse level cannot resolve a rod's faint
/// highlight well, so its best few distinct poses compete again at full resolution.
const FINALISTS: usize = 3;

pub fn fit(levels: &Levels, seed: (f64, f64), offsets: &Offsets, position_step: f64) -> Fitted {
    let f = levels.factor;
    let n_angles = (levels.period / COARSE_ANGLE_STEP).round().max(1.0) as usize;
    let mut tried: Vec<(f32, Pose)> = Vec::with_capacity(n_angles * offsets.len());
    for k in 0..n_angles {
        let phi = k as f64 * levels.period / n_angles as f64;
        let (s, c) = phi.sin_cos();
        for &(a, b) in offsets {
            let x = seed.0 + a * c + b * s;
            let y = seed.1 - a * s + b * c;
            let pose = Pose {
                x: x / f,
                y: y / f,
                phi,
            };
            let sc = levels
                .coarse_model
                .score(pose, levels.coarse, Some(levels.coarse_explained));
            tried.push((sc.total, Pose { x, y, phi }));
        }
    }
    tried.sort_by(|a, b| b.0.total_cmp(&a.0));
    let distinct = 0.3 * levels.fine_model.half_width as f64;
    let mut finalists: Vec<Pose> = Vec::with_capacity(FINALISTS);
    for (_, p) in tried {
        let far = finalists.iter().all(|q| {
            let dphi = (p.phi - q.phi).rem_euclid(levels.period);
            let dphi = dphi.min(levels.period - dphi);
            dphi > 2.0 * COARSE_ANGLE_STEP || (p.x - q.x).hypot(p.y - q.y) > distinct
        });
        if far {
            finalists.push(p);
            if finalists.len() == FINALISTS {
                break;
            }
        }
    }
    finalists
        .into_iter()
        .map(|p| refine(levels, p, position_step.max(1.0)))
        .max_by(|a, b| a.score.total.total_cmp(&b.score.total))
        .expect("at least one pose is tried")
}

/// Parabolic coordinate refinement at full resolution from a starting pose.
pub fn refine(levels: &Levels, start: Pose, position_step: f64) -> Fitted {
    let eval = |p: Pose| {
        levels
            .fine_model
            .score(p, levels.fine, Some(levels.fine_explained))
            .total as f64
    };
    let mut pose = start;
    let mut value = eval(pose);
    let mut hx = position_step;
    let mut ha = 0.5 * COARSE_ANGLE_STEP;
    for _ in 0..6 {
        for axis in 0..3 {
            let h = if axis == 2 { ha } else { hx };
            let shifted = |d: f64| {
                let mut p = pose;
                match axis {
                    0 => p.x += d,
                    1 => p.y += d,
                    _ => p.phi += d,
                }
                p
            };
            let minus = eval(shifted(-h));
            let plus = eval(shifted(h));
            let curvature = minus - 2.0 * value + plus;
            let step = if curvature < 0.0 {
                (0.5 * h * (minus - plus) / curvature).clamp(-h, h)
            } else if plus > minus {
                h
            } else {
                -h
            };
            let candidate = shifted(step);
            let v = eval(candidate);
            if v > value {
                pose = candidate;
                value = v;
            } else if plus > value && plus >= minus {
                pose = shifted(h);
                value = plus;
            } else if minus > value {
                pose = shifted(-h);
                value = minus;
            }
        }
        hx *= 0.5;
        ha *= 0.5;
    }
    let score = levels
        .fine_model
        .score(pose, levels.fine, Some(levels.fine_explained));
    Fitted { pose, score }
}
