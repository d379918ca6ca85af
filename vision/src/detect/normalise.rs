//! Backlight normalisation: divides out the uneven bright field and maps the photograph to a
//! darkness in [0, 1] (0 = bright field, 1 = grain interior), whatever the bit depth, exposure
//! or contrast.

use image::DynamicImage;
use rayon::prelude::*;

use super::plane::Plane;

/// Normalised photograph.
pub struct Darkness {
    pub plane: Plane,
    /// Fraction of pixels darker than half-way between field and grain.
    pub dark_fraction: f64,
}

/// Grey levels in [0, 1] of any 8/16-bit or float photograph.
pub fn grey_plane(image: &DynamicImage) -> Plane {
    let luma = image.to_luma32f();
    Plane {
        width: luma.width() as usize,
        height: luma.height() as usize,
        data: luma.into_raw(),
    }
}

/// `block`: side (pixels) of the cells the bright field is estimated on; about two grain
/// lengths, so that nearly every cell shows some light between or through the grains.
pub fn darkness(grey: &Plane, block: usize) -> Darkness {
    let smooth = grey.blurred(1.0);
    let field = bright_field(&smooth, block.max(8));
    let mut ratio = Plane::new(grey.width, grey.height, 0.0);
    ratio
        .data
        .par_iter_mut()
        .zip(grey.data.par_iter().zip(field.data.par_iter()))
        .for_each(|(r, (&g, &f))| *r = g / f.max(1e-6));
    let grain_level = grain_level(&ratio);
    let span = (1.0 - grain_level).max(0.05);
    let mut plane = ratio;
    plane
        .data
        .par_iter_mut()
        .for_each(|v| *v = ((1.0 - *v) / span).clamp(0.0, 1.0));
    let dark = plane.data.par_iter().filter(|&&d| d > 0.5).count();
    Darkness {
        dark_fraction: dark as f64 / plane.data.len().max(1) as f64,
        plane,
    }
}

/// Typical normalised grey of grain interiors: the median of pixels clearly below the field.
/// Falls back to black when nothing is dark (an empty photograph).
fn grain_level(ratio: &Plane) -> f32 {
    let dark = |v: &&f32| **v < 0.75;
    match median(&ratio.data, dark) {
        Some(m) => m.clamp(0.0, 0.7),
        None => 0.0,
    }
}

/// The element of rank n / 2 (as `select_nth_unstable` gives it) of the `n` values that pass
/// `keep`, or None for fewer than 16. In parallel and exact: a histogram of the values' top
/// 16 bits (in an order-preserving key) finds the bin that holds that rank, and only the
/// values in that bin are selected among.
fn median(values: &[f32], keep: impl Fn(&&f32) -> bool + Sync) -> Option<f32> {
    // Orders like f32::total_cmp.
    let key = |v: f32| {
        let b = v.to_bits();
        if b >> 31 == 1 { !b } else { b | 0x8000_0000 }
    };
    const BINS: usize = 1 << 16;
    let histogram = values
        .par_chunks(1 << 16)
        .map(|chunk| {
            let mut h = vec![0u32; BINS];
            for v in chunk.iter().filter(&keep) {
                h[(key(*v) >> 16) as usize] += 1;
            }
            h
        })
        .reduce(
            || vec![0u32; BINS],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let n: usize = histogram.iter().map(|&c| c as usize).sum();
    if n < 16 {
        return None;
    }
    let mut rank = n / 2;
    let bin = histogram
        .iter()
        .position(|&c| {
            if rank < c as usize {
                true
            } else {
                rank -= c as usize;
                false
            }
        })
        .expect("the rank lies in some bin");
    let mut in_bin: Vec<f32> = values
        .par_iter()
        .filter(|v| keep(v) && (key(**v) >> 16) as usize == bin)
        .copied()
        .collect();
    let (_, m, _) = in_bin.select_nth_unstable_by(rank, |a, b| a.total_cmp(b));
    Some(*m)
}

/// The bright field: per cell the brightest (blurred) level, cells with no light filled from
/// their neighbours, then interpolated bilinearly between cell centres.
fn bright_field(smooth: &Plane, block: usize) -> Plane {
    let bw = smooth.width.div_ceil(block);
    let bh = smooth.height.div_ceil(block);
    let mut cells: Vec<f32> = (0..bw * bh)
        .into_par_iter()
        .map(|i| {
            let (bx, by) = (i % bw, i / bw);
            let mut m = 0.0f32;
            for r in by * block..((by + 1) * block).min(smooth.height) {
                let line = &smooth.data[r * smooth.width..(r + 1) * smooth.width];
                for &v in &line[bx * block..((bx + 1) * block).min(smooth.width)] {
                    m = m.max(v);
                }
            }
            m
        })
        .collect();
    // A cell entirely covered by grains shows at best a corner sliver: its maximum is not
    // the field. Cells well below the typical maximum are re-estimated from neighbours.
    let mut sorted = cells.clone();
    sorted.sort_by(|a, b| a.total_cmp(b));
    let typical = sorted[(sorted.len() * 3) / 4];
    let mut valid: Vec<bool> = cells
        .iter()
        .map(|&c| c >= 0.7 * typical && c > 0.0)
        .collect();
    // Sliver-lit cells still underestimate: take the max over the 3 x 3 neighbourhood of
    // valid cells (the backlight varies on a scale much larger than a cell).
    let dilated: Vec<f32> = (0..bw * bh)
        .map(|i| {
            let (bx, by) = ((i % bw) as isize, (i / bw) as isize);
            let mut m = 0.0f32;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (x, y) = (bx + dx, by + dy);
                    if x >= 0 && y >= 0 && (x as usize) < bw && (y as usize) < bh {
                        let j = y as usize * bw + x as usize;
                        if valid[j] {
                            m = m.max(cells[j]);
                        }
                    }
                }
            }
            m
        })
        .collect();
    for (i, &d) in dilated.iter().enumerate() {
        if d > 0.0 {
            cells[i] = d;
            valid[i] = true;
        }
    }
    fill_from_neighbours(&mut cells, &mut valid, bw, bh, typical.max(1e-3));
    interpolate(&cells, bw, bh, block, smooth.width, smooth.height)
}

