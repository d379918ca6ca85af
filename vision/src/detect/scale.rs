//! Plausibility of the stated scale: the grains' own sizes measured in the photograph (the
//! nuts' holes; the thickness of dark regions for rods) compared with what the scale predicts.

use image::{GrayImage, Luma};
use imageproc::distance_transform::euclidean_squared_distance_transform;

use super::plane::Plane;
use super::seeds::BrightBlob;
use crate::GrainShape;

/// The scale (pixels per metre) the photograph suggests, when there is enough evidence.
pub fn measured_scale(shape: GrainShape, dark: &Plane, blobs: &[BrightBlob]) -> Option<f64> {
    match shape {
        GrainShape::Square { hole_diameter, .. } => {
            // Round, enclosed bright blobs: in a deposit of nuts most are holes.
            let mut diameters: Vec<f64> = blobs
                .iter()
                .filter(|b| b.area >= 6.0 && b.area / (b.extent * b.extent) > 0.55)
                .map(|b| 2.0 * (b.area / std::f64::consts::PI).sqrt())
                .collect();
            if diameters.len() < 5 {
                return None;
            }
            Some(median(&mut diameters) / hole_diameter)
        }
        GrainShape::Rod { width, .. } => {
            let thickness = ridge_half_thicknesses(dark);
            if thickness.len() < 20 {
                return None;
            }
            let mut t = thickness;
            t.sort_by(|a, b| a.total_cmp(b));
            // Single rods set the lower part of the distribution; rods merged face to face
            // only make regions thicker.
            let q = t[t.len() / 2];
            Some((2.0 * q + 1.0) / width)
        }
    }
}

/// Distance-transform values on the ridges (local maxima) of the dark area.
fn ridge_half_thicknesses(dark: &Plane) -> Vec<f64> {
    let (w, h) = (dark.width, dark.height);
    let field = GrayImage::from_fn(w as u32, h as u32, |c, r| {
        Luma([if dark.at(c as usize, r as usize) > 0.5 {
            0
        } else {
            255
        }])
    });
    let depth = euclidean_squared_distance_transform(&field);
    let mut out = Vec::new();
    for r in 1..h.saturating_sub(1) {
        for c in 1..w.saturating_sub(1) {
            let d = depth.get_pixel(c as u32, r as u32)[0];
            if d < 4.0 {
                continue;
            }
            // Ridge: no neighbour deeper (plateaus along a rod's axis count).
            let mut ridge = true;
            for (dc, dr) in [
                (-1i32, -1i32),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                if depth.get_pixel((c as i32 + dc) as u32, (r as i32 + dr) as u32)[0] > d {
                    ridge = false;
                    break;
                }
            }
            if ridge {
                out.push(d.sqrt());
            }
        }
    }
    out
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}
