//! The starting state: grains dropped at random places without overlap (random sequential
//! addition). Starting from overlapping random places instead lets the first relaxation push
//! grains out of crowded spots into clumps, leaving cavities that the squeeze then cannot close.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::contact::{Body, contact};
use super::relax::{Box2, min_image};

/// Tries per grain before it is placed anyway (the relaxation then removes its overlap).
const TRIES: usize = 200;

/// Places bodies one by one at random free places; `angle` draws each one's orientation.
pub fn scatter(
    count: usize,
    domain: &Box2,
    half_length: f64,
    half_width: f64,
    rng: &mut ChaCha8Rng,
    mut angle: impl FnMut(&mut ChaCha8Rng) -> f64,
) -> Vec<Body> {
    let reach = 2.0 * half_length.hypot(half_width);
    let nx = ((domain.width / reach).floor() as usize).max(1);
    let ny = ((domain.height / reach).floor() as usize).max(1);
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); nx * ny];
    let cell_of = |x: f64, y: f64| {
        let cx = ((x / domain.width * nx as f64) as usize).min(nx - 1);
        let cy = ((y / domain.height * ny as f64) as usize).min(ny - 1);
        (cx, cy)
    };
    let mut bodies: Vec<Body> = Vec::with_capacity(count);
    for _ in 0..count {
        let theta = angle(rng);
        let mut candidate = Body::new(0.0, 0.0, theta, half_length, half_width);
        for _ in 0..TRIES {
            candidate.x = rng.random::<f64>() * domain.width;
            candidate.y = rng.random::<f64>() * domain.height;
            let (cx, cy) = cell_of(candidate.x, candidate.y);
            let mut free = true;
            'search: for dy in [ny - 1, 0, 1] {
                for dx in [nx - 1, 0, 1] {
                    let cell = ((cy + dy) % ny) * nx + (cx + dx) % nx;
                    for &j in &cells[cell] {
                        let other = &bodies[j as usize];
                        if contact(other, &candidate, min_image(other, &candidate, domain))
                            .is_some()
                        {
                            free = false;
                            break 'search;
                        }
                    }
                }
            }
            if free {
                break;
            }
        }
        let (cx, cy) = cell_of(candidate.x, candidate.y);
        cells[cy * nx + cx].push(bodies.len() as u32);
        bodies.push(candidate);
    }
    bodies
}
