//! A small test-image maker (independent of the crate's renderer): dense touching grains as
//! anti-aliased spheropolygons on an uneven bright field, with nut holes, rod highlights,
//! blur, noise and dust; and one-to-one matching against the truth.
#![allow(dead_code)]

use image::{DynamicImage, ImageBuffer, Luma};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vision::{Detection, GrainShape};

pub const MM: f64 = 1e-3;

pub fn nut() -> GrainShape {
    GrainShape::Square {
        side: 6.9 * MM,
        hole_diameter: 3.3 * MM,
    }
}

pub fn long_rod() -> GrainShape {
    GrainShape::Rod {
        length: 8.9 * MM,
        width: 3.0 * MM,
    }
}

pub fn short_rod() -> GrainShape {
    GrainShape::Rod {
        length: 4.9 * MM,
        width: 3.0 * MM,
    }
}

/// Grains (x, y in metres from the bottom-left, theta) in a width x height frame (metres).
pub struct Scene {
    pub shape: GrainShape,
    pub width: f64,
    pub height: f64,
    pub grains: Vec<(f64, f64, f64)>,
}

pub struct Style {
    pub blur_px: f32,
    pub noise: f32,
    /// Grain grey relative to the field.
    pub grain_level: f32,
    /// Rod highlight amplitude relative to the field.
    pub highlight: f32,
    pub dust: usize,
    pub sixteen_bit: bool,
    pub seed: u64,
}

impl Style {
    pub fn lab() -> Self {
        Style {
            blur_px: 0.8,
            noise: 0.02,
            grain_level: 0.12,
            highlight: 0.12,
            dust: 6,
            sixteen_bit: false,
            seed: 1,
        }
    }
}

/// Rods stacked face to face in columns that also touch end to end, the columns staggered:
/// a solid dark block whose only inner cues are the highlights and corner slivers.
pub fn rod_block(shape: GrainShape, angle: f64, columns: usize, stack: usize) -> Scene {
    rod_stacks(shape, angle, columns, stack, 0.0)
}

/// Columns of rods stacked face to face, `gap` (metres) between the columns' ends.
pub fn rod_stacks(shape: GrainShape, angle: f64, columns: usize, stack: usize, gap: f64) -> Scene {
    let (l, d) = (shape.length(), shape.width());
    let (s, c) = angle.sin_cos();
    let axis = (c, s);
    let normal = (-s, c);
    let mut grains = Vec::new();
    let (cx, cy) = (
        0.5 * (columns as f64 + 1.0) * l,
        0.5 * (stack as f64 + 1.0) * d,
    );
    for j in 0..stack {
        let shift = if j % 2 == 0 { 0.0 } else { 0.37 * l };
        for i in 0..columns {
            let a = (i as f64 - 0.5 * (columns as f64 - 1.0)) * (l + gap) + shift;
            let b = (j as f64 - 0.5 * (stack as f64 - 1.0)) * d;
            grains.push((a * axis.0 + b * normal.0, a * axis.1 + b * normal.1, angle));
        }
    }
    frame_around(shape, grains, cx.max(cy) * 2.0 + 4.0 * l)
}

/// Squares in a lattice tilted by `angle`, touching face to face, every other row sheared.
pub fn square_lattice(angle: f64, columns: usize, rows: usize) -> Scene {
    let shape = nut();
    let side = shape.width();
    let (s, c) = angle.sin_cos();
    let mut grains = Vec::new();
    for j in 0..rows {
        let shift = if j % 2 == 0 { 0.0 } else { 0.31 * side };
        for i in 0..columns {
            let a = (i as f64 - 0.5 * (columns as f64 - 1.0)) * side + shift;
            let b = (j as f64 - 0.5 * (rows as f64 - 1.0)) * side;
            grains.push((a * c - b * s, a * s + b * c, angle));
        }
    }
    let size = (columns.max(rows) as f64 + 3.0) * side * 1.5;
    frame_around(shape, grains, size)
}

