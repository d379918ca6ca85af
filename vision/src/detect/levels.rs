//! Whether a frame can be a backlit photograph of grains at all, before anything is sought in
//! it. A backlit photograph shows two levels: the bright background (the light between and
//! around the grains) and the dark grains in front of it, apart by more than the sensor's
//! noise. A black, white, saturated or uniform frame lacks one of them, and the normaliser,
//! which stretches whatever darkness it finds to [0, 1], would stretch noise into grains.

use image::DynamicImage;

/// Grey values (fractions of full scale) read at most, spread over the frame's rows: the
/// percentiles and the noise are measured as well on a million pixels as on all of them,
/// and a frame of hundreds of megapixels is not converted whole.
const MAX_SAMPLES: u64 = 1 << 20;

/// The bright background must reach this fraction of full scale (its 99th percentile):
/// below it the frame was not lit (five levels of eight bits).
pub const MIN_BACKGROUND: f64 = 0.02;

/// Fraction of the frame's pixels whose level is taken for the grains': the darkest 0.1 %.
/// Low, so that a photograph holding a single grain (0.15 % of a full frame at 10 px/mm)
/// still shows its grains' level.
const GRAIN_QUANTILE: f64 = 0.001;

/// Fraction of the frame's pixels brighter than the background's level: its 99th percentile,
/// so that specks of glare do not count as background.
const BACKGROUND_QUANTILE: f64 = 0.99;

/// The grains must block at least this fraction of the background's light. Grains let
/// through at most a third of it even in the renderer's hardest look (stray light 0.30):
/// they block about 0.6 there, and nearly all of it in a lab photograph.
pub const MIN_GRAIN_DARKNESS: f64 = 0.2;

/// The grains' and the background's levels must lie this many noise deviations apart. Noise
/// alone puts the darkest 0.1 % and the 99th percentile of a uniform frame 5.4 deviations
/// apart; the renderer's hardest look shows its grains about 20 deviations below its
/// background.
pub const MIN_SEPARATION_IN_NOISE: f64 = 8.0;

/// The levels measured in a frame (fractions of full scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levels {
    /// The bright background: the 99th percentile.
    pub background: f64,
    /// The dark grains: the darkest 0.1 %.
    pub grains: f64,
    /// Standard deviation of the pixel noise, from the differences of neighbouring pixels
    /// (their median absolute value: edges between grain and background are too few to move
    /// it).
    pub noise: f64,
}

impl Levels {
    /// Measured on up to [`MAX_SAMPLES`] pixels of `image`, whole rows spread evenly over it;
    /// `None` for an empty frame.
    pub fn of(image: &DynamicImage) -> Option<Levels> {
        let (width, height) = (image.width(), image.height());
        if width == 0 || height == 0 {
            return None;
        }
        let row_step = (u64::from(width) * u64::from(height)).div_ceil(MAX_SAMPLES) as u32;
        let mut grey = Vec::new();
        let mut steps = Vec::new();
        for row in (0..height).step_by(row_step.max(1) as usize) {
            let line = image.crop_imm(0, row, width, 1).to_luma32f().into_raw();
            steps.extend(line.windows(2).map(|p| (p[1] - p[0]).abs()));
            grey.extend(line);
        }
        let background = f64::from(quantile(&mut grey, BACKGROUND_QUANTILE));
        let grains = f64::from(quantile(&mut grey, GRAIN_QUANTILE));
        // |a - b| of two independent normal deviates has median 0.6745 x sqrt(2) sigma.
        let noise = if steps.is_empty() {
            0.0
        } else {
            f64::from(quantile(&mut steps, 0.5)) / (0.6745 * std::f64::consts::SQRT_2)
        };
        Some(Levels {
            background,
            grains,
            noise,
        })
    }

    /// Why these levels cannot be a backlit photograph of grains, if they cannot.
    pub fn unusable(&self) -> Option<String> {
        if self.background < MIN_BACKGROUND {
            return Some(format!(
                "the frame has no bright background (99th percentile darkness {:.2}; a backlit \
                 photograph shows its light at least at {MIN_BACKGROUND} of full scale)",
                1.0 - self.background
            ));
        }
        let darkness = 1.0 - self.grains / self.background;
        if darkness < MIN_GRAIN_DARKNESS {
            return Some(format!(
                "the frame has no dark grains: its darkest 0.1 % (grey {:.3} of full scale) \
                 blocks {:.0} % of its background's light (grey {:.3}), grains block at least \
                 {:.0} %",
                self.grains,
                100.0 * darkness,
                self.background,
                100.0 * MIN_GRAIN_DARKNESS
            ));
        }
        let separation = self.background - self.grains;
        if separation < MIN_SEPARATION_IN_NOISE * self.noise {
            return Some(format!(
                "the frame has no contrast above its noise: its background (grey {:.3}) and \
                 darkest 0.1 % (grey {:.3}) lie {:.1} noise deviations ({:.3}) apart, grains \
                 lie at least {MIN_SEPARATION_IN_NOISE} apart",
                self.background,
                self.grains,
                separation / self.noise,
                self.noise
            ));
        }
        None
    }
}

/// The value of rank `q` x (n - 1) among `values` (reordered).
fn quantile(values: &mut [f32], q: f64) -> f32 {
    let rank = ((values.len() - 1) as f64 * q).round() as usize;
    *values.select_nth_unstable_by(rank, f32::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::testing::Lcg;
    use image::{GrayImage, Luma};

    fn frame(width: u32, height: u32, mut level: impl FnMut(u32, u32) -> f32) -> DynamicImage {
        DynamicImage::ImageLuma8(GrayImage::from_fn(width, height, |x, y| {
            Luma([(255.0 * level(x, y).clamp(0.0, 1.0)).round() as u8])
        }))
    }

    /// Gaussian-ish noise: the sum of four uniforms, scaled to a standard deviation of `sigma`.
    fn noisy(rng: &mut Lcg, sigma: f32) -> f32 {
        let s: f32 = (0..4).map(|_| rng.unit_f32() - 0.5).sum();
        s * sigma / (4.0f32 / 12.0).sqrt()
    }

    #[test]
    fn levels_name_what_is_missing() {
        let reason = |image: &DynamicImage| Levels::of(image).unwrap().unusable();
        let black = reason(&frame(60, 40, |_, _| 0.0)).unwrap();
        assert!(
            black.contains("no bright background") && black.contains("1.00"),
            "{black}"
        );
        for level in [1.0, 0.5, 0.03] {
            let flat = reason(&frame(60, 40, |_, _| level)).unwrap();
            assert!(flat.contains("no dark grains"), "{level}: {flat}");
        }
        let mut rng = Lcg(7);
        let noise = frame(200, 150, |_, _| 0.5 + noisy(&mut rng, 0.05));
        let noise = reason(&noise).unwrap();
        assert!(noise.contains("no contrast above its noise"), "{noise}");
        // Dark disks on a noisy, vignetted background: a photograph.
        let mut rng = Lcg(9);
        let disks = frame(200, 150, |x, y| {
            let (dx, dy) = (x as f32 % 50.0 - 25.0, y as f32 % 50.0 - 25.0);
            let r2 = ((x as f32 - 100.0).powi(2) + (y as f32 - 75.0).powi(2)) / 125.0f32.powi(2);
            let field = 0.6 * (1.0 - 0.35 * r2);
            let lit = if dx * dx + dy * dy < 100.0 { 0.3 } else { 1.0 };
            field * lit + noisy(&mut rng, 0.02)
        });
        assert_eq!(reason(&disks), None);
    }
}
