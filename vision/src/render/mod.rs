//! Synthetic backlit photographs of grain outlines.
//!
//! Light passes the glass, is stopped by the grains (dark with anti-aliased edges, through the
//! nuts' holes it passes), is dimmed by dust and scratches, blurred by the lens, scaled by an
//! uneven backlight, and read by a noisy sensor. Edges are anti-aliased analytically: a pixel's
//! coverage is its signed distance to the rounded outline over a one-pixel ramp, and the
//! coverages of different grains add (they do not overlap), so two faces that touch leave no
//! light between them while the rounded corners do.

mod blur;
mod glass;
mod light;
mod look;
mod style;

pub use look::{Look, LookRange};
pub use style::Style;

use image::{DynamicImage, GrayImage, ImageBuffer, Luma};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::{Frame, GrainOutline, GrainShape};
use glass::Mark;
use light::Backlight;

/// A rendered photograph: sensor levels in [0, 1], row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Photograph {
    pub columns: u32,
    pub rows: u32,
    pub levels: Vec<f32>,
}

impl Photograph {
    /// 16-bit greyscale (full scale 65535).
    pub fn to_luma16(&self) -> ImageBuffer<Luma<u16>, Vec<u16>> {
        let data = self
            .levels
            .iter()
            .map(|&v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16)
            .collect();
        ImageBuffer::from_raw(self.columns, self.rows, data).expect("size matches")
    }

