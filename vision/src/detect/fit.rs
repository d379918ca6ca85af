//! Pose fit of one candidate: a coarse search over angle and position on the downsampled
//! darkness, a few parabolic steps there for its best distinct poses, then sub-pixel,
//! sub-degree Newton refinement on the full-resolution darkness of each (of those within
//! [`Levels::finalist_margin`] of the best).

use nalgebra::{Matrix3, Vector3};

use super::model::{Model, Pose, Score};
use super::plane::Bordered;

/// The two resolution levels a fit works on.
#[derive(Clone, Copy)]
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
    /// A finalist whose climbed coarse total falls short of the best climbed one by more than
    /// this fraction of it is not refined (infinite: every finalist is).
    pub finalist_margin: f64,
    /// Distinct coarse poses refined at full resolution ([`FINALISTS`] unless a shortcut
    /// asks for fewer), besides the far finalist of a fit over every angle.
    pub finalists: usize,
}

/// Positions tried around a seed, in the grain's own frame (along, across the long axis;
/// full-resolution pixels): a seed on a rod's axis may sit anywhere along it.
pub type Offsets = [(f64, f64)];

#[derive(Clone, Copy, Debug)]
pub struct Fitted {
    pub pose: Pose,
    pub score: Score,
}

/// Coarse angle step (radians): fine enough that the refinement starts inside the basin.
const COARSE_ANGLE_STEP: f64 = 6.0 * std::f64::consts::PI / 180.0;

/// Coarse poses refined at full resolution: the coarse level cannot resolve a rod's faint
/// highlight well, so its best few distinct poses compete again at full resolution. Fewer is
/// faster and turns more rods (lab rod53 on seeds 1-4 with one: 3.8 -> 2.9 s a photograph
/// and 0.81 -> 1.04 degrees at 10 px/mm; see `DetectParams::finalists`).
pub const FINALISTS: usize = 3;

/// Least turn from each of the three finalists of a fit over every angle for the best pose so
/// turned to be refined as a fourth: the three best distinct coarse poses can all be variants
/// of one wrong pose (a rod fitted diagonally across two lying face to face), and the right
/// pose, turned well away, then never competes refined.
const FAR_FINALIST_ANGLE: f64 = 45.0 * std::f64::consts::PI / 180.0;

/// Half-width of the angle search around a seed's known axis (radians): the highlight's
/// direction is good to a few degrees.
const AXIS_ANGLE_RANGE: f64 = 9.0 * std::f64::consts::PI / 180.0;

