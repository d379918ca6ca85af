//! Pose fit of one candidate: a coarse search over angle and position on the downsampled
//! darkness, then sub-pixel, sub-degree refinement on the full-resolution darkness by
//! successive parabolic steps along x, y and the angle.

use super::model::{Model, Pose, Score};
use super::plane::Bordered;

/// The two resolution levels a fit works on.
pub struct Levels<'a> {
    pub fine: &'a Bordered,
    /// Darkness not yet explained by accepted grains, full resolution.
    pub fine_free: &'a Bordered,
    pub coarse: &'a Bordered,
    pub coarse_free: &'a Bordered,
    pub fine_model: &'a Model,
    pub coarse_model: &'a Model,
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

/// Half-width of the angle search around a seed's known axis (radians): the highlight's
/// direction is good to a few degrees.
const AXIS_ANGLE_RANGE: f64 = 9.0 * std::f64::consts::PI / 180.0;

/// `axis`: the grain's angle when the seed knows it (a rod's highlight), searched only within
/// [`AXIS_ANGLE_RANGE`] of it; otherwise every angle of the symmetry period is tried.
pub fn fit(
    levels: &Levels,
    seed: (f64, f64),
    offsets: &Offsets,
    position_step: f64,
    axis: Option<f64>,
) -> Fitted {
    let f = levels.factor;
    let angles: Vec<f64> = match axis {
        Some(phi) => {
            let step = 0.5 * COARSE_ANGLE_STEP;
            let k = (AXIS_ANGLE_RANGE / step).round() as i32;
            (-k..=k).map(|i| phi + i as f64 * step).collect()
        }
        None => {
            let n = (levels.period / COARSE_ANGLE_STEP).round().max(1.0) as usize;
            (0..n)
                .map(|k| k as f64 * levels.period / n as f64)
                .collect()
        }
    };
    let distinct = 0.3 * levels.fine_model.half_width() as f64;
    let close = |p: &Pose, q: &Pose, angle: f64, distance: f64| {
        let dphi = (p.phi - q.phi).rem_euclid(levels.period);
        let dphi = dphi.min(levels.period - dphi);
        dphi <= angle && (p.x - q.x).hypot(p.y - q.y) <= distance
    };
    let mut tried: Vec<(f32, Pose)> = Vec::with_capacity(angles.len() * offsets.len());
    let mut witnesses = Witnesses::default();
    for &phi in &angles {
        let (s, c) = phi.sin_cos();
        for &(a, b) in offsets {
            let x = seed.0 + a * c + b * s;
            let y = seed.1 - a * s + b * c;
            let pose = Pose {
                x: x / f,
                y: y / f,
                phi,
            };
            let Some(sc) = levels.coarse_model.score_unless_below(
                pose,
                levels.coarse,
                levels.coarse_free,
                witnesses.threshold,
            ) else {
                continue;
            };
            let pose = Pose { x, y, phi };
            tried.push((sc.total, pose));
            // Twice the distinct-finalist distances, with a hair for rounding: poses that
            // far apart cannot both be near one finalist.
            witnesses.offer(sc.total, pose, |p, q| {
                close(p, q, 4.0 * COARSE_ANGLE_STEP + 1e-9, 2.0 * distinct + 1e-9)
            });
        }
    }
    tried.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut finalists: Vec<Pose> = Vec::with_capacity(FINALISTS);
    for (_, p) in tried {
        let far = finalists
            .iter()
            .all(|q| !close(&p, q, 2.0 * COARSE_ANGLE_STEP, distinct));
        if far {
            finalists.push(p);
            if finalists.len() == FINALISTS {
                break;
            }
        }
    }
    // Finalists compete after a cheap refinement on the coarse level; the winner alone is
    // refined at full resolution.
    let coarse_eval = |p: Pose| {
        let scaled = Pose {
            x: p.x / f,
            y: p.y / f,
            phi: p.phi,
        };
        let total = levels
            .coarse_model
            .score(scaled, levels.coarse, levels.coarse_free)
            .total as f64;
        (total, ())
    };
    let step = position_step.max(f);
    // The coarse level barely resolves a rod's highlight: the finalists, climbed there,
    // are compared at full resolution.
    // Only the best needs its full score: a finalist certainly below it is given up on. On
    // ties the later finalist wins.
    let mut best: Option<(Pose, Score)> = None;
    for p in finalists {
        let (p, _) = climb(
            &coarse_eval,
            p,
            coarse_eval(p),
            step,
            0.5 * COARSE_ANGLE_STEP,
            2,
        );
        let threshold = best.map_or(f32::NEG_INFINITY, |(_, s)| s.total);
        let Some(score) =
            levels
                .fine_model
                .score_unless_below(p, levels.fine, levels.fine_free, threshold)
        else {
            continue;
        };
        if best.is_none_or(|(_, s)| score.total.total_cmp(&s.total).is_ge()) {
            best = Some((p, score));
        }
    }
    let (winner, winner_score) = best.expect("at least one pose is tried");
    refine(levels, winner, winner_score, 0.5 * f)
}

