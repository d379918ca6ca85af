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
    half_diagonal: f64,
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
            half_diagonal: 0.5 * f64::from(columns).hypot(f64::from(rows)),
        }
    }

    /// Field level at a continuous pixel position.
    pub fn at(&self, column: f64, row: f64) -> f64 {
        let (dx, dy) = (column - 0.5 * self.columns, row - 0.5 * self.rows);
        let half_diagonal = self.half_diagonal;
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

/// Two independent draws of the standard normal distribution (both halves of Box-Muller, in
/// f32: the sensor noise needs neither more precision nor the cost).
pub fn standard_normal_pair<R: Rng>(rng: &mut R) -> (f32, f32) {
    let u1: f32 = 1.0 - rng.random::<f32>();
    let u2: f32 = rng.random::<f32>();
    let radius = (-2.0 * u1.ln()).sqrt();
    let (s, c) = (std::f32::consts::TAU * u2).sin_cos();
    (radius * c, radius * s)
}

/// Standard deviation of the sensor reading at a true level: shot noise from `full_well`
/// electrons at full scale, plus read noise.
pub fn sensor_sigma(level: f32, style: &Style) -> f32 {
    let shot = if style.full_well > 0.0 {
        level.max(0.0) / style.full_well as f32
    } else {
        0.0
    };
    (shot + (style.read_noise * style.read_noise) as f32).sqrt()
}
