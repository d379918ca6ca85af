//! The moves one grain (or a pair) may make, each taken only when it lowers the objective:
//! small nudges along x, y and the angle, and the discrete jumps the greedy acceptance's
//! mistakes need, which no chain of small downhill moves reaches: a nut turned by half its
//! symmetry period, a rod turned a quarter, slipped by half or a whole width across or half a
//! length along, and two rods lying side by side turned together about their middle.

use std::f64::consts::FRAC_PI_2;

use super::super::model::Pose;
use super::objective::Canvas;
use crate::GrainShape;

/// How far the smallest nudges move an outline's farthest point (pixels): below this the
/// objective of an anti-aliased outline on a pixel grid is nearly flat.
const FINEST_STEP_PX: f64 = 0.125;
/// How far from its pose a grain's band reaches (pixels): nudges within it are priced on
/// the band alone.
const BAND_REACH_PX: f64 = 2.5;
/// Rounds of nudging at each step size, each taking the best of the six nudges.
const NUDGE_ROUNDS: usize = 8;
/// A jump is polished by nudges before it is judged when, raw, it costs less than this
/// many pixels of misfit per pixel of the outline's perimeter: a jump into the right place
/// lands off its best pose by up to a pixel, which costs about a pixel-wide strip along the
/// outline's sides.
const JUMP_SLACK_PER_PERIMETER_PX: f64 = 0.5;

/// What the moves know of the grains' size and symmetry.
#[derive(Clone, Copy, Debug)]
pub struct Geometry {
    pub shape: GrainShape,
    /// Length and width (pixels).
    pub length: f64,
    pub width: f64,
}

impl Geometry {
    fn is_rod(&self) -> bool {
        matches!(self.shape, GrainShape::Rod { .. })
    }

    /// What a jump may cost raw and still be polished before it is judged.
    pub fn jump_slack(&self) -> f64 {
        JUMP_SLACK_PER_PERIMETER_PX * 2.0 * (self.length + self.width)
    }

    /// The jumps of one grain from `p`: poses it may take at once.
    pub fn jumps(&self, p: Pose) -> Vec<Pose> {
        let (s, c) = p.phi.sin_cos();
        // Unit vectors along the axis and across it (pixels, rows down).
        let along = (c, -s);
        let across = (s, c);
        let shift = |q: Pose, d: (f64, f64), k: f64| Pose {
            x: q.x + k * d.0,
            y: q.y + k * d.1,
            phi: q.phi,
        };
        let turned = |by: f64| Pose {
            phi: p.phi + by,
            ..p
        };
        if !self.is_rod() {
            return vec![turned(0.5 * FRAC_PI_2)];
        }
        let (l, w) = (self.length, self.width);
        let quarter = turned(FRAC_PI_2);
        let mut out = vec![quarter];
        // A rod fitted standing across its neighbour's end lies along it, a half length less
        // a half width to one side.
        for k in [-1.0, 1.0] {
            out.push(shift(quarter, along, k * 0.5 * (l - w)));
        }
        for k in [-0.5, 0.5, -1.0, 1.0] {
            out.push(shift(p, across, k * w));
        }
        for k in [-0.5, 0.5] {
            out.push(shift(p, along, k * l));
        }
        out
    }

    /// The six nudges of `p` by `step` pixels (the angle by as much at the outline's end).
    fn nudges(&self, p: Pose, step: f64) -> [Pose; 6] {
        let turn = step / (0.5 * self.length.hypot(self.width));
        [
            Pose { x: p.x + step, ..p },
            Pose { x: p.x - step, ..p },
            Pose { y: p.y + step, ..p },
            Pose { y: p.y - step, ..p },
            Pose {
                phi: p.phi + turn,
                ..p
            },
            Pose {
                phi: p.phi - turn,
                ..p
            },
        ]
    }

