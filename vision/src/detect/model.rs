//! The rendered grain model a candidate pose is scored with: an anti-aliased rounded
//! rectangle (spheropolygon, rounding 0.05 D), the bright hole of a nut, the faint highlight
//! along a rod's axis, and a thin ring of field around the outline.

use crate::GrainShape;

use super::plane::Plane;

/// Rounding radius of the grains' corners, as a fraction of the width D.
const ROUNDING: f64 = 0.05;
/// Relative weights of the cues; the interior term has weight 1.
const RING_WEIGHT: f32 = 0.5;
const HOLE_WEIGHT: f32 = 1.0;
const HIGHLIGHT_WEIGHT: f32 = 2.0;

/// A pose in continuous pixel coordinates (column, row; row 0 at the top). `phi` is the
/// frame angle (counter-clockwise with y up): the long axis points along (cos phi, -sin phi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub phi: f64,
}

/// Grain geometry in pixels at one resolution level.
#[derive(Clone, Copy, Debug)]
pub struct Model {
    pub half_length: f32,
    pub half_width: f32,
    round: f32,
    hole_radius: f32,
    highlight_sigma: f32,
    highlight_half_length: f32,
    /// Width of the anti-aliasing ramp of the outline (pixels).
    soft: f32,
    /// Width of the ring of field scored outside the outline (pixels).
    ring: f32,
}

/// Score of one pose.
#[derive(Clone, Copy, Debug, Default)]
pub struct Score {
    /// Objective maximised by the fit (all cues).
    pub total: f32,
    /// Agreement of interior and hole with the photograph, in [-1, 1]: the confidence.
    pub agreement: f32,
    /// Fraction of the outline's area that lies inside the photograph.
    pub visible: f32,
}

impl Model {
    /// `px_per_m` at this level (full scale divided by the level's downsampling factor).
    pub fn new(shape: GrainShape, px_per_m: f64) -> Self {
        Self::with_softness(shape, px_per_m, 1.0)
    }

    /// `soft`: width of the outline's ramp (pixels); a softer model gives the coarse search a
    /// smoother objective, so grid poses near the truth score near its maximum.
    pub fn with_softness(shape: GrainShape, px_per_m: f64, soft: f64) -> Self {
        let length = shape.length() * px_per_m;
        let width = shape.width() * px_per_m;
        let (hole_radius, highlight_sigma, highlight_half_length) = match shape {
            GrainShape::Square { hole_diameter, .. } => (0.5 * hole_diameter * px_per_m, 0.0, 0.0),
            GrainShape::Rod { .. } => (0.0, (0.1 * width).max(0.5), 0.5 * (length - width)),
        };
        Model {
            half_length: (0.5 * length) as f32,
            half_width: (0.5 * width) as f32,
            round: (ROUNDING * width) as f32,
            hole_radius: hole_radius as f32,
            highlight_sigma: highlight_sigma as f32,
            highlight_half_length: highlight_half_length.max(0.0) as f32,
            soft: soft as f32,
            ring: (0.08 * width).clamp(soft, 2.5 * soft) as f32,
        }
    }

    /// Signed distance (pixels) from the outline, negative inside, in grain coordinates.
    #[inline]
    fn signed_distance(&self, u: f32, v: f32) -> f32 {
        let qx = u.abs() - (self.half_length - self.round);
        let qy = v.abs() - (self.half_width - self.round);
        let outside = (qx.max(0.0).powi(2) + qy.max(0.0).powi(2)).sqrt();
        outside + qx.max(qy).min(0.0) - self.round
    }

    /// Coverage in [0, 1] of a pixel centred at (u, v) in grain coordinates.
    #[inline]
    pub fn coverage(&self, u: f32, v: f32) -> f32 {
        (0.5 - self.signed_distance(u, v) / self.soft).clamp(0.0, 1.0)
    }

    /// Half extents (columns, rows) of the axis-aligned box that holds the pose and its ring.
    pub fn extent(&self, phi: f64) -> (f32, f32) {
        let (s, c) = (phi.sin().abs() as f32, phi.cos().abs() as f32);
        let pad = self.ring + self.soft + 1.0;
        (
            c * self.half_length + s * self.half_width + pad,
            s * self.half_length + c * self.half_width + pad,
        )
    }