/// `axis`: the grain's angle when the seed knows it (a rod's highlight), searched only within
/// [`AXIS_ANGLE_RANGE`] of it; otherwise every angle of the symmetry period is tried, and
/// where the period leaves room (rods) the best pose turned [`FAR_FINALIST_ANGLE`] away from
/// the finalists is refined too.
pub fn fit(
    levels: &Levels,
    seed: (f64, f64),
    offsets: &Offsets,
    position_step: f64,
    axis: Option<f64>,
) -> Fitted {
    let f = levels.factor;
    // Over every angle, a rod's best poses turned away from the three finalists: a pose can
    // lie that far from them only where the period leaves room.
    let far_finalist = axis.is_none() && levels.period > 2.0 * FAR_FINALIST_ANGLE;
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
    // Coarse poses scored in full, and those given up on (kept only when a far finalist may
    // be sought among them), each with its place in the order tried.
    let mut tried: Vec<(f32, usize, Pose)> = Vec::with_capacity(angles.len() * offsets.len());
    let mut given_up: Vec<(usize, Pose)> = Vec::new();
    // The finalists picked: `DetectParams` refuses none, a `Levels` built elsewhere gets one.
    let wanted = levels.finalists.max(1);
    let mut witnesses = Witnesses::new(wanted);
    let on_coarse = |p: Pose| Pose {
        x: p.x / f,
        y: p.y / f,
        phi: p.phi,
    };
    let coarse_unless_below = |p: Pose, below: f32| {
        levels.coarse_model.score_unless_below(
            on_coarse(p),
            levels.coarse,
            levels.coarse_free,
            below,
        )
    };
    let mut index = 0;
    for &phi in &angles {
        let (s, c) = phi.sin_cos();
        for &(a, b) in offsets {
            let x = seed.0 + a * c + b * s;
            let y = seed.1 - a * s + b * c;
            let pose = Pose { x, y, phi };
            let at = index;
            index += 1;
            let Some(sc) = coarse_unless_below(pose, witnesses.threshold) else {
                if far_finalist {
                    given_up.push((at, pose));
                }
                continue;
            };
            tried.push((sc.total, at, pose));
            // Twice the distinct-finalist distances, with a hair for rounding: poses that
            // far apart cannot both be near one finalist.
            witnesses.offer(sc.total, pose, |p, q| {
                close(p, q, 4.0 * COARSE_ANGLE_STEP + 1e-9, 2.0 * distinct + 1e-9)
            });
        }
    }
    // Best first; on ties the pose tried first (the sort is stable).
    tried.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut finalists: Vec<Pose> = Vec::with_capacity(wanted + 1);
    for &(_, _, p) in &tried {
        let far = finalists
            .iter()
            .all(|q| !close(&p, q, 2.0 * COARSE_ANGLE_STEP, distinct));
        if far {
            finalists.push(p);
            if finalists.len() == wanted {
                break;
            }
        }
    }
    if far_finalist {
        let turned_away = |p: &Pose| {
            finalists
                .iter()
                .all(|q| !close(p, q, FAR_FINALIST_ANGLE, f64::INFINITY))
        };
        if let Some(p) = far_from(&tried, &given_up, turned_away, |p, below| {
            coarse_unless_below(p, below).map(|sc| sc.total)
        }) {
            finalists.push(p);
        }
    }
    let coarse_eval = |p: Pose| {
        levels
            .coarse_model
            .score(on_coarse(p), levels.coarse, levels.coarse_free)
            .total as f64
    };
    let step = position_step.max(f);
    // The coarse level barely resolves a rod's highlight, so the finalists, climbed there,
    // are each refined at full resolution and compared refined, which picks the right rod
    // more often than comparing them before refining (lab, 10 px/mm: rod3 recall 98.2 ->
    // 98.7 %, rod53 98.0 -> 98.2 %). A nut's outline the coarse level does resolve: the
    // finalists far behind the best there are not refined. On ties the later finalist wins.
    let climbed: Vec<(Pose, f64)> = finalists
        .into_iter()
        .map(|p| {
            climb(
                &coarse_eval,
                p,
                coarse_eval(p),
                step,
                0.5 * COARSE_ANGLE_STEP,
                2,
            )
        })
        .collect();
    let top = climbed
        .iter()
        .map(|&(_, v)| v)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut best: Option<Fitted> = None;
    for (p, v) in climbed {
        // (An infinite margin times a zero total would be NaN, hence the finiteness test.)
        if levels.finalist_margin.is_finite() && v < top - levels.finalist_margin * top.abs() {
            continue;
        }
        let refined = refine(levels, p);
        if best
            .as_ref()
            .is_none_or(|b| refined.score.total.total_cmp(&b.score.total).is_ge())
        {
            best = Some(refined);
        }
    }
    best.expect("at least one pose is tried")
}

/// The best coarse pose `turned_away` from the finalists, as though every pose had been scored
/// in full: among those `tried` (best first, each with its place in the order tried), then
/// among those `given_up` on, each `rescore`d unless certainly below the best so far. Ties go
/// to the pose tried first.
fn far_from(
    tried: &[(f32, usize, Pose)],
    given_up: &[(usize, Pose)],
    turned_away: impl Fn(&Pose) -> bool,
    rescore: impl Fn(Pose, f32) -> Option<f32>,
) -> Option<Pose> {
    let mut best = tried.iter().find(|t| turned_away(&t.2)).copied();
    for &(at, p) in given_up {
        if !turned_away(&p) {
            continue;
        }
        let below = best.map_or(f32::NEG_INFINITY, |b| b.0);
        if let Some(total) = rescore(p, below)
            && best.is_none_or(|(t, first, _)| total > t || (total == t && at < first))
        {
            best = Some((total, at, p));
        }
    }
    best.map(|(_, _, p)| p)
}