    /// 8-bit greyscale (full scale 255).
    pub fn to_luma8(&self) -> GrayImage {
        let data = self
            .levels
            .iter()
            .map(|&v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect();
        ImageBuffer::from_raw(self.columns, self.rows, data).expect("size matches")
    }

    /// The photograph at a bit depth (8 or 16) as a `DynamicImage`.
    pub fn to_image(&self, bits: u8) -> DynamicImage {
        if bits == 8 {
            DynamicImage::ImageLuma8(self.to_luma8())
        } else {
            DynamicImage::ImageLuma16(self.to_luma16())
        }
    }
}

/// Side of the square tiles that index which grains and marks reach which pixels.
const TILE: usize = 32;

/// A grain prepared for drawing.
struct Stamp {
    outline: GrainOutline,
    axes: ([f64; 2], [f64; 2]),
    hole_radius: f64,
    /// Outer radius of the bore's chamfer ring, and how much of the light the ring sends back.
    chamfer_radius: f64,
    chamfer_glint: f64,
    /// Peak of the axis highlight (rods), and its standard deviation across the axis (metres).
    highlight: f64,
    highlight_sigma: f64,
    /// Squared distance from the centre beyond which the grain covers nothing of a pixel.
    reach_squared: f64,
}

/// Draws the grains in `frame` as `style` asks. The same grains, frame, style and seed give the
/// same photograph whatever the number of threads.
pub fn render(grains: &[GrainOutline], frame: &Frame, style: &Style, seed: u64) -> Photograph {
    let columns = frame.columns() as usize;
    let rows = frame.rows() as usize;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let backlight = Backlight::new(
        style,
        rng.random::<f64>() * std::f64::consts::TAU,
        frame.columns(),
        frame.rows(),
    );
    let marks = glass::marks(frame, style, &mut rng);
    let noise_seed: u64 = rng.random();

    let stamps: Vec<Stamp> = grains
        .iter()
        .filter(|g| g.overlaps_frame(frame))
        .map(|g| Stamp {
            outline: *g,
            axes: g.axes(),
            hole_radius: style.bore_scale * g.hole_radius(),
            chamfer_radius: style.bore_scale * g.hole_radius() + style.chamfer_mm * 1e-3,
            chamfer_glint: style.chamfer_glint,
            highlight: match g.shape {
                GrainShape::Rod { .. } => style.rod_highlight,
                GrainShape::Square { .. } => 0.0,
            },
            highlight_sigma: style.rod_highlight_width * g.shape.width(),
            reach_squared: (g.shape.bounding_radius() + 1.0 / frame.scale).powi(2),
        })
        .collect();
    let tiles_x = columns.div_ceil(TILE).max(1);
    let tiles_y = rows.div_ceil(TILE).max(1);
    let grain_tiles = tile_index(
        stamps.iter().map(|s| {
            let r = s.outline.shape.bounding_radius();
            [
                s.outline.x - r,
                s.outline.y - r,
                s.outline.x + r,
                s.outline.y + r,
            ]
        }),
        frame,
        tiles_x,
        tiles_y,
    );
    let mark_tiles = tile_index(marks.iter().map(Mark::bounds), frame, tiles_x, tiles_y);

    let mut transmission = vec![1.0f32; columns * rows];
    let opaque = 1.0 - style.grain_transmission;
    transmission
        .par_chunks_mut(columns.max(1))
        .enumerate()
        .for_each(|(row, out)| {
            let tile_row = row / TILE;
            for (column, t) in out.iter_mut().enumerate() {
                let tile = tile_row * tiles_x + column / TILE;
                let (x, y) = frame.to_frame(column as f64 + 0.5, row as f64 + 0.5);
                let mut blocked = 0.0;
                for &i in &grain_tiles[tile] {
                    blocked += grain_blocking(&stamps[i as usize], x, y, frame.scale) * opaque;
                }
                let mut light = (1.0 - blocked).max(0.0);
                for &i in &mark_tiles[tile] {
                    light *= 1.0 - marks[i as usize].blocking(x, y, frame.scale);
                }
                *t = light as f32;
            }
        });

    blur::gaussian(&mut transmission, columns, rows, style.blur_px);

    transmission
        .par_chunks_mut(columns.max(1))
        .enumerate()
        .for_each(|(row, out)| {
            let mut rng = ChaCha8Rng::seed_from_u64(noise_seed);
            rng.set_stream(row as u64);
            for (pair, vs) in out.chunks_mut(2).enumerate() {
                let noise = light::standard_normal_pair(&mut rng);
                for (k, v) in vs.iter_mut().enumerate() {
                    let column = 2 * pair + k;
                    let field = backlight.at(column as f64 + 0.5, row as f64 + 0.5) as f32;
                    let level = style.black_level as f32 + field * *v;
                    let normal = if k == 0 { noise.0 } else { noise.1 };
                    *v = (level + light::sensor_sigma(level, style) * normal).clamp(0.0, 1.0);
                }
            }
        });
    Photograph {
        columns: columns as u32,
        rows: rows as u32,
        levels: transmission,
    }
}

/// Fraction of the light a grain blocks at a frame point (before its transmission), with the
/// hole open and the axis highlight taken off.
fn grain_blocking(s: &Stamp, x: f64, y: f64, scale: f64) -> f64 {
    let (dx, dy) = (x - s.outline.x, y - s.outline.y);
    if dx * dx + dy * dy > s.reach_squared {
        return 0.0;
    }
    let (u, v) = s.axes;
    let (lx, ly) = (dx * u[0] + dy * u[1], dx * v[0] + dy * v[1]);
    let distance = s.outline.local_signed_distance(lx, ly);
    let mut coverage = (0.5 - distance * scale).clamp(0.0, 1.0);
    if coverage == 0.0 {
        return 0.0;
    }
    if s.hole_radius > 0.0 {
        let radius = (lx * lx + ly * ly).sqrt();
        let hole = (0.5 - (radius - s.hole_radius) * scale).clamp(0.0, 1.0);
        coverage = (coverage - hole).max(0.0);
        if s.chamfer_glint > 0.0 && s.chamfer_radius > s.hole_radius {
            let disc = (0.5 - (radius - s.chamfer_radius) * scale).clamp(0.0, 1.0);
            coverage *= 1.0 - s.chamfer_glint * (disc - hole).max(0.0);
        }
    }
    if s.highlight > 0.0 {
        let across = ly / s.highlight_sigma;
        coverage *= 1.0 - s.highlight * (-0.5 * across * across).exp();
    }
    coverage
}

/// For each tile, the items whose bounding box (frame metres) reaches it.
fn tile_index(
    bounds: impl Iterator<Item = [f64; 4]>,
    frame: &Frame,
    tiles_x: usize,
    tiles_y: usize,
) -> Vec<Vec<u32>> {
    let mut tiles = vec![Vec::new(); tiles_x * tiles_y];
    // One pixel of slack for the anti-aliasing ramp.
    let slack = 1.0;
    for (i, [x0, y0, x1, y1]) in bounds.enumerate() {
        let (c0, r1) = frame.to_pixel(x0, y0);
        let (c1, r0) = frame.to_pixel(x1, y1);
        let tile_of = |p: f64, n: usize| ((p / TILE as f64).floor().max(0.0) as usize).min(n - 1);
        if c1 + slack < 0.0 || r1 + slack < 0.0 {
            continue;
        }
        let (tx0, tx1) = (tile_of(c0 - slack, tiles_x), tile_of(c1 + slack, tiles_x));
        let (ty0, ty1) = (tile_of(r0 - slack, tiles_y), tile_of(r1 + slack, tiles_y));
        for ty in ty0..=ty1 {
            for tx in tx0..=tx1 {
                tiles[ty * tiles_x + tx].push(i as u32);
            }
        }
    }
    tiles
}
