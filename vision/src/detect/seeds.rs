//! Where to try a grain: the bright holes of nuts (strong centre cues), and the deepest points
//! of the dark area no accepted grain explains yet.

use image::GrayImage;
use imageproc::distance_transform::euclidean_squared_distance_transform;
use rayon::prelude::*;

use super::plane::{NEIGHBOURS, Plane};
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
    let mask: Vec<u8> = dark
        .data
        .par_iter()
        .zip(explained.data.par_iter())
        .map(|(&d, &e)| if d * (1.0 - e) > 0.5 { 0 } else { 255 })
        .collect();
    let field = GrayImage::from_raw(w as u32, h as u32, mask).expect("one byte per pixel");
    let depth = euclidean_squared_distance_transform(&field);
    let min2 = min_depth * min_depth;
    let at = |c: usize, r: usize| depth.get_pixel(c as u32, r as u32)[0];
    let mut peaks: Vec<(f64, usize, usize)> = (0..h)
        .into_par_iter()
        .flat_map_iter(|r| {
            (0..w).filter_map(move |c| {
                let d = at(c, r);
                if d < min2 {
                    return None;
                }
                let deeper = NEIGHBOURS.iter().any(|&(dc, dr)| {
                    let (cc, rr) = (c as isize + dc, r as isize + dr);
                    rr >= 0
                        && cc >= 0
                        && (rr as usize) < h
                        && (cc as usize) < w
                        && at(cc as usize, rr as usize) > d
                });
                (!deeper).then_some((d, c, r))
            })
        })
        .collect();
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