/// Farthest (pixels, along x or y) that a pose [`fit`] scores lies from the position its
/// coarse search started from (seed plus offset), with `position_step` and the levels'
/// `factor`: the finalists' climbs (two sweeps, the step halved) then their refinement.
pub fn fit_drift(position_step: f64, factor: f64) -> f64 {
    1.5 * position_step.max(factor) + refine_drift(factor)
}

/// The reach of [`refine`]'s first steps (pixels), with the levels' `factor`.
fn refine_step(factor: f64) -> f64 {
    0.5 * factor
}

/// Farthest (pixels, along x or y) that a pose [`refine`] scores lies from its start, with
/// the levels' `factor`: the probes, then steps no longer than the first reach each.
pub fn refine_drift(factor: f64) -> f64 {
    0.5 + NEWTON_STEPS as f64 * refine_step(factor).max(0.5)
}

/// Newton refinement at full resolution from a starting pose: each pose scored gives the
/// total and its gradient in one pass over the taps ([`Model::score_with_slopes`]); the
/// curvature is measured once by differences of the gradient along x, y and the angle, then
/// kept up to date from the steps taken (BFGS), each step kept inside a box that shrinks
/// when a step does not pay. Its first steps reach half a coarse pixel: a start from the
/// coarse level, or a pose already fitted, is that close.
pub fn refine(levels: &Levels, start: Pose) -> Fitted {
    let mut newton = Newton::start(levels, start, refine_step(levels.factor));
    newton.steps(levels, NEWTON_STEPS);
    newton.fitted()
}

/// The state of one Newton refinement, in (x, y, angle).
struct Newton {
    pose: Pose,
    value: f64,
    score: Score,
    gradient: Vector3<f64>,
    /// Curvature of the negated total (positive definite at a maximum).
    curvature: Matrix3<f64>,
    /// Largest step along each coordinate.
    reach: Vector3<f64>,
    /// Probe steps: half a pixel, and the angle that moves the grain's ends half a pixel.
    probe: Vector3<f64>,
    converged: bool,
}

fn moved(p: Pose, d: &Vector3<f64>) -> Pose {
    Pose {
        x: p.x + d.x,
        y: p.y + d.y,
        phi: p.phi + d.z,
    }
}

fn eval_slopes(levels: &Levels, p: Pose) -> (f64, Score, Vector3<f64>) {
    let (score, gradient) = levels
        .fine_model
        .score_with_slopes(p, levels.fine, levels.fine_free);
    (score.total as f64, score, Vector3::from(gradient))
}

impl Newton {
    /// Scores the start and measures the curvature there (four passes over the taps); the
    /// best of the poses scored becomes the current one.
    fn start(levels: &Levels, start: Pose, position_step: f64) -> Newton {
        let (value, score, gradient) = eval_slopes(levels, start);
        let half_length = f64::from(levels.fine_model.half_length()).max(1.0);
        let probe = Vector3::new(0.5, 0.5, 0.5 / half_length);
        let mut curvature = Matrix3::zeros();
        let mut best: Option<(f64, Pose, Score, Vector3<f64>)> = None;
        for axis in 0..3 {
            let mut d = Vector3::zeros();
            d[axis] = probe[axis];
            let q = moved(start, &d);
            let (v, s, g) = eval_slopes(levels, q);
            curvature.set_column(axis, &(-(g - gradient) / probe[axis]));
            if v > value && best.is_none_or(|(bv, ..)| v > bv) {
                best = Some((v, q, s, g));
            }
        }
        let curvature = 0.5 * (curvature + curvature.transpose());
        let (value, pose, score, gradient) = best.unwrap_or((value, start, score, gradient));
        let position_reach = position_step.max(0.5);
        Newton {
            pose,
            value,
            score,
            gradient,
            curvature,
            reach: Vector3::new(position_reach, position_reach, 0.5 * COARSE_ANGLE_STEP),
            probe,
            converged: false,
        }
    }

