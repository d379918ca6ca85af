//! The backlight (vignetting and a gradient) and the sensor (shot and read noise).

use rand::Rng;

use super::Style;

/// Uneven backlight across the frame: a radial falloff and a linear gradient.
pub struct Backlight {
    pub level: f64,
    pub vignetting: f64,
    pub gradient: f64,
    /// Unit direction in which the light grows (pixel axes).
    pub direction: [f64; 2],
    pub columns: f64,
    pub rows: f64,
}

impl Backlight {
    pub fn new(style: &Style, angle: f64, columns: u32, rows: u32) -> Self {
        Backlight {
            level: style.field_level,
            vignetting: style.vignetting,
            gradient: style.gradient,
            direction: [angle.cos(), angle.sin()],
            columns: columns as f64,
            rows: rows as f64,
        }
    }

    /// Field level at a continuous pixel position.
    pub fn at(&self, column: f64, row: f64) -> f64 {
        let (dx, dy) = (column - 0.5 * self.columns, row - 0.5 * self.rows);
        let half_diagonal = 0.5 * self.columns.hypot(self.rows);
        let radial = (dx * dx + dy * dy) / (half_diagonal * half_diagonal);
        let along = (dx * self.direction[0] + dy * self.direction[1]) / (2.0 * half_diagonal);
        self.level * (1.0 - self.vignetting * radial) * (1.0 + self.gradient * along)
    }
}

/// One draw of the standard normal distribution (Box-Muller).
pub fn standard_normal<R: Rng>(rng: &mut R) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The level a sensor reads for a true level: shot noise from `full_well` electrons at full
/// scale, plus read noise.
pub fn sensor<R: Rng>(level: f64, style: &Style, rng: &mut R) -> f64 {
    let shot = if style.full_well > 0.0 {
        (level.max(0.0) / style.full_well).sqrt()
    } else {
        0.0
    };
    let sigma = shot.hypot(style.read_noise);
    if sigma > 0.0 {
        level + sigma * standard_normal(rng)
    } else {
        level
    }
}
