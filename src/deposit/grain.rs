use std::f64::consts::PI;

/// One grain of a deposit, in SI units (metres, radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grain {
    /// Centre, from the left edge of the frame (or the silo's left wall).
    pub x: f64,
    /// Centre, upward from the bottom edge of the frame (or the floor).
    pub y: f64,
    /// Angle of the long axis (a side, for squares) counter-clockwise from +x, folded by symmetry.
    pub theta: f64,
    /// Outline length (the long side).
    pub length: f64,
    /// Outline width D (the short side; the side, for squares).
    pub width: f64,
    /// Detector confidence in [0, 1]; `None` for simulated grains.
    pub confidence: Option<f64>,
    /// True when the grain is cut by the edge of the photograph.
    pub cut: bool,
}

impl Grain {
    /// A grain whose pose is known exactly (simulated or built): no detector confidence, not
    /// cut by a frame.
    pub fn placed(x: f64, y: f64, theta: f64, length: f64, width: f64) -> Self {
        Self {
            x,
            y,
            theta,
            length,
            width,
            confidence: None,
            cut: false,
        }
    }

    /// A grain whose sides differ by less than 2 % is a square.
    pub fn is_square(&self) -> bool {
        (self.length - self.width).abs() < 0.02 * self.width
    }

    /// The angle after which the outline looks the same: pi/2 for squares, pi for rods.
    pub fn symmetry_period(&self) -> f64 {
        if self.is_square() { PI / 2.0 } else { PI }
    }

    /// This grain with theta folded into [0, period).
    pub fn folded(mut self) -> Self {
        self.theta = fold_angle(self.theta, self.symmetry_period());
        self
    }
}

/// Folds an angle into [0, period).
pub fn fold_angle(theta: f64, period: f64) -> f64 {
    let t = theta.rem_euclid(period);
    // rem_euclid can round up to exactly `period` for tiny negative inputs.
    if t >= period { 0.0 } else { t }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folding_respects_symmetry() {
        assert!((fold_angle(-0.1, PI) - (PI - 0.1)).abs() < 1e-12);
        assert!((fold_angle(PI / 2.0 + 0.2, PI / 2.0) - 0.2).abs() < 1e-12);
        assert_eq!(fold_angle(-1e-300, PI), 0.0);
        assert!(fold_angle(7.0 * PI + 0.3, PI) < PI);
    }
}