    /// Scores a pose against the darkness, pixels already explained by accepted grains
    /// counting as field for the interior (so grains do not overlap).
    pub fn score(&self, pose: Pose, dark: &Plane, explained: Option<&Plane>) -> Score {
        let (ex, ey) = self.extent(pose.phi);
        let (sin, cos) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
        let (px, py) = (pose.x as f32, pose.y as f32);
        let c0 = (px - ex).floor() as isize;
        let c1 = (px + ex).ceil() as isize;
        let r0 = (py - ey).floor() as isize;
        let r1 = (py + ey).ceil() as isize;
        let (w, h) = (dark.width as isize, dark.height as isize);
        let (mut inside, mut inside_w, mut hole, mut hole_w) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        let (mut ring, mut highlight) = (0.0f32, 0.0f32);
        let mut area_all = 0.0f32;
        let inv2s2 = if self.highlight_sigma > 0.0 {
            1.0 / (2.0 * self.highlight_sigma * self.highlight_sigma)
        } else {
            0.0
        };
        let (box_u, box_v) = (
            self.half_length + self.ring + 1.0,
            self.half_width + self.ring + 1.0,
        );
        for r in r0..=r1 {
            let dy = r as f32 + 0.5 - py;
            let visible_row = r >= 0 && r < h;
            // Columns of this row inside the rotated box around the outline.
            let (lo_u, hi_u) = span(cos, -dy * sin, box_u);
            let (lo_v, hi_v) = span(sin, dy * cos, box_v);
            let lo = ((px + lo_u.max(lo_v) - 0.5).floor() as isize).max(c0);
            let hi = ((px + hi_u.min(hi_v) - 0.5).ceil() as isize).min(c1);
            for c in lo..=hi {
                let dx = c as f32 + 0.5 - px;
                let u = dx * cos - dy * sin;
                let v = dx * sin + dy * cos;
                let sd = self.signed_distance(u, v);
                if sd > self.ring {
                    continue;
                }
                let cov = (0.5 - sd / self.soft).clamp(0.0, 1.0);
                area_all += cov;
                if !visible_row || c < 0 || c >= w {
                    continue;
                }
                let i = r as usize * dark.width + c as usize;
                let d = dark.data[i];
                if cov < 1.0 {
                    ring += (1.0 - cov) * (1.0 - 2.0 * d);
                }
                if cov <= 0.0 {
                    continue;
                }
                let d_eff = match explained {
                    Some(e) => d * (1.0 - e.data[i]),
                    None => d,
                };
                let mut interior = cov;
                if self.hole_radius > 0.0 {
                    let rho = (u * u + v * v).sqrt();
                    let hc = (0.5 + (self.hole_radius - rho) / self.soft).clamp(0.0, 1.0);
                    if hc > 0.0 {
                        hole += hc * (1.0 - 2.0 * d);
                        hole_w += hc;
                        interior *= 1.0 - hc;
                    }
                }
                inside += interior * (2.0 * d_eff - 1.0);
                inside_w += interior;
                if inv2s2 > 0.0 && u.abs() < self.highlight_half_length {
                    highlight -= cov * (-v * v * inv2s2).exp() * d;
                }
            }
        }
        let visible = if area_all > 0.0 {
            (inside_w + hole_w) / area_all
        } else {
            0.0
        };
        let agreement = if inside_w + hole_w > 0.0 {
            (inside + hole) / (inside_w + hole_w)
        } else {
            -1.0
        };
        Score {
            total: inside + HOLE_WEIGHT * hole + RING_WEIGHT * ring + HIGHLIGHT_WEIGHT * highlight,
            agreement,
            visible: visible.min(1.0),
        }
    }

    /// Adds this pose's opacity to the explained map (clamped to 1).
    pub fn paint(&self, pose: Pose, explained: &mut Plane) {
        let (ex, ey) = self.extent(pose.phi);
        let (sin, cos) = (pose.phi.sin() as f32, pose.phi.cos() as f32);
        let (px, py) = (pose.x as f32, pose.y as f32);
        let c0 = ((px - ex).floor() as isize).max(0);
        let c1 = ((px + ex).ceil() as isize).min(explained.width as isize - 1);
        let r0 = ((py - ey).floor() as isize).max(0);
        let r1 = ((py + ey).ceil() as isize).min(explained.height as isize - 1);
        for r in r0..=r1 {
            let dy = r as f32 + 0.5 - py;
            for c in c0..=c1 {
                let dx = c as f32 + 0.5 - px;
                let u = dx * cos - dy * sin;
                let v = dx * sin + dy * cos;
                let cov = self.coverage(u, v);
                if cov > 0.0 {
                    let e = &mut explained.data[r as usize * explained.width + c as usize];
                    *e = (*e + cov).min(1.0);
                }
            }
        }
    }

    /// Corners of the outline (pixels), for the cut test and overlays.
    pub fn corners(&self, pose: Pose) -> [(f64, f64); 4] {
        let (s, c) = pose.phi.sin_cos();
        let (a, b) = (self.half_length as f64, self.half_width as f64);
        [(a, b), (-a, b), (-a, -b), (a, -b)].map(|(u, v)| {
            // Inverse of u = dx cos - dy sin, v = dx sin + dy cos.
            (pose.x + u * c + v * s, pose.y - u * s + v * c)
        })
    }
}

/// The interval of dx where |coef * dx + offset| <= bound.
#[inline]
fn span(coef: f32, offset: f32, bound: f32) -> (f32, f32) {
    if coef.abs() < 1e-6 {
        return if offset.abs() <= bound {
            (f32::NEG_INFINITY, f32::INFINITY)
        } else {
            (1.0, -1.0)
        };
    }
    let a = (-bound - offset) / coef;
    let b = (bound - offset) / coef;
    (a.min(b), a.max(b))
}
