//! Plausibility of the stated scale: the grains' own sizes measured in the photograph (the
//! nuts' holes; the thickness of dark regions for rods) compared with what the scale predicts.
//!
//! The measurement is a heuristic: blur and low contrast thin the dark area and merge holes
//! into the field, and a blurred, low-contrast photograph at 6 px/mm measured 1.8 and 3.1
//! px/mm. So by default a disagreement is a warning naming both scales ([`ScaleCheck::Warn`]),
//! and the photograph is detected at the stated scale: a correct photograph is never refused,
//! and a wrong scale or outline still shows in the warning and in the fraction of the dark
//! area the grains found explain.

use std::str::FromStr;

use image::{GrayImage, Luma};
use imageproc::distance_transform::euclidean_squared_distance_transform;

use super::DetectError;
use super::plane::{NEIGHBOURS, Plane};
use super::seeds::BrightBlob;
use crate::GrainShape;

/// What to do when the scale measured in a photograph disagrees with the stated one
/// (`facets detect --scale-check`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ScaleCheck {
    /// Detect at the stated scale and warn with the scale measured.
    #[default]
    Warn,
    /// Refuse the photograph, naming both scales.
    Refuse,
    /// Measure nothing.
    Off,
}

impl ScaleCheck {
    pub const NAMES: [&'static str; 3] = ["warn", "refuse", "off"];
}

impl FromStr for ScaleCheck {
    type Err = DetectError;

    fn from_str(s: &str) -> Result<Self, DetectError> {
        match s {
            "warn" => Ok(ScaleCheck::Warn),
            "refuse" => Ok(ScaleCheck::Refuse),
            "off" => Ok(ScaleCheck::Off),
            _ => Err(DetectError::InvalidParams(format!(
                "scale check (--scale-check) is `{s}`, expected one of {}",
                ScaleCheck::NAMES.join(", ")
            ))),
        }
    }
}

impl std::fmt::Display for ScaleCheck {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ScaleCheck::Warn => "warn",
            ScaleCheck::Refuse => "refuse",
            ScaleCheck::Off => "off",
        })
    }
}

/// The stated scale `given` against the one `measured` (pixels per metre): `None` when they
/// agree, a warning when they do not and `check` warns, an error when it refuses.
pub fn judge(
    shape: GrainShape,
    given: f64,
    measured: f64,
    check: ScaleCheck,
) -> Result<Option<String>, DetectError> {
    let ratio = measured / given;
    let (low, high, what) = match shape {
        GrainShape::Square { .. } => (0.75, 1.33, "the size of the nuts' holes"),
        GrainShape::Rod { .. } => (0.6, 1.7, "the thickness of the dark grains"),
    };
    if (low..=high).contains(&ratio) || check == ScaleCheck::Off {
        return Ok(None);
    }
    let (given_px_per_mm, measured_px_per_mm) = (given * 1e-3, measured * 1e-3);
    match check {
        ScaleCheck::Refuse => Err(DetectError::ImplausibleScale {
            given_px_per_mm,
            measured_px_per_mm,
            what,
        }),
        _ => Ok(Some(format!(
            "the stated scale {given_px_per_mm:.2} px/mm (--px-per-mm) disagrees with the \
             {measured_px_per_mm:.2} px/mm that {what} suggests; detected at the stated scale \
             (check --px-per-mm and --shape; --scale-check refuse refuses such photographs)"
        ))),
    }
}

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
            let q = single_rod_half_thickness(&thickness);
            Some((2.0 * q + 1.0) / width)
        }
    }
}

/// The half-thickness (px) of a single rod among the ridge values of the dark area. Rods lying
/// face to face merge into regions two and three rods thick, whose ridges cluster at twice and
/// three times the single rod's value; in an ordered deposit they can hold most of the ridge
/// (a photograph of rows and stacks gave 205, 107 and 104 ridge pixels at 15, 30 and 45 px),
/// so the median would measure a double rod. The single rod is the thinnest cluster that holds
/// a quarter as many ridge pixels as the fullest one; stray short ridges (the branches of the
/// medial axis into corners, specks) hold far fewer.
fn single_rod_half_thickness(thickness: &[f64]) -> f64 {
    let top = thickness.iter().copied().fold(0.0, f64::max) as usize;
    let mut counts = vec![0usize; top + 3];
    for &t in thickness {
        counts[t as usize + 1] += 1;
    }
    // Counts of three neighbouring 1 px bins: a cluster split across a bin edge stays whole.
    let smooth: Vec<usize> = (1..=top + 1)
        .map(|k| counts[k - 1] + counts[k] + counts[k + 1])
        .collect();
    let fullest = smooth.iter().copied().max().unwrap_or(0);
    let peak = (0..smooth.len())
        .find(|&k| {
            4 * smooth[k] >= fullest
                && (k == 0 || smooth[k] >= smooth[k - 1])
                && (k + 1 == smooth.len() || smooth[k] >= smooth[k + 1])
        })
        .unwrap_or(0) as f64
        + 0.5;
    // The three bins counted at the peak lie within 1.5 px of its centre: never empty.
    let mut near: Vec<f64> = thickness
        .iter()
        .copied()
        .filter(|&t| (t - peak).abs() <= 0.2 * peak + 1.5)
        .collect();
    median(&mut near)
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
            for (dc, dr) in NEIGHBOURS {
                if depth.get_pixel((c as isize + dc) as u32, (r as isize + dr) as u32)[0] > d {
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

#[cfg(test)]
mod tests {
    use super::single_rod_half_thickness;

    /// Ridge values spread over 1 px bins: `counts[k]` values in [k, k + 1).
    fn spread(counts: &[usize]) -> Vec<f64> {
        let mut t = Vec::new();
        for (k, &n) in counts.iter().enumerate() {
            t.extend((0..n).map(|i| k as f64 + (i as f64 + 0.5) / n as f64));
        }
        t
    }

    #[test]
    fn stacks_of_rods_do_not_double_the_single_rod() {
        // The ridge histogram of a rendered deposit of long rods (3 mm at 10 px/mm: a single
        // rod is 15 px thick on each side of its axis) lying in rows and stacks, which the
        // median took for 20.3 px/mm: single, double and triple rods at 15, 30 and 45 px.
        let ordered = spread(&[
            0, 0, 0, 12, 0, 3, 3, 2, 0, 1, 1, 0, 2, 1, 5, 205, 14, 0, 1, 0, 3, 0, 1, 0, 0, 0, 0, 0,
            0, 10, 107, 15, 21, 5, 6, 1, 0, 0, 0, 3, 6, 9, 29, 7, 4, 104, 10, 11, 3, 2, 2, 1, 1, 0,
            0, 0, 0, 0, 0, 0, 0, 4, 2, 2, 1, 1, 0, 0, 1,
        ]);
        let half = single_rod_half_thickness(&ordered);
        assert!((15.0..16.0).contains(&half), "{half}");
        // Loose rods: the single rod is also the fullest cluster.
        let loose = spread(&[
            0, 0, 4, 2, 1, 3, 1, 2, 40, 180, 30, 2, 0, 3, 1, 0, 0, 9, 12, 2,
        ]);
        let half = single_rod_half_thickness(&loose);
        assert!((9.0..10.0).contains(&half), "{half}");
    }
}