fn frame_around(shape: GrainShape, grains: Vec<(f64, f64, f64)>, size: f64) -> Scene {
    let grains = grains
        .into_iter()
        .map(|(x, y, t)| (x + 0.5 * size, y + 0.5 * size, t))
        .collect();
    Scene {
        shape,
        width: size,
        height: size,
        grains,
    }
}

fn rounded_rect_sd(u: f64, v: f64, hl: f64, hw: f64, r: f64) -> f64 {
    let qx = u.abs() - (hl - r);
    let qy = v.abs() - (hw - r);
    qx.max(0.0).hypot(qy.max(0.0)) + qx.max(qy).min(0.0) - r
}

/// Renders the scene at `px_per_mm`: 4 x 4 supersampled coverage, then blur and noise.
pub fn render(scene: &Scene, px_per_mm: f64, style: &Style) -> DynamicImage {
    let scale = px_per_mm / MM;
    let cols = (scene.width * scale).round() as usize;
    let rows = (scene.height * scale).round() as usize;
    // Transmission in [0, 1]: 1 = field.
    let mut t = vec![1.0f32; cols * rows];
    let (l, d) = (scene.shape.length() * scale, scene.shape.width() * scale);
    let hole_r = match scene.shape {
        GrainShape::Square { hole_diameter, .. } => 0.5 * hole_diameter * scale,
        GrainShape::Rod { .. } => 0.0,
    };
    let is_rod = matches!(scene.shape, GrainShape::Rod { .. });
    let round = 0.05 * d;
    let n = 4;
    for &(x, y, theta) in &scene.grains {
        let px = x * scale;
        let py = rows as f64 - y * scale;
        let (s, c) = theta.sin_cos();
        let reach = 0.5 * l.hypot(d) + 2.0;
        let c0 = (px - reach).floor().max(0.0) as usize;
        let c1 = ((px + reach).ceil() as usize).min(cols);
        let r0 = (py - reach).floor().max(0.0) as usize;
        let r1 = ((py + reach).ceil() as usize).min(rows);
        for r in r0..r1 {
            for col in c0..c1 {
                let mut cover = 0.0;
                let mut light = 0.0;
                for sy in 0..n {
                    for sx in 0..n {
                        let dx = col as f64 + (sx as f64 + 0.5) / n as f64 - px;
                        let dy = r as f64 + (sy as f64 + 0.5) / n as f64 - py;
                        let u = dx * c - dy * s;
                        let v = dx * s + dy * c;
                        if rounded_rect_sd(u, v, 0.5 * l, 0.5 * d, round) > 0.0 {
                            continue;
                        }
                        if u.hypot(v) < hole_r {
                            continue;
                        }
                        cover += 1.0;
                        if is_rod && u.abs() < 0.5 * (l - d) {
                            light += (-(v * v) / (2.0 * (0.1 * d).powi(2))).exp();
                        }
                    }
                }
                let k = (n * n) as f64;
                let cover = cover / k;
                if cover > 0.0 {
                    let grain =
                        style.grain_level as f64 + style.highlight as f64 * light / k / cover;
                    let i = r * cols + col;
                    t[i] = (t[i] as f64 * (1.0 - cover) + grain.min(1.0) * cover).min(t[i] as f64)
                        as f32;
                }
            }
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(style.seed);
    // Dust: small dark specks on the glass.
    for _ in 0..style.dust {
        let (x, y) = (
            rng.random_range(0.0..cols as f64),
            rng.random_range(0.0..rows as f64),
        );
        let rad = 0.25 * px_per_mm;
        for r in (y - rad).max(0.0) as usize..((y + rad).ceil() as usize).min(rows) {
            for c in (x - rad).max(0.0) as usize..((x + rad).ceil() as usize).min(cols) {
                if (c as f64 + 0.5 - x).hypot(r as f64 + 0.5 - y) < rad {
                    t[r * cols + c] *= 0.4;
                }
            }
        }
    }
    let t = blur(&t, cols, rows, style.blur_px);
    let max = if style.sixteen_bit { 65535.0 } else { 255.0 };
    let px: Vec<f32> = t
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let (c, r) = (
                (i % cols) as f32 / cols as f32,
                (i / cols) as f32 / rows as f32,
            );
            // Uneven backlight: brighter off-centre, dimmer towards a corner.
            let field = 0.85 - 0.3 * ((c - 0.3).powi(2) + (r - 0.7).powi(2));
            let noise = style.noise
                * (rng.random::<f32>() + rng.random::<f32>() + rng.random::<f32>() - 1.5)
                * 2.0;
            ((v * field + noise).clamp(0.0, 1.0)) * max
        })
        .collect();
    if style.sixteen_bit {
        let raw: Vec<u16> = px.iter().map(|&v| v.round() as u16).collect();
        DynamicImage::ImageLuma16(
            ImageBuffer::<Luma<u16>, _>::from_raw(cols as u32, rows as u32, raw).unwrap(),
        )
    } else {
        let raw: Vec<u8> = px.iter().map(|&v| v.round() as u8).collect();
        DynamicImage::ImageLuma8(
            ImageBuffer::<Luma<u8>, _>::from_raw(cols as u32, rows as u32, raw).unwrap(),
        )
    }
}