    /// At most `n` more steps (one pass over the taps each).
    fn steps(&mut self, levels: &Levels, n: usize) {
        for _ in 0..n {
            if self.converged {
                return;
            }
            let step = newton_step(&self.curvature, &self.gradient);
            let scale = step.abs().component_div(&self.reach).max().max(1.0);
            let step = step / scale;
            let q = moved(self.pose, &step);
            let (v, s, g) = eval_slopes(levels, q);
            // Secant update of the curvature from the gradient change along the step.
            bfgs_update(&mut self.curvature, &step, &(self.gradient - g));
            self.converged = step.x.abs().max(step.y.abs()) < CONVERGED * self.probe.x
                && step.z.abs() < CONVERGED * self.probe.z;
            if v > self.value {
                (self.value, self.pose, self.score, self.gradient) = (v, q, s, g);
            } else {
                self.reach = 0.5 * step.abs().sup(&(1e-3 * self.probe));
            }
        }
    }

    fn fitted(&self) -> Fitted {
        Fitted {
            pose: self.pose,
            score: self.score,
        }
    }
}

/// Most Newton steps after the curvature is measured.
const NEWTON_STEPS: usize = 6;

/// A refinement ends when its step moves the outline by less than this fraction of a probe
/// step (half a pixel): 0.05 px. A tenth of a pixel is below what the photograph resolves,
/// and a tolerance of 0.01 px took a fifth more passes for the same detections to within a
/// grain per thousand.
const CONVERGED: f64 = 0.1;

/// The step `curvature`^-1 `gradient` (an ascent step when the curvature of the negated
/// total is positive definite); where it is not, a step along the gradient scaled by the
/// diagonal's magnitude.
fn newton_step(curvature: &Matrix3<f64>, gradient: &Vector3<f64>) -> Vector3<f64> {
    match curvature.cholesky() {
        Some(c) => c.solve(gradient),
        None => gradient.component_div(&curvature.diagonal().abs().map(|d| d.max(1e-9))),
    }
}

/// BFGS update of a positive definite curvature from a step `s` and the gradient change
/// `y` along it (of the negated total); skipped when the pair does not keep it positive.
fn bfgs_update(b: &mut Matrix3<f64>, s: &Vector3<f64>, y: &Vector3<f64>) {
    let bs = *b * s;
    let (ys, sbs) = (y.dot(s), s.dot(&bs));
    if ys > 1e-10 * y.norm() * s.norm() && sbs > 0.0 {
        *b += y * y.transpose() / ys - bs * bs.transpose() / sbs;
    }
}

/// Successive parabolic steps along x, y and the angle, halving the steps each sweep.
/// `eval` gives the value climbed, `first` its value at `start` (known to the caller, so no
/// pose is scored twice). Returns the pose reached and its value.
fn climb(
    eval: &dyn Fn(Pose) -> f64,
    start: Pose,
    first: f64,
    position_step: f64,
    angle_step: f64,
    sweeps: usize,
) -> (Pose, f64) {
    let mut pose = start;
    let mut value = first;
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
            // A step clamped to the bracket lands on a pose just scored.
            let v = if step == h {
                plus
            } else if step == -h {
                minus
            } else {
                eval(candidate)
            };
            if v > value {
                (pose, value) = (candidate, v);
            } else if plus > value && plus >= minus {
                (pose, value) = (shifted(h), plus);
            } else if minus > value {
                (pose, value) = (shifted(-h), minus);
            }
        }
        hx *= 0.5;
        ha *= 0.5;
    }
    (pose, value)
}

/// The best coarse poses scored so far, and the score below which a pose cannot be a
/// finalist. The finalists are picked greedily, best first, each not close to one picked
/// before; if as many poses as the finalists scoring at least t lie pairwise so far apart that no pose is
/// close to two of them, the greedy pick takes its finalists among the poses scoring at least
/// t whatever else was scored, and a pose certainly below t need not be scored in full.
struct Witnesses {
    best: Vec<(f32, Pose)>,
    threshold: f32,
    /// Finalists the fit picks: that many witnesses set the threshold.
    finalists: usize,
}

/// Best poses kept as candidate witnesses.
const WITNESS_POOL: usize = 24;

