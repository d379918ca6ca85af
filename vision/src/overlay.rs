//! Detected outlines drawn over the photograph, to check a detection by eye.

use image::{DynamicImage, Rgb, RgbImage};
use imageproc::drawing::draw_line_segment_mut;

use crate::detect::Detection;

/// Whole grains in green, grains cut by the frame in orange, low confidence (< 0.7) in red.
pub fn draw_outlines(photo: &DynamicImage, detections: &[Detection], scale: f64) -> RgbImage {
    let mut out = photo.to_rgb8();
    let rows = out.height() as f64;
    for d in detections {
        let o = d.outline;
        let colour = if d.confidence < 0.7 {
            Rgb([230, 30, 30])
        } else if d.cut {
            Rgb([255, 150, 0])
        } else {
            Rgb([0, 200, 60])
        };
        let (a, b) = (
            0.5 * o.shape.length() * scale,
            0.5 * o.shape.width() * scale,
        );
        let (s, c) = o.theta.sin_cos();
        let (px, py) = (o.x * scale, rows - o.y * scale);
        let corners = [(a, b), (-a, b), (-a, -b), (a, -b)]
            .map(|(u, v)| ((px + u * c + v * s) as f32, (py - u * s + v * c) as f32));
        for k in 0..4 {
            draw_line_segment_mut(&mut out, corners[k], corners[(k + 1) % 4], colour);
        }
        draw_line_segment_mut(
            &mut out,
            (px as f32 - 1.5, py as f32),
            (px as f32 + 1.5, py as f32),
            colour,
        );
    }
    out
}