    /// Nudges the grain at `p` (which the canvas holds) downhill, from steps of `first`
    /// pixels down to the finest; the canvas is left holding it where it ended. Returns that
    /// pose and the objective's change.
    pub fn polish(&self, canvas: &mut Canvas, p: Pose, first: f64) -> (Pose, f64) {
        let mut held = p;
        let mut band = canvas.band(held, BAND_REACH_PX);
        // The pose's change from `held`, and the change the canvas has made already.
        let mut best = (held, 0.0);
        let mut made = 0.0;
        let mut step = first;
        while step >= FINEST_STEP_PX {
            for _ in 0..NUDGE_ROUNDS {
                let mut round = best;
                for q in self.nudges(best.0, step) {
                    let e = canvas.change_near(&band, q);
                    if e < round.1 {
                        round = (q, e);
                    }
                }
                if round.1 >= best.1 {
                    break;
                }
                best = round;
                // Far from the band's pose, the band is moved along: the canvas takes the
                // pose, and the changes start from it.
                if (best.0.x - held.x).hypot(best.0.y - held.y) > 0.5 * BAND_REACH_PX {
                    canvas.apply(&[held], &[best.0]);
                    made += best.1;
                    held = best.0;
                    best = (held, 0.0);
                    band = canvas.band(held, BAND_REACH_PX);
                }
            }
            step *= 0.5;
        }
        if best.0 != held {
            canvas.apply(&[held], &[best.0]);
        }
        (best.0, made + best.1)
    }

    /// Moves the grain at `p` (which the canvas holds) to its best jump, polished, when that
    /// lowers the objective; returns the pose and the change.
    pub fn best_jump(&self, canvas: &mut Canvas, p: Pose) -> Option<(Pose, f64)> {
        let slack = self.jump_slack();
        for q in self.jumps(p) {
            let raw = canvas.change(&[p], &[q]);
            if raw > slack {
                continue;
            }
            canvas.apply(&[p], &[q]);
            let (q, e) = self.polish(canvas, q, 1.0);
            if raw + e < 0.0 {
                return Some((q, raw + e));
            }
            canvas.apply(&[q], &[p]);
        }
        None
    }

    /// Two rods `a` and `b` near each other (centres less than a length apart) turned
    /// together by a quarter: each in its place (two rods at right angles fitted each with
    /// the other's angle), and, when parallel, about their middle (a pair fitted standing
    /// across the pair it is).
    pub fn pair_turns(&self, a: Pose, b: Pose) -> Vec<[Pose; 2]> {
        if !self.is_rod() || (b.x - a.x).hypot(b.y - a.y) >= self.length {
            return Vec::new();
        }
        let in_place = |p: Pose| Pose {
            phi: p.phi + FRAC_PI_2,
            ..p
        };
        let mut out = vec![[in_place(a), in_place(b)]];
        let dphi = (a.phi - b.phi).rem_euclid(std::f64::consts::PI);
        if dphi.min(std::f64::consts::PI - dphi) < 0.2 {
            let (mx, my) = (0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
            // Turned a quarter counter-clockwise (y up) about the middle: the offset
            // (dx, dy) in rows-down pixels becomes (dy, -dx).
            let turn = |p: Pose| Pose {
                x: mx + (p.y - my),
                y: my - (p.x - mx),
                phi: p.phi + FRAC_PI_2,
            };
            out.push([turn(a), turn(b)]);
        }
        out
    }

    /// The first nudge step of a grain's polish in sweep `sweep` (pixels): a pixel, then
    /// finer as the grains settle.
    pub fn sweep_step(sweep: usize) -> f64 {
        (0.5f64).powi(sweep.min(2) as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Turning a parallel pair about its middle keeps them a width apart and turns each a
    /// quarter; rods a length apart are no pair, and rods at an angle only turn in place.
    #[test]
    fn a_pair_turned_stays_a_pair() {
        let g = Geometry {
            shape: GrainShape::Rod {
                length: 4.9e-3,
                width: 3e-3,
            },
            length: 49.0,
            width: 30.0,
        };
        let a = Pose {
            x: 100.0,
            y: 100.0,
            phi: 0.3,
        };
        let (s, c) = a.phi.sin_cos();
        let b = Pose {
            x: a.x + 30.0 * s,
            y: a.y + 30.0 * c,
            ..a
        };
        let turns = g.pair_turns(a, b);
        assert_eq!(turns.len(), 2);
        let [p, q] = turns[1];
        assert!(((p.x - q.x).hypot(p.y - q.y) - 30.0).abs() < 1e-9);
        assert!((p.phi - a.phi - FRAC_PI_2).abs() < 1e-12);
        let end = Pose {
            x: a.x + 50.0 * c,
            y: a.y - 50.0 * s,
            ..a
        };
        assert!(g.pair_turns(a, end).is_empty(), "a length apart");
        assert_eq!(
            g.pair_turns(
                a,
                Pose {
                    phi: a.phi + 1.5,
                    ..b
                }
            )
            .len(),
            1
        );
    }
}
