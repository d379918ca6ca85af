//! Synthetic deposits: a lattice of grains with random jitter of position and angle. Stand-ins
//! for benchmarks and samples, not a physical model of a filling.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Deposit, Grain};

/// `n` grains of `length` x `width` (m) on a square lattice that fills `frame`
/// ([x_min, x_max, y_min, y_max], m) row by row, each moved by up to `jitter` lattice spacings
/// and turned by a uniformly random angle within +- `angle_spread` (rad) of 0.
pub fn jittered_lattice(
    n: usize,
    length: f64,
    width: f64,
    frame: [f64; 4],
    jitter: f64,
    angle_spread: f64,
    seed: u64,
) -> Deposit {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (w, h) = (frame[1] - frame[0], frame[3] - frame[2]);
    let spacing = (w * h / n as f64).sqrt();
    let columns = ((w / spacing).floor() as usize).max(1);
    let grains = (0..n)
        .map(|k| {
            let (c, r) = (k % columns, k / columns);
            let x = frame[0] + (c as f64 + 0.5 + jitter * rng.random_range(-1.0..1.0)) * spacing;
            let y = frame[2] + (r as f64 + 0.5 + jitter * rng.random_range(-1.0..1.0)) * spacing;
            let theta = angle_spread * rng.random_range(-1.0..1.0);
            Grain::placed(x, y, theta, length, width).folded()
        })
        .collect();
    Deposit { grains }
}