fn fill_from_neighbours(cells: &mut [f32], valid: &mut [bool], bw: usize, bh: usize, default: f32) {
    if !valid.iter().any(|&v| v) {
        cells.iter_mut().for_each(|c| *c = default);
        return;
    }
    while valid.iter().any(|&v| !v) {
        let snapshot = valid.to_vec();
        let values = cells.to_vec();
        for i in 0..bw * bh {
            if snapshot[i] {
                continue;
            }
            let (bx, by) = ((i % bw) as isize, (i / bw) as isize);
            let (mut s, mut n) = (0.0, 0);
            for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                let (x, y) = (bx + dx, by + dy);
                if x >= 0 && y >= 0 && (x as usize) < bw && (y as usize) < bh {
                    let j = y as usize * bw + x as usize;
                    if snapshot[j] {
                        s += values[j];
                        n += 1;
                    }
                }
            }
            if n > 0 {
                cells[i] = s / n as f32;
                valid[i] = true;
            }
        }
    }
}

fn interpolate(cells: &[f32], bw: usize, bh: usize, block: usize, w: usize, h: usize) -> Plane {
    let mut out = Plane::new(w, h, 0.0);
    let b = block as f32;
    // The columns' cells and weights, the same on every row.
    let columns: Vec<(usize, usize, f32)> = (0..w)
        .map(|c| {
            let fx = ((c as f32 + 0.5) / b - 0.5).clamp(0.0, (bw - 1) as f32);
            let x0 = fx.floor() as usize;
            (x0, (x0 + 1).min(bw - 1), fx - x0 as f32)
        })
        .collect();
    out.data
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(r, line)| {
            let fy = ((r as f32 + 0.5) / b - 0.5).clamp(0.0, (bh - 1) as f32);
            let y0 = fy.floor() as usize;
            let y1 = (y0 + 1).min(bh - 1);
            let ty = fy - y0 as f32;
            for (o, &(x0, x1, tx)) in line.iter_mut().zip(&columns) {
                let top = cells[y0 * bw + x0] * (1.0 - tx) + cells[y0 * bw + x1] * tx;
                let bottom = cells[y1 * bw + x0] * (1.0 - tx) + cells[y1 * bw + x1] * tx;
                *o = top * (1.0 - ty) + bottom * ty;
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::testing::Lcg;

    /// What `grain_level` computed before the histogram: select among the kept values.
    fn selected(values: &[f32], limit: f32) -> Option<f32> {
        let mut kept: Vec<f32> = values.iter().copied().filter(|&v| v < limit).collect();
        if kept.len() < 16 {
            return None;
        }
        let mid = kept.len() / 2;
        Some(*kept.select_nth_unstable_by(mid, |a, b| a.total_cmp(b)).1)
    }

    #[test]
    fn median_is_the_selected_element_with_ties_zeros_and_few_values() {
        let mut rng = Lcg(12345);
        let mut next = || rng.unit_f32();
        let spread: Vec<f32> = (0..300_001).map(|_| 1.2 * next()).collect();
        // Quantised to 1/256: many ties, and runs of exact zeros.
        let ties: Vec<f32> = (0..200_000)
            .map(|_| ((next() - 0.3).max(0.0) * 256.0).floor() / 256.0)
            .collect();
        let few: Vec<f32> = (0..40).map(|k| k as f32 / 40.0).collect();
        for values in [&spread, &ties, &few] {
            for limit in [0.75, 0.02, 2.0] {
                assert_eq!(
                    median(values, |v: &&f32| **v < limit),
                    selected(values, limit),
                    "limit {limit}, {} values",
                    values.len()
                );
            }
        }
    }
}
