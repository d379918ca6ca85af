//! Where a grain lies, for the feeder: its L x D rectangle (which contains the rounded DEM
//! outline, so rectangles that do not overlap are grains that do not touch).

use sim::Vec2;

/// A placed L x D rectangle.
#[derive(Clone, Copy, Debug)]
pub struct Placed {
    pub centre: Vec2,
    pub angle: f64,
    /// Half length and half width (m).
    pub half: [f64; 2],
}

impl Placed {
    pub fn axes(&self) -> [Vec2; 2] {
        let (s, c) = self.angle.sin_cos();
        [Vec2::new(c, s), Vec2::new(-s, c)]
    }

    /// Half the extent along a unit direction.
    fn reach_along(&self, d: Vec2) -> f64 {
        let [a, b] = self.axes();
        self.half[0] * a.dot(&d).abs() + self.half[1] * b.dot(&d).abs()
    }

    /// Half the horizontal extent.
    pub fn half_width_x(&self) -> f64 {
        self.reach_along(Vec2::new(1.0, 0.0))
    }

    pub fn bounding_radius(&self) -> f64 {
        self.half[0].hypot(self.half[1])
    }

    pub fn corners(&self) -> [Vec2; 4] {
        let [a, b] = self.axes();
        let (a, b) = (a * self.half[0], b * self.half[1]);
        let c = self.centre;
        [c - a - b, c + a - b, c + a + b, c - a + b]
    }

    /// True when the two rectangles share interior (separating-axis test).
    pub fn overlaps(&self, other: &Placed) -> bool {
        let d = other.centre - self.centre;
        let reach = self.bounding_radius() + other.bounding_radius();
        if d.norm_squared() >= reach * reach {
            return false;
        }
        self.axes()
            .into_iter()
            .chain(other.axes())
            .all(|axis| d.dot(&axis).abs() < self.reach_along(axis) + other.reach_along(axis))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separating_axes() {
        let square = |x: f64, y: f64, angle: f64| Placed {
            centre: Vec2::new(x, y),
            angle,
            half: [1.0, 1.0],
        };
        assert!(square(0.0, 0.0, 0.0).overlaps(&square(1.9, 0.0, 0.0)));
        assert!(!square(0.0, 0.0, 0.0).overlaps(&square(2.1, 0.0, 0.0)));
        // A diamond's corner reaches sqrt(2) from its centre.
        assert!(square(0.0, 0.0, 0.0).overlaps(&square(2.3, 0.0, std::f64::consts::FRAC_PI_4)));
        assert!(!square(0.0, 0.0, 0.0).overlaps(&square(2.5, 0.0, std::f64::consts::FRAC_PI_4)));
        // Corners clear along the diagonal although the bounding circles overlap.
        assert!(!square(0.0, 0.0, 0.0).overlaps(&square(2.05, 2.05, 0.0)));
        let rod = Placed {
            centre: Vec2::zeros(),
            angle: std::f64::consts::FRAC_PI_2,
            half: [3.0, 0.5],
        };
        assert!((rod.half_width_x() - 0.5).abs() < 1e-12);
    }
}