fn blur(t: &[f32], cols: usize, rows: usize, sigma: f32) -> Vec<f32> {
    if sigma <= 0.0 {
        return t.to_vec();
    }
    let rad = (3.0 * sigma).ceil() as isize;
    let k: Vec<f32> = (-rad..=rad)
        .map(|i| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp())
        .collect();
    let sum: f32 = k.iter().sum();
    let pass = |src: &[f32], horizontal: bool| -> Vec<f32> {
        let mut out = vec![0.0f32; src.len()];
        for r in 0..rows as isize {
            for c in 0..cols as isize {
                let mut acc = 0.0;
                for (j, kv) in k.iter().enumerate() {
                    let o = j as isize - rad;
                    let (rr, cc) = if horizontal {
                        (r, (c + o).clamp(0, cols as isize - 1))
                    } else {
                        ((r + o).clamp(0, rows as isize - 1), c)
                    };
                    acc += kv * src[rr as usize * cols + cc as usize];
                }
                out[r as usize * cols + c as usize] = acc / sum;
            }
        }
        out
    };
    pass(&pass(t, true), false)
}

/// Matching of detections to the truth (nearest within half a grain width, one to one).
#[derive(Debug)]
pub struct Metrics {
    pub truth: usize,
    pub detected: usize,
    pub matched: usize,
    pub centre_rms_mm: f64,
    pub centre_max_mm: f64,
    pub angle_rms_deg: f64,
    pub angle_max_deg: f64,
}

impl Metrics {
    pub fn recall(&self) -> f64 {
        self.matched as f64 / self.truth.max(1) as f64
    }
    pub fn precision(&self) -> f64 {
        self.matched as f64 / self.detected.max(1) as f64
    }
}

pub fn compare(scene: &Scene, found: &[Detection]) -> Metrics {
    let period = scene.shape.symmetry_period();
    let mut used = vec![false; found.len()];
    let (mut n, mut se, mut emax, mut sa, mut amax) = (0, 0.0, 0.0f64, 0.0, 0.0f64);
    for &(x, y, t) in &scene.grains {
        let best = found
            .iter()
            .enumerate()
            .filter(|(i, _)| !used[*i])
            .map(|(i, d)| (i, (d.outline.x - x).hypot(d.outline.y - y)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((i, e)) = best
            && e < 0.5 * scene.shape.width()
        {
            used[i] = true;
            n += 1;
            se += e * e;
            emax = emax.max(e);
            let da = (found[i].outline.theta - t).rem_euclid(period);
            let da = da.min(period - da).to_degrees();
            sa += da * da;
            amax = amax.max(da);
        }
    }
    let m = n.max(1) as f64;
    Metrics {
        truth: scene.grains.len(),
        detected: found.len(),
        matched: n,
        centre_rms_mm: (se / m).sqrt() / MM,
        centre_max_mm: emax / MM,
        angle_rms_deg: (sa / m).sqrt(),
        angle_max_deg: amax,
    }
}
