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
            let r0 = r * factor;
            let r1 = (r0 + factor).min(self.height);
            for (c, o) in out.iter_mut().enumerate() {
                let c0 = c * factor;
                let c1 = (c0 + factor).min(self.width);
                let mut sum = 0.0;
                for rr in r0..r1 {
                    let line = &self.data[rr * self.width..];
                    sum += line[c0..c1].iter().sum::<f32>();
                }
                *o = sum / ((r1 - r0) * (c1 - c0)) as f32;
            }
        });
        Plane {
            width: w,
            height: h,
            data,
        }
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
                for (c, o) in out.iter_mut().enumerate() {
                    let mut s = 0.0;
                    for (k, kv) in kernel.iter().enumerate() {
                        let cc = (c as isize + k as isize - radius).clamp(0, w - 1) as usize;
                        s += kv * line[cc];
                    }
                    *o = s;
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
