use crate::math::{Vec2, cross};

/// Area, first moment and polar second moment of a rounded convex polygon about the origin.
///
/// The outline is split exactly into the core polygon, one rectangle of depth r along each
/// edge and one circular sector at each vertex; the sectors add up to a full disk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoundedMoments {
    pub area: f64,
    pub first_moment: Vec2,
    /// Integral of |x|^2 over the outline.
    pub polar_moment: f64,
}

impl RoundedMoments {
    pub fn of(vertices: &[Vec2], radius: f64) -> Self {
        let n = vertices.len();
        let mut total = polygon_moments(vertices);
        for k in 0..n {
            let a = vertices[k];
            let b = vertices[(k + 1) % n];
            let normal = outward_normal(a, b);
            let slab = polygon_moments(&[a, a + normal * radius, b + normal * radius, b]);
            total.add_scaled(&slab, 1.0);

            let prev = vertices[(k + n - 1) % n];
            total.add_scaled(
                &sector_moments(a, outward_normal(prev, a), normal, radius),
                1.0,
            );
        }
        total
    }

    pub fn centroid(&self) -> Vec2 {
        self.first_moment / self.area
    }

    /// Polar second moment about the centroid.
    pub fn polar_moment_about_centroid(&self) -> f64 {
        self.polar_moment - self.first_moment.norm_squared() / self.area
    }

    fn add_scaled(&mut self, other: &Self, sign: f64) {
        self.area += sign * other.area;
        self.first_moment += sign * other.first_moment;
        self.polar_moment += sign * other.polar_moment;
    }
}

/// Outward unit normal of edge a -> b of a counter-clockwise polygon.
pub(crate) fn outward_normal(a: Vec2, b: Vec2) -> Vec2 {
    let e = (b - a).normalize();
    Vec2::new(e.y, -e.x)
}

/// Signed moments of a simple polygon (positive when counter-clockwise).
fn polygon_moments(vertices: &[Vec2]) -> RoundedMoments {
    let n = vertices.len();
    let (mut area, mut first, mut polar) = (0.0, Vec2::zeros(), 0.0);
    for k in 0..n {
        let (p, q) = (vertices[k], vertices[(k + 1) % n]);
        let c = cross(p, q);
        area += c / 2.0;
        first += (p + q) * c / 6.0;
        polar += c * (p.norm_squared() + p.dot(&q) + q.norm_squared()) / 12.0;
    }
    RoundedMoments {
        area,
        first_moment: first,
        polar_moment: polar,
    }
}

/// The disk sector of radius r at `apex` between the outward normals of its two edges.
fn sector_moments(apex: Vec2, normal_in: Vec2, normal_out: Vec2, radius: f64) -> RoundedMoments {
    let angle = cross(normal_in, normal_out).atan2(normal_in.dot(&normal_out));
    let area = angle * radius * radius / 2.0;
    let bisector = (normal_in + normal_out).normalize();
    let half = angle / 2.0;
    let centroid_distance = if half > 1e-12 {
        2.0 * radius * half.sin() / (3.0 * half)
    } else {
        2.0 * radius / 3.0
    };
    let first_about_apex = bisector * (area * centroid_distance);
    let polar_about_apex = angle * radius.powi(4) / 4.0;
    RoundedMoments {
        area,
        first_moment: apex * area + first_about_apex,
        polar_moment: polar_about_apex
            + 2.0 * apex.dot(&first_about_apex)
            + apex.norm_squared() * area,
    }
}

#[cfg(test)]
/// Area of the rounded outline, from the core's area and perimeter (Steiner formula).
pub(crate) fn steiner_area(core_area: f64, core_perimeter: f64, radius: f64) -> f64 {
    core_area + core_perimeter * radius + std::f64::consts::PI * radius * radius
}
