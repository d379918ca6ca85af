//! Where to try a grain: the bright holes of nuts (strong centre cues), and the deepest points
//! of the dark area no accepted grain explains yet.

use image::{GrayImage, Luma};
use imageproc::distance_transform::euclidean_squared_distance_transform;
use rayon::prelude::*;

use super::plane::Plane;
use super::regions;

/// A bright blob enclosed by dark: a nut's hole, or light between grains.
#[derive(Clone, Copy, Debug)]
pub struct BrightBlob {
    /// Centroid (full-resolution pixels).
    pub x: f64,
    pub y: f64,
    pub area: f64,
    /// Side of its bounding box, the larger one.
    pub extent: f64,
}

/// Bright blobs (darkness < 0.5) that do not touch the photograph's edge.
pub fn bright_blobs(dark: &Plane) -> Vec<BrightBlob> {
    let (w, h) = (dark.width, dark.height);
    let mask: Vec<bool> = dark.data.par_iter().map(|&d| d < 0.5).collect();
    regions::regions(&mask, w, h)
        .into_iter()
        .filter(|b| !b.touches_edge(w, h))
        .map(|b| BrightBlob {
            x: b.sum_x / b.count,
            y: b.sum_y / b.count,
            area: b.count,
            extent: ((b.max_col - b.min_col + 1).max(b.max_row - b.min_row + 1)) as f64,
        })
        .collect()
}

/// Blobs the size and shape of a nut's hole of radius `hole_radius` pixels.
pub fn hole_seeds(blobs: &[BrightBlob], hole_radius: f64) -> Vec<(f64, f64)> {
    let area = std::f64::consts::PI * hole_radius * hole_radius;
    blobs
        .iter()
        .filter(|b| b.area > 0.35 * area && b.area < 1.8 * area && b.extent < 3.0 * hole_radius)
        .map(|b| (b.x, b.y))
        .collect()
}

/// Local maxima of the distance to the nearest pixel that is not dark-and-unexplained, on
/// the coarse level; at least `min_depth` deep and `spacing` apart (coarse pixels). Returned
/// in full-resolution pixels, deepest first.
pub fn residual_seeds(
    dark: &Plane,
    explained: &Plane,
    min_depth: f64,
    spacing: f64,
    factor: f64,
) -> Vec<(f64, f64)> {
    let (w, h) = (dark.width, dark.height);
    // Foreground of the transform = everything that is NOT residual dark area.
    let field = GrayImage::from_fn(w as u32, h as u32, |c, r| {
        let i = r as usize * w + c as usize;
        Luma([if dark.data[i] * (1.0 - explained.data[i]) > 0.5 {
            0
        } else {
            255
        }])
    });
    let depth = euclidean_squared_distance_transform(&field);
    let min2 = min_depth * min_depth;
    let mut peaks = Vec::new();
    for r in 0..h {
        for c in 0..w {
            let d = depth.get_pixel(c as u32, r as u32)[0];
            if d < min2 {
                continue;
            }
            let mut is_max = true;
            'n: for dr in -1isize..=1 {
                for dc in -1isize..=1 {
                    let (rr, cc) = (r as isize + dr, c as isize + dc);
                    if (dr, dc) != (0, 0)
                        && rr >= 0
                        && cc >= 0
                        && (rr as usize) < h
                        && (cc as usize) < w
                        && depth.get_pixel(cc as u32, rr as u32)[0] > d
                    {
                        is_max = false;
                        break 'n;
                    }
                }
            }
            if is_max {
                peaks.push((d, c, r));
            }
        }
    }
    peaks.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.2, a.1).cmp(&(b.2, b.1))));
    let mut kept: Vec<(f64, f64)> = Vec::new();
    let s2 = spacing * spacing;
    for (_, c, r) in peaks {
        let (x, y) = (c as f64 + 0.5, r as f64 + 0.5);
        if kept
            .iter()
            .all(|&(kx, ky)| (kx - x).powi(2) + (ky - y).powi(2) >= s2)
        {
            kept.push((x, y));
        }
    }
    kept.into_iter()
        .map(|(x, y)| (x * factor, y * factor))
        .collect()
}