impl Witnesses {
    fn new(finalists: usize) -> Self {
        Witnesses {
            best: Vec::with_capacity(WITNESS_POOL + 1),
            threshold: f32::NEG_INFINITY,
            finalists,
        }
    }

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
        let mut taken: Vec<&(f32, Pose)> = Vec::with_capacity(self.finalists);
        for w in &self.best {
            if taken.iter().all(|t| !near(&t.1, &w.1)) {
                taken.push(w);
                if taken.len() == self.finalists {
                    self.threshold = self.threshold.max(w.0);
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Whatever the number of finalists, the poses the witnesses let a fit give up on never
    /// change its finalists: the greedy pick among the poses kept is the pick among all.
    #[test]
    fn poses_given_up_on_never_change_the_finalists() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (angle, distance) = (2.0 * COARSE_ANGLE_STEP, 1.5);
        let period = std::f64::consts::PI;
        let close = |p: &Pose, q: &Pose, angle: f64, distance: f64| {
            let dphi = (p.phi - q.phi).rem_euclid(period);
            dphi.min(period - dphi) <= angle && (p.x - q.x).hypot(p.y - q.y) <= distance
        };
        let pick = |poses: &[(f32, Pose)], wanted: usize| {
            let mut sorted = poses.to_vec();
            sorted.sort_by(|a, b| b.0.total_cmp(&a.0));
            let mut finalists: Vec<Pose> = Vec::new();
            for (_, p) in sorted {
                if finalists.iter().all(|q| !close(&p, q, angle, distance)) {
                    finalists.push(p);
                    if finalists.len() == wanted {
                        break;
                    }
                }
            }
            finalists
        };
        for case in 0..300 {
            let wanted = 1 + case % 3;
            let n = rng.random_range(1..80);
            // Distinct totals: ties would make the pick depend on the order tried.
            let mut totals: Vec<f32> = (0..n).map(|k| k as f32).collect();
            for k in (1..n).rev() {
                totals.swap(k, rng.random_range(0..=k));
            }
            let all: Vec<(f32, Pose)> = totals
                .into_iter()
                .map(|total| {
                    let pose = Pose {
                        x: rng.random_range(0.0..6.0),
                        y: rng.random_range(0.0..3.0),
                        phi: rng.random_range(0.0..period),
                    };
                    (total, pose)
                })
                .collect();
            let mut witnesses = Witnesses::new(wanted);
            let mut kept = Vec::new();
            for &(total, pose) in &all {
                if total < witnesses.threshold {
                    continue;
                }
                kept.push((total, pose));
                witnesses.offer(total, pose, |p, q| {
                    close(p, q, 2.0 * angle + 1e-9, 2.0 * distance + 1e-9)
                });
            }
            assert_eq!(pick(&kept, wanted), pick(&all, wanted), "case {case}");
        }
    }

    /// The far finalist found from the poses scored in full and those given up on is the one
    /// a search scoring every pose in full finds: the best turned away, ties to the first.
    #[test]
    fn the_far_finalist_is_the_one_scoring_every_pose_would_give() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..200 {
            let n = rng.random_range(1..60);
            // Totals on a coarse grid, so that ties occur.
            let all: Vec<(f32, Pose)> = (0..n)
                .map(|k| {
                    let total = rng.random_range(0..20) as f32;
                    let phi = rng.random_range(0.0..std::f64::consts::PI);
                    (
                        total,
                        Pose {
                            x: k as f64,
                            y: 0.0,
                            phi,
                        },
                    )
                })
                .collect();
            let turned_away = |p: &Pose| p.phi > 1.0;
            let expected = {
                let mut order: Vec<usize> = (0..n).collect();
                order.sort_by(|&i, &j| all[j].0.total_cmp(&all[i].0));
                order
                    .into_iter()
                    .find(|&i| turned_away(&all[i].1))
                    .map(|i| all[i].1)
            };
            // Given up on: poses below a threshold, as the witnesses would leave them.
            let threshold = rng.random_range(0..25) as f32;
            let (mut tried, mut given_up) = (Vec::new(), Vec::new());
            for (k, &(total, p)) in all.iter().enumerate() {
                if total < threshold {
                    given_up.push((k, p));
                } else {
                    tried.push((total, k, p));
                }
            }
            tried.sort_by(|a, b| b.0.total_cmp(&a.0));
            let rescore = |p: Pose, below: f32| {
                let total = all[p.x as usize].0;
                (total >= below).then_some(total)
            };
            let found = far_from(&tried, &given_up, turned_away, rescore);
            assert_eq!(found, expected, "case {case}");
        }
    }
}
