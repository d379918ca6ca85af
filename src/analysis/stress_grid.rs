//! The coarse-grained stress on a whole grid at once, by Fourier series: the same field as
//! [`super::coarse_grain::stress_at`] (Gaussian kernel, exact line integrals), evaluated in
//! O(contacts x modes + grid x modes) instead of O(grid x contacts in reach).
//!
//! The field is the convolution of the kernel with the contacts' line measures. On a periodic
//! box padded by the cut-off radius c w on every side, each branch's line measure has the exact
//! transform (e^{-ik.b} - e^{-ik.a}) / (i k.v), and the kernel's is exp(-k^2 w^2 / 4). Modes are
//! kept for |k| <= 2c/w, where the kernel's transform has fallen to exp(-c^2): both the
//! truncation and the periodic images (at least 2 c w away) are bounded by exp(-c^2) relative,
//! the same bound as the direct sum's cut-off.
//!
//! Parallel over rows of modes and over grid rows; each sum runs in a fixed order, so the
//! result does not depend on the thread count.

use rayon::prelude::*;

use super::coarse_grain::{Branch, CoarseGrainInput, Stress};

#[derive(Clone, Copy, Debug, Default)]
struct C(f64, f64);

impl C {
    #[inline]
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    #[inline]
    fn expi(phase: f64) -> C {
        let (s, c) = phase.sin_cos();
        C(c, s)
    }
}

