//! Where to try a grain: the bright holes of nuts (strong centre cues), and the deepest points
//! of the dark area no accepted grain explains yet.

use image::{GrayImage, Luma};
use imageproc::distance_transform::euclidean_squared_distance_transform;
use imageproc::region_labelling::{Connectivity, connected_components};

use super::plane::Plane;

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
    let mask = GrayImage::from_fn(w as u32, h as u32, |c, r| {
        Luma([u8::from(dark.at(c as usize, r as usize) < 0.5)])
    });
    let labels = connected_components(&mask, Connectivity::Eight, Luma([0u8]));
    let n = labels.pixels().map(|p| p[0]).max().unwrap_or(0) as usize;
    // Per label: count, sum x, sum y, bounding box, touches edge.
    let mut acc = vec![
        (
            0.0f64,
            0.0f64,
            0.0f64,
            usize::MAX,
            0usize,
            usize::MAX,
            0usize,
            false
        );
        n + 1
    ];
    for (c, r, p) in labels.enumerate_pixels() {
        let l = p[0] as usize;
        if l == 0 {
            continue;
        }
        let (c, r) = (c as usize, r as usize);
        let a = &mut acc[l];
        a.0 += 1.0;
        a.1 += c as f64 + 0.5;
        a.2 += r as f64 + 0.5;
        a.3 = a.3.min(c);
        a.4 = a.4.max(c);
        a.5 = a.5.min(r);
        a.6 = a.6.max(r);
        a.7 |= c == 0 || r == 0 || c + 1 == w || r + 1 == h;
    }
    acc.iter()
        .skip(1)
        .filter(|a| a.0 > 0.0 && !a.7)
        .map(|a| BrightBlob {
            x: a.1 / a.0,
            y: a.2 / a.0,
            area: a.0,
            extent: ((a.4 - a.3 + 1).max(a.6 - a.5 + 1)) as f64,
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
