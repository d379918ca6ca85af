//! Separable Gaussian blur (the lens), parallel over rows; each output pixel is a fixed sum of
//! the same inputs whatever the thread count.

use rayon::prelude::*;

fn kernel(sigma: f64) -> Vec<f32> {
    let radius = (3.0 * sigma).ceil() as i64;
    let weights: Vec<f64> = (-radius..=radius)
        .map(|i| (-0.5 * (i as f64 / sigma).powi(2)).exp())
        .collect();
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| (w / total) as f32).collect()
}

/// Blurs a row-major `width` x `height` image in place; edges repeat the border pixel.
pub fn gaussian(pixels: &mut [f32], width: usize, height: usize, sigma: f64) {
    if sigma <= 0.0 || width == 0 || height == 0 {
        return;
    }
    let k = kernel(sigma);
    let radius = (k.len() / 2) as i64;
    let mut horizontal = vec![0.0f32; pixels.len()];
    horizontal
        .par_chunks_mut(width)
        .zip(pixels.par_chunks(width))
        .for_each(|(out, row)| {
            for (x, o) in out.iter_mut().enumerate() {
                let mut sum = 0.0;
                for (j, w) in k.iter().enumerate() {
                    let xi = (x as i64 + j as i64 - radius).clamp(0, width as i64 - 1);
                    sum += w * row[xi as usize];
                }
                *o = sum;
            }
        });
    pixels
        .par_chunks_mut(width)
        .enumerate()
        .for_each(|(y, out)| {
            out.fill(0.0);
            for (j, w) in k.iter().enumerate() {
                let yi = (y as i64 + j as i64 - radius).clamp(0, height as i64 - 1) as usize;
                let src = &horizontal[yi * width..(yi + 1) * width];
                for (o, s) in out.iter_mut().zip(src) {
                    *o += w * s;
                }
            }
        });
}
