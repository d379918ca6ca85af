//! Dust specks and scratches on the glass, drawn from the seed.

use std::f64::consts::PI;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::Style;
use crate::Frame;

/// A mark on the glass, in frame coordinates (metres).
#[derive(Clone, Copy, Debug)]
pub enum Mark {
    /// A round speck.
    Dust {
        x: f64,
        y: f64,
        radius: f64,
        opacity: f64,
    },
    /// A thin straight scratch from (x0, y0) to (x1, y1).
    Scratch {
        x0: f64,
        y0: f64,
        x1: f64,
        y1: f64,
        half_width: f64,
        opacity: f64,
    },
}

impl Mark {
    /// Bounding box (min x, min y, max x, max y), metres.
    pub fn bounds(&self) -> [f64; 4] {
        match *self {
            Mark::Dust { x, y, radius, .. } => [x - radius, y - radius, x + radius, y + radius],
            Mark::Scratch {
                x0,
                y0,
                x1,
                y1,
                half_width,
                ..
            } => [
                x0.min(x1) - half_width,
                y0.min(y1) - half_width,
                x0.max(x1) + half_width,
                y0.max(y1) + half_width,
            ],
        }
    }

    /// Fraction of light the mark blocks at a point, anti-aliased over one pixel.
    pub fn blocking(&self, px: f64, py: f64, scale: f64) -> f64 {
        let (distance, opacity) = match *self {
            Mark::Dust {
                x,
                y,
                radius,
                opacity,
            } => ((px - x).hypot(py - y) - radius, opacity),
            Mark::Scratch {
                x0,
                y0,
                x1,
                y1,
                half_width,
                opacity,
            } => {
                let (dx, dy) = (x1 - x0, y1 - y0);
                let t = (((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                (
                    (px - x0 - t * dx).hypot(py - y0 - t * dy) - half_width,
                    opacity,
                )
            }
        };
        // Marks thinner than a pixel still dim it in proportion to the area they cover.
        let thin = match *self {
            Mark::Dust { radius, .. } => (2.0 * radius * scale).min(1.0),
            Mark::Scratch { half_width, .. } => (2.0 * half_width * scale).min(1.0),
        };
        opacity * thin * (0.5 - distance * scale).clamp(0.0, 1.0)
    }
}

/// Dust and scratches for a frame, as the style asks.
pub fn marks(frame: &Frame, style: &Style, rng: &mut ChaCha8Rng) -> Vec<Mark> {
    let area_cm2 = frame.width * frame.height * 1e4;
    let mut out = Vec::new();
    let dust = poisson_count(style.dust_per_cm2 * area_cm2, rng);
    for _ in 0..dust {
        let radius = style.dust_radius_mm * 1e-3 * (0.2 + 0.8 * rng.random::<f64>());
        out.push(Mark::Dust {
            x: rng.random::<f64>() * frame.width,
            y: rng.random::<f64>() * frame.height,
            radius,
            opacity: style.dust_opacity * (0.4 + 0.6 * rng.random::<f64>()),
        });
    }
    let scratches = poisson_count(style.scratches_per_100cm2 * area_cm2 / 100.0, rng);
    for _ in 0..scratches {
        let length = style.scratch_length_mm * 1e-3 * (0.1 + 0.9 * rng.random::<f64>());
        let angle = rng.random::<f64>() * PI;
        let (x0, y0) = (
            rng.random::<f64>() * frame.width,
            rng.random::<f64>() * frame.height,
        );
        out.push(Mark::Scratch {
            x0,
            y0,
            x1: x0 + length * angle.cos(),
            y1: y0 + length * angle.sin(),
            half_width: 0.5 * style.scratch_width_mm * 1e-3,
            opacity: style.scratch_opacity * (0.5 + 0.5 * rng.random::<f64>()),
        });
    }
    out
}

/// A Poisson-distributed count of mean `mean` (normal approximation for large means).
fn poisson_count(mean: f64, rng: &mut ChaCha8Rng) -> usize {
    if mean <= 0.0 {
        return 0;
    }
    if mean > 50.0 {
        let normal = super::light::standard_normal(rng);
        return (mean + mean.sqrt() * normal).round().max(0.0) as usize;
    }
    let limit = (-mean).exp();
    let mut product = rng.random::<f64>();
    let mut count = 0;
    while product > limit {
        product *= rng.random::<f64>();
        count += 1;
    }
    count
}