/// Parabolic coordinate refinement at full resolution from a starting pose and its score.
pub fn refine(levels: &Levels, start: Pose, start_score: Score, position_step: f64) -> Fitted {
    let eval = |p: Pose| {
        let score = levels.fine_model.score(p, levels.fine, levels.fine_free);
        (score.total as f64, score)
    };
    let (pose, score) = climb(
        &eval,
        start,
        (start_score.total as f64, start_score),
        position_step.max(0.5),
        0.5 * COARSE_ANGLE_STEP,
        5,
    );
    Fitted { pose, score }
}

/// Successive parabolic steps along x, y and the angle, halving the steps each sweep.
/// `eval` gives the value climbed and what goes with it, `first` what it gives at `start`
/// (known to the callers, so no pose is scored twice).
fn climb<T: Copy>(
    eval: &dyn Fn(Pose) -> (f64, T),
    start: Pose,
    first: (f64, T),
    position_step: f64,
    angle_step: f64,
    sweeps: usize,
) -> (Pose, T) {
    let mut pose = start;
    let (mut value, mut carried) = first;
    let mut hx = position_step;
    let mut ha = angle_step;
    for _ in 0..sweeps {
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
            let (minus, minus_carried) = eval(shifted(-h));
            let (plus, plus_carried) = eval(shifted(h));
            let curvature = minus - 2.0 * value + plus;
            let step = if curvature < 0.0 {
                (0.5 * h * (minus - plus) / curvature).clamp(-h, h)
            } else if plus > minus {
                h
            } else {
                -h
            };
            let candidate = shifted(step);
            // A step clamped to the bracket lands on a pose just scored.
            let (v, v_carried) = if step == h {
                (plus, plus_carried)
            } else if step == -h {
                (minus, minus_carried)
            } else {
                eval(candidate)
            };
            if v > value {
                (pose, value, carried) = (candidate, v, v_carried);
            } else if plus > value && plus >= minus {
                (pose, value, carried) = (shifted(h), plus, plus_carried);
            } else if minus > value {
                (pose, value, carried) = (shifted(-h), minus, minus_carried);
            }
        }
        hx *= 0.5;
        ha *= 0.5;
    }
    (pose, carried)
}

/// The best coarse poses scored so far, and the score below which a pose cannot be a
/// finalist. The finalists are picked greedily, best first, each not close to one picked
/// before; if [`FINALISTS`] poses scoring at least t lie pairwise so far apart that no pose is
/// close to two of them, the greedy pick takes its finalists among the poses scoring at least
/// t whatever else was scored, and a pose certainly below t need not be scored in full.
struct Witnesses {
    best: Vec<(f32, Pose)>,
    threshold: f32,
}

impl Default for Witnesses {
    fn default() -> Self {
        Witnesses {
            best: Vec::with_capacity(WITNESS_POOL + 1),
            threshold: f32::NEG_INFINITY,
        }
    }
}

/// Best poses kept as candidate witnesses.
const WITNESS_POOL: usize = 24;

impl Witnesses {
    /// `near`: whether two poses might both be close to one finalist.
    fn offer(&mut self, total: f32, pose: Pose, near: impl Fn(&Pose, &Pose) -> bool) {
        if total <= self.threshold {
            return;
        }
        let at = self.best.partition_point(|(t, _)| *t >= total);
        if at >= WITNESS_POOL {
            return;
        }
        self.best.insert(at, (total, pose));
        self.best.truncate(WITNESS_POOL);
        // Greedily, best first, poses far from every one taken: any such set is a valid
        // witness, and the greedy one is good enough.
        let mut taken: Vec<&(f32, Pose)> = Vec::with_capacity(FINALISTS);
        for w in &self.best {
            if taken.iter().all(|t| !near(&t.1, &w.1)) {
                taken.push(w);
                if taken.len() == FINALISTS {
                    self.threshold = self.threshold.max(w.0);
                    return;
                }
            }
        }
    }
}
