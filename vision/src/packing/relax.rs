//! Overlap removal in a periodic box: Gauss-Seidel sweeps over neighbouring pairs, each pair
//! pushed apart (and turned) at its contact point as a position-based rigid-body correction.

use super::contact::{Body, contact};

/// A periodic box holding the bodies being packed.
pub struct Box2 {
    pub width: f64,
    pub height: f64,
}

/// Cell list rebuilt every sweep: cells at least one bounding diameter wide.
struct Cells {
    nx: usize,
    ny: usize,
    heads: Vec<Vec<u32>>,
}

impl Cells {
    fn build(bodies: &[Body], domain: &Box2, reach: f64) -> Self {
        let nx = ((domain.width / reach).floor() as usize).max(1);
        let ny = ((domain.height / reach).floor() as usize).max(1);
        let mut heads = vec![Vec::new(); nx * ny];
        for (i, b) in bodies.iter().enumerate() {
            let cx = ((b.x / domain.width * nx as f64) as usize).min(nx - 1);
            let cy = ((b.y / domain.height * ny as f64) as usize).min(ny - 1);
            heads[cy * nx + cx].push(i as u32);
        }
        Cells { nx, ny, heads }
    }

    /// Every unordered pair of bodies in the same or adjacent cells, once.
    fn pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let mut neighbours = Vec::with_capacity(9);
        for cy in 0..self.ny {
            for cx in 0..self.nx {
                let here = cy * self.nx + cx;
                neighbours.clear();
                for dy in [-1i64, 0, 1] {
                    for dx in [-1i64, 0, 1] {
                        let x = (cx as i64 + dx).rem_euclid(self.nx as i64) as usize;
                        let y = (cy as i64 + dy).rem_euclid(self.ny as i64) as usize;
                        let cell = y * self.nx + x;
                        // Each pair of cells once, and a small grid must not list a cell twice.
                        if cell >= here && !neighbours.contains(&cell) {
                            neighbours.push(cell);
                        }
                    }
                }
                for &other in &neighbours {
                    for (k, &i) in self.heads[here].iter().enumerate() {
                        let start = if other == here { k + 1 } else { 0 };
                        for &j in &self.heads[other][start..] {
                            out.push((i, j));
                        }
                    }
                }
            }
        }
        out
    }
}

/// Settings of one relaxation.
pub struct Relax {
    /// Stop once the deepest overlap of a sweep is below this (metres).
    pub tolerance: f64,
    pub max_sweeps: usize,
    /// Scales the turning part of each correction (1: rigid-body physics; less: grains keep
    /// their orientation, as in a slow, aligned filling).
    pub rotation_mobility: f64,
}

/// Removes overlaps; returns the deepest overlap of the last sweep and whether it met the
/// tolerance.
pub fn relax(bodies: &mut [Body], domain: &Box2, settings: &Relax) -> (f64, bool) {
    let reach = bodies
        .iter()
        .map(|b| 2.0 * b.half_length.hypot(b.half_width))
        .fold(0.0, f64::max);
    let mut deepest = f64::INFINITY;
    for _ in 0..settings.max_sweeps {
        let cells = Cells::build(bodies, domain, reach);
        deepest = sweep(bodies, domain, &cells.pairs(), settings.rotation_mobility);
        for b in bodies.iter_mut() {
            b.x = b.x.rem_euclid(domain.width);
            b.y = b.y.rem_euclid(domain.height);
        }
        if deepest < settings.tolerance {
            return (deepest, true);
        }
    }
    (deepest, false)
}

/// Largest overlap among all pairs (no correction).
pub fn deepest_overlap(bodies: &[Body], domain: &Box2) -> f64 {
    let reach = bodies
        .iter()
        .map(|b| 2.0 * b.half_length.hypot(b.half_width))
        .fold(0.0, f64::max);
    let cells = Cells::build(bodies, domain, reach);
    cells
        .pairs()
        .into_iter()
        .filter_map(|(i, j)| {
            let (a, b) = (&bodies[i as usize], &bodies[j as usize]);
            contact(a, b, min_image(a, b, domain)).map(|c| c.depth)
        })
        .fold(0.0, f64::max)
}

fn min_image(a: &Body, b: &Body, domain: &Box2) -> [f64; 2] {
    let mut dx = b.x - a.x;
    let mut dy = b.y - a.y;
    dx -= domain.width * (dx / domain.width).round();
    dy -= domain.height * (dy / domain.height).round();
    [dx, dy]
}

fn sweep(bodies: &mut [Body], domain: &Box2, pairs: &[(u32, u32)], rotation: f64) -> f64 {
    let mut deepest: f64 = 0.0;
    for &(i, j) in pairs {
        let (i, j) = (i as usize, j as usize);
        let (a, b) = (bodies[i], bodies[j]);
        let d = min_image(&a, &b, domain);
        let bound = a.half_length.hypot(a.half_width) + b.half_length.hypot(b.half_width);
        if d[0] * d[0] + d[1] * d[1] >= bound * bound {
            continue;
        }
        let Some(c) = contact(&a, &b, d) else {
            continue;
        };
        deepest = deepest.max(c.depth);
        // Grains of equal density: mass ~ area, inertia of a rectangle.
        let (ma, ia) = mass_inertia(&a);
        let (mb, ib) = mass_inertia(&b);
        let n = c.normal;
        let ra = c.point;
        let rb = [c.point[0] - d[0], c.point[1] - d[1]];
        let ra_n = ra[0] * n[1] - ra[1] * n[0];
        let rb_n = rb[0] * n[1] - rb[1] * n[0];
        let wa = 1.0 / ma + rotation * ra_n * ra_n / ia;
        let wb = 1.0 / mb + rotation * rb_n * rb_n / ib;
        // A hair more than the depth, so that the pair ends just apart rather than just touching.
        let impulse = OVER_RELAXATION * c.depth / (wa + wb);
        bodies[i].x -= n[0] * impulse / ma;
        bodies[i].y -= n[1] * impulse / ma;
        bodies[i].theta -= rotation * ra_n * impulse / ia;
        bodies[j].x += n[0] * impulse / mb;
        bodies[j].y += n[1] * impulse / mb;
        bodies[j].theta += rotation * rb_n * impulse / ib;
    }
    deepest
}

const OVER_RELAXATION: f64 = 1.6;

fn mass_inertia(b: &Body) -> (f64, f64) {
    let (l, w) = (2.0 * b.half_length, 2.0 * b.half_width);
    let m = l * w;
    (m, m * (l * l + w * w) / 12.0)
}
