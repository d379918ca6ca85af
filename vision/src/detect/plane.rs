//! A single-channel f32 image, row-major, the working format of every detector stage.

use rayon::prelude::*;

#[derive(Clone, Debug)]
pub struct Plane {
    pub width: usize,
    pub height: usize,
    pub data: Vec<f32>,
}

impl Plane {
    pub fn new(width: usize, height: usize, value: f32) -> Self {
        Plane {
            width,
            height,
            data: vec![value; width * height],
        }
    }

    #[inline]
    pub fn at(&self, col: usize, row: usize) -> f32 {
        self.data[row * self.width + col]
    }

    /// Mean over `factor` x `factor` blocks: the coarse level the pose search runs on.
    pub fn downsample(&self, factor: usize) -> Plane {
        if factor <= 1 {
            return self.clone();
        }
        let w = self.width.div_ceil(factor);
        let h = self.height.div_ceil(factor);
        let mut data = vec![0.0f32; w * h];
        data.par_chunks_mut(w).enumerate().for_each(|(r, out)| {
            for (c, o) in out.iter_mut().enumerate() {
                *o = self.block_mean(factor, c, r);
            }
        });
        Plane {
            width: w,
            height: h,
            data,
        }
    }

    /// Pixel (`col`, `row`) of [`Plane::downsample`] by `factor`: the mean of its block
    /// (partial at the right and bottom edges).
    pub fn block_mean(&self, factor: usize, col: usize, row: usize) -> f32 {
        if factor <= 1 {
            return self.data[row * self.width + col];
        }
        let r0 = row * factor;
        let r1 = (r0 + factor).min(self.height);
        let c0 = col * factor;
        let c1 = (c0 + factor).min(self.width);
        let mut sum = 0.0;
        for rr in r0..r1 {
            let line = &self.data[rr * self.width..];
            sum += line[c0..c1].iter().sum::<f32>();
        }
        sum / ((r1 - r0) * (c1 - c0)) as f32
    }

    /// Separable Gaussian blur (edges clamped).
    pub fn blurred(&self, sigma: f32) -> Plane {
        if sigma <= 0.0 {
            return self.clone();
        }
        let radius = (3.0 * sigma).ceil() as isize;
        let kernel: Vec<f32> = (-radius..=radius)
            .map(|i| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp())
            .collect();
        let norm: f32 = kernel.iter().sum();
        let kernel: Vec<f32> = kernel.iter().map(|k| k / norm).collect();
        let (w, h) = (self.width as isize, self.height as isize);
        let mut tmp = vec![0.0f32; self.data.len()];
        tmp.par_chunks_mut(self.width)
            .enumerate()
            .for_each(|(r, out)| {
                let line = &self.data[r * self.width..(r + 1) * self.width];
                let clamped = |c: usize| {
                    let mut s = 0.0;
                    for (k, kv) in kernel.iter().enumerate() {
                        let cc = (c as isize + k as isize - radius).clamp(0, w - 1) as usize;
                        s += kv * line[cc];
                    }
                    s
                };
                let span = kernel.len() - 1;
                if line.len() <= span {
                    out.iter_mut()
                        .enumerate()
                        .for_each(|(c, o)| *o = clamped(c));
                    return;
                }
                // Inside, tap by tap over the whole row, which vectorises; each output adds
                // its taps in the same order as at the edges, so the sums are the same.
                let (lo, hi) = (radius as usize, line.len() - radius as usize);
                for (k, kv) in kernel.iter().enumerate() {
                    let taps = &line[k..k + hi - lo];
                    for (o, v) in out[lo..hi].iter_mut().zip(taps) {
                        *o += kv * v;
                    }
                }
                for c in (0..lo).chain(hi..line.len()) {
                    out[c] = clamped(c);
                }
            });
        let mut data = vec![0.0f32; self.data.len()];
        data.par_chunks_mut(self.width)
            .enumerate()
            .for_each(|(r, out)| {
                for (k, kv) in kernel.iter().enumerate() {
                    let rr = (r as isize + k as isize - radius).clamp(0, h - 1) as usize;
                    let line = &tmp[rr * self.width..(rr + 1) * self.width];
                    for (o, v) in out.iter_mut().zip(line) {
                        *o += kv * v;
                    }
                }
            });
        Plane {
            width: self.width,
            height: self.height,
            data,
        }
    }
}

