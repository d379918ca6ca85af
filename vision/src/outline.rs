//! Geometry of a placed grain outline: corners, rounded-corner distance, and frame clipping.
//!
//! Grains are spheropolygons: the L x W rectangle with its corners rounded by r = 0.05 D
//! (D the width). The outer size stays L x W, so faces that touch face to face leave no gap and
//! only the rounded corners let light through.

use crate::{Frame, GrainOutline, GrainShape};

/// Rounding radius of a grain's corners as a fraction of its width D.
pub const ROUNDING_FRACTION: f64 = 0.05;

impl GrainShape {
    /// A square nut of side `side` whose hole scales with it (3.3 mm for the 6.9 mm DIN 557 M4).
    pub fn nut(side: f64) -> Self {
        GrainShape::Square {
            side,
            hole_diameter: side * 3.3 / 6.9,
        }
    }

    /// Area of the outline (the hole removed, rounded corners counted).
    pub fn area(&self) -> f64 {
        let r = ROUNDING_FRACTION * self.width();
        let corners = (4.0 - std::f64::consts::PI) * r * r;
        let hole = match *self {
            GrainShape::Square { hole_diameter, .. } => {
                std::f64::consts::PI * hole_diameter * hole_diameter / 4.0
            }
            GrainShape::Rod { .. } => 0.0,
        };
        self.length() * self.width() - corners - hole
    }

    /// Radius of the circle around the centre that holds the whole outline.
    pub fn bounding_radius(&self) -> f64 {
        0.5 * self.length().hypot(self.width())
    }
}

impl GrainOutline {
    /// Unit vectors of the long axis and of the short axis.
    pub fn axes(&self) -> ([f64; 2], [f64; 2]) {
        let (s, c) = self.theta.sin_cos();
        ([c, s], [-s, c])
    }

    /// Half the length and half the width.
    pub fn half_extents(&self) -> (f64, f64) {
        (0.5 * self.shape.length(), 0.5 * self.shape.width())
    }

    /// The four corners of the (unrounded) rectangle, counter-clockwise.
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let (u, v) = self.axes();
        let (a, b) = self.half_extents();
        let at = |su: f64, sv: f64| {
            [
                self.x + su * a * u[0] + sv * b * v[0],
                self.y + su * a * u[1] + sv * b * v[1],
            ]
        };
        [at(1.0, 1.0), at(-1.0, 1.0), at(-1.0, -1.0), at(1.0, -1.0)]
    }

    /// A frame point in the grain's own axes (along the length, along the width).
    pub fn to_local(&self, x: f64, y: f64) -> (f64, f64) {
        let (u, v) = self.axes();
        let (dx, dy) = (x - self.x, y - self.y);
        (dx * u[0] + dy * u[1], dx * v[0] + dy * v[1])
    }

    /// Signed distance (metres) from a grain-local point to the rounded outline: negative inside.
    /// The hole is not part of this distance; see [`GrainOutline::hole_radius`].
    pub fn local_signed_distance(&self, lx: f64, ly: f64) -> f64 {
        let (a, b) = self.half_extents();
        let r = ROUNDING_FRACTION * self.shape.width();
        let qx = lx.abs() - (a - r);
        let qy = ly.abs() - (b - r);
        let outside = qx.max(0.0).hypot(qy.max(0.0));
        outside + qx.max(qy).min(0.0) - r
    }

    /// Radius of the through hole (nuts), zero for rods.
    pub fn hole_radius(&self) -> f64 {
        match self.shape {
            GrainShape::Square { hole_diameter, .. } => 0.5 * hole_diameter,
            GrainShape::Rod { .. } => 0.0,
        }
    }

    /// True when any part of the outline lies inside the frame.
    pub fn overlaps_frame(&self, frame: &Frame) -> bool {
        let corners = self.corners();
        let (min_x, max_x, min_y, max_y) = bounds(&corners);
        if max_x <= 0.0 || min_x >= frame.width || max_y <= 0.0 || min_y >= frame.height {
            return false;
        }
        // Separating axes of the grain itself (the frame's axes were tested above).
        let (u, v) = self.axes();
        let frame_corners = [
            [0.0, 0.0],
            [frame.width, 0.0],
            [frame.width, frame.height],
            [0.0, frame.height],
        ];
        let (a, b) = self.half_extents();
        for (axis, half) in [(u, a), (v, b)] {
            let centre = self.x * axis[0] + self.y * axis[1];
            let proj = frame_corners.map(|p| p[0] * axis[0] + p[1] * axis[1]);
            let lo = proj.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = proj.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if hi <= centre - half || lo >= centre + half {
                return false;
            }
        }
        true
    }

    /// True when part of the outline lies outside the frame (the photograph cuts the grain).
    pub fn is_cut_by(&self, frame: &Frame) -> bool {
        let (min_x, max_x, min_y, max_y) = bounds(&self.corners());
        min_x < 0.0 || min_y < 0.0 || max_x > frame.width || max_y > frame.height
    }
}

fn bounds(points: &[[f64; 2]; 4]) -> (f64, f64, f64, f64) {
    let mut b = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in points {
        b.0 = b.0.min(p[0]);
        b.1 = b.1.max(p[0]);
        b.2 = b.2.min(p[1]);
        b.3 = b.3.max(p[1]);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rod(x: f64, y: f64, theta: f64) -> GrainOutline {
        GrainOutline {
            x,
            y,
            theta,
            shape: GrainShape::Rod {
                length: 8.9e-3,
                width: 3e-3,
            },
        }
    }

    #[test]
    fn signed_distance_matches_the_rounded_rectangle() {
        let g = rod(0.0, 0.0, 0.3);
        // Middle of a long face: exactly on the outline.
        assert!(g.local_signed_distance(0.0, 1.5e-3).abs() < 1e-12);
        // Centre: half the width inside.
        assert!((g.local_signed_distance(0.0, 0.0) + 1.5e-3).abs() < 1e-12);
        // The sharp corner lies outside the rounded one by r (sqrt 2 - 1).
        let r = ROUNDING_FRACTION * 3e-3;
        let d = g.local_signed_distance(4.45e-3, 1.5e-3);
        assert!((d - r * (2f64.sqrt() - 1.0)).abs() < 1e-12, "{d}");
    }

    #[test]
    fn frame_clipping() {
        let frame = Frame {
            width: 0.05,
            height: 0.03,
            scale: 1e4,
        };
        assert!(rod(0.02, 0.01, 0.0).overlaps_frame(&frame));
        assert!(!rod(0.02, 0.01, 0.0).is_cut_by(&frame));
        // Centre outside, but the long axis reaches in.
        let edge = rod(-3e-3, 0.01, 0.0);
        assert!(edge.overlaps_frame(&frame) && edge.is_cut_by(&frame));
        // Diagonal rod near a corner whose bounding box touches the frame but outline does not.
        let off = rod(-3.2e-3, -3.2e-3, -std::f64::consts::FRAC_PI_4);
        assert!(!off.overlaps_frame(&frame));
        assert!(!rod(0.07, 0.01, 0.0).overlaps_frame(&frame));
    }
}
