use super::PlacedCore;

/// A lower bound on the distance between two placed cores (zero or negative when they may
/// overlap): the widest gap between their shadows on the normal of any edge of either. A
/// convex core lies behind each of its edge lines, so the other core's vertex nearest to that
/// line is no closer to the core than its distance from the line. The bound is exact when the
/// nearest features are a vertex and an edge, and short of the distance when they are two
/// corners; it never exceeds it, which is what a test that skips pairs needs.
pub fn core_core_separation(first: &PlacedCore, second: &PlacedCore) -> f64 {
    apart_behind(first, second).max(apart_behind(second, first))
}

/// The widest gap between `other` and the lines of `owner`'s edges (q . n - a . n rounds
/// differently from (q - a) . n by ~1e-18 m: the callers leave a margin far above that).
fn apart_behind(owner: &PlacedCore, other: &PlacedCore) -> f64 {
    let mut widest = f64::NEG_INFINITY;
    for e in 0..owner.len() {
        let n = owner.normal(e);
        let mut nearest = f64::INFINITY;
        for q in other.vertices {
            nearest = nearest.min(q.dot(&n));
        }
        widest = widest.max(nearest - owner.vertices[e].dot(&n));
    }
    widest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Vec2, rotate};
    use crate::shape::Spheropolygon;

    /// A core's vertices and edge directions, placed at `centre` and turned by `angle`.
    fn placed(shape: &Spheropolygon, centre: Vec2, angle: f64) -> (Vec<Vec2>, Vec<Vec2>) {
        let (sin, cos) = angle.sin_cos();
        let vertices = shape
            .vertices()
            .iter()
            .map(|v| centre + rotate(*v, cos, sin))
            .collect();
        let directions = shape
            .edge_directions()
            .iter()
            .map(|d| rotate(*d, cos, sin))
            .collect();
        (vertices, directions)
    }

    fn core<'a>(
        vertices: &'a [Vec2],
        directions: &'a [Vec2],
        shape: &'a Spheropolygon,
    ) -> PlacedCore<'a> {
        PlacedCore {
            vertices,
            directions,
            lengths: shape.edge_lengths(),
            radius: shape.radius(),
            centre: Vec2::zeros(),
            arm: 0.0,
        }
    }

    /// Distance between two convex polygons that do not overlap, by brute force: the nearest
    /// points are a vertex of one and a point of an edge of the other.
    fn distance(a: &[Vec2], b: &[Vec2]) -> f64 {
        let to_segment = |p: Vec2, s: Vec2, t: Vec2| {
            let d = t - s;
            let u = ((p - s).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (p - (s + d * u)).norm()
        };
        let one_way = |a: &[Vec2], b: &[Vec2]| {
            a.iter()
                .flat_map(|p| (0..b.len()).map(move |e| to_segment(*p, b[e], b[(e + 1) % b.len()])))
                .fold(f64::INFINITY, f64::min)
        };
        one_way(a, b).min(one_way(b, a))
    }

    #[test]
    fn never_exceeds_the_distance_and_is_exact_face_to_face() {
        let rod = Spheropolygon::rounded_rectangle(0.0089, 0.003, 0.00015).unwrap();
        let square = Spheropolygon::rounded_rectangle(0.0069, 0.0069, 0.00035).unwrap();
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut apart, mut tight) = (0, 0);
        for _ in 0..4000 {
            let other = if next() < 0.5 { &rod } else { &square };
            let (va, da) = placed(&rod, Vec2::zeros(), next() * 7.0);
            let centre = Vec2::new(next() - 0.5, next() - 0.5) * 0.03;
            let (vb, db) = placed(other, centre, next() * 7.0);
            let bound = core_core_separation(&core(&va, &da, &rod), &core(&vb, &db, other));
            if bound > 0.0 {
                let exact = distance(&va, &vb);
                assert!(bound <= exact * (1.0 + 1e-12), "{bound} > {exact}");
                apart += 1;
                if bound > 0.99 * exact {
                    tight += 1;
                }
            }
        }
        // Random placements: most are apart, and the bound is the distance for most of them
        // (vertex against edge); corner against corner gives less.
        assert!(
            apart > 2000 && tight > apart / 2,
            "{apart} apart, {tight} tight"
        );
        // Face to face, 1 mm apart.
        let (va, da) = placed(&square, Vec2::zeros(), 0.0);
        let (vb, db) = placed(&square, Vec2::new(0.0062 + 0.001, 0.002), 0.0);
        let bound = core_core_separation(&core(&va, &da, &square), &core(&vb, &db, &square));
        assert!((bound - 0.001).abs() < 1e-12, "{bound}");
        // Overlapping cores: no positive bound.
        let (vb, db) = placed(&square, Vec2::new(0.005, 0.001), 0.3);
        let bound = core_core_separation(&core(&va, &da, &square), &core(&vb, &db, &square));
        assert!(bound <= 0.0, "{bound}");
    }
}