/// The eight neighbours of a pixel, as (column, row) offsets, in raster order.
pub const NEIGHBOURS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// A plane with a border of one pixel repeating its edge, what the tap sums read: a pixel's
/// right and lower neighbours are always there (read as one pair), and a neighbour index
/// clamped onto the border reads what clamping it onto the plane would.
#[derive(Clone, Debug)]
pub struct Bordered {
    /// Size of the plane inside the border.
    pub width: usize,
    pub height: usize,
    /// Row length with the border (width + 2).
    pub stride: usize,
    /// height + 2 rows of `stride`: pixel (c, r) of the plane at (r + 1) * stride + c + 1.
    pub data: Vec<f32>,
}

impl Bordered {
    pub fn new(plane: &Plane) -> Self {
        let (width, height) = (plane.width, plane.height);
        let stride = width + 2;
        let mut data = Vec::with_capacity(stride * (height + 2));
        for r in 0..height + 2 {
            let row = r.saturating_sub(1).min(height.saturating_sub(1));
            let line = &plane.data[row * width..(row + 1) * width];
            data.push(line.first().copied().unwrap_or(0.0));
            data.extend_from_slice(line);
            data.push(line.last().copied().unwrap_or(0.0));
        }
        Bordered {
            width,
            height,
            stride,
            data,
        }
    }

    /// Sets pixel (col, row) of the plane, and its copies in the border.
    pub fn set(&mut self, col: usize, row: usize, value: f32) {
        // Off the edges (nearly every pixel painted) the pixel has no copy.
        if col > 0 && row > 0 && col + 1 < self.width && row + 1 < self.height {
            self.data[(row + 1) * self.stride + col + 1] = value;
            return;
        }
        let copies = |i: usize, n: usize| {
            // Padded index of the pixel, and of its copy when it lies on an edge.
            let first = (i == 0).then_some(0);
            let last = (i + 1 == n).then_some(n + 1);
            [Some(i + 1), first, last].into_iter().flatten()
        };
        for r in copies(row, self.height) {
            for c in copies(col, self.width) {
                self.data[r * self.stride + c] = value;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The blur's rows, summed tap by tap inside, are bit for bit the clamped sum at every
    /// pixel, for rows shorter than the kernel too.
    #[test]
    fn blur_inside_and_at_the_edges_is_the_clamped_sum() {
        for (w, h, sigma) in [
            (1, 1, 1.0f32),
            (5, 3, 1.0),
            (7, 4, 1.0),
            (40, 9, 1.7),
            (300, 5, 3.0),
        ] {
            let mut plane = Plane::new(w, h, 0.0);
            for (i, v) in plane.data.iter_mut().enumerate() {
                *v = ((i * 7919) % 101) as f32 / 100.0;
            }
            let radius = (3.0 * sigma).ceil() as isize;
            let kernel: Vec<f32> = (-radius..=radius)
                .map(|i| (-(i * i) as f32 / (2.0 * sigma * sigma)).exp())
                .collect();
            let norm: f32 = kernel.iter().sum();
            let kernel: Vec<f32> = kernel.iter().map(|k| k / norm).collect();
            let clamp = |c: isize, r: isize| {
                plane.at(
                    c.clamp(0, w as isize - 1) as usize,
                    r.clamp(0, h as isize - 1) as usize,
                )
            };
            let blurred = plane.blurred(sigma);
            for r in 0..h as isize {
                for c in 0..w as isize {
                    let mut want = 0.0f32;
                    for (j, kj) in kernel.iter().enumerate() {
                        let rr = r + j as isize - radius;
                        let mut row = 0.0f32;
                        for (k, kv) in kernel.iter().enumerate() {
                            row += kv * clamp(c + k as isize - radius, rr);
                        }
                        want += kj * row;
                    }
                    let got = blurred.at(c as usize, r as usize);
                    assert_eq!(
                        got.to_bits(),
                        want.to_bits(),
                        "{w} x {h}, sigma {sigma}, at ({c}, {r})"
                    );
                }
            }
        }
    }

    /// The border repeats the edge, also after pixels on the edge and in corners are set.
    #[test]
    fn border_repeats_the_edge() {
        let mut plane = Plane::new(4, 3, 0.0);
        for (i, v) in plane.data.iter_mut().enumerate() {
            *v = i as f32;
        }
        let mut bordered = Bordered::new(&plane);
        for (c, r, v) in [
            (0, 0, 50.0),
            (3, 2, 60.0),
            (1, 0, 70.0),
            (3, 1, 80.0),
            (2, 1, 90.0),
        ] {
            plane.data[r * 4 + c] = v;
            bordered.set(c, r, v);
        }
        for r in -1..=3i32 {
            for c in -1..=4i32 {
                let clamped = plane.at(c.clamp(0, 3) as usize, r.clamp(0, 2) as usize);
                let i = (r + 1) as usize * bordered.stride + (c + 1) as usize;
                assert_eq!(bordered.data[i], clamped, "at ({c}, {r})");
            }
        }
    }
}