/// Stress at every (x, y) of the grid xs x ys, row by row (y outer, x inner), like
/// [`super::coarse_grain::grid_points`].
pub fn stress_on_grid(
    branches: &[Branch],
    xs: &[f64],
    ys: &[f64],
    input: &CoarseGrainInput,
) -> Vec<Stress> {
    if branches.is_empty() || xs.is_empty() || ys.is_empty() {
        return vec![[0.0; 4]; xs.len() * ys.len()];
    }
    let w = input.w;
    let reach = input.cutoff * w;
    let (mut lo, mut hi) = (
        [xs[0].min(xs[xs.len() - 1]), ys[0].min(ys[ys.len() - 1])],
        [xs[0].max(xs[xs.len() - 1]), ys[0].max(ys[ys.len() - 1])],
    );
    for &x in xs {
        lo[0] = lo[0].min(x);
        hi[0] = hi[0].max(x);
    }
    for &y in ys {
        lo[1] = lo[1].min(y);
        hi[1] = hi[1].max(y);
    }
    for b in branches {
        for k in 0..2 {
            lo[k] = lo[k].min(b.a[k].min(b.b[k]));
            hi[k] = hi[k].max(b.a[k].max(b.b[k]));
        }
    }
    // Period: the extent plus the reach on each side, so every image is at least 2 reach away.
    let len = [hi[0] - lo[0] + 2.0 * reach, hi[1] - lo[1] + 2.0 * reach];
    let k_max = 2.0 * input.cutoff / w;
    let dk = [
        std::f64::consts::TAU / len[0],
        std::f64::consts::TAU / len[1],
    ];
    let nkx = (k_max / dk[0]).ceil() as usize;
    let nky = (k_max / dk[1]).ceil() as i64;
    let kys: Vec<f64> = (-nky..=nky).map(|n| n as f64 * dk[1]).collect();

    struct Prep {
        a: [f64; 2],
        b: [f64; 2],
        v: [f64; 2],
        t: [f64; 4],
    }
    // Coordinates relative to the box corner keep the phases small.
    let prep: Vec<Prep> = branches
        .iter()
        .map(|br| {
            let a = [br.a[0] - lo[0], br.a[1] - lo[1]];
            let b = [br.b[0] - lo[0], br.b[1] - lo[1]];
            let v = [a[0] - b[0], a[1] - b[1]];
            Prep {
                a,
                b,
                v,
                t: [
                    -br.force[0] * v[0],
                    -br.force[0] * v[1],
                    -br.force[1] * v[0],
                    -br.force[1] * v[1],
                ],
            }
        })
        .collect();

    // Coefficients c_hat(kx_m, ky_n) for m = 0..=nkx (the field is real: negative kx are the
    // conjugates), times the kernel's transform; zero outside |k| <= k_max.
    let coefficients: Vec<Vec<[C; 4]>> = kys
        .par_iter()
        .map(|&ky| {
            let mut row = vec![[C::default(); 4]; nkx + 1];
            let m_max = if ky.abs() > k_max {
                return row;
            } else {
                (((k_max * k_max - ky * ky).sqrt() / dk[0]).floor() as usize).min(nkx)
            };
            for p in &prep {
                let mut ea = C::expi(-ky * p.a[1]);
                let mut eb = C::expi(-ky * p.b[1]);
                let sa = C::expi(-dk[0] * p.a[0]);
                let sb = C::expi(-dk[0] * p.b[0]);
                for (m, slot) in row.iter_mut().enumerate().take(m_max + 1) {
                    let kx = m as f64 * dk[0];
                    let theta = kx * p.v[0] + ky * p.v[1];
                    // (e^{-ik.b} - e^{-ik.a}) / (i theta), with e^{-ik.b} = e^{-ik.a} e^{i theta}.
                    let f = if theta.abs() > 1e-4 {
                        let inv = 1.0 / theta;
                        C((eb.1 - ea.1) * inv, (ea.0 - eb.0) * inv)
                    } else {
                        ea.mul(C(1.0 - theta * theta / 6.0, 0.5 * theta))
                    };
                    for (acc, t) in slot.iter_mut().zip(p.t) {
                        acc.0 += t * f.0;
                        acc.1 += t * f.1;
                    }
                    ea = ea.mul(sa);
                    eb = eb.mul(sb);
                }
            }
            for (m, slot) in row.iter_mut().enumerate() {
                let kx = m as f64 * dk[0];
                let k2 = kx * kx + ky * ky;
                let kernel = if k2 <= k_max * k_max {
                    (-k2 * w * w / 4.0).exp() * if m == 0 { 1.0 } else { 2.0 }
                } else {
                    0.0
                };
                for c in slot.iter_mut() {
                    c.0 *= kernel;
                    c.1 *= kernel;
                }
            }
            row
        })
        .collect();

    // Sum over kx for each x: G[n][i] = sum_m c(m, n) e^{i kx_m x_i}.
    let g: Vec<Vec<[C; 4]>> = coefficients
        .par_iter()
        .map(|row| {
            xs.iter()
                .map(|&x| {
                    let step = C::expi(dk[0] * (x - lo[0]));
                    let mut e = C(1.0, 0.0);
                    let mut acc = [C::default(); 4];
                    for c in row {
                        for k in 0..4 {
                            let z = c[k].mul(e);
                            acc[k].0 += z.0;
                            acc[k].1 += z.1;
                        }
                        e = e.mul(step);
                    }
                    acc
                })
                .collect()
        })
        .collect();
    let area = len[0] * len[1];
    ys.par_iter()
        .flat_map_iter(|&y| {
            let phases: Vec<C> = kys.iter().map(|ky| C::expi(ky * (y - lo[1]))).collect();
            let g = &g;
            (0..xs.len()).map(move |i| {
                let mut s = [0.0; 4];
                for (n, e) in phases.iter().enumerate() {
                    for k in 0..4 {
                        // Real part of G e^{i ky y}.
                        s[k] += g[n][i][k].0 * e.0 - g[n][i][k].1 * e.1;
                    }
                }
                s.map(|v| v / area)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::coarse_grain::{grid_points, linspace, stress_at};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn fourier_grid_equals_direct_sum() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let d = 3e-3;
        // Random branches of length ~D in any direction, random forces: no structure to help.
        let branches: Vec<Branch> = (0..400)
            .map(|_| {
                let a = [rng.random_range(0.0..0.08), rng.random_range(0.0..0.05)];
                let ang: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let l = d * rng.random_range(0.0..1.5);
                Branch {
                    a,
                    b: [a[0] + l * ang.cos(), a[1] + l * ang.sin()],
                    force: [rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)],
                }
            })
            .collect();
        let input = CoarseGrainInput::new(3.0 * d);
        let xs = linspace(-0.01, 0.09, 23);
        let ys = linspace(-0.005, 0.055, 17);
        let fast = stress_on_grid(&branches, &xs, &ys, &input);
        let direct = stress_at(&branches, &grid_points(&xs, &ys), &input);
        let scale = direct
            .iter()
            .flat_map(|s| s.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for (f, s) in fast.iter().zip(&direct) {
            for k in 0..4 {
                // Each method is within exp(-4.5^2) = 1.6e-9 of the uncut field.
                assert!(
                    (f[k] - s[k]).abs() < 1e-8 * scale,
                    "{k}: {} vs {} (scale {scale})",
                    f[k],
                    s[k]
                );
            }
        }
    }
}
