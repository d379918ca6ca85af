//! Between deposit tables and photographs: grain outlines from a deposit, and the truth table
//! of a photograph.

use std::path::{Path, PathBuf};

use anyhow::bail;
use image::ImageFormat;
use vision::render::{Style, render};
use vision::{Frame, GrainOutline, GrainShape};

use crate::deposit::{Deposit, FrameMm, Grain, write_deposit_csv};
use crate::io::write_atomic;

/// The outline of a deposit grain: a nut (hole scaled with the side: 3.3 mm for 6.9 mm) when
/// its sides are equal, else a rod.
pub fn outline_of(grain: &Grain) -> GrainOutline {
    let shape = if grain.is_square() {
        GrainShape::nut(grain.width)
    } else {
        GrainShape::Rod {
            length: grain.length,
            width: grain.width,
        }
    };
    GrainOutline {
        x: grain.x,
        y: grain.y,
        theta: grain.theta,
        shape,
    }
}

/// A region of a deposit to photograph: its bottom-left corner in deposit coordinates and its
/// size (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub x0: f64,
    pub y0: f64,
    pub width: f64,
    pub height: f64,
}

impl Region {
    /// The region a frame in millimetres covers (`--frame-mm`).
    pub fn of_frame(frame: &FrameMm) -> Region {
        Region {
            x0: frame.x_min * 1e-3,
            y0: frame.y_min * 1e-3,
            width: frame.width_mm() * 1e-3,
            height: frame.height_mm() * 1e-3,
        }
    }

    /// The smallest region holding every grain of a deposit whole.
    pub fn around(deposit: &Deposit) -> Option<Region> {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for g in &deposit.grains {
            let r = 0.5 * g.length.hypot(g.width);
            b = [
                b[0].min(g.x - r),
                b[1].min(g.y - r),
                b[2].max(g.x + r),
                b[3].max(g.y + r),
            ];
        }
        (b[0] < b[2]).then(|| Region {
            x0: b[0],
            y0: b[1],
            width: b[2] - b[0],
            height: b[3] - b[1],
        })
    }
}

/// Largest photograph rendered, in pixels (about 10 bytes a pixel of working memory: 1 GB).
pub const MAX_PIXELS: f64 = 100e6;

/// The frame of a photograph of `region` at `px_per_mm`, checked: a finite positive scale
/// (`--px-per-mm`), a finite region of positive size (`--frame-mm`), at least one pixel and at
/// most [`MAX_PIXELS`].
pub fn photograph_frame(region: &Region, px_per_mm: f64) -> anyhow::Result<Frame> {
    if !(px_per_mm.is_finite() && px_per_mm > 0.0) {
        bail!("--px-per-mm is {px_per_mm}, expected a finite scale above 0 (pixels per mm)");
    }
    let Region {
        x0,
        y0,
        width,
        height,
    } = *region;
    if !([x0, y0, width, height].iter().all(|v| v.is_finite()) && width > 0.0 && height > 0.0) {
        bail!(
            "--frame-mm is {},{},{},{} mm, expected finite {} with x_min < x_max and \
             y_min < y_max",
            x0 * 1e3,
            (x0 + width) * 1e3,
            y0 * 1e3,
            (y0 + height) * 1e3,
            FrameMm::SYNTAX
        );
    }
    let scale = px_per_mm * 1e3;
    let frame = Frame {
        width,
        height,
        scale,
    };
    let pixels = (width * scale).round() * (height * scale).round();
    if pixels > MAX_PIXELS {
        bail!(
            "the photograph would have {:.0} Mpx (frame {:.1} x {:.1} mm at {px_per_mm:.2} px/mm); \
             the limit is {:.0} Mpx: lower --px-per-mm or give a smaller --frame-mm",
            pixels / 1e6,
            width * 1e3,
            height * 1e3,
            MAX_PIXELS / 1e6
        );
    }
    if frame.columns() == 0 || frame.rows() == 0 {
        bail!(
            "the frame ({:.3} x {:.3} mm) is smaller than one pixel at {px_per_mm} px/mm \
             (--px-per-mm, --frame-mm)",
            width * 1e3,
            height * 1e3
        );
    }
    Ok(frame)
}

/// Outlines of the deposit's grains that show in `region`, in frame coordinates (origin at the
/// region's bottom-left corner), and the truth table of the photograph: the same grains, frame
/// coordinates, folded angles, `cut` set for grains the frame cuts.
pub fn frame_deposit(
    deposit: &Deposit,
    region: &Region,
    frame: &Frame,
) -> (Vec<GrainOutline>, Deposit) {
    let mut outlines = Vec::new();
    let mut truth = Deposit::default();
    for g in &deposit.grains {
        let mut o = outline_of(g);
        o.x -= region.x0;
        o.y -= region.y0;
        if !o.overlaps_frame(frame) {
            continue;
        }
        outlines.push(o);
        truth.grains.push(
            Grain {
                x: o.x,
                y: o.y,
                confidence: Some(1.0),
                cut: o.is_cut_by(frame),
                ..*g
            }
            .folded(),
        );
    }
    (outlines, truth)
}

/// The truth table beside a photograph: `PHOTO.truth.csv`.
pub fn truth_path(photo: &Path) -> PathBuf {
    photo.with_extension("truth.csv")
}

/// Renders `outlines` over `frame` in `style` (noise, dust and light of `seed`) and writes the
/// photograph as a PNG of `bits` bits per pixel, with its truth table beside it
/// ([`truth_path`]), the truth first: a photograph on disk always has its truth.
pub fn write_photograph(
    path: &Path,
    outlines: &[GrainOutline],
    truth: &Deposit,
    frame: &Frame,
    style: &Style,
    seed: u64,
    bits: u8,
) -> anyhow::Result<PathBuf> {
    let image = render(outlines, frame, style, seed).to_image(bits);
    let truth_file = truth_path(path);
    write_deposit_csv(&truth_file, truth)?;
    write_atomic(path, |w| {
        image.write_to(w, ImageFormat::Png)?;
        Ok(())
    })?;
    Ok(truth_file)
}

/// The deposit table of generated or detected outlines (frame coordinates).
pub fn deposit_of(outlines: &[GrainOutline], frame: &Frame) -> Deposit {
    Deposit {
        grains: outlines
            .iter()
            .map(|o| {
                Grain {
                    x: o.x,
                    y: o.y,
                    theta: o.theta,
                    length: o.shape.length(),
                    width: o.shape.width(),
                    confidence: Some(1.0),
                    cut: o.is_cut_by(frame),
                }
                .folded()
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_become_nuts_with_scaled_holes() {
        let g = Grain::placed(0.01, 0.02, 0.1, 6.9e-3, 6.9e-3);
        let o = outline_of(&g);
        match o.shape {
            GrainShape::Square {
                side,
                hole_diameter,
            } => assert!(side == 6.9e-3 && (hole_diameter - 3.3e-3).abs() < 1e-12),
            other => panic!("a square grain became {other:?}"),
        }
        let rod = outline_of(&Grain {
            length: 8.9e-3,
            width: 3e-3,
            ..g
        });
        assert!(matches!(rod.shape, GrainShape::Rod { .. }));
    }
}
